// tracers/methods.h — the method registry: a method name turned into a per-ray function.
//
// Contract: make_method(name, tape, options) returns a function that answers one ray with the
// named method (solvers/ray.h semantics: certified methods prove what they claim; approximate
// methods use the same result type and are measured against the certified one). The function is
// thread-safe (each thread keeps its own scratch space) and reads `tape`, which must outlive it.
// Work done once per scene (a global Lipschitz bound, an octree) is done by make_method. This is
// the one place where `--method` names become calls, shared by `certray query` and `render`.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "expr/tape.h"
#include "interval/interval.h"
#include "solvers/ray.h"

namespace certray::tracers {

/// The knobs of every method; each method reads the ones it documents and ignores the rest.
struct MethodOptions {
    /// Most whole-tape evaluations per ray before answering unknown (certified, and a cap on the
    /// steps of every iterative method).
    std::uint64_t budget = 20000;
    /// Convergence distance of the tracers (scene units): a hit is reported when |f|/λ < epsilon.
    double epsilon = 1e-6;
    /// Fixed step of ray marching (scene units).
    double step = 1e-2;
    /// Over-relaxation of enhanced sphere tracing (steps of (1 + kappa)·|f|/λ).
    double kappa = 0.2;
    /// Samples along the ray of the Hermite method.
    unsigned samples = 64;
    /// Subdivision depth of the octree methods (certified-octree, octree, approx, approx-plain).
    int depth = 5;
    /// The scene bounds: where global constants are computed and outside which tracers stop.
    /// Unset: each ray's own segment [o + tmin·d, o + tmax·d] bounds it.
    std::optional<std::array<Interval, 3>> bounds;
};

/// One ray in, one answer out; thread-safe.
using RayFunction = std::function<RayResult(const Ray&)>;

/// The names make_method accepts, in the order `--help` lists them.
std::vector<std::string> method_names();

/// One line per method: "name: what it does (certified|approximate)".
std::string describe_methods();

/// The per-ray function of method `name` on `tape`. Throws std::invalid_argument naming the
/// available methods when `name` is unknown.
RayFunction make_method(std::string_view name, const expr::Tape& tape,
                        const MethodOptions& options);

}  // namespace certray::tracers
