// tracers/render.h — 3D images: one ray per pixel answered by any registered method, shown as an
// AOV (shade, depth, steps, normal, status).
//
// Contract: pixel (i, j) (j = 0 the top row) is the camera ray through its centre, clipped to the
// bounds box (camera.h), answered by the RayFunction (tracers/methods.h) — a ray that misses the
// box is a Miss with no evaluation. The statistics count every pixel's status and the method's
// whole-tape evaluations. The AOVs: shade = Lambert + ambient from the gradient of f at the hit
// point t (one directional light), misses show a background gradient and unknowns magenta;
// depth = hit distance, near bright; steps = evaluations per pixel on a log colour ramp; normal =
// (n + 1)/2 as RGB; status = hit white, miss dark blue, unknown magenta. Tiles of 16×16 pixels are
// spread over threads; no allocation per pixel beyond what the method does.
// Reference: pbrt-v4's film/tile loop; docs/theory/rendering.md.
#pragma once

#include <algorithm>
#include <boost/container/vector.hpp>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "expr/tape.h"
#include "solvers/ray.h"
#include "tracers/camera.h"
#include "tracers/methods.h"
#include "tracers/progress.h"
#include "tracers/rgb_image.h"

namespace certray::tracers {

class ConeMarch;

/// What a 3D image shows.
enum class Aov : std::uint8_t { Shade, Depth, Steps, Normal, Status };

/// The AOV named `name` ("shade", "depth", "steps", "normal", "status"); false if unknown.
bool parse_aov(std::string_view name, Aov& aov);

/// Everything a 3D image needs besides the scene and the method.
struct RenderOptions {
    unsigned width = 640;
    unsigned height = 480;
    Camera camera;
    Box3 bounds{{{-2, 2}, {-2, 2}, {-2, 2}}};
    Vec3 light{-0.4, -0.9, 1.2};  ///< direction towards the light (normalised when used)
    Aov aov = Aov::Shade;
    unsigned threads = 0;              ///< worker threads; 0: one per hardware thread
    WorkProgress* progress = nullptr;  ///< when set, advanced tile by tile (tracers/progress.h)
    /// When set, each tile's rays are first cone-marched (tracers/cone.h): the method then traces
    /// each ray from where the march proved it free of zeros, and a ray proven free on its whole
    /// segment is a Miss without a call. Only for methods that never step past the first root
    /// given the same Lipschitz bounds (MethodInfo::cone); each pixel's evaluations include its
    /// share of the march's.
    const ConeMarch* cone = nullptr;
    /// Keep every pixel's answer (RenderResult::answers). False: the caller wants the image and
    /// the totals alone; for a local AOV (aov_is_local) the coherent renderer then colours each
    /// tile from its own answers and leaves `answers` empty (its width and height set), writing
    /// no image-sized arrays (a 512² image's 7.6 MB: their first touch was 5–8% of Barth's
    /// image, docs/benchmarks.md, session 25). Other renderers keep them.
    bool answers = true;
};

/// Per-image totals.
struct RenderStats {
    std::uint64_t hit = 0, miss = 0, unknown = 0;
    EvalCounts evals;
    std::uint64_t max_pixel_evals = 0;
    double seconds = 0;

    /// Counts one pixel: its status and its evaluations (the most for one pixel).
    void count_pixel(Status s, std::uint64_t pixel_evals) {
        hit += s == Status::Hit;
        miss += s == Status::Miss;
        unknown += s == Status::Unknown;
        max_pixel_evals = std::max(max_pixel_evals, pixel_evals);
    }
    /// Adds the pixels counted in `o` (a part of the image counted apart).
    void count_pixels(const RenderStats& o) {
        hit += o.hit;
        miss += o.miss;
        unknown += o.unknown;
        max_pixel_evals = std::max(max_pixel_evals, o.max_pixel_evals);
    }
};

/// Memory for a pixel buffer of `bytes` (PixelAllocator); throws std::bad_alloc.
void* allocate_pixels(std::size_t bytes);
void free_pixels(void* p);

/// The allocator of pixel buffers: a buffer of 2 MiB or more is aligned to 2 MiB and marked for
/// transparent huge pages (Linux; elsewhere an ordinary allocation), so that a large image's
/// first touch takes a fault per 2 MiB instead of one per 4 KiB page (on a 1024² image the
/// faults, taken by two threads at once, had been most of the time of an image with nothing in
/// it).
template <class T>
struct PixelAllocator {
    using value_type = T;
    PixelAllocator() = default;
    template <class U>
    PixelAllocator(const PixelAllocator<U>&) {}
    T* allocate(std::size_t n) { return static_cast<T*>(allocate_pixels(n * sizeof(T))); }
    void deallocate(T* p, std::size_t) { free_pixels(p); }
    template <class U>
    bool operator==(const PixelAllocator<U>&) const {
        return true;
    }
};

/// A pixel buffer: a vector that resize(n, boost::container::default_init) leaves unwritten, so
/// that a threaded renderer's workers write (and first touch) their own tiles.
template <class T>
using PixelBuffer = boost::container::vector<T, PixelAllocator<T>>;

/// The answers of every pixel (row-major, top row first), before colouring.
struct PixelAnswers {
    unsigned width = 0, height = 0;
    PixelBuffer<Status> status;
    PixelBuffer<double> t;                     ///< hit (or unknown) parameter; NaN for a miss
    PixelBuffer<std::uint64_t> evals;          ///< evals.total() per pixel
    PixelBuffer<std::array<float, 3>> normal;  ///< unit normal at a hit (facing the camera)
};

/// The image and its totals.
struct RenderResult {
    RgbImage image;
    PixelAnswers answers;
    RenderStats stats;
};

/// Renders `tape` with `method` (see the file contract). Throws std::invalid_argument for a bad
/// camera or an empty size; rethrows what the method throws.
RenderResult render_3d(const expr::Tape& tape, const RayFunction& method,
                       const RenderOptions& options);

/// The range of values a depth image (hit t) or a steps image (evaluations per pixel) shows; for
/// other AOVs and images without a hit, lo > hi.
struct AovRange {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -std::numeric_limits<double>::infinity();
};
AovRange aov_range(const PixelAnswers& answers, Aov aov);

/// Whether a pixel's colour in `aov` is its own answer's alone (shade, normal, status), or also
/// depends on the whole image's (depth and steps scale their ramps to its range).
bool aov_is_local(Aov aov);

/// What colorize_span needs besides a pixel's answer: the unit light, and for depth and steps
/// the image's range.
struct AovScale {
    Vec3 light{0, 0, 1};
    double tmin = std::numeric_limits<double>::infinity();
    double tmax = -std::numeric_limits<double>::infinity();
    std::uint64_t emax = 0;
    double log_emax = 0;
};
/// The scale of `answers` (for an AOV that is local, the light alone).
AovScale aov_scale(const PixelAnswers& answers, Aov aov, const Vec3& light);
/// Colours pixels i0 … i1 − 1 of row j of `answers` into img as colorize does, without the colour
/// bar, pixel (i, j) of the answers at (x0 + i, y0 + j) of the image (answers of the image's size:
/// x0 = y0 = 0; a tile's own: its corner); a renderer that colours its tiles as it answers them
/// calls it for a local AOV.
void colorize_span(const PixelAnswers& answers, Aov aov, const AovScale& scale, unsigned j,
                   unsigned i0, unsigned i1, RgbImage& img, unsigned x0 = 0, unsigned y0 = 0);

/// Colours answers as `aov` (used by render_3d; exposed to recolour without re-tracing). Depth and
/// steps images carry a colour bar at the bottom right (least value left, greatest right; the
/// values: aov_range). Rows are shared out to `threads` workers (0: one per hardware thread).
RgbImage colorize(const PixelAnswers& answers, Aov aov, const Vec3& light, unsigned threads = 1);

}  // namespace certray::tracers
