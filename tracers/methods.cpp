// tracers/methods.cpp — the registry of methods (see methods.h).
#include "tracers/methods.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>

#include "expr/derived.h"
#include "solvers/analytic.h"
#include "solvers/certified.h"
#include "solvers/exact.h"
#include "solvers/hermite.h"
#include "tracers/approx.h"
#include "tracers/bounding.h"
#include "tracers/march.h"
#include "tracers/octree.h"
#include "tracers/segment_trace.h"
#include "tracers/sphere_trace.h"

namespace certray::tracers {
namespace {

/// The analytic methods, after checking that g is piecewise polynomial along every ray.
RayFunction make_analytic(const expr::Tape& tape, const MethodOptions& o,
                          solvers::AnalyticOptions::Mode mode, std::string_view name) {
    const std::string why = solvers::why_not_polynomial(tape);
    if (!why.empty()) {
        throw std::invalid_argument("method '" + std::string(name) +
                                    "' does not apply to this scene: f is not piecewise "
                                    "polynomial along rays (" +
                                    why + "); use certified");
    }
    solvers::AnalyticOptions opt;
    opt.mode = mode;
    opt.budget = o.budget;
    return [&tape, opt](const Ray& ray) { return solvers::analytic_first_root(tape, ray, opt); };
}

TraceOptions trace_options(const MethodOptions& o) {
    TraceOptions t;
    t.epsilon = o.epsilon;
    t.step = o.step;
    t.kappa = o.kappa;
    t.budget = o.budget;
    return t;
}

/// The ray clipped to the bounds, if any: false when it misses them (the scene is inside).
bool clip(const MethodOptions& o, Ray& ray) {
    if (!o.bounds) return true;
    const Interval in = ray_box(ray, *o.bounds);
    if (in.is_empty()) return false;
    ray.tmin = std::max(ray.tmin, in.lower());
    ray.tmax = std::min(ray.tmax, in.upper());
    return ray.tmin <= ray.tmax;
}

/// A tracer that needs no λ (march, segment), on each ray clipped to the bounds.
RayFunction make_clipped_tracer(const expr::Tape& tape, const MethodOptions& o,
                                RayResult (*trace)(const expr::Tape&, const Ray&,
                                                   const TraceOptions&)) {
    const TraceOptions topt = trace_options(o);
    return [&tape, o, topt, trace](const Ray& r) {
        Ray ray = r;
        RayResult miss;
        miss.status = Status::Miss;
        if (!clip(o, ray)) return miss;
        return trace(tape, ray, topt);
    };
}

/// The certified solver with the options' budget (and the affine refinement if asked).
RayFunction make_certified(const expr::Tape& tape, const MethodOptions& o, bool affine) {
    solvers::CertifiedOptions opt;
    opt.budget = o.budget;
    opt.affine = affine;
    return [&tape, opt](const Ray& ray) { return solvers::certified_first_root(tape, ray, opt); };
}

using Tracer = RayResult (*)(const expr::Tape&, const Ray&, double, const TraceOptions&);

/// Sphere tracing with a proven global λ: over the bounds (computed once; rays clipped to them),
/// or else over each ray's own segment box (one gradient evaluation per ray, counted).
RayFunction make_lipschitz_tracer(const expr::Tape& tape, const MethodOptions& o, Tracer trace) {
    const TraceOptions topt = trace_options(o);
    const double global =
        o.bounds ? global_lipschitz(tape, *o.bounds) : std::numeric_limits<double>::quiet_NaN();
    return [&tape, o, topt, global, trace](const Ray& r) {
        Ray ray = r;
        RayResult miss;
        miss.status = Status::Miss;
        if (!clip(o, ray)) return miss;
        double lambda = global;
        std::uint64_t extra = 0;
        if (!o.bounds) {
            // The segment's box: o + [tmin, tmax]·d in interval arithmetic (rounded outward).
            std::array<Interval, 3> box;
            for (int i = 0; i < 3; ++i) {
                box[i] = Interval(ray.o[i]) + Interval(ray.tmin, ray.tmax) * Interval(ray.d[i]);
            }
            lambda = expr::lipschitz_bound(tape, box);
            extra = 1;
        }
        RayResult res = trace(tape, ray, lambda, topt);
        res.evals.gradient += extra;
        return res;
    };
}

/// A tracer that holds inside `bounds` (the octree's, the bounding volumes'), applied there; the
/// parts of the ray before and after the bounds by segment tracing (local bounds along the ray,
/// never past the first root), so that nothing outside the bounds is assumed empty.
RayFunction inside_and_out(const expr::Tape& tape, const std::array<Interval, 3>& bounds,
                           const TraceOptions& topt,
                           std::function<RayResult(const Ray&, const TraceOptions&)> inside) {
    return [&tape, bounds, topt, inside](const Ray& r) {
        auto with_budget = [&topt](std::uint64_t left) {
            TraceOptions opt = topt;
            opt.budget = left;
            return opt;
        };
        return trace_in_parts(
            r, bounds, topt.budget,
            [&](const Ray& seg, std::uint64_t left) { return inside(seg, with_budget(left)); },
            [&](const Ray& seg, std::uint64_t left) {
                return segment_trace(tape, seg, with_budget(left));
            });
    };
}

/// The bounds the octree methods subdivide: the given ones, else [−2, 2]³ (the gallery's frame).
std::array<Interval, 3> octree_bounds(const MethodOptions& o) {
    if (o.bounds) return *o.bounds;
    return {Interval(-2, 2), Interval(-2, 2), Interval(-2, 2)};
}

ApproxOptions approx_options(const MethodOptions& o) {
    ApproxOptions a;
    a.octree.max_depth = o.depth;
    return a;
}

struct Entry {
    std::string_view name;
    std::string_view summary;
    RayFunction (*make)(const expr::Tape&, const MethodOptions&);
};

const Entry kMethods[] = {
    {"certified",
     "interval bisection with interval Newton (Snyder 1992); certified; knob: --budget",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         return make_certified(tape, o, false);
     }},
    {"certified-affine",
     "certified, where the interval enclosure of g over a parameter interval holds 0 it is "
     "intersected with the affine form of g in t (tighter on long segments; one more "
     "evaluation); certified; knob: --budget",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         return make_certified(tape, o, true);
     }},
    {"march",
     "ray marching with a fixed step (Perlin 1989), a sign change refined to --epsilon; "
     "approximate (skips features thinner than the step); knobs: --step, --epsilon, --budget, "
     "--bounds",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         return make_clipped_tracer(tape, o, &march);
     }},
    {"sphere",
     "sphere tracing (Hart 1996) with a proven global Lipschitz bound from the DAG (over "
     "--bounds, else over each ray's segment); never steps past the first root; knobs: "
     "--epsilon, --budget, --bounds",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         return make_lipschitz_tracer(tape, o, &sphere_trace);
     }},
    {"enhanced",
     "enhanced sphere tracing (Keinert 2014): over-relaxed steps (1 + kappa)|f|/lambda with the "
     "step-back rule, same guarantee; knobs: --kappa, --epsilon, --budget, --bounds",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         return make_lipschitz_tracer(tape, o, &enhanced_trace);
     }},
    {"segment",
     "segment tracing (Galin 2020) with local bounds of |grad f . d| over each segment from the "
     "DAG's interval derivatives; never steps past the first root; knobs: --epsilon, --budget, "
     "--bounds",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         return make_clipped_tracer(tape, o, &segment_trace);
     }},
    {"certified-bvh",
     "certified, with bounding volumes: inside the bounds (default [-2,2]^3) each ray's tape "
     "keeps only the primitives whose boxes its segment meets (same zeros and sign along it), "
     "outside them the full tape; certified; knobs: --budget, --bounds",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         auto scene = std::make_shared<const BoundedScene>(tape, octree_bounds(o));
         const std::uint64_t budget = o.budget;
         return [scene, budget](const Ray& ray) { return bounded_certified(*scene, ray, budget); };
     }},
    {"certified-octree",
     "certified, accelerated by an octree over the bounds (default [-2,2]^3, --depth 5): empty and "
     "full cells skipped, each ambiguous cell solved with its pruned tape; the ray outside the "
     "bounds with the full tape; certified; knobs: --budget, --bounds, --depth",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         auto tree = std::make_shared<const Octree>(tape, octree_bounds(o),
                                                    OctreeOptions{o.depth, std::size_t{1} << 20});
         solvers::CertifiedOptions opt;
         opt.budget = o.budget;
         return [tree, opt](const Ray& ray) { return tree->certified(ray, opt); };
     }},
    {"octree",
     "sphere tracing with the local Lipschitz bound of each octree cell (Hart 1996) inside the "
     "bounds (default [-2,2]^3, --depth 5); before and after them, segment tracing; approximate, "
     "never steps past the first root; knobs: --epsilon, --budget, "
     "--bounds, --depth",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         auto tree = std::make_shared<const Octree>(tape, octree_bounds(o),
                                                    OctreeOptions{o.depth, std::size_t{1} << 20});
         return inside_and_out(tape, tree->bounds(), trace_options(o),
                               [tree](const Ray& ray, const TraceOptions& opt) {
                                   return tree->sphere(ray, opt.epsilon, opt.budget);
                               });
     }},
    {"bvh",
     "sphere tracing with bounding volumes (Hart 1996): f's unions, intersections and "
     "complements down to its primitives, each with a box (interval slab contraction) and a "
     "Lipschitz bound, unions as a BVH; a primitive far from the point is bounded by the "
     "distance to its box. Inside the bounds (default [-2,2]^3); before and after them, segment "
     "tracing; approximate, never steps past the first root; knobs: "
     "--epsilon, --budget, --bounds",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         auto scene = std::make_shared<const BoundedScene>(tape, octree_bounds(o));
         return inside_and_out(tape, scene->bounds(), trace_options(o),
                               [scene](const Ray& ray, const TraceOptions& opt) {
                                   return bounded_sphere_trace(*scene, ray, opt);
                               });
     }},
    {"analytic",
     "piecewise-polynomial scenes (algebraic, CSG and blobs of polynomials): g's coefficients "
     "from one evaluation over polynomials in t, split where a min/max/abs branch changes "
     "(Wyvill 1990), each piece by closed forms up to degree 4 (approximate) and Bernstein "
     "clipping above (certified); knob: --budget",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         return make_analytic(tape, o, solvers::AnalyticOptions::Mode::ClosedForm, "analytic");
     }},
    {"bernstein",
     "piecewise-polynomial scenes: every piece by Bernstein-basis isolation with Bezier "
     "clipping (Nishita 1994) on the interval coefficients; certified; knob: --budget",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         return make_analytic(tape, o, solvers::AnalyticOptions::Mode::Bernstein, "bernstein");
     }},
    {"exact",
     "polynomial scenes: g's coefficients in exact rational arithmetic (GMP), its first root "
     "isolated by a Sturm sequence (Sturm 1829) and bisection at doubles to adjacent doubles, "
     "with its multiplicity; tangent and clustered roots proven; degree at most 64; certified; "
     "knob: --budget",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         const std::string why = solvers::why_not_exact_polynomial(tape);
         if (!why.empty()) {
             throw std::invalid_argument(
                 "method 'exact' does not apply to this scene: f is not a polynomial in x, y, z "
                 "with rational coefficients (" +
                 why + "); use certified");
         }
         solvers::ExactOptions opt;
         opt.budget = o.budget;
         return [&tape, opt](const Ray& ray) { return solvers::exact_first_root(tape, ray, opt); };
     }},
    {"hermite",
     "g and g' sampled at --samples + 1 points, cubic Hermite pieces solved in turn (Sherstyuk "
     "1999); approximate (misses features thinner than the spacing); knob: --samples",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         solvers::HermiteOptions opt;
         opt.samples = o.samples;
         return
             [&tape, opt](const Ray& ray) { return solvers::hermite_first_root(tape, ray, opt); };
     }},
    {"approx",
     "certified, per-cell Taylor models (a degree 1-3 polynomial with a proven remainder) on the "
     "ambiguous cells of an octree over the bounds (default [-2,2]^3, --depth 5): parts of a "
     "cell's "
     "segment excluded by the model, the rest finished by the certified solver on the pruned "
     "tape; the ray outside the bounds with the full tape; certified; knobs: --budget, --bounds, "
     "--depth",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         auto approx = std::make_shared<const Approx>(tape, octree_bounds(o), approx_options(o));
         solvers::CertifiedOptions opt;
         opt.budget = o.budget;
         return [approx, opt](const Ray& ray) { return approx->certified(ray, opt); };
     }},
    {"approx-plain",
     "the per-cell polynomial models of approx without their remainder, solved in closed form "
     "(cubic) on each ambiguous cell's segment; the scene is taken as empty outside the bounds; "
     "approximate (may miss or invent roots); knobs: --bounds, --depth",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         auto approx = std::make_shared<const Approx>(tape, octree_bounds(o), approx_options(o));
         return [approx](const Ray& ray) { return approx->plain(ray); };
     }},
    {"reference",
     "certified, every evaluation in 256-bit MPFR intervals: enclosures of adjacent doubles, the "
     "ground truth of the benchmarks (about 100x slower); certified; knob: --budget",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         solvers::CertifiedOptions opt;
         opt.budget = o.budget;
         return [&tape, opt](const Ray& ray) {
             return solvers::certified_first_root_reference(tape, ray, opt);
         };
     }},
};

}  // namespace

std::vector<std::string> method_names() {
    std::vector<std::string> names;
    for (const Entry& e : kMethods) names.emplace_back(e.name);
    return names;
}

std::string describe_methods() {
    std::string s;
    for (const Entry& e : kMethods) {
        s += std::string(e.name) + ": " + std::string(e.summary) + "\n";
    }
    return s;
}

RayFunction make_method(std::string_view name, const expr::Tape& tape,
                        const MethodOptions& options) {
    for (const Entry& e : kMethods) {
        if (e.name != name) continue;
        NearestScope env;  // what make builds (λ, octrees) is computed in the library's environment
        RayFunction fn = e.make(tape, options);
        // Each ray in the library's floating-point environment, whatever the calling thread's.
        return [fn = std::move(fn)](const Ray& ray) {
            NearestScope ray_env;
            return fn(ray);
        };
    }
    std::string list;
    for (const Entry& e : kMethods) list += (list.empty() ? "" : ", ") + std::string(e.name);
    throw std::invalid_argument("unknown method '" + std::string(name) +
                                "'; available methods: " + list);
}

}  // namespace certray::tracers
