// tracers/camera.h — a pinhole camera, rays clipped to the scene bounds, and auto-framing.
//
// Contract: camera_ray gives the ray through a point of the image plane (pixel units, (0, 0) the
// top-left corner), with a unit direction, tmin = 0 and tmax = ∞; clip_ray narrows [tmin, tmax] to
// where the ray is inside the bounds box (slab method, conservative: the clipped segment contains
// every t of the original range whose point lies in the box, up to one rounding of the slab
// parameters, which is widened outward by a few ulps). surface_extent encloses the surface: every
// point of the bounds where f = 0 (or where f is not proven defined) lies in the returned box.
// frame_box places a camera that sees the whole box. Reference: pbrt-v4 (PerspectiveCamera);
// docs/theory/rendering.md.
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "expr/tape.h"
#include "solvers/ray.h"

namespace certray::tracers {

using Vec3 = std::array<double, 3>;
/// An axis-aligned box: {{x0, x1}, {y0, y1}, {z0, z1}}.
using Box3 = std::array<std::array<double, 2>, 3>;

/// A pinhole camera: where it is, what it looks at, which way is up, the vertical field of view.
struct Camera {
    Vec3 eye{4, -8, 3.2};
    Vec3 target{0, 0, 0};
    Vec3 up{0, 0, 1};
    double fov_degrees = 35;
};

/// The orthonormal frame of a camera and the image-plane scale, computed once per image.
class CameraFrame {
  public:
    /// Throws std::invalid_argument when eye = target, up is parallel to the view direction,
    /// the fov is not in (0, 180), or the size is empty.
    CameraFrame(const Camera& camera, unsigned width, unsigned height);
    /// The ray through image point (px, py) in pixels from the top-left corner (pixel (i, j)
    /// has its centre at (i + 0.5, j + 0.5)); unit direction, tmin 0, tmax ∞.
    Ray ray(double px, double py) const;
    /// The rays of pixels (i0 + k, j), k < n, clipped to `box`: rays[k] and in[k] are, bit for
    /// bit, ray(i0 + k + 0.5, j + 0.5) and what clip_ray does to it, computed eight at a time
    /// (vectors where the machine has them). The caller holds round-to-nearest.
    void clipped_row(unsigned i0, unsigned j, unsigned n, const Box3& box, Ray* rays,
                     bool* in) const;
    /// True only where no ray of pixels [i0, i0 + w) × [j0, j0 + h) meets `box`, not even the
    /// clipped_row() rays (whose clip reaches a few ulps past the box): proven by interval
    /// arithmetic over the pixels' directions and the box widened by a billionth. False where
    /// it cannot tell (then each ray's clip decides).
    bool misses(unsigned i0, unsigned j0, unsigned w, unsigned h, const Box3& box) const;
    const Vec3& eye() const { return eye_; }
    const Vec3& forward() const { return forward_; }
    const Vec3& right() const { return right_; }
    const Vec3& up() const { return up_; }

  private:
    Vec3 eye_, forward_, right_, up_;
    double scale_;  ///< tan(fov/2) / (height/2): image-plane units per pixel at distance 1
    double half_w_, half_h_;
};

/// Narrows ray.tmin/tmax to the part inside `box`; false when the ray misses the box.
bool clip_ray(Ray& ray, const Box3& box);

/// A box enclosing every point of `bounds` where f may vanish (0 ∈ F over a cell, or F not
/// proven defined), by `levels` rounds of subdivision into octants; nullopt when the surface is
/// proven absent from the bounds. `threads` as surface_cells.
std::optional<Box3> surface_extent(const expr::Tape& tape, const Box3& bounds, int levels = 5,
                                   unsigned threads = 1);

/// The cells of the last subdivision level of surface_extent (empty when the surface is proven
/// absent): every point of the bounds where f may vanish lies in one of them, in depth-first
/// order. The cells of the third level (at most 64) are subdivided on `threads` workers
/// (tracers/parallel.h; 0: one per hardware thread); the same cells in the same order with any.
std::vector<Box3> surface_cells(const expr::Tape& tape, const Box3& bounds, int levels = 5,
                                unsigned threads = 1);

/// Whether a cell of surface_cells(tape, bounds, levels) touches a face of `bounds` (a side of
/// the cell on or past it): the same subdivision, descending only into cells that touch a face
/// (no other cell has such descendants) and stopping at the first (every worker stops). The same
/// answer as testing every cell surface_cells gives, in a fraction of its evaluations.
bool surface_cells_touch_bounds(const expr::Tape& tape, const Box3& bounds, int levels = 5,
                                unsigned threads = 1);

/// The smallest box containing all `boxes`; nullopt when there are none.
std::optional<Box3> hull(const std::vector<Box3>& boxes);

/// A camera looking at the centre of `hull` from direction `from`, z up, far enough that every
/// corner of every box of `boxes` projects inside the image, with a small margin.
Camera frame_boxes(const std::vector<Box3>& boxes, const Box3& hull, double fov_degrees,
                   double aspect, Vec3 from = {1, -2, 0.8});

/// A camera looking at the centre of `box` from direction `from` (default (1, −2, 0.8)), z up,
/// far enough that the projections of all eight corners of the box fit the image (fov and aspect
/// width/height), with a small margin.
Camera frame_box(const Box3& box, double fov_degrees, double aspect, Vec3 from = {1, -2, 0.8});

/// Small vector helpers.
// Inline: a coherent image calls them per hit pixel (6% of Fidget's colonnade heightmap as calls).
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 normalize(const Vec3& v) {
    const double n = std::sqrt(dot(v, v));
    if (!(n > 0) || !std::isfinite(n)) return {0, 0, 0};
    return {v[0] / n, v[1] / n, v[2] / n};
}
Vec3 cross(const Vec3& a, const Vec3& b);

}  // namespace certray::tracers
