// tracers/methods.cpp — the registry of methods (see methods.h).
#include "tracers/methods.h"

#include <memory>
#include <stdexcept>

#include "solvers/analytic.h"
#include "solvers/certified.h"
#include "solvers/hermite.h"
#include "tracers/octree.h"

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

/// The bounds the octree methods subdivide: the given ones, else [−2, 2]³ (the gallery's frame).
std::array<Interval, 3> octree_bounds(const MethodOptions& o) {
    if (o.bounds) return *o.bounds;
    return {Interval(-2, 2), Interval(-2, 2), Interval(-2, 2)};
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
         solvers::CertifiedOptions opt;
         opt.budget = o.budget;
         return
             [&tape, opt](const Ray& ray) { return solvers::certified_first_root(tape, ray, opt); };
     }},
    {"certified-affine",
     "certified, where the interval enclosure of g over a parameter interval holds 0 it is "
     "intersected with the affine form of g in t (tighter on long segments; one more "
     "evaluation); certified; knob: --budget",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         solvers::CertifiedOptions opt;
         opt.budget = o.budget;
         opt.affine = true;
         return
             [&tape, opt](const Ray& ray) { return solvers::certified_first_root(tape, ray, opt); };
     }},
    {"certified-octree",
     "certified, accelerated by an octree over the bounds (default [-2,2]^3, depth 5): empty and "
     "full cells skipped, each ambiguous cell solved with its pruned tape; the ray outside the "
     "bounds with the full tape; certified; knobs: --budget, --bounds",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         auto tree = std::make_shared<const Octree>(tape, octree_bounds(o));
         solvers::CertifiedOptions opt;
         opt.budget = o.budget;
         return [tree, opt](const Ray& ray) { return tree->certified(ray, opt); };
     }},
    {"octree",
     "sphere tracing with the local Lipschitz bound of each octree cell (Hart 1996) inside the "
     "bounds (default [-2,2]^3, depth 5; the scene is taken as empty outside them); approximate, "
     "never steps past a root inside the bounds; knobs: --epsilon, --budget, --bounds",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         auto tree = std::make_shared<const Octree>(tape, octree_bounds(o));
         const double eps = o.epsilon;
         const std::uint64_t budget = o.budget;
         return [tree, eps, budget](const Ray& ray) { return tree->sphere(ray, eps, budget); };
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
    {"hermite",
     "g and g' sampled at --samples + 1 points, cubic Hermite pieces solved in turn (Sherstyuk "
     "1999); approximate (misses features thinner than the spacing); knob: --samples",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         solvers::HermiteOptions opt;
         opt.samples = o.samples;
         return
             [&tape, opt](const Ray& ray) { return solvers::hermite_first_root(tape, ray, opt); };
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
        if (e.name == name) return e.make(tape, options);
    }
    std::string list;
    for (const Entry& e : kMethods) list += (list.empty() ? "" : ", ") + std::string(e.name);
    throw std::invalid_argument("unknown method '" + std::string(name) +
                                "'; available methods: " + list);
}

}  // namespace certray::tracers
