// tests/apps/render_cli_test.cpp — `certray render` end to end: runs the built binary on 3D, 2D
// and JSON scenes and checks the PNG files, the printed counts, and that bad options fail with a
// message and leave no file behind.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/cli_fixture.h"
#include "tracers/png_io.h"

namespace {

namespace fs = std::filesystem;

using certray::testing::slurp;

class RenderCli : public certray::testing::CliFixture {
  protected:
    void SetUp() override {
        CliFixture::SetUp();
        write("sphere.expr", "x^2 + y^2 + z^2 - 1\n");
        write("disk.expr", "x^2 + y^2 - 0.5625\n");
    }
};

TEST_F(RenderCli, Renders3dScene) {
    for (const char* aov : {"shade", "depth", "steps", "normal", "status"}) {
        ASSERT_EQ(run(std::string("render sphere.expr -o out.png --size 40x30 --aov ") + aov), 0)
            << err_;
        const certray::tracers::RgbImage img = certray::tracers::read_png(path("out.png").string());
        EXPECT_EQ(img.width, 40u);
        EXPECT_EQ(img.height, 30u);
        EXPECT_NE(out_.find("hit "), std::string::npos) << out_;
        EXPECT_NE(out_.find("unknown 0"), std::string::npos) << out_;
        EXPECT_FALSE(fs::exists(path("out.png.tmp")));
    }
}

/// The float32 values of a .npy file written by certray (version 1.0, little-endian, C order).
std::vector<float> read_npy(const fs::path& p, std::string& header) {
    const std::string bytes = certray::testing::slurp(p);
    EXPECT_EQ(bytes.substr(0, 6), "\x93NUMPY");
    const std::size_t len = static_cast<unsigned char>(bytes[8]) |
                            (static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8);
    header = bytes.substr(10, len);
    EXPECT_EQ((10 + len) % 64, 0u);
    std::vector<float> v((bytes.size() - 10 - len) / 4);
    std::memcpy(v.data(), bytes.data() + 10 + len, v.size() * 4);
    return v;
}

TEST_F(RenderCli, AovsAsFloatDataAndWithAColourBar) {
    // From (0, -5, 0) towards the centre, the middle pixel of a 41x31 image looks along +y: the
    // unit sphere is met at t = 4; the corners miss it.
    write("cam.json", R"({"scene": "sphere.expr", "camera": {"eye": [0, -5, 0], "target": [0, 0, 0],
        "up": [0, 0, 1], "fov": 30}})");
    ASSERT_EQ(run("render cam.json -o d.png --size 41x31 --aov depth --data d.npy"), 0) << err_;
    std::string header;
    const std::vector<float> depth = read_npy(path("d.npy"), header);
    EXPECT_NE(header.find("'descr': '<f4'"), std::string::npos) << header;
    EXPECT_NE(header.find("'shape': (31, 41)"), std::string::npos) << header;
    ASSERT_EQ(depth.size(), 41u * 31u);
    EXPECT_NEAR(depth[15 * 41 + 20], 4.0f, 1e-5f);
    EXPECT_TRUE(std::isnan(depth[0]));
    EXPECT_NE(out_.find("depth: hit t from 4"), std::string::npos) << out_;
    // status as data: 0 hit, 1 miss; normal as 3 channels; pfm rows bottom up.
    ASSERT_EQ(run("render cam.json -o s.png --size 41x31 --aov status --data s.pfm"), 0) << err_;
    const std::string pfm = certray::testing::slurp(path("s.pfm"));
    const std::string head = "Pf\n41 31\n-1.0\n";
    ASSERT_EQ(pfm.substr(0, head.size()), head);
    std::vector<float> status(41 * 31);
    std::memcpy(status.data(), pfm.data() + head.size(), status.size() * 4);
    EXPECT_EQ(status[15 * 41 + 20], 0.0f);  // the middle row is the middle row either way
    EXPECT_EQ(status[0], 1.0f);
    ASSERT_EQ(run("render cam.json -o n.png --size 41x31 --aov normal --data n.npy"), 0) << err_;
    const std::vector<float> normal = read_npy(path("n.npy"), header);
    EXPECT_NE(header.find("'shape': (31, 41, 3)"), std::string::npos) << header;
    // The middle pixel sees the sphere at (0, -1, 0): the normal facing the camera is (0, -1, 0).
    EXPECT_NEAR(normal[3 * (15 * 41 + 20) + 1], -1.0f, 1e-3f);
    // Shade is not data; other extensions are refused; nothing is left behind.
    EXPECT_EQ(run("render cam.json -o x.png --size 41x31 --data x.npy"), 2);
    EXPECT_EQ(run("render cam.json -o x.png --size 41x31 --aov depth --data x.csv"), 2);
    EXPECT_FALSE(fs::exists(path("x.png")));
    // The colour bar of a 64x48 depth image: 16x4 pixels at (44, 40), bright (near) on the left,
    // dark (far) on the right, in a dark frame.
    ASSERT_EQ(run("render cam.json -o bar.png --size 64x48 --aov depth"), 0) << err_;
    const certray::tracers::RgbImage bar = certray::tracers::read_png(path("bar.png").string());
    EXPECT_EQ(bar.at(44, 41)[0], 255);
    EXPECT_LT(bar.at(59, 41)[0], 45);
    EXPECT_LT(bar.at(43, 41)[0], 30);
    EXPECT_GT(bar.at(51, 41)[0], bar.at(52, 41)[0]);
}

TEST_F(RenderCli, CameraFlagsAsInTheJson) {
    // The same camera as AovsAsFloatDataAndWithAColourBar's JSON: the middle pixel meets the unit
    // sphere at t = 4.
    ASSERT_EQ(run("render sphere.expr -o d.png --size 41x31 --aov depth --data d.npy --eye 0 -5 0 "
                  "--target 0 0 0 --up 0 0 1 --fov 30"),
              0)
        << err_;
    std::string header;
    const std::vector<float> depth = read_npy(path("d.npy"), header);
    ASSERT_EQ(depth.size(), 41u * 31u);
    EXPECT_NEAR(depth[15 * 41 + 20], 4.0f, 1e-5f);
    // A 2D scene takes no camera.
    EXPECT_EQ(run("render disk.expr -o x.png --eye 0 -5 0"), 2);
    EXPECT_NE(err_.find("--eye"), std::string::npos) << err_;
    EXPECT_EQ(run("render sphere.expr -o x.png --eye 0 -5"), 2);  // three numbers
}

TEST_F(RenderCli, SurfaceAndOrthographicCamera) {
    EXPECT_EQ(run("render sphere.expr -o s.png --size 32x24"), 0) << err_;
    EXPECT_NE(out_.find("surface zero"), std::string::npos) << out_;  // .expr: zero by default
    EXPECT_EQ(run("render sphere.expr -o s.png --size 32x24 --surface solid"), 0) << err_;
    EXPECT_NE(out_.find("surface solid"), std::string::npos) << out_;
    EXPECT_NE(out_.find("unknown 0"), std::string::npos) << out_;
    // Ortho over the default bounds [-2, 2]^3 from z = 2 down: the unit sphere's top is at t = 1
    // under the middle pixel of an odd-sized image.
    ASSERT_EQ(run("render sphere.expr -o o.png --size 33x33 --camera ortho --aov depth --data "
                  "o.npy"),
              0)
        << err_;
    std::string header;
    const std::vector<float> depth = read_npy(path("o.npy"), header);
    ASSERT_EQ(depth.size(), 33u * 33u);
    EXPECT_NEAR(depth[16 * 33 + 16], 1.0f, 1e-5f);
    EXPECT_TRUE(std::isnan(depth[0]));  // the corner ray passes beside the sphere
    EXPECT_EQ(run("render sphere.expr -o o.png --camera ortho --method sphere"), 2);
    EXPECT_EQ(run("render sphere.expr -o o.png --camera ortho --eye 0 0 5"), 2);
    EXPECT_EQ(run("render sphere.expr -o o.png --camera ortho --per-ray"), 2);  // not ignored
    EXPECT_NE(err_.find("--per-ray"), std::string::npos) << err_;
    EXPECT_EQ(run("render sphere.expr -o o.png --surface hollow"), 2);
}

TEST_F(RenderCli, ModelsAsTheirAuthorsMadeThemRenderWithNoUnknownPixel) {
    // Fidget's and Lipschitz-Pruning's models, drawn as their renderers draw them: the solid
    // f < 0, every pixel proven (hit or miss).
    const std::string scenes = std::string(CERTRAY_SOURCE_DIR) + "/scenes/";
    // Fidget's bear divides by a function that vanishes on a plane (a pole every vertical ray
    // crosses); its colonnade touches 0 along planes (103 unknown pixels at 256x256 before the
    // coherent walk split undecided leaves again with pruned tapes).
    for (const char* model : {"tanglecube.vm 48x36", "test.json 48x36", "molecule.json 24x18",
                              "fidget/bear.vm 64x48", "fidget/colonnade.vm 256x256"}) {
        const std::string m(model);
        const std::string file = m.substr(0, m.find(' ')), size = m.substr(m.find(' ') + 1);
        ASSERT_EQ(run("render '" + scenes + file + "' -o m.png -q --size " + size), 0) << err_;
        EXPECT_NE(out_.find("surface solid"), std::string::npos) << file << ": " << out_;
        EXPECT_NE(out_.find(", unknown 0 pixels"), std::string::npos) << file << ": " << out_;
        EXPECT_EQ(out_.find("hit 0,"), std::string::npos) << file << ": " << out_;
    }
}

TEST_F(RenderCli, Renders2dSceneWithExactCount) {
    // 64×64 over [−1, 1]²: centres (2i + 1 − 64)/64 exactly, so f < 0 ⇔ a² + b² < 0.5625·64².
    long expected = 0;
    for (long i = 0; i < 64; ++i) {
        for (long j = 0; j < 64; ++j) {
            const long a = 2 * i + 1 - 64, b = 2 * j + 1 - 64;
            expected += a * a + b * b < 2304;
        }
    }
    ASSERT_EQ(run("render disk.expr -o disk.png --size 64x64"), 0) << err_;
    EXPECT_NE(out_.find("inside (f < 0) " + std::to_string(expected) + " pixels"),
              std::string::npos)
        << out_ << " expected " << expected;
    const certray::tracers::RgbImage img = certray::tracers::read_png(path("disk.png").string());
    EXPECT_EQ(img.width, 64u);
    EXPECT_EQ(img.height, 64u);
}

TEST_F(RenderCli, JsonScene) {
    write("scene.json",
          R"({"scene": "sphere.expr", "size": [20, 10], "method": "certified",
              "camera": {"eye": [0, -5, 0], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 30},
              "bounds": [[-2, 2], [-2, 2], [-2, 2]], "light": [0, -1, 1]})");
    ASSERT_EQ(run("render scene.json -o j.png"), 0) << err_;
    const certray::tracers::RgbImage img = certray::tracers::read_png(path("j.png").string());
    EXPECT_EQ(img.width, 20u);
    EXPECT_EQ(img.height, 10u);
    write("bad.json", R"({"scene": "sphere.expr", "colour": 3})");
    EXPECT_NE(run("render bad.json -o bad.png"), 0);
    EXPECT_NE(err_.find("colour"), std::string::npos) << err_;
    EXPECT_FALSE(fs::exists(path("bad.png")));
}

TEST_F(RenderCli, BadOptionsFailAndLeaveNoFile) {
    for (const char* size : {"0x5", "abc", "20000x10", "10x", "x10", "5x-3", "1.5x2"}) {
        EXPECT_NE(run(std::string("render sphere.expr -o bad.png --size ") + size), 0) << size;
        EXPECT_NE(err_.find("--size"), std::string::npos) << size << ": " << err_;
        EXPECT_FALSE(fs::exists(path("bad.png"))) << size;
        EXPECT_FALSE(fs::exists(path("bad.png.tmp"))) << size;
    }
    EXPECT_NE(run("render sphere.expr -o bad.png --method nosuch"), 0);
    EXPECT_NE(err_.find("certified"), std::string::npos) << err_;  // the list of methods
    EXPECT_FALSE(fs::exists(path("bad.png")));
    EXPECT_NE(run("render missing.expr -o bad.png"), 0);
    EXPECT_FALSE(fs::exists(path("bad.png")));
    EXPECT_NE(run("render sphere.expr -o no_such_dir/bad.png --size 8x8"), 0);
    EXPECT_FALSE(fs::exists(path("no_such_dir")));
}

TEST_F(RenderCli, ThreeDOptionsOnA2dSceneAreAnError) {
    EXPECT_EQ(run("render disk.expr -o d.png --size 8x8 --method certified --aov depth"), 2);
    EXPECT_NE(err_.find("certray render: --method, --aov are 3D options, but 'disk.expr' is a 2D "
                        "scene (it reads x and y only), drawn as the sign of f"),
              std::string::npos)
        << err_;
    EXPECT_FALSE(fs::exists(path("d.png")));
    for (const char* opt : {"--method certified", "--aov shade", "--budget 10", "--epsilon 0.1"}) {
        EXPECT_EQ(run(std::string("render disk.expr -o d.png --size 8x8 ") + opt), 2) << opt;
        const std::string name = std::string(opt).substr(0, std::string(opt).find(' '));
        EXPECT_NE(err_.find(name + " is a 3D option"), std::string::npos) << err_;
        EXPECT_NE(err_.find("2D scene"), std::string::npos) << err_;
    }
}

TEST_F(RenderCli, ThreeDKeysOfAJsonSceneOnA2dSceneAreAnInputError) {
    write("disk.json", R"({"scene": "disk.expr", "method": "sphere", "light": [0, 0, 1]})");
    EXPECT_EQ(run("render disk.json -o d.png --size 8x8"), 1);
    EXPECT_NE(err_.find("disk.json: \"method\", \"light\" apply to 3D scenes only; this scene "
                        "is 2D"),
              std::string::npos)
        << err_;
    EXPECT_FALSE(fs::exists(path("d.png")));
    write("disk2.json", R"({"scene": "disk.expr", "size": [16, 8]})");
    EXPECT_EQ(run("render disk2.json -o d.png"), 0) << err_;
}

TEST_F(RenderCli, OnlyPngIsWritten) {
    EXPECT_EQ(run("render sphere.expr -o x.jpg --size 8x8"), 2);
    EXPECT_EQ(err_, "certray render: cannot write 'x.jpg': only .png is supported\n");
    EXPECT_FALSE(fs::exists(path("x.jpg")));
    EXPECT_EQ(run("render sphere.expr -o noext --size 8x8"), 2);
    EXPECT_NE(err_.find("only .png is supported"), std::string::npos) << err_;
    EXPECT_EQ(run("render sphere.expr -o x.PNG --size 8x8"), 0) << err_;
    EXPECT_TRUE(fs::exists(path("x.PNG")));
}

TEST_F(RenderCli, TwoDPixelsAreSquare) {
    // A square region on a 2:1 image: x widened to [-2, 2], said on stderr (not with --quiet).
    ASSERT_EQ(run("render disk.expr -o d.png --size 80x40"), 0) << err_;
    EXPECT_NE(out_.find("80x40 over [-2, 2] x [-1, 1]"), std::string::npos) << out_;
    EXPECT_NE(err_.find("widened to [-2, 2] x [-1, 1]"), std::string::npos) << err_;
    ASSERT_EQ(run("render disk.expr -o d.png --size 40x80 --quiet"), 0) << err_;
    EXPECT_NE(out_.find("40x80 over [-1, 1] x [-2, 2]"), std::string::npos) << out_;
    EXPECT_TRUE(err_.empty()) << err_;
    // Without --size, the image takes the aspect of the bounds (a square here).
    ASSERT_EQ(run("render disk.expr -o d.png"), 0) << err_;
    EXPECT_NE(out_.find("1024x1024 over [-1, 1] x [-1, 1]"), std::string::npos) << out_;
}

TEST_F(RenderCli, ProgressLinesWhenStderrIsAFile) {
    // A run shorter than the threshold (2 s by default) prints no progress at all.
    ASSERT_EQ(run("render sphere.expr -o s.png --size 16x12"), 0) << err_;
    EXPECT_TRUE(err_.empty()) << err_;
    // With the threshold at 0, lines (not a bar: no carriage return) in 3D and 2D.
    setenv("CERTRAY_PROGRESS_SECONDS", "0", 1);
    ASSERT_EQ(run("render sphere.expr -o s.png --size 64x48"), 0) << err_;
    EXPECT_NE(err_.find("certray render: 100% (12 tiles) in "), std::string::npos) << err_;
    EXPECT_EQ(err_.find('\r'), std::string::npos) << err_;
    ASSERT_EQ(run("render disk.expr -o d.png --size 64x64"), 0) << err_;
    EXPECT_NE(err_.find("certray render: 100% ("), std::string::npos) << err_;
    // --quiet: nothing on stderr; the summary stays on stdout.
    ASSERT_EQ(run("render sphere.expr -o s.png --size 64x48 --quiet"), 0) << err_;
    EXPECT_TRUE(err_.empty()) << err_;
    EXPECT_NE(out_.find("3D scene 64x48"), std::string::npos) << out_;
    unsetenv("CERTRAY_PROGRESS_SECONDS");
}

TEST_F(RenderCli, HelpDescribesRender) {
    ASSERT_EQ(run("render --help"), 0);
    for (const char* word : {"--size", "--aov", "--method", "--bounds LO HI", "--threads", "2D",
                             "--quiet", ".expr", ".vm", ".txt", ".json", "Lipschitz-Pruning"}) {
        EXPECT_NE(out_.find(word), std::string::npos) << word;
    }
}

}  // namespace
