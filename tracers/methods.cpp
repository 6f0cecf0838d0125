// tracers/methods.cpp — the registry of methods (see methods.h).
#include "tracers/methods.h"

#include <stdexcept>

#include "solvers/certified.h"

namespace certray::tracers {
namespace {

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
     "certified, each parameter interval also enclosed by the affine form of g in t (tighter on "
     "long segments, two evaluations per step); certified; knob: --budget",
     [](const expr::Tape& tape, const MethodOptions& o) -> RayFunction {
         solvers::CertifiedOptions opt;
         opt.budget = o.budget;
         opt.affine = true;
         return
             [&tape, opt](const Ray& ray) { return solvers::certified_first_root(tape, ray, opt); };
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
