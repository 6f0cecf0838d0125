// tracers/methods.h — the method registry: a method name turned into a per-ray function.
//
// Contract: make_method(name, tape, options) returns a function that answers one ray with the
// named method (solvers/ray.h semantics: certified methods prove what they claim; approximate
// methods use the same result type and are measured against the certified one). The function is
// thread-safe (each thread keeps its own scratch space) and reads `tape`, which must outlive it
// (the public API, api/scene.h, owns both). The registry is data: each method's name, whether it is
// certified, the knobs it reads and its sweep in the study (MethodInfo); the CLI's options,
// `certray methods`, the bench and the Python module are made from it. Work done once per scene (a
// global Lipschitz bound, an octree) is done by make_method. This is the one place where `--method`
// names become calls, shared by `certray query` and `render`.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "expr/tape.h"
#include "interval/interval.h"
#include "solvers/ray.h"

namespace certray::tracers {

/// Which surface a query answers (docs/design.md): Zero, the first t with f = 0; Solid, the first
/// entry into {f < 0} (what CSG, SDF and CAD models mean: regions where f ≡ 0 are not interior).
enum class Surface : std::uint8_t { Zero, Solid };

/// "zero" or "solid".
std::string_view name(Surface s);
/// The surface named `name`; throws std::invalid_argument for another name.
Surface parse_surface(std::string_view name);

/// The knobs of every method, with their defaults; which method reads which is in its
/// MethodInfo, and resolve_knobs refuses the others.
struct MethodOptions {
    /// The surface answered. Certified methods answer either (under Solid every certified method
    /// runs the solid solver, solvers/solid.h, on the whole tape: proven, not accelerated yet);
    /// the approximate methods approximate the zero surface whatever this is.
    Surface surface = Surface::Zero;
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
    /// Subdivision depth of the octree methods (certified-octree, octree, certified-taylor,
    /// taylor-plain).
    int depth = 5;
    /// 1: on a polynomial scene, a certified hit wider than 4 ulps is re-decided exactly
    /// (solvers/exact.h); 0: the interval enclosure is kept (faster; still proven).
    int tighten = 1;
    /// Most wall-clock seconds per ray of the approximate tracers (0: no limit).
    double seconds = 1.0;
    /// The scene bounds: where global constants are computed and outside which tracers stop.
    /// Unset: each ray's own segment [o + tmin·d, o + tmax·d] bounds it.
    std::optional<std::array<Interval, 3>> bounds;
};

/// Whether and how an image cone-marches a method's rays (MethodInfo::cone).
enum class ConeMarching : std::uint8_t {
    None,    ///< every ray from the camera
    Global,  ///< free balls of the global Lipschitz bound only (ConeOptions::local_bounds off)
    Local,   ///< and of local bounds where the global one is loose
};

/// One ray in, one answer out; thread-safe.
using RayFunction = std::function<RayResult(const Ray&)>;

/// How a knob's value is read: a count ≥ 1, an integer, a real, or the bounds cube [lo, hi]³.
enum class KnobKind : std::uint8_t { Count, Integer, Real, Bounds };

/// One knob of the methods: its name (the CLI's `--name`, Python's keyword), what it means, the
/// values it accepts, and where it lives in MethodOptions (whose initialisers are the defaults,
/// written once).
struct Knob {
    std::string_view name;
    KnobKind kind;
    std::string_view help;
    double min;  ///< least accepted value (inclusive)
    double max;  ///< greatest accepted value (inclusive)
    double (*get)(const MethodOptions&);
    void (*set)(MethodOptions&, double);
};

/// Every knob, in the order `--help` lists them (bounds last; its value is set as a pair).
const std::vector<Knob>& knobs();

/// A knob's values in the error-against-run-time study (certray bench).
struct Sweep {
    std::string_view knob;
    std::vector<double> values;
};

/// What the registry knows of a method.
struct MethodInfo {
    std::string_view name;
    /// True when every hit and miss is proven (solvers/ray.h); false for approximations, which
    /// are measured against the certified methods, never trusted.
    bool certified;
    std::string_view summary;
    /// The knobs the method reads; setting any other is an error.
    std::vector<std::string_view> knobs;
    /// Its sweep in the study (first knob first); empty: the defaults only.
    std::vector<Sweep> sweep;
    /// How an image shares the empty space in front of this method's rays (tracers/cone.h,
    /// RenderOptions::cone): the tracers that never step past the first root given Lipschitz
    /// bounds (sphere, enhanced, segment, octree, bvh) start each ray where a cone march of its
    /// tile proved it free, with the global and local bounds their own steps use; ray marching
    /// (march), whose samples could only see f of one sign there, with the global bound alone
    /// (its own steps are cheap: local bounds cost it more than they save). docs/benchmarks.md,
    /// "Cone marching".
    ConeMarching cone = ConeMarching::None;
};

/// Every method, in the order `--help` lists them.
const std::vector<MethodInfo>& method_infos();

/// The method named `name`; throws std::invalid_argument naming the available ones.
const MethodInfo& method_info(std::string_view name);

/// The name a renamed method has now ("approx" → "certified-taylor", "approx-plain" →
/// "taylor-plain"; the old names still work everywhere), or null when `old_name` is not one.
const std::string_view* renamed_method(std::string_view old_name);

/// The names make_method accepts, in the order `--help` lists them (without the old names).
std::vector<std::string> method_names();

/// The methods as text: per method its name, certified or approximate, what it does, and its
/// knobs with their defaults.
std::string describe_methods();

/// Knob values as a user gives them, by name (the CLI's options that were set, Python's keyword
/// arguments); the bounds as the pair "bounds" = {lo, hi}.
struct KnobValues {
    std::vector<std::pair<std::string, double>> values;
    std::optional<std::array<double, 2>> bounds;
};

/// The options of method `name` with `given` applied over the defaults. Throws
/// std::invalid_argument for an unknown method, an unknown knob, a knob the method does not read
/// ("method 'sphere' does not read 'samples'; its knobs: epsilon, budget, bounds"), a value out of
/// range or not an integer where one is needed, or bounds that are not finite with lo < hi.
MethodOptions resolve_knobs(std::string_view name, const KnobValues& given);

/// The per-ray function of method `name` on `tape`, which must outlive it. Throws
/// std::invalid_argument naming the available methods when `name` is unknown, and when the
/// method does not apply to the scene. Every call runs in the library's floating-point
/// environment (NearestScope), whatever the calling thread's.
RayFunction make_method(std::string_view name, const expr::Tape& tape,
                        const MethodOptions& options);

}  // namespace certray::tracers
