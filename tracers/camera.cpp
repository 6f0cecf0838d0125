// tracers/camera.cpp — pinhole camera, ray clipping and auto-framing (see camera.h).
#include "tracers/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "expr/eval.h"
#include "expr/prune.h"
#include "interval/interval.h"

namespace certray::tracers {

Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

CameraFrame::CameraFrame(const Camera& camera, unsigned width, unsigned height) {
    if (width == 0 || height == 0) throw std::invalid_argument("camera: empty image size");
    if (!(camera.fov_degrees > 0 && camera.fov_degrees < 180)) {
        throw std::invalid_argument("camera: fov must be in (0, 180) degrees");
    }
    eye_ = camera.eye;
    forward_ = normalize(
        {camera.target[0] - eye_[0], camera.target[1] - eye_[1], camera.target[2] - eye_[2]});
    if (dot(forward_, forward_) == 0) throw std::invalid_argument("camera: eye equals target");
    right_ = normalize(cross(forward_, camera.up));
    if (dot(right_, right_) == 0) {
        throw std::invalid_argument("camera: up is parallel to the view direction");
    }
    up_ = cross(right_, forward_);
    scale_ = std::tan(camera.fov_degrees * (M_PI / 360.0)) / (0.5 * height);
    half_w_ = 0.5 * width;
    half_h_ = 0.5 * height;
}

Ray CameraFrame::ray(double px, double py) const {
    const double u = (px - half_w_) * scale_;
    const double v = (half_h_ - py) * scale_;
    Ray r;
    r.o = eye_;
    r.d = normalize({forward_[0] + u * right_[0] + v * up_[0],
                     forward_[1] + u * right_[1] + v * up_[1],
                     forward_[2] + u * right_[2] + v * up_[2]});
    r.tmin = 0;
    r.tmax = std::numeric_limits<double>::infinity();
    return r;
}

bool clip_ray(Ray& ray, const Box3& box) {
    double t0 = ray.tmin, t1 = ray.tmax;
    for (int a = 0; a < 3; ++a) {
        const double o = ray.o[a], d = ray.d[a];
        if (d == 0) {
            if (o < box[a][0] || o > box[a][1]) return false;
            continue;
        }
        double ta = (box[a][0] - o) / d, tb = (box[a][1] - o) / d;
        if (ta > tb) std::swap(ta, tb);
        // Each slab parameter is one rounding of a subtraction and a division away from the
        // exact one: step a few ulps outward so the clipped segment keeps the whole box.
        ta = detail::step_down(ta, 4);
        tb = detail::step_up(tb, 4);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    if (!(t0 <= t1)) return false;
    ray.tmin = t0;
    ray.tmax = t1;
    return true;
}

namespace {

/// The subdivision of surface_cells, depth first: `leaf(cell)` for each cell of the last level
/// where f may vanish, only below cells for which `descend(box)` holds; stops at the first leaf
/// that returns true (and returns true then).
template <class Descend, class Leaf>
bool visit_surface_cells(const expr::Tape& tape, const Box3& bounds, int levels, Descend descend,
                         Leaf leaf) {
    // Each cell evaluated with the list pruned to its parent (equal to f there), so that a CSG
    // tree of thousands of primitives is not evaluated whole on every small cell; one list and one
    // register file per level.
    using Ssa = std::vector<expr::Instr>;
    using Box = std::array<UpInterval, 3>;
    levels = std::clamp(levels, 0, 6);  // at most 8^6 cells
    struct Level {
        std::vector<UpInterval> values;
        Ssa list;
    };
    std::vector<Level> level(static_cast<std::size_t>(levels) + 1);
    expr::PruneWorkspace ws;
    ws.absolute_values = true;
    RoundingScope up;  // UpInterval arithmetic below; midpoints are only split points
    const auto visit = [&](const auto& self, const Box& box, const Ssa& list, int depth) -> bool {
        if (!descend(box)) return false;
        Level& l = level[static_cast<std::size_t>(depth)];
        if (l.values.size() < list.size()) l.values.resize(list.size());
        expr::detail::run<UpInterval>(list, box, l.values.data());
        const UpInterval v = l.values[list.back().out];
        if (v.defined && !v.is_empty() && !possibly_zero(v)) return false;  // f cannot vanish
        if (depth == levels) {
            return leaf(Box3{{{box[0].lower(), box[0].upper()},
                              {box[1].lower(), box[1].upper()},
                              {box[2].lower(), box[2].upper()}}});
        }
        const Ssa* sub = &list;
        if (expr::prune_ssa(list, l.values.data(), ws, l.list)) sub = &l.list;
        const double m[3] = {0.5 * box[0].lower() + 0.5 * box[0].upper(),
                             0.5 * box[1].lower() + 0.5 * box[1].upper(),
                             0.5 * box[2].lower() + 0.5 * box[2].upper()};
        for (int k = 0; k < 8; ++k) {
            Box s;
            for (int a = 0; a < 3; ++a) {
                s[a] = (k >> a) & 1 ? UpInterval(m[a], box[a].upper())
                                    : UpInterval(box[a].lower(), m[a]);
            }
            if (self(self, s, *sub, depth + 1)) return true;
        }
        return false;
    };
    const Box root{UpInterval(bounds[0][0], bounds[0][1]), UpInterval(bounds[1][0], bounds[1][1]),
                   UpInterval(bounds[2][0], bounds[2][1])};
    return visit(visit, root, tape.ssa(), 0);
}

}  // namespace

std::vector<Box3> surface_cells(const expr::Tape& tape, const Box3& bounds, int levels) {
    std::vector<Box3> out;
    visit_surface_cells(
        tape, bounds, levels, [](const auto&) { return true; },
        [&](const Box3& cell) {
            out.push_back(cell);
            return false;
        });
    return out;
}

bool surface_cells_touch_bounds(const expr::Tape& tape, const Box3& bounds, int levels) {
    const auto touches = [&](const auto& box) {
        for (int a = 0; a < 3; ++a) {
            if (box[a].lower() <= bounds[a][0] || box[a].upper() >= bounds[a][1]) return true;
        }
        return false;
    };
    return visit_surface_cells(tape, bounds, levels, touches, [](const Box3&) { return true; });
}

std::optional<Box3> hull(const std::vector<Box3>& boxes) {
    if (boxes.empty()) return std::nullopt;
    Box3 box = boxes.front();
    for (const Box3& c : boxes) {
        for (int a = 0; a < 3; ++a) {
            box[a][0] = std::min(box[a][0], c[a][0]);
            box[a][1] = std::max(box[a][1], c[a][1]);
        }
    }
    return box;
}

std::optional<Box3> surface_extent(const expr::Tape& tape, const Box3& bounds, int levels) {
    return hull(surface_cells(tape, bounds, levels));
}

Camera frame_box(const Box3& box, double fov_degrees, double aspect, Vec3 from) {
    return frame_boxes({box}, box, fov_degrees, aspect, from);
}

Camera frame_boxes(const std::vector<Box3>& boxes, const Box3& hull, double fov_degrees,
                   double aspect, Vec3 from) {
    Vec3 c;
    for (int a = 0; a < 3; ++a) c[a] = 0.5 * (hull[a][0] + hull[a][1]);
    const Vec3 dir = normalize(from);
    const Vec3 forward{-dir[0], -dir[1], -dir[2]};
    const Vec3 right = normalize(cross(forward, {0, 0, 1}));
    const Vec3 up = cross(right, forward);
    const double tan_v = std::tan(fov_degrees * (M_PI / 360.0));
    const double tan_h = tan_v * aspect;
    // The eye sits at c + D·dir. Corner p (relative to c) is at depth D + p·forward and projects
    // inside the image when |p·right| <= tan_h·depth and |p·up| <= tan_v·depth.
    double distance = 1e-6;
    for (const Box3& box : boxes) {
        for (int k = 0; k < 8; ++k) {
            Vec3 p;
            for (int a = 0; a < 3; ++a) p[a] = box[a][(k >> a) & 1] - c[a];
            const double depth_needed =
                std::max(std::abs(dot(p, right)) / tan_h, std::abs(dot(p, up)) / tan_v);
            distance = std::max(distance, depth_needed - dot(p, forward));
        }
    }
    distance *= 1.08;  // a margin around the silhouette
    Camera cam;
    cam.target = c;
    cam.eye = {c[0] + dir[0] * distance, c[1] + dir[1] * distance, c[2] + dir[2] * distance};
    cam.up = {0, 0, 1};
    cam.fov_degrees = fov_degrees;
    return cam;
}

}  // namespace certray::tracers
