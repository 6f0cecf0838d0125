// apps/render.h — `certray render`: a PNG image of a scene.
//
// Contract (docs/guide/cli.md): SCENE is an .expr, .vm, .txt (particles) or .json file — a
// Lipschitz-Pruning CSG tree, or a render scene {"scene", "bounds", "camera", "light", "method",
// "size"} (all optional but "scene", whose path is relative to the JSON file; any other key is an
// error naming it). Options given on the command line override the JSON's. A scene that reads z is
// 3D (auto-framed inside the bounds, one ray per pixel answered by the method); one that does not
// is 2D, each pixel the sign of the double evaluation of f at its centre — identical to the brute
// force — computed by the interval quadtree of tracers/image2d.h; the 3D options (--method, --aov,
// --budget, --epsilon) given for a 2D scene are a usage error, never silently ignored. The 2D image
// has square pixels: the bounds are widened on the longer axis of the image when their aspect
// differs from the image's (said on stderr), and without a size the image's aspect follows the
// bounds'. OUT must end in .png (any case). The PNG is written to OUT.tmp and renamed into place
// when complete: a failed run leaves no file. Progress goes to stderr (apps/progress.h) unless
// quiet; a summary goes to stdout (2D: inside and undefined pixel counts and time; 3D:
// hit/miss/unknown pixel counts, total evaluations and time).
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace certray::apps {

struct RenderCliOptions {
    std::string scene;                    ///< .expr, .vm or .json
    std::string out;                      ///< the PNG to write
    std::optional<std::string> method;    ///< a name of tracers::method_names() (3D only)
    std::optional<std::string> size;      ///< "WxH"
    std::optional<std::string> aov;       ///< shade (default)|depth|steps|normal|status (3D only)
    std::vector<double> bounds;           ///< {lo, hi}: the cube [lo, hi]^3 (2D: the square)
    unsigned threads = 0;                 ///< 0: one per hardware thread
    std::optional<std::uint64_t> budget;  ///< evaluations per ray before unknown
    std::optional<double> epsilon;        ///< convergence distance of the tracers
    bool quiet = false;                   ///< no progress and no notes on stderr
    std::optional<std::string> data;      ///< also the AOV as float data: .npy or .pfm (3D)
    std::vector<double> eye, target, up;  ///< the camera, overriding framing and JSON (3D)
    std::optional<double> fov;            ///< vertical field of view in degrees (3D)
    std::optional<std::string> surface;   ///< zero|solid (3D; default: the scene's)
    std::optional<std::string> camera;    ///< pinhole (default) | ortho (3D)
    bool per_ray = false;                 ///< certified by independent rays, not coherently
};

/// Largest accepted image side.
inline constexpr unsigned kMaxImageSide = 16384;

/// Parses "WxH" with 1 ≤ W, H ≤ kMaxImageSide; false with a message in `error` otherwise.
bool parse_size(const std::string& text, unsigned& width, unsigned& height, std::string& error);

/// Runs the render; returns the exit code (0 success, 2 for bad options, including 3D options for a
/// 2D scene and an OUT that is not .png, after printing why on stderr). Throws certray::InputError
/// for bad scene files and std::runtime_error when the image cannot be written.
int run_render(const RenderCliOptions& options, std::ostream& out);

}  // namespace certray::apps
