// api/query.cpp — certray::query (include/certray/query.h).
#include "certray/query.h"

#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "tracers/coherent.h"
#include "tracers/parallel.h"

namespace certray {

const std::vector<MethodInfo>& methods() { return tracers::method_infos(); }

const MethodInfo& method_info(std::string_view name) { return tracers::method_info(name); }

void check_ray(const Ray& ray, std::size_t index) {
    static const char* const kNames[] = {"ox", "oy", "oz", "dx", "dy", "dz"};
    auto fail = [&](const std::string& what) {
        throw std::invalid_argument("ray " + std::to_string(index) + ": " + what);
    };
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(ray.o[i])) fail(std::string(kNames[i]) + " is not a finite number");
        if (!std::isfinite(ray.d[i])) {
            fail(std::string(kNames[3 + i]) + " is not a finite number");
        }
    }
    if (!std::isfinite(ray.tmin)) fail("tmin is not a finite number");
    if (std::isnan(ray.tmax) || ray.tmax == -HUGE_VAL) fail("tmax is NaN or -inf");
    if (ray.tmin > ray.tmax) fail("tmin > tmax");
}

namespace {

tracers::RayFunction prepare(const Scene& scene, const QueryOptions& options) {
    tracers::MethodOptions mo = tracers::resolve_knobs(options.method, options.knobs);
    mo.surface = options.surface;
    // The scene owns the tape that the method reads (Scene's shared state outlives the call).
    return tracers::make_method(options.method, scene.tape(), mo);
}

/// The rays answered together by the coherent walk, when they form a bundle and the method is
/// `certified`: its knobs (budget, tighten) as the per-ray method reads them.
std::optional<std::vector<RayResult>> query_bundle(const Scene& scene, std::span<const Ray> rays,
                                                   const QueryOptions& options) {
    if (!options.coherent || options.cancel != nullptr) return std::nullopt;
    if (tracers::method_info(options.method).name != "certified") return std::nullopt;
    const tracers::MethodOptions mo = tracers::resolve_knobs(options.method, options.knobs);
    tracers::CoherentOptions co;
    co.surface = options.surface;
    co.render.threads = options.threads;
    co.certified = solvers::CertifiedOptions{};
    co.certified.budget = mo.budget;
    co.certified.tighten = mo.tighten != 0;
    std::optional<std::vector<RayResult>> out = tracers::query_coherent(scene.tape(), rays, co);
    if (out && options.progress) options.progress(rays.size(), rays.size());
    return out;
}

}  // namespace

std::vector<RayResult> query(const Scene& scene, std::span<const Ray> rays,
                             const QueryOptions& options) {
    for (std::size_t i = 0; i < rays.size(); ++i) check_ray(rays[i], i);
    if (std::optional<std::vector<RayResult>> bundle = query_bundle(scene, rays, options)) {
        return std::move(*bundle);
    }
    const tracers::RayFunction fn = prepare(scene, options);
    std::vector<RayResult> results(rays.size());
    tracers::ParallelOptions po;
    po.threads = options.threads;
    po.progress = options.progress;
    po.cancel = options.cancel;
    const bool finished =
        tracers::parallel_for(rays.size(), po, [&](std::size_t b, std::size_t e, unsigned) {
            for (std::size_t i = b; i < e; ++i) results[i] = fn(rays[i]);
        });
    if (!finished) throw Cancelled();
    return results;
}

RayResult query_one(const Scene& scene, const Ray& ray, const QueryOptions& options) {
    check_ray(ray);
    return prepare(scene, options)(ray);
}

}  // namespace certray
