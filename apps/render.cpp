// apps/render.cpp — `certray render`: options and JSON scenes to tracers/ calls, then a PNG.
#include "apps/render.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>

#include "apps/progress.h"
#include "certray/certray.h"
#include "expr/input_error.h"
#include "expr/load.h"
#include "expr/parser.h"
#include "expr/scene_import.h"
#include "expr/tape.h"
#include "tracers/aov_data.h"
#include "tracers/camera.h"
#include "tracers/image2d.h"
#include "tracers/methods.h"
#include "tracers/png_io.h"
#include "tracers/render.h"

namespace certray::apps {
namespace {

namespace fs = std::filesystem;
using tracers::Box3;
using tracers::Vec3;

/// What a scene file gives: the graph, and whatever a JSON scene sets.
struct SceneSpec {
    expr::Graph graph;
    std::optional<Box3> bounds;
    std::optional<nlohmann::json> camera;
    std::optional<Vec3> light;
    std::optional<std::string> method;
    std::optional<std::pair<unsigned, unsigned>> size;
    tracers::Surface surface = tracers::Surface::Zero;  ///< what the scene's authors mean
};

[[noreturn]] void fail(const std::string& file, const std::string& message) {
    throw InputError(file, 0, 0, message);
}

Vec3 read_vec3(const std::string& file, const nlohmann::json& j, const std::string& key) {
    if (!j.is_array() || j.size() != 3 ||
        !std::all_of(j.begin(), j.end(), [](const auto& v) { return v.is_number(); })) {
        fail(file, "\"" + key + "\" must be an array of three numbers");
    }
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

SceneSpec load_json_scene(const std::string& path) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(expr::detail::read_file(path));
    } catch (const nlohmann::json::exception& e) {
        fail(path, std::string("not valid JSON: ") + e.what());
    }
    if (!j.is_object()) fail(path, "a scene must be a JSON object");
    if (!j.contains("scene")) {
        // Not a render scene: a Lipschitz-Pruning CSG tree (expr/scene_import.h), framed by its
        // own bounds when it gives them.
        const expr::CsgScene csg = expr::import_csg_json_file(path);
        SceneSpec s;
        s.graph = csg.graph;
        s.surface = tracers::Surface::Solid;
        if (csg.has_bounds) {
            Box3 box;
            for (int a = 0; a < 3; ++a) box[a] = {csg.bounds_min[a], csg.bounds_max[a]};
            s.bounds = box;
        }
        return s;
    }
    static const char* kKeys[] = {"scene", "bounds", "camera", "light", "method", "size"};
    for (const auto& [key, value] : j.items()) {
        if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys)) {
            fail(path, "unknown key \"" + key +
                           "\" (expected scene, bounds, camera, light, method, size)");
        }
    }
    if (!j.contains("scene") || !j["scene"].is_string()) {
        fail(path, "\"scene\" (a path to an .expr, .vm, .txt or .json file) is required");
    }
    SceneSpec s;
    const fs::path scene = fs::path(path).parent_path() / j["scene"].get<std::string>();
    {
        const Scene loaded = Scene::load(scene.string());
        s.graph = loaded.graph();
        s.bounds = loaded.bounds();  // the file's own (a .vm's [-1, 1]^3), unless "bounds" is set
        s.surface = loaded.default_surface();
    }
    if (j.contains("bounds")) {
        const auto& b = j["bounds"];
        if (!b.is_array() || b.size() != 3)
            fail(path, "\"bounds\" must be [[x0,x1],[y0,y1],[z0,z1]]");
        Box3 box;
        for (int a = 0; a < 3; ++a) {
            if (!b[a].is_array() || b[a].size() != 2 || !b[a][0].is_number() ||
                !b[a][1].is_number() || !(b[a][0].get<double>() < b[a][1].get<double>())) {
                fail(path, "\"bounds\" must be [[x0,x1],[y0,y1],[z0,z1]] with lo < hi");
            }
            box[a] = {b[a][0].get<double>(), b[a][1].get<double>()};
        }
        s.bounds = box;
    }
    if (j.contains("camera")) {
        const auto& c = j["camera"];
        if (!c.is_object()) fail(path, "\"camera\" must be an object");
        for (const auto& [key, value] : c.items()) {
            if (key != "eye" && key != "target" && key != "up" && key != "fov") {
                fail(path, "unknown key \"camera." + key + "\" (expected eye, target, up, fov)");
            }
            if (key == "fov" && !value.is_number()) fail(path, "\"camera.fov\" must be a number");
            if (key != "fov") read_vec3(path, value, "camera." + key);
        }
        s.camera = c;
    }
    if (j.contains("light")) s.light = read_vec3(path, j["light"], "light");
    if (j.contains("method")) {
        if (!j["method"].is_string()) fail(path, "\"method\" must be a string");
        s.method = j["method"].get<std::string>();
    }
    if (j.contains("size")) {
        const auto& z = j["size"];
        if (!z.is_array() || z.size() != 2 || !z[0].is_number_integer() ||
            !z[1].is_number_integer() || z[0].get<long long>() < 1 || z[1].get<long long>() < 1 ||
            z[0].get<long long>() > kMaxImageSide || z[1].get<long long>() > kMaxImageSide) {
            fail(path,
                 "\"size\" must be [width, height], each 1 to " + std::to_string(kMaxImageSide));
        }
        s.size = std::pair{z[0].get<unsigned>(), z[1].get<unsigned>()};
    }
    return s;
}

std::string method_list() {
    std::string list;
    for (const std::string& m : tracers::method_names()) list += (list.empty() ? "" : ", ") + m;
    return list;
}

/// The 2D image size and bounds with square pixels: without a size, the longer side of the bounds
/// gets kDefault2dSide pixels and the other side its share; with a size whose aspect differs from
/// the bounds', the bounds are widened about their centre on the axis that is too short.
void fit_2d_aspect(tracers::Image2dOptions& io, std::optional<std::pair<unsigned, unsigned>> size,
                   bool quiet) {
    constexpr unsigned kDefault2dSide = 1024;
    const double bw = io.x[1] - io.x[0], bh = io.y[1] - io.y[0];
    if (!size) {
        const double r = bw / bh;
        io.width =
            r >= 1 ? kDefault2dSide
                   : std::clamp<unsigned>(static_cast<unsigned>(std::lround(kDefault2dSide * r)), 1,
                                          kMaxImageSide);
        io.height =
            r >= 1 ? std::clamp<unsigned>(static_cast<unsigned>(std::lround(kDefault2dSide / r)), 1,
                                          kMaxImageSide)
                   : kDefault2dSide;
        return;
    }
    io.width = size->first;
    io.height = size->second;
    const double px = bw / io.width, py = bh / io.height;  // pixel width and height
    if (std::abs(px - py) <= 1e-12 * std::max(px, py)) return;
    const std::array<double, 2> x0 = io.x, y0 = io.y;
    if (px < py) {
        const double c = 0.5 * (io.x[0] + io.x[1]), half = 0.5 * py * io.width;
        io.x = {c - half, c + half};
    } else {
        const double c = 0.5 * (io.y[0] + io.y[1]), half = 0.5 * px * io.height;
        io.y = {c - half, c + half};
    }
    if (!quiet) {
        std::cerr << "certray render: the bounds [" << x0[0] << ", " << x0[1] << "] x [" << y0[0]
                  << ", " << y0[1] << "] widened to [" << io.x[0] << ", " << io.x[1] << "] x ["
                  << io.y[0] << ", " << io.y[1] << "] so that the " << io.width << "x" << io.height
                  << " pixels are square\n";
    }
}

int render_2d_scene(const RenderCliOptions& o, const expr::Tape& tape, const SceneSpec& spec,
                    std::optional<std::pair<unsigned, unsigned>> size, std::ostream& out) {
    std::string given;
    if (o.method) given += ", --method";
    if (o.aov) given += ", --aov";
    if (o.budget) given += ", --budget";
    if (o.epsilon) given += ", --epsilon";
    if (o.data) given += ", --data";
    if (!o.eye.empty()) given += ", --eye";
    if (o.surface) given += ", --surface";
    if (o.camera) given += ", --camera";
    if (!o.target.empty()) given += ", --target";
    if (!o.up.empty()) given += ", --up";
    if (o.fov) given += ", --fov";
    if (!given.empty()) {
        const bool one = given.find(',', 1) == std::string::npos;
        std::cerr << "certray render: " << given.substr(2)
                  << (one ? " is a 3D option" : " are 3D options") << ", but '" << o.scene
                  << "' is a 2D scene (it reads x and y only), drawn as the sign of f at each "
                     "pixel centre\n";
        return 2;
    }
    std::string keys;
    if (spec.method) keys += ", \"method\"";
    if (spec.camera) keys += ", \"camera\"";
    if (spec.light) keys += ", \"light\"";
    if (!keys.empty()) {
        fail(o.scene, keys.substr(2) +
                          " apply to 3D scenes only; this scene is 2D (it reads x and y "
                          "only), drawn as the sign of f at each pixel centre");
    }
    tracers::Image2dOptions io;
    if (o.bounds.size() == 2) {
        io.x = io.y = {o.bounds[0], o.bounds[1]};
    } else if (spec.bounds) {
        io.x = (*spec.bounds)[0];
        io.y = (*spec.bounds)[1];
    }
    fit_2d_aspect(io, size, o.quiet);
    io.threads = o.threads;
    tracers::WorkProgress work;
    io.progress = &work;
    ProgressReport report("certray render", work, progress_mode_for_stderr(o.quiet));
    const tracers::Image2d img = tracers::render_2d(tape, io);
    report.finish();
    tracers::RgbImage rgb(img.width, img.height);
    for (unsigned j = 0; j < img.height; ++j) {
        for (unsigned i = 0; i < img.width; ++i) {
            switch (img.at(i, j)) {
                case tracers::Pixel2d::Inside:
                    rgb.set(i, j, 20, 20, 28);
                    break;
                case tracers::Pixel2d::Outside:
                    rgb.set(i, j, 255, 255, 255);
                    break;
                case tracers::Pixel2d::Undefined:
                    rgb.set(i, j, 255, 0, 255);
                    break;
            }
        }
    }
    tracers::write_png(o.out, rgb);
    out << "2D scene " << img.width << "x" << img.height << " over [" << io.x[0] << ", " << io.x[1]
        << "] x [" << io.y[0] << ", " << io.y[1] << "]: inside (f < 0) " << img.inside
        << " pixels, undefined (NaN) " << img.undefined << " pixels, " << img.seconds << " s\n";
    return 0;
}

}  // namespace

bool parse_size(const std::string& text, unsigned& width, unsigned& height, std::string& error) {
    const std::size_t x = text.find('x');
    auto parse = [](std::string_view s, unsigned& v) {
        if (s.empty() || s.size() > 6) return false;
        const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        return ec == std::errc() && p == s.data() + s.size();
    };
    if (x == std::string::npos || !parse(std::string_view(text).substr(0, x), width) ||
        !parse(std::string_view(text).substr(x + 1), height) || width < 1 || height < 1 ||
        width > kMaxImageSide || height > kMaxImageSide) {
        error = "--size '" + text +
                "': expected WxH with whole numbers 1 <= W, H <= " + std::to_string(kMaxImageSide) +
                " (e.g. 640x480)";
        return false;
    }
    return true;
}

int run_render(const RenderCliOptions& o, std::ostream& out) {
    std::string ext = fs::path(o.out).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext != ".png") {
        std::cerr << "certray render: cannot write '" << o.out << "': only .png is supported\n";
        return 2;
    }
    std::optional<std::pair<unsigned, unsigned>> size;
    if (o.size) {
        unsigned w = 0, h = 0;
        std::string error;
        if (!parse_size(*o.size, w, h, error)) {
            std::cerr << "certray render: " << error << "\n";
            return 2;
        }
        size = std::pair{w, h};
    }
    tracers::Aov aov;
    const std::string aov_name = o.aov.value_or("shade");
    if (!tracers::parse_aov(aov_name, aov)) {
        std::cerr << "certray render: unknown --aov '" << aov_name
                  << "'; expected shade, depth, steps, normal or status\n";
        return 2;
    }
    std::string data_ext;
    if (o.data) {
        data_ext = fs::path(*o.data).extension().string();
        std::transform(data_ext.begin(), data_ext.end(), data_ext.begin(),
                       [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        if (data_ext != ".npy" && data_ext != ".pfm") {
            std::cerr << "certray render: cannot write '" << *o.data
                      << "': --data takes .npy or .pfm\n";
            return 2;
        }
        if (aov == tracers::Aov::Shade) {
            std::cerr << "certray render: --data needs --aov depth, steps, normal or status "
                         "(shade is a picture, not data)\n";
            return 2;
        }
    }
    if (!o.bounds.empty() && !(o.bounds.size() == 2 && o.bounds[0] < o.bounds[1])) {
        std::cerr << "certray render: --bounds needs two numbers lo < hi\n";
        return 2;
    }
    const std::vector<std::string> names = tracers::method_names();
    auto check_method = [&](const std::string& m) {
        if (std::find(names.begin(), names.end(), m) != names.end()) return true;
        if (tracers::renamed_method(m)) return true;
        std::cerr << "certray render: unknown method '" << m
                  << "'; available methods: " << method_list() << "\n";
        return false;
    };
    if (o.method && !check_method(*o.method)) return 2;

    SceneSpec spec;
    if (fs::path(o.scene).extension() == ".json") {
        spec = load_json_scene(o.scene);
    } else {
        const Scene loaded = Scene::load(o.scene);
        spec.graph = loaded.graph();
        spec.bounds = loaded.bounds();  // a .vm's [-1, 1]^3 (Fidget's models), else none
        spec.surface = loaded.default_surface();
    }
    if (!size && spec.size) size = spec.size;
    const expr::Tape tape(spec.graph);
    if (!tape.uses_var(2)) return render_2d_scene(o, tape, spec, size, out);

    const std::string method = o.method ? *o.method : spec.method.value_or("certified");
    if (!check_method(method)) return 2;
    const std::string_view* now = tracers::renamed_method(method);
    if (now && !o.quiet) {
        std::cerr << "certray render: method '" << method << "' is now called '" << *now
                  << "' (the old name still works)\n";
    }
    RenderSettings rs;
    rs.method = method;
    rs.surface = o.surface ? tracers::parse_surface(*o.surface) : spec.surface;
    rs.ortho = o.camera && *o.camera == "ortho";
    rs.coherent = !o.per_ray;
    rs.depth_pixels = o.data ? 0.0 : 0.5;  // an image needs depths to half a pixel, data all digits
    if (rs.ortho && (!o.eye.empty() || !o.target.empty() || !o.up.empty() || o.fov)) {
        std::cerr << "certray render: --camera ortho looks along -z over the bounds: it takes no "
                     "--eye, --target, --up or --fov\n";
        return 2;
    }
    if (rs.ortho && o.per_ray) {
        std::cerr << "certray render: --camera ortho is drawn by the coherent certified renderer "
                     "only: drop --per-ray, or use the pinhole camera for one solve per pixel\n";
        return 2;
    }
    if (rs.ortho && tracers::method_info(method).name != "certified") {
        std::cerr << "certray render: --camera ortho is drawn by the coherent certified renderer: "
                     "use --method certified\n";
        return 2;
    }
    if (o.budget) rs.knobs.values.emplace_back("budget", static_cast<double>(*o.budget));
    if (o.epsilon) rs.knobs.values.emplace_back("epsilon", *o.epsilon);
    if (o.bounds.size() == 2) {
        rs.bounds = Box3{
            {{o.bounds[0], o.bounds[1]}, {o.bounds[0], o.bounds[1]}, {o.bounds[0], o.bounds[1]}}};
    } else if (spec.bounds) {
        rs.bounds = spec.bounds;
    }
    rs.width = size ? size->first : 640;
    rs.height = size ? size->second : 480;
    rs.aov = aov;
    rs.threads = o.threads;
    // The answers are read back for --data and the depth and steps AOVs' ranges only.
    rs.answers = o.data.has_value() || aov == tracers::Aov::Depth || aov == tracers::Aov::Steps;
    tracers::WorkProgress work;
    rs.progress = &work;
    if (spec.light) rs.light = *spec.light;
    if (spec.camera && spec.camera->contains("fov")) {
        rs.fov_degrees = (*spec.camera)["fov"].get<double>();
    }
    if (o.fov) rs.fov_degrees = *o.fov;
    const Scene scene = Scene::from_graph(spec.graph);
    // Auto-framed (the cells where the surface may be, seen whole), then the JSON's camera keys.
    if (!o.quiet && surface_reaches_bounds(scene, render_bounds(scene, rs), rs.threads)) {
        const Box3 b = render_bounds(scene, rs);
        std::cerr << "certray render: warning: the surface may reach the bounds [" << b[0][0]
                  << ", " << b[0][1] << "] x [" << b[1][0] << ", " << b[1][1] << "] x [" << b[2][0]
                  << ", " << b[2][1]
                  << "]: the picture may be clipped there (try larger --bounds)\n";
    }
    // (The heightmap has no camera to frame.)
    tracers::Camera camera =
        rs.ortho ? tracers::Camera{}
                 : auto_frame(scene, render_bounds(scene, rs), rs.fov_degrees,
                              static_cast<double>(rs.width) / rs.height, rs.threads);
    if (spec.camera) {
        const auto& c = *spec.camera;
        if (c.contains("eye")) camera.eye = read_vec3(o.scene, c["eye"], "camera.eye");
        if (c.contains("target")) camera.target = read_vec3(o.scene, c["target"], "camera.target");
        if (c.contains("up")) camera.up = read_vec3(o.scene, c["up"], "camera.up");
    }
    // The command line's camera over the JSON's and the framing.
    auto vec = [](const std::vector<double>& v) { return Vec3{v[0], v[1], v[2]}; };
    if (!o.eye.empty()) camera.eye = vec(o.eye);
    if (!o.target.empty()) camera.target = vec(o.target);
    if (!o.up.empty()) camera.up = vec(o.up);
    camera.fov_degrees = rs.fov_degrees;
    rs.camera = camera;
    ProgressReport report("certray render", work, progress_mode_for_stderr(o.quiet));
    tracers::RenderResult r;
    try {
        r = render(scene, rs);
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        if (what.find("does not read") == std::string::npos &&
            what.find("knob '") == std::string::npos) {
            throw;  // a method that does not apply to the scene: an input error
        }
        std::cerr << "certray render: " << what << "\n";
        return 2;
    }
    report.finish();
    tracers::write_png(o.out, r.image);
    if (o.data) {
        const tracers::FloatImage data = tracers::aov_data(r.answers, aov);
        if (data_ext == ".npy") {
            tracers::write_npy(*o.data, data);
        } else {
            tracers::write_pfm(*o.data, data);
        }
    }
    if (aov == tracers::Aov::Depth || aov == tracers::Aov::Steps) {
        const tracers::AovRange range = tracers::aov_range(r.answers, aov);
        if (range.lo <= range.hi) {
            out << (aov == tracers::Aov::Depth ? "depth: hit t from " : "steps: evaluations from ")
                << range.lo << (aov == tracers::Aov::Depth ? " (bright) to " : " to ") << range.hi
                << " (colour bar at the bottom right, left to right)\n";
        }
    }
    const unsigned threads =
        o.threads > 0 ? o.threads : std::max(1u, std::thread::hardware_concurrency());
    out << "3D scene " << rs.width << "x" << rs.height << ", method " << method << ", surface "
        << tracers::name(*rs.surface) << ", aov " << aov_name << ": hit " << r.stats.hit
        << ", miss " << r.stats.miss << ", unknown " << r.stats.unknown << " pixels; evaluations "
        << r.stats.evals.total() << " (value " << r.stats.evals.value << ", interval "
        << r.stats.evals.interval << ", gradient " << r.stats.evals.gradient << "; per pixel "
        << static_cast<double>(r.stats.evals.total()) /
               std::max<double>(1.0, static_cast<double>(rs.width) * rs.height)
        << ", max per pixel " << r.stats.max_pixel_evals << "); " << r.stats.seconds << " s on "
        << threads << " threads\n";
    return 0;
}

}  // namespace certray::apps
