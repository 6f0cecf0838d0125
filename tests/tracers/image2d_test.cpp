// tests/tracers/image2d_test.cpp — the 2D quadtree (tracers/image2d): exact pixel counts, and
// equality with the brute-force double evaluation at every pixel centre.
#include "tracers/image2d.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <chrono>
#include <filesystem>
#include <string>

#include "expr/eval.h"
#include "expr/load.h"
#include "expr/parser.h"
#include "expr/tape.h"
#include "tests/support/image2d_reference.h"
#include "tests/support/random_dag.h"

namespace certray::tracers {
namespace {

using testing::kScenesDir;
using testing::without_z;

/// Number of pixels where two classifications differ (and the first such pixel in `where`).
std::size_t mismatches(const Image2d& img, const std::vector<Pixel2d>& ref, std::string& where) {
    std::size_t n = 0;
    for (std::size_t k = 0; k < ref.size(); ++k) {
        if (img.pixels[k] != ref[k]) {
            if (n++ == 0) {
                where = "pixel (" + std::to_string(k % img.width) + ", " +
                        std::to_string(k / img.width) + ")";
            }
        }
    }
    return n;
}

TEST(Image2d, ProsperoHas132816InsidePixels) {
    // Fidget's reference image of prospero.vm: 1024² over [−1, 1]², 132,816 pixels with f < 0.
    const expr::Tape tape(expr::load_graph_file((kScenesDir / "prospero.vm").string()));
    Image2dOptions o;
    const Image2d img = render_2d(tape, o);
    EXPECT_EQ(img.inside, 132816u);
    EXPECT_EQ(img.undefined, 0u);
    EXPECT_GT(img.tiles_filled, 0u);  // the quadtree did decide tiles without their pixels
}

TEST(Image2d, ProsperoQuadtreeEqualsBruteForce) {
    const expr::Tape tape(expr::load_graph_file((kScenesDir / "prospero.vm").string()));
    Image2dOptions o;
    o.width = 97;  // odd sizes: tiles of every shape, centres not on a dyadic lattice
    o.height = 61;
    o.root_tile = 16;
    const Image2d img = render_2d(tape, o);
    std::string where;
    EXPECT_EQ(mismatches(img, testing::brute_force_2d(tape, o).pixels, where), 0u) << where;
}

/// Pixels of the disk x² + y² < r² (r² = num/den) over [−1.5, 1.5] × [−1, 1] at 96 × 64: the
/// centres are exactly (2i + 1 − 96)/64 and (63 − 2j)/64, so the count is an integer question.
std::uint64_t disk_pixels(std::int64_t num, std::int64_t den) {
    std::uint64_t n = 0;
    for (std::int64_t j = 0; j < 64; ++j) {
        for (std::int64_t i = 0; i < 96; ++i) {
            const std::int64_t a = 2 * i + 1 - 96, b = 63 - 2 * j;
            n += (a * a + b * b) * den < 4096 * num;
        }
    }
    return n;
}

TEST(Image2d, DiskCountIsExact) {
    Image2dOptions o;
    o.x = {-1.5, 1.5};
    o.y = {-1.0, 1.0};
    o.width = 96;
    o.height = 64;
    o.root_tile = 16;
    // 0.5625 = 9/16 exactly; for 0.49 the literal's double differs from 49/100 by ~1e-17, far less
    // than the gap between n/4096 and 0.49 for any integer n, so 49/100 decides the same pixels.
    const std::pair<std::string, std::pair<int, int>> cases[] = {
        {"x^2 + y^2 - 0.5625", {9, 16}},
        {"x^2 + y^2 - 0.49", {49, 100}},
        {"sqrt(x^2 + y^2) - 0.75", {9, 16}}};
    for (const auto& [text, r2] : cases) {
        const expr::Tape tape(expr::parse_expr(text));
        const std::uint64_t expected = disk_pixels(r2.first, r2.second);
        EXPECT_EQ(render_2d(tape, o).inside, expected) << text;
        Image2dOptions brute = o;
        brute.use_quadtree = false;
        EXPECT_EQ(render_2d(tape, brute).inside, expected) << text;
    }
    // Sanity of the lattice count itself: about π·r² / (pixel area 1/1024) pixels.
    EXPECT_NEAR(static_cast<double>(disk_pixels(9, 16)), 3.14159265 * 0.5625 * 1024, 20);
}

TEST(Image2d, UndefinedPixelsAreCounted) {
    // sqrt(x) − 2 is NaN exactly for x < 0 (the left half of an even-width image over [−1, 1])
    // and ≤ 1 − 2 < 0 on the right half.
    const expr::Tape tape(expr::parse_expr("sqrt(x) - 2"));
    Image2dOptions o;
    o.width = 40;
    o.height = 30;
    const Image2d img = render_2d(tape, o);
    EXPECT_EQ(img.undefined, 20u * 30u);
    EXPECT_EQ(img.inside, 20u * 30u);
}

TEST(Image2d, OverflowFollowsTheDoubleEvaluation) {
    // Found by the random-DAG property: the real function is cos(cos(y)) − 2 < 0 for the huge but
    // finite y = 1e600 − x, whose enclosures are bounded ([cos 1 − 2, −1]); in double 1e300·1e300
    // overflows to inf and cos(inf) is NaN at every pixel. The image is the double evaluation's:
    // an overflowing tile is never decided from its enclosure.
    const expr::Tape tape(expr::parse_expr("cos(cos(1e300 * 1e300 - x)) - 2"));
    Image2dOptions o;
    o.width = 24;
    o.height = 16;
    const Image2d img = render_2d(tape, o);
    EXPECT_EQ(img.undefined, 24u * 16u);
    EXPECT_EQ(img.inside, 0u);
    std::string where;
    EXPECT_EQ(mismatches(img, testing::brute_force_2d(tape, o).pixels, where), 0u) << where;
}

TEST(Image2d, RejectsBadInput) {
    Image2dOptions o;
    o.width = 0;
    EXPECT_THROW(render_2d(expr::Tape(expr::parse_expr("x")), o), std::invalid_argument);
    EXPECT_THROW(render_2d(expr::Tape(expr::parse_expr("x + z")), Image2dOptions{}),
                 std::invalid_argument);
}

TEST(Image2d, ThreadsGiveTheSameImage) {
    const expr::Tape tape(expr::load_graph_file((kScenesDir / "prospero.vm").string()));
    Image2dOptions o;
    o.width = 256;
    o.height = 256;
    o.threads = 1;
    const Image2d one = render_2d(tape, o);
    o.threads = 2;
    const Image2d two = render_2d(tape, o);
    EXPECT_EQ(one.pixels, two.pixels);
}

RC_GTEST_PROP(Image2d, RandomDagQuadtreeEqualsBruteForce, ()) {
    const expr::Graph g = without_z(*testing::gen_dag(16), 0.25);
    const expr::Tape tape(g);
    Image2dOptions o;
    o.width = 32;
    o.height = 32;
    o.root_tile = 16;
    o.threads = 1;
    const double lo = *rc::gen::element(-1.0, -2.0, -0.3, 0.0);
    const double hi = *rc::gen::element(1.0, 3.0, 0.7, 1e-3);
    o.x = {lo, hi};
    o.y = {lo - 0.5, hi + 0.25};
    const Image2d img = render_2d(tape, o);
    std::string where;
    RC_ASSERT(mismatches(img, testing::brute_force_2d(tape, o).pixels, where) == 0u);
}

}  // namespace
}  // namespace certray::tracers
