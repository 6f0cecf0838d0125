// api/render.cpp — certray::render (include/certray/render.h).
#include "certray/render.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "interval/interval.h"
#include "tracers/cone.h"

namespace certray {

tracers::Box3 render_bounds(const Scene& scene, const RenderSettings& s) {
    if (s.bounds) {
        for (const auto& [lo, hi] : *s.bounds) {
            if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi)) {
                throw std::invalid_argument("render bounds: expected finite lo < hi on each axis");
            }
        }
        return *s.bounds;
    }
    if (scene.bounds()) return *scene.bounds();
    return {{{-2, 2}, {-2, 2}, {-2, 2}}};
}

tracers::Camera auto_frame(const Scene& scene, const tracers::Box3& bounds, double fov_degrees,
                           double aspect, unsigned threads) {
    NearestScope env;
    const std::vector<tracers::Box3> cells =
        tracers::surface_cells(scene.tape(), bounds, 5, threads);
    const std::optional<tracers::Box3> extent = tracers::hull(cells);
    return extent ? tracers::frame_boxes(cells, *extent, fov_degrees, aspect)
                  : tracers::frame_box(bounds, fov_degrees, aspect);
}

bool surface_reaches_bounds(const Scene& scene, const tracers::Box3& bounds, unsigned threads) {
    NearestScope env;
    return tracers::surface_cells_touch_bounds(scene.tape(), bounds, 5, threads);
}

tracers::RenderResult render(const Scene& scene, const RenderSettings& s) {
    if (scene.is_2d()) {
        throw std::invalid_argument(
            "render: the scene does not read z (a 2D scene): draw it as the image of f < 0 "
            "(tracers/image2d.h) instead");
    }
    if (s.width == 0 || s.height == 0) throw std::invalid_argument("render: empty image size");
    // An image needs no enclosure of a few ulps: unless asked, polynomial hits keep their
    // (proven) interval enclosure instead of the exact re-decision (3x the time on the Barth
    // sextic).
    KnobValues knobs = s.knobs;
    const MethodInfo& info = tracers::method_info(s.method);
    const bool reads_tighten =
        std::find(info.knobs.begin(), info.knobs.end(), "tighten") != info.knobs.end();
    const bool set_tighten = std::any_of(knobs.values.begin(), knobs.values.end(),
                                         [](const auto& kv) { return kv.first == "tighten"; });
    if (reads_tighten && !set_tighten) knobs.values.emplace_back("tighten", 0);
    tracers::MethodOptions mo = tracers::resolve_knobs(s.method, knobs);
    mo.surface = s.surface.value_or(scene.default_surface());
    tracers::RenderOptions ro;
    ro.width = s.width;
    ro.height = s.height;
    ro.bounds = render_bounds(scene, s);
    ro.aov = s.aov;
    ro.light = s.light;
    ro.threads = s.threads;
    ro.progress = s.progress;
    ro.answers = s.answers;
    ro.camera = s.camera  ? *s.camera
                : s.ortho ? tracers::Camera{}  // the heightmap has no camera to frame
                          : auto_frame(scene, ro.bounds, s.fov_degrees,
                                       static_cast<double>(s.width) / s.height, s.threads);
    mo.bounds = std::array<Interval, 3>{Interval(ro.bounds[0][0], ro.bounds[0][1]),
                                        Interval(ro.bounds[1][0], ro.bounds[1][1]),
                                        Interval(ro.bounds[2][0], ro.bounds[2][1])};
    const std::string_view name = info.name;  // an old name resolved
    if (name == "certified" && (s.coherent || s.ortho)) {
        NearestScope env;
        tracers::CoherentOptions co;
        co.render = ro;
        co.projection = s.ortho ? tracers::Projection::Ortho : tracers::Projection::Pinhole;
        co.surface = mo.surface;
        co.depth_pixels = s.depth_pixels;
        co.certified.budget = mo.budget;
        if (mo.tighten != 0) {  // asked for: 4-ulp hits, as the per-ray method gives
            co.certified.tighten = true;
            co.certified.hit_width = 0;
            co.depth_pixels = 0;
        }
        return tracers::render_3d_coherent(scene.tape(), co);
    }
    if (s.ortho) {
        throw std::invalid_argument(
            "the orthographic camera is drawn by the coherent certified renderer: use the method "
            "certified");
    }
    const tracers::RayFunction fn = tracers::make_method(s.method, scene.tape(), mo);
    std::optional<tracers::ConeMarch> cone;
    if (info.cone != tracers::ConeMarching::None && s.coherent) {
        NearestScope env;
        tracers::ConeOptions copt;
        copt.epsilon = mo.epsilon;
        copt.local_bounds = info.cone == tracers::ConeMarching::Local;
        cone.emplace(scene.tape(), ro.bounds, copt);
        ro.cone = &*cone;
    }
    return tracers::render_3d(scene.tape(), fn, ro);
}

}  // namespace certray
