// tracers/march.h — ray marching (Perlin & Hoffert 1989) and the pieces every classical tracer
// shares: TraceOptions and the rigorous point/step helpers.
//
// Contract of march(): samples g(t) = f(o + t·d) at a fixed spacing of `step` scene units from
// tmin; at an exact zero it reports Hit at that t; at a sign change between two samples it
// bisects the bracket until it is narrower than `epsilon` scene units and reports Hit with the
// bracket [t_lo, t_hi] (t its midpoint). Miss when tmax is reached with no sign change; Unknown
// when g is NaN / undefined at a sample or the budget of evaluations is spent. An approximate
// method: a root pair closer than `step` is skipped (a thin shell is missed). Each sample is one
// double evaluation (counted in evals.value). Reference: docs/theory/sphere_tracing.md.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>

#include "expr/tape.h"
#include "interval/interval.h"
#include "solvers/ray.h"

namespace certray::tracers {

class RegionTapes;  // tracers/region_tapes.h

/// The knobs of the classical tracers (a subset of MethodOptions).
struct TraceOptions {
    /// Convergence distance (scene units): a tracer reports a hit when |f|/λ < epsilon.
    double epsilon = 1e-6;
    /// Fixed step of ray marching (scene units).
    double step = 1e-2;
    /// Over-relaxation of enhanced sphere tracing: steps of (1 + kappa)·|f|/λ.
    double kappa = 0.2;
    /// Most whole-tape evaluations (any kind) per ray; then the answer is Unknown.
    std::uint64_t budget = 20000;
    /// Most wall-clock seconds per ray (0: no limit); then the answer is Unknown. A tracer that
    /// crawls on a model without a usable Lipschitz bound ends in bounded time.
    double seconds = 1.0;
    /// Sphere tracing stops Unknown at t (no root before it) where its bound falls below
    /// epsilon while the first-order estimate puts the surface farther than 4·epsilon: the bound
    /// is loose there, and stepping on would crawl (Lipschitz-Pruning's molecule: λ ≈ 10¹⁷⁶,
    /// local bounds as loose near its smooth unions: 720–900 evaluations a pixel). For callers
    /// that go on by segment tracing from there (the registry's sphere and enhanced); off, the
    /// tracer steps on (it stops only for a usable estimate or the budget).
    bool hand_over_crawls = false;
};

/// The moment a ray's time budget (TraceOptions::seconds) runs out.
class Deadline {
  public:
    explicit Deadline(double seconds)
        : end_(seconds > 0 ? std::chrono::steady_clock::now() +
                                 std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(seconds))
                           : std::chrono::steady_clock::time_point::max()) {}
    /// True once the time is up.
    bool passed() const { return std::chrono::steady_clock::now() >= end_; }
    /// passed() at every 16th step of a loop (`step` its counter), false at the others: a clock
    /// read costs as much as a step on a short tape (a third of march's time on the tanglecube),
    /// and 15 steps more are microseconds.
    bool passed_at(std::uint64_t step) const { return (step & 15) == 0 && passed(); }
    /// The seconds left, for the TraceOptions::seconds of a tracer run within this one's time:
    /// 0 (no limit) when this deadline has none, else at least 1 ns (a passed deadline still
    /// limits: the nested tracer stops at once).
    double seconds_left() const {
        if (end_ == std::chrono::steady_clock::time_point::max()) return 0;
        const double left =
            std::chrono::duration<double>(end_ - std::chrono::steady_clock::now()).count();
        return std::max(left, 1e-9);
    }

  private:
    std::chrono::steady_clock::time_point end_;
};

/// Ray marching with a fixed step and bisection of the first sign change (see the file contract).
RayResult march(const expr::Tape& tape, const Ray& ray, const TraceOptions& options);

/// march() evaluating each sample with the tape of its region (RegionTapes::at: the same value
/// of f, on a tape that is often much shorter): the same contract.
RayResult march(const RegionTapes& regions, const Ray& ray, const TraceOptions& options);

namespace detail {

/// An enclosure of g(t) = f(o + t·d) at the exact real parameter t (the point o + t·d is enclosed
/// by interval arithmetic, so rounding of the point cannot hide a smaller |g|). Per-thread
/// evaluator: no allocation once warm.
Interval g_at(const expr::Tape& tape, const Ray& ray, double t);

/// A box of two doubles per axis around o + t·d at the exact real t (fma, one double outward).
std::array<Interval, 3> point_box(const Ray& ray, double t);

/// min{|x| : x ∈ v}, the mignitude (0 if v contains 0); NaN if v is empty.
double mignitude(const Interval& v);

/// True when v is non-empty and decorated defined.
inline bool usable(const Interval& v) { return !v.is_empty() && v.defined; }

/// The signed distance bound v/λ of a value v of f with a Lipschitz bound λ (finite, ≥ 0), rounded
/// outward; for λ = 0 (f constant on the region) ±inf by v's sign, or v itself if it may be 0.
Interval distance_bound(const Interval& v, double lambda);

/// A distance bound from a *local* Lipschitz bound: λ_loc over the box p inflated by rho, and
/// min(|v|/λ_loc, rho) with v's sign (v: f over p, certainly non-zero) — a surface point within rho
/// is reached inside that box, a farther one is farther than rho. Not usable (empty) when λ_loc is
/// not finite and positive. One interval-gradient evaluation of the tape — of the tape of the
/// box's region when `regions` is given (the same function there). With `within` (a convex box
/// holding the exact point, e.g. the box of the ray's segment [o + tmin·d, o + tmax·d]), λ_loc is
/// taken over the box cut to `within`: then the result bounds the distance to the surface only
/// for the points of `within` (for a ray: along its segment, all a tracer steps over), since the
/// straight path from the point to any of them stays in the cut box.
Interval local_distance_bound(const expr::Tape& tape, const std::array<Interval, 3>& p,
                              const Interval& v, double rho, const RegionTapes* regions = nullptr,
                              const std::array<Interval, 3>* within = nullptr);

/// A local bound's box (cut to `within`) and λ over it, kept for reuse on one ray.
struct LocalBox {
    bool valid = false;
    std::array<Interval, 3> box{};
    double lambda = 0;
};

/// local_distance_bound, reusing `cache`: where p's box inflated by some ρ′ ≥ ρ/2 and cut to
/// `within` fits inside the cached box, and that box is at most 16ρ wide on each side of its
/// centre (a much larger box's λ may be far looser than a fresh one's), min(|v|/λ, min(ρ′, ρ)) with
/// the cached λ (every surface point of `within` nearer than ρ′ to p lies in the cached box, and so
/// does the straight path to it: λ bounds ∇f there), and no evaluation; otherwise a new bound over
/// p ⊕ ρ cut to `within`, stored in `cache`, and `evaluated` set (one interval-gradient
/// evaluation). A tracer converging on a surface shrinks its boxes step by step, so each falls
/// inside the last one.
Interval local_distance_bound(const expr::Tape& tape, const std::array<Interval, 3>& p,
                              const Interval& v, double rho, const RegionTapes* regions,
                              const std::array<Interval, 3>& within, LocalBox& cache,
                              bool& evaluated);

/// ‖∇f(p)‖ in double (one gradient evaluation). A local λ over any box holding p is at least this:
/// where it is ≥ λ/k, no local bound can beat λ by k× (the tracers' gradient probe).
double gradient_norm(const expr::Tape& tape, const std::array<double, 3>& p);

/// The centre of a point's box.
std::array<double, 3> midpoint(const std::array<Interval, 3>& p);

/// The box of the ray's segment o + [tmin, tmax]·d, rounded outward (infinite where tmax is).
std::array<Interval, 3> segment_box(const Ray& ray);

/// An upper bound on ‖d‖₂ (rounded upward).
double norm_up(const std::array<double, 3>& d);

// The directed operations below run in round-to-nearest (the library's environment, which
// make_method and the renderers set): the rounding error of the nearest result is computed
// exactly (TwoSum, fma) and the result moved one double when it lies on the wrong side — no
// rounding-mode switch (a switch pair cost a third of enhanced sphere tracing's time on the
// tanglecube). Where the error is not exact (overflow, subnormal results) they fall back to
// interval arithmetic.

/// The largest double ≤ a / b for a ≥ 0, b > 0 (+inf when b is 0 and a > 0).
double div_down(double a, double b);

/// The largest double ≤ a · b.
double mul_down(double a, double b);

/// The largest double ≤ a + b.
double add_down(double a, double b);

/// The smallest double ≥ a + b.
double add_up(double a, double b);

/// The answer for a degenerate ray (zero direction or tmin = tmax, g constant): Hit at tmin if
/// g is exactly 0, Miss if g is certainly nonzero, Unknown otherwise. One interval evaluation.
RayResult degenerate(const expr::Tape& tape, const Ray& ray);

}  // namespace detail

}  // namespace certray::tracers
