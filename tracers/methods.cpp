// tracers/methods.cpp — the registry of methods (see methods.h).
#include "tracers/methods.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>

#include "expr/derived.h"
#include "solvers/analytic.h"
#include "solvers/certified.h"
#include "solvers/exact.h"
#include "solvers/hermite.h"
#include "solvers/solid.h"
#include "tracers/approx.h"
#include "tracers/bounding.h"
#include "tracers/march.h"
#include "tracers/octree.h"
#include "tracers/region_tapes.h"
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
    t.seconds = o.seconds;
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

/// The certified solver with the options' budget (and the affine refinement if asked).
RayFunction make_certified(const expr::Tape& tape, const MethodOptions& o, bool affine) {
    solvers::CertifiedOptions opt;
    opt.budget = o.budget;
    opt.affine = affine;
    opt.tighten = o.tighten != 0;
    return [&tape, opt](const Ray& ray) { return solvers::certified_first_root(tape, ray, opt); };
}

using Tracer = RayResult (*)(const RegionTapes&, const Ray&, double, const TraceOptions&);

/// The bounds the octree methods subdivide: the given ones, else [−2, 2]³ (the gallery's frame).
std::array<Interval, 3> octree_bounds(const MethodOptions& o) {
    if (o.bounds) return *o.bounds;
    return {Interval(-2, 2), Interval(-2, 2), Interval(-2, 2)};
}

/// The region-pruned tapes of `tape` over the octree bounds (built once per method, shared by
/// every ray; points outside the bounds use the full tape).
std::shared_ptr<const RegionTapes> region_tapes(const expr::Tape& tape, const MethodOptions& o) {
    return std::make_shared<const RegionTapes>(tape, octree_bounds(o));
}

/// The registry's segment tracing: each pass from `regions`' tapes where shorter, and a first
/// segment one region cell long (SegmentOptions::regions, first_length); the defaults without.
SegmentOptions segment_options(const RegionTapes* regions) {
    SegmentOptions so;
    so.regions = regions;
    if (regions) so.first_length = regions->leaf_size();
    return so;
}

/// `res`, an answer on `ray`, unless it is Unknown with evaluations and time left: then segment
/// tracing on [res.t_lo, ray.tmax] (no root lies before res.t_lo), with the evaluations of both;
/// its passes from `regions`' tapes where shorter (SegmentOptions::regions).
RayResult segments_after(const expr::Tape& tape, const Ray& ray, const RayResult& res,
                         const TraceOptions& topt, const Deadline& deadline,
                         const RegionTapes* regions) {
    if (res.status != Status::Unknown || !(res.t_lo >= ray.tmin && res.t_lo <= ray.tmax) ||
        res.evals.total() >= topt.budget || deadline.passed()) {
        return res;
    }
    TraceOptions opt = topt;
    opt.budget = topt.budget - res.evals.total();
    opt.seconds = deadline.seconds_left();
    RayResult rest =
        segment_trace(tape, Ray{ray.o, ray.d, res.t_lo, ray.tmax}, opt, segment_options(regions));
    rest.evals += res.evals;
    return rest;
}

/// Sphere tracing with a proven global λ: over the bounds (computed once; rays clipped to them),
/// or else over each ray's own segment box (one gradient evaluation per ray, counted).
RayFunction make_lipschitz_tracer(const expr::Tape& tape, const MethodOptions& o, Tracer trace) {
    TraceOptions topt = trace_options(o);
    topt.hand_over_crawls = true;  // segments_after goes on where sphere tracing crawls
    const double global =
        o.bounds ? global_lipschitz(tape, *o.bounds) : std::numeric_limits<double>::quiet_NaN();
    auto regions = region_tapes(tape, o);
    return [&tape, o, topt, global, trace, regions](const Ray& r) {
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
        // No usable global bound (a jump, a clamp without distance semantics, an unbounded
        // derivative): sphere tracing cannot step; segment tracing's local bounds along the ray
        // can, and never step past the first root either. The same where sphere tracing stops
        // unknown with budget and time left (g undefined at a point, the step vanished): segment
        // tracing goes on from there (no root lies before it).
        const Deadline deadline(topt.seconds);
        RayResult res;
        res.status = Status::Unknown;
        res.t_lo = ray.tmin;
        if (std::isfinite(lambda) && lambda > 0) {
            // Half the budget at most: a ray that crawls along a surface it grazes (free radii
            // far above epsilon, far below the distance left) goes on by segment tracing.
            TraceOptions first = topt;
            first.budget = std::max<std::uint64_t>(1, topt.budget / 2);
            res = trace(*regions, ray, lambda, first);
        }
        res.evals.gradient += extra;
        return segments_after(tape, ray, res, topt, deadline, regions.get());
    };
}

/// A tracer that holds inside `bounds` (the octree's, the bounding volumes'), applied there; the
/// parts of the ray before and after the bounds by segment tracing (local bounds along the ray,
/// never past the first root), so that nothing outside the bounds is assumed empty.
RayFunction inside_and_out(const expr::Tape& tape, const std::array<Interval, 3>& bounds,
                           const TraceOptions& topt,
                           std::function<RayResult(const Ray&, const TraceOptions&)> inside) {
    return [&tape, bounds, topt, inside](const Ray& r) {
        const Deadline deadline(topt.seconds);  // one time budget for the whole ray
        auto with_budget = [&topt, &deadline](std::uint64_t left) {
            TraceOptions opt = topt;
            opt.budget = left;
            opt.seconds = deadline.seconds_left();
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

ApproxOptions approx_options(const MethodOptions& o) {
    ApproxOptions a;
    a.octree.max_depth = o.depth;
    return a;
}

struct Entry {
    MethodInfo info;
    RayFunction (*make)(const expr::Tape&, const MethodOptions&);
};

/// The methods, in the order `--help` lists them.
const std::vector<Entry>& entries() {
    static const std::vector<Entry> kMethods = {
        {{"certified",
          true,
          "interval bisection with interval Newton (Snyder 1992)",
          {"budget", "tighten"},
          {{"budget", {30, 100, 1000, 20000}}},
          ConeMarching::None},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             return make_certified(tape, o, false);
         }},
        {{"certified-affine",
          true,
          "certified, where the interval enclosure of g over a parameter interval holds 0 it is "
          "intersected with the affine form of g in t (tighter on long segments; one more "
          "evaluation)",
          {"budget", "tighten"},
          {{"budget", {30, 100, 1000, 20000}}},
          ConeMarching::None},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             return make_certified(tape, o, true);
         }},
        {{"march",
          false,
          "ray marching with a fixed step (Perlin 1989), a sign change refined to --epsilon; "
          "approximate (skips features thinner than the step)",
          {"step", "epsilon", "budget", "bounds", "seconds"},
          {{"step", {0.1, 0.03, 0.01, 0.003}}},
          ConeMarching::Global},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             const TraceOptions topt = trace_options(o);
             auto regions = region_tapes(tape, o);
             return [o, topt, regions](const Ray& r) {
                 Ray ray = r;
                 RayResult miss;
                 miss.status = Status::Miss;
                 if (!clip(o, ray)) return miss;
                 return march(*regions, ray, topt);
             };
         }},
        {{"sphere",
          false,
          "sphere tracing (Hart 1996) with a proven global Lipschitz bound from the DAG (over "
          "--bounds, else over each ray's segment), outgrown by local bounds where it is loose; "
          "where no finite bound exists, sphere tracing stops unknown or has spent half the "
          "budget, segment tracing; never steps past the first root",
          {"epsilon", "budget", "bounds", "seconds"},
          {{"epsilon", {1e-2, 1e-4, 1e-6, 1e-9}}},
          ConeMarching::Local},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             return make_lipschitz_tracer(tape, o, &sphere_trace);
         }},
        {{"enhanced",
          false,
          "enhanced sphere tracing (Keinert 2014): over-relaxed steps (1 + kappa)|f|/lambda with "
          "the step-back rule, same guarantee",
          {"kappa", "epsilon", "budget", "bounds", "seconds"},
          {{"epsilon", {1e-2, 1e-4, 1e-6, 1e-9}}, {"kappa", {0.2, 0.5}}},
          ConeMarching::Local},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             return make_lipschitz_tracer(tape, o, &enhanced_trace);
         }},
        {{"segment",
          false,
          "segment tracing (Galin 2020) with local bounds of |grad f . d| over each segment from "
          "the DAG's interval derivatives; never steps past the first root",
          {"epsilon", "budget", "bounds", "seconds"},
          {{"epsilon", {1e-2, 1e-4, 1e-6, 1e-9}}},
          ConeMarching::Local},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             // Each pass from the tape of the region holding its segment where that is shorter.
             auto regions = region_tapes(tape, o);
             const TraceOptions topt = trace_options(o);
             return [&tape, o, topt, regions](const Ray& r) {
                 Ray ray = r;
                 RayResult miss;
                 miss.status = Status::Miss;
                 if (!clip(o, ray)) return miss;
                 return segment_trace(tape, ray, topt, segment_options(regions.get()));
             };
         }},
        {{"certified-bvh",
          true,
          "certified, with bounding volumes: inside the bounds (default [-2,2]^3) each ray's tape "
          "keeps only the primitives whose boxes its segment meets (same zeros and sign along "
          "it), outside them the full tape",
          {"budget", "bounds"},
          {{"budget", {30, 100, 1000, 20000}}},
          ConeMarching::None},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             auto scene = std::make_shared<const BoundedScene>(tape, octree_bounds(o));
             const std::uint64_t budget = o.budget;
             return
                 [scene, budget](const Ray& ray) { return bounded_certified(*scene, ray, budget); };
         }},
        {{"certified-octree",
          true,
          "certified, accelerated by an octree over the bounds (default [-2,2]^3, --depth 5): "
          "empty and full cells skipped, each ambiguous cell solved with its pruned tape; the ray "
          "outside the bounds with the full tape",
          {"budget", "bounds", "depth", "tighten"},
          {{"budget", {30, 100, 1000, 20000}}, {"depth", {3, 7}}},
          ConeMarching::None},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             auto tree = std::make_shared<const Octree>(
                 tape, octree_bounds(o), OctreeOptions{o.depth, std::size_t{1} << 20});
             solvers::CertifiedOptions opt;
             opt.budget = o.budget;
             opt.tighten = o.tighten != 0;
             return [tree, opt](const Ray& ray) { return tree->certified(ray, opt); };
         }},
        {{"octree",
          false,
          "sphere tracing with the local Lipschitz bound of each octree cell (Hart 1996) inside "
          "the bounds (default [-2,2]^3, --depth 5), cells whose segment's enclosure excludes 0 "
          "skipped; segment tracing before and after the bounds and in a cell without a finite "
          "bound or left undecided after 16 steps; approximate, never steps past the first root",
          {"epsilon", "budget", "bounds", "depth", "seconds"},
          {{"epsilon", {1e-2, 1e-4, 1e-6, 1e-9}}, {"depth", {3, 7}}},
          ConeMarching::Local},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             auto tree = std::make_shared<const Octree>(
                 tape, octree_bounds(o), OctreeOptions{o.depth, std::size_t{1} << 20});
             return inside_and_out(tape, tree->bounds(), trace_options(o),
                                   [tree](const Ray& ray, const TraceOptions& opt) {
                                       return tree->sphere(ray, opt);
                                   });
         }},
        {{"bvh",
          false,
          "sphere tracing with bounding volumes (Hart 1996): f's unions, intersections and "
          "complements down to its primitives, each with a box (interval slab contraction) and a "
          "Lipschitz bound, unions as a BVH; a primitive far from the point is bounded by the "
          "distance to its box. Inside the bounds (default [-2,2]^3); before and after them, and "
          "where the distance is undefined or 32 steps leave the ray undecided, segment tracing; "
          "approximate, never steps past the first root",
          {"epsilon", "budget", "bounds", "seconds"},
          {{"epsilon", {1e-2, 1e-4, 1e-6, 1e-9}}},
          ConeMarching::Local},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             auto scene = std::make_shared<const BoundedScene>(tape, octree_bounds(o));
             return inside_and_out(tape, scene->bounds(), trace_options(o),
                                   [scene](const Ray& ray, const TraceOptions& opt) {
                                       // Where the bounding volumes give no distance (a leaf
                                       // with no finite λ) or after kSphereSteps, segment
                                       // tracing goes on.
                                       const Deadline deadline(opt.seconds);
                                       TraceOptions first = opt;
                                       first.budget = std::min(opt.budget, kSphereSteps);
                                       return segments_after(
                                           scene->tape(), ray,
                                           bounded_sphere_trace(*scene, ray, first), opt, deadline,
                                           scene->region_tapes());
                                   });
         }},
        {{"analytic",
          false,
          "piecewise-polynomial scenes (algebraic, CSG and blobs of polynomials): g's "
          "coefficients from one evaluation over polynomials in t, split where a min/max/abs "
          "branch changes (Wyvill 1990), each piece by closed forms up to degree 4 (approximate) "
          "and Bernstein clipping above (certified)",
          {"budget"},
          {},
          ConeMarching::None},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             return make_analytic(tape, o, solvers::AnalyticOptions::Mode::ClosedForm, "analytic");
         }},
        {{"bernstein",
          true,
          "piecewise-polynomial scenes: every piece by Bernstein-basis isolation with Bezier "
          "clipping (Nishita 1994) on the interval coefficients",
          {"budget"},
          {},
          ConeMarching::None},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             return make_analytic(tape, o, solvers::AnalyticOptions::Mode::Bernstein, "bernstein");
         }},
        {{"exact",
          true,
          "polynomial scenes: g's coefficients in exact rational arithmetic (GMP), its first root "
          "isolated by a Sturm sequence (Sturm 1829) and bisection at doubles to adjacent "
          "doubles, with its multiplicity; tangent and clustered roots proven; degree at most 64",
          {"budget"},
          {},
          ConeMarching::None},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             const std::string why = solvers::why_not_exact_polynomial(tape);
             if (!why.empty()) {
                 throw std::invalid_argument(
                     "method 'exact' does not apply to this scene: f is not a polynomial in x, y, "
                     "z "
                     "with rational coefficients (" +
                     why + "); use certified");
             }
             solvers::ExactOptions opt;
             opt.budget = o.budget;
             return
                 [&tape, opt](const Ray& ray) { return solvers::exact_first_root(tape, ray, opt); };
         }},
        {{"hermite",
          false,
          "g and g' sampled at --samples + 1 points, cubic Hermite pieces solved in turn "
          "(Sherstyuk 1999); approximate (misses features thinner than the spacing)",
          {"samples"},
          {{"samples", {8, 32, 128}}},
          ConeMarching::None},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             solvers::HermiteOptions opt;
             opt.samples = o.samples;
             return [&tape, opt](const Ray& ray) {
                 return solvers::hermite_first_root(tape, ray, opt);
             };
         }},
        {{"certified-taylor",
          true,
          "certified, per-cell Taylor models (a degree 1-3 polynomial with a proven remainder) on "
          "the ambiguous cells of an octree over the bounds (default [-2,2]^3, --depth 5): parts "
          "of a cell's segment excluded by the model, the rest finished by the certified solver "
          "on the pruned tape; the ray outside the bounds with the full tape",
          {"budget", "bounds", "depth", "tighten"},
          {{"depth", {3, 5, 7}}},
          ConeMarching::None},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             auto approx =
                 std::make_shared<const Approx>(tape, octree_bounds(o), approx_options(o));
             solvers::CertifiedOptions opt;
             opt.budget = o.budget;
             opt.tighten = o.tighten != 0;
             return [approx, opt](const Ray& ray) { return approx->certified(ray, opt); };
         }},
        {{"taylor-plain",
          false,
          "the per-cell polynomial models of certified-taylor without their remainder, solved in "
          "closed "
          "form (cubic) on each ambiguous cell's segment; the scene is taken as empty outside the "
          "bounds; approximate (may miss or invent roots)",
          {"bounds", "depth"},
          {{"depth", {3, 5, 7}}},
          ConeMarching::None},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             auto approx =
                 std::make_shared<const Approx>(tape, octree_bounds(o), approx_options(o));
             return [approx](const Ray& ray) { return approx->plain(ray); };
         }},
        {{"reference",
          true,
          "certified, every evaluation in 256-bit MPFR intervals: enclosures of adjacent doubles, "
          "the ground truth of the benchmarks (about 100x slower)",
          {"budget"},
          {},
          ConeMarching::None},
         [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
             solvers::CertifiedOptions opt;
             opt.budget = o.budget;
             return [&tape, opt](const Ray& ray) {
                 return solvers::certified_first_root_reference(tape, ray, opt);
             };
         }},
    };
    return kMethods;
}

}  // namespace

const std::vector<Knob>& knobs() {
    constexpr double kHuge = 1e300;
    static const std::vector<Knob> kKnobs = {
        {"budget", KnobKind::Count, "most whole-tape evaluations per ray before answering unknown",
         1, 1e18, [](const MethodOptions& o) { return static_cast<double>(o.budget); },
         [](MethodOptions& o, double v) { o.budget = static_cast<std::uint64_t>(v); }},
        {"epsilon", KnobKind::Real,
         "convergence distance of the tracers (scene units): a hit when |f|/lambda < epsilon",
         1e-300, kHuge, [](const MethodOptions& o) { return o.epsilon; },
         [](MethodOptions& o, double v) { o.epsilon = v; }},
        {"step", KnobKind::Real, "fixed step of ray marching (scene units)", 1e-300, kHuge,
         [](const MethodOptions& o) { return o.step; },
         [](MethodOptions& o, double v) { o.step = v; }},
        {"kappa", KnobKind::Real,
         "over-relaxation of enhanced sphere tracing: steps of (1 + kappa)|f|/lambda", 0, 1,
         [](const MethodOptions& o) { return o.kappa; },
         [](MethodOptions& o, double v) { o.kappa = v; }},
        {"samples", KnobKind::Count, "samples along the ray of the Hermite method", 1, 1e6,
         [](const MethodOptions& o) { return static_cast<double>(o.samples); },
         [](MethodOptions& o, double v) { o.samples = static_cast<unsigned>(v); }},
        {"depth", KnobKind::Integer, "subdivision depth of the octree methods", 0, 10,
         [](const MethodOptions& o) { return static_cast<double>(o.depth); },
         [](MethodOptions& o, double v) { o.depth = static_cast<int>(v); }},
        {"seconds", KnobKind::Real,
         "most wall-clock seconds per ray of an approximate tracer, then unknown (0: no limit)", 0,
         3600, [](const MethodOptions& o) { return o.seconds; },
         [](MethodOptions& o, double v) { o.seconds = v; }},
        {"tighten", KnobKind::Integer,
         "1: a polynomial scene's hits wider than 4 ulps are re-decided in exact rational "
         "arithmetic; 0: the interval enclosure is kept (faster, still proven)",
         0, 1, [](const MethodOptions& o) { return static_cast<double>(o.tighten); },
         [](MethodOptions& o, double v) { o.tighten = static_cast<int>(v); }},
        {"bounds", KnobKind::Bounds,
         "the scene bounds, the cube [lo, hi]^3: where global constants and octrees are computed "
         "(unset: each ray's own segment; octrees and bounding volumes [-2, 2]^3)",
         -kHuge, kHuge, [](const MethodOptions&) { return 0.0; }, [](MethodOptions&, double) {}},
    };
    return kKnobs;
}

const std::vector<MethodInfo>& method_infos() {
    static const std::vector<MethodInfo> kInfos = [] {
        std::vector<MethodInfo> v;
        for (const Entry& e : entries()) v.push_back(e.info);
        return v;
    }();
    return kInfos;
}

namespace {

std::string joined(const std::vector<std::string_view>& names) {
    std::string s;
    for (std::string_view n : names) s += (s.empty() ? "" : ", ") + std::string(n);
    return s;
}

/// Old names that still work (with a note: renamed_method).
constexpr std::pair<std::string_view, std::string_view> kRenamed[] = {
    {"approx", "certified-taylor"},
    {"approx-plain", "taylor-plain"},
};

const Entry& entry(std::string_view name) {
    if (const std::string_view* now = renamed_method(name)) name = *now;
    for (const Entry& e : entries()) {
        if (e.info.name == name) return e;
    }
    std::vector<std::string_view> names;
    for (const Entry& e : entries()) names.push_back(e.info.name);
    throw std::invalid_argument("unknown method '" + std::string(name) +
                                "'; available methods: " + joined(names));
}

const Knob* find_knob(std::string_view name) {
    for (const Knob& k : knobs()) {
        if (k.name == name) return &k;
    }
    return nullptr;
}

std::string format_value(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

}  // namespace

const MethodInfo& method_info(std::string_view name) { return entry(name).info; }

const std::string_view* renamed_method(std::string_view old_name) {
    for (const auto& [old, now] : kRenamed) {
        if (old == old_name) return &now;
    }
    return nullptr;
}

std::vector<std::string> method_names() {
    std::vector<std::string> names;
    for (const Entry& e : entries()) names.emplace_back(e.info.name);
    return names;
}

std::string describe_methods() {
    const MethodOptions defaults;
    std::string s;
    for (const Entry& e : entries()) {
        s += std::string(e.info.name) + " (" + (e.info.certified ? "certified" : "approximate") +
             "): " + std::string(e.info.summary) + "\n    knobs:";
        for (std::string_view k : e.info.knobs) {
            const Knob* knob = find_knob(k);
            s += " --" + std::string(k);
            if (knob && knob->kind != KnobKind::Bounds) {
                s += " (default " + format_value(knob->get(defaults)) + ")";
            }
        }
        if (e.info.knobs.empty()) s += " none";
        s += "\n";
    }
    return s;
}

MethodOptions resolve_knobs(std::string_view name, const KnobValues& given) {
    const MethodInfo& info = method_info(name);
    MethodOptions o;
    auto reads = [&](std::string_view knob) {
        for (std::string_view k : info.knobs) {
            if (k == knob) return true;
        }
        return false;
    };
    auto refuse = [&](std::string_view knob) {
        throw std::invalid_argument(
            "method '" + std::string(name) + "' does not read '" + std::string(knob) +
            "'; its knobs: " + (info.knobs.empty() ? std::string("none") : joined(info.knobs)));
    };
    for (const auto& [knob_name, value] : given.values) {
        const Knob* knob = find_knob(knob_name);
        if (!knob || knob->kind == KnobKind::Bounds) {
            std::vector<std::string_view> all;
            for (const Knob& k : knobs()) all.push_back(k.name);
            throw std::invalid_argument("unknown knob '" + knob_name + "'; knobs: " + joined(all));
        }
        if (!reads(knob->name)) refuse(knob->name);
        const bool integral = knob->kind != KnobKind::Real;
        if (!(value >= knob->min && value <= knob->max) ||
            (integral && value != std::floor(value))) {
            throw std::invalid_argument("knob '" + knob_name + "' = " + format_value(value) +
                                        ": expected " + (integral ? "an integer" : "a number") +
                                        " in [" + format_value(knob->min) + ", " +
                                        format_value(knob->max) + "]");
        }
        knob->set(o, value);
    }
    if (given.bounds) {
        if (!reads("bounds")) refuse("bounds");
        const auto [lo, hi] = *given.bounds;
        if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi)) {
            throw std::invalid_argument("bounds [" + format_value(lo) + ", " + format_value(hi) +
                                        "]: expected finite lo < hi");
        }
        const Interval b(lo, hi);
        o.bounds = std::array<Interval, 3>{b, b, b};
    }
    return o;
}

std::string_view name(Surface s) { return s == Surface::Solid ? "solid" : "zero"; }

Surface parse_surface(std::string_view n) {
    if (n == "zero") return Surface::Zero;
    if (n == "solid") return Surface::Solid;
    throw std::invalid_argument("unknown surface '" + std::string(n) + "'; expected zero or solid");
}

RayFunction make_method(std::string_view name, const expr::Tape& tape,
                        const MethodOptions& options) {
    const Entry& e = entry(name);
    NearestScope env;  // what make builds (λ, octrees) is computed in the library's environment
    RayFunction fn;
    if (options.surface == Surface::Solid && e.info.certified) {
        // The solid surface: the certified solid solver on the whole tape (its MPFR variant for
        // the reference), for every certified method.
        solvers::SolidOptions so;
        so.budget = options.budget;
        so.affine = e.info.name == "certified-affine";
        if (e.info.name == "reference") {
            fn = [&tape, so](const Ray& ray) {
                return solvers::solid_first_entry_reference(tape, ray, so);
            };
        } else {
            fn = [&tape, so](const Ray& ray) { return solvers::solid_first_entry(tape, ray, so); };
        }
    } else {
        fn = e.make(tape, options);
    }
    // Each ray in the library's floating-point environment, whatever the calling thread's.
    return [fn = std::move(fn)](const Ray& ray) {
        NearestScope ray_env;
        return fn(ray);
    };
}

}  // namespace certray::tracers
