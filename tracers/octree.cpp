// tracers/octree.cpp — octree build (interval classification, pruned tapes, local λ), ray walk
// in entry order, and the certified and sphere-tracing methods on it (see octree.h).
#include "tracers/octree.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <unordered_map>

#include "expr/derived.h"
#include "expr/eval.h"
#include "expr/prune.h"
#include "tracers/march.h"
#include "tracers/segment_trace.h"
#include "tracers/sphere_trace.h"

namespace certray::tracers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Scratch of one thread.
struct Scratch {
    std::vector<std::uint32_t> stack;
    std::vector<std::pair<double, std::uint32_t>> children;
};
thread_local Scratch t_scratch;

}  // namespace

namespace {

// The geometry below runs in UpInterval arithmetic: the callers hold a RoundingScope (one mode
// switch per ray walk instead of two per operation).

std::array<Interval, 3> inflate_up(const std::array<Interval, 3>& box) {
    std::array<Interval, 3> r;
    const UpInterval k(std::ldexp(1.0, -20));
    for (int i = 0; i < 3; ++i) {
        const UpInterval lo(box[i].lower()), hi(box[i].upper());
        const UpInterval pad = (hi - lo) * k;
        r[i] = Interval((lo - pad).lower(), (hi + pad).upper());
    }
    return r;
}

bool segment_inside_up(const Ray& ray, double t0, double t1, const std::array<Interval, 3>& box) {
    if (!(std::isfinite(t0) && std::isfinite(t1))) return false;
    const UpInterval t(t0, t1);
    for (int i = 0; i < 3; ++i) {
        const UpInterval p = UpInterval(ray.o[i]) + t * UpInterval(ray.d[i]);
        if (!(p.lower() >= box[i].lower() && p.upper() <= box[i].upper())) return false;
    }
    return true;
}

Interval ray_box_up(const Ray& ray, const std::array<Interval, 3>& box) {
    double te = -kInf, tx = kInf;
    for (int i = 0; i < 3; ++i) {
        const double o = ray.o[i], d = ray.d[i];
        if (d == 0) {
            if (!(o >= box[i].lower() && o <= box[i].upper())) return Interval::empty();
            continue;
        }
        // Upward mode: every operation rounds up, so a lower bound is the negated upper bound
        // of the negated quantity (no interval division: the walk's slabs were a third of the
        // octree tracer's time on the tanglecube). Entering at the slab side facing the origin.
        const double below = o - box[i].lower(), above = box[i].upper() - o;  // both rounded up
        if (d > 0) {
            te = std::max(te, -(below / d));  // (lo − o)/d = −(o − lo)/d
            tx = std::min(tx, above / d);
        } else {
            const double nd = -d;
            te = std::max(te, -(above / nd));  // (hi − o)/d = −(hi − o)/|d|
            tx = std::min(tx, below / nd);     // (lo − o)/d = (o − lo)/|d|
        }
    }
    if (!(te <= tx)) return Interval::empty();
    return Interval(te, tx);
}

}  // namespace

std::array<Interval, 3> inflate(const std::array<Interval, 3>& box) {
    RoundingScope scope;
    return inflate_up(box);
}

bool segment_inside(const Ray& ray, double t0, double t1, const std::array<Interval, 3>& box) {
    RoundingScope scope;
    return segment_inside_up(ray, t0, t1, box);
}

Interval ray_box(const Ray& ray, const std::array<Interval, 3>& box) {
    RoundingScope scope;
    return ray_box_up(ray, box);
}

bool face_window(const Ray& ray, double a, double b, const RayResult& r, double& lo, double& hi) {
    if (r.status != Status::Unknown || !(r.t_lo <= r.t_hi) || !std::isfinite(a) ||
        !std::isfinite(b) || !std::isfinite(r.t_lo) || !std::isfinite(r.t_hi)) {
        return false;
    }
    const double scale = std::max(std::fabs(a), std::fabs(b));
    const double ulps16 = 16 * (std::nextafter(scale, kInf) - scale);
    const double width = r.t_hi - r.t_lo;
    const double tol = width + ulps16;
    if (!(r.t_hi + tol >= b || r.t_lo - tol <= a)) return false;
    const double reach = std::max({b - a, 4 * width, ulps16});
    lo = std::max(ray.tmin, r.t_lo - reach);
    hi = std::min(ray.tmax, r.t_hi + reach);
    return lo <= hi && std::isfinite(lo) && std::isfinite(hi);
}

Octree::Octree(const expr::Tape& tape, const std::array<Interval, 3>& bounds,
               const OctreeOptions& options)
    : tape_(tape), bounds_(bounds), options_(options) {
    const auto start = std::chrono::steady_clock::now();
    build();
    stats_.build_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void Octree::build() {
    stats_.full_tape_instructions = tape_.size();
    // Depth first; each piece of work holds the tape its cell is pruned from, so a branch's tape
    // is freed once its last child has been pruned from it: only the leaves' tapes stay (with
    // every branch's kept to the end, Lipschitz-Pruning's molecule peaked at 3.7 GB).
    struct Work {
        std::uint32_t node;
        int depth;
        std::shared_ptr<const expr::Tape> tape;
    };
    std::vector<Work> work;
    work.push_back({0, 0, std::make_shared<const expr::Tape>(tape_)});
    nodes_.push_back(Node{bounds_, State::Ambiguous, 0, 0, 0});
    std::unordered_map<const expr::Tape*, std::uint32_t> leaf_tape;  // tapes_ index of a tape
    while (!work.empty()) {
        const Work w = std::move(work.back());
        work.pop_back();
        const std::array<Interval, 3> box = nodes_[w.node].box;
        const std::array<Interval, 3> wide = inflate(box);
        expr::PruneResult pr = expr::prune(*w.tape, wide);
        std::shared_ptr<const expr::Tape> tape = w.tape;
        if (pr.after < pr.before) tape = std::make_shared<const expr::Tape>(std::move(pr.tape));
        Node& n = nodes_[w.node];
        if (!possibly_zero(pr.value)) {  // no zero in the cell (also: undefined on all of it)
            n.state = !pr.value.is_empty() && pr.value.upper() < 0 ? State::Full : State::Empty;
            ++(n.state == State::Empty ? stats_.empty : stats_.full);
            continue;
        }
        if (w.depth >= options_.max_depth || nodes_.size() + 8 > options_.max_nodes) {
            n.state = State::Ambiguous;
            ++stats_.ambiguous;
            const auto [at, added] =
                leaf_tape.emplace(tape.get(), static_cast<std::uint32_t>(tapes_.size()));
            if (added) tapes_.push_back(tape);
            n.tape = at->second;
            n.lambda = expr::lipschitz_bound(*tape, wide);
            continue;
        }
        n.state = State::Branch;
        n.first_child = static_cast<std::uint32_t>(nodes_.size());
        const std::array<double, 3> mid{midpoint(box[0]), midpoint(box[1]), midpoint(box[2])};
        for (int c = 0; c < 8; ++c) {
            std::array<Interval, 3> cb;
            for (int i = 0; i < 3; ++i) {
                cb[i] = (c >> i) & 1 ? Interval(mid[i], box[i].upper())
                                     : Interval(box[i].lower(), mid[i]);
            }
            work.push_back({static_cast<std::uint32_t>(nodes_.size()), w.depth + 1, tape});
            nodes_.push_back(Node{cb, State::Ambiguous, 0, 0, 0});
        }
    }
    stats_.nodes = nodes_.size();
    stats_.distinct_tapes = tapes_.size();
    for (const auto& t : tapes_) stats_.tape_instructions += t->size();
    stats_.bytes = nodes_.size() * sizeof(Node) +
                   stats_.tape_instructions * 2 * sizeof(expr::Instr);  // SSA + register form
}

void Octree::walk(const Ray& ray, double t0, double t1, std::vector<Segment>& out) const {
    out.clear();
    if (!(t0 <= t1)) return;
    Scratch& s = t_scratch;
    RoundingScope scope;
    s.stack.clear();
    s.stack.push_back(0);
    while (!s.stack.empty()) {
        const std::uint32_t i = s.stack.back();
        s.stack.pop_back();
        const Node& n = nodes_[i];
        if (n.state == State::Empty || n.state == State::Full) continue;
        const Interval seg = ray_box_up(ray, n.box);
        if (seg.is_empty()) continue;
        const double a = std::max(seg.lower(), t0), b = std::min(seg.upper(), t1);
        if (!(a <= b)) continue;
        if (n.state == State::Ambiguous) {
            out.push_back({i, a, b});
            continue;
        }
        // Children in order of entry: pushed last-first so the first is examined next.
        s.children.clear();
        for (std::uint32_t c = 0; c < 8; ++c) {
            const Node& k = nodes_[n.first_child + c];
            if (k.state == State::Empty || k.state == State::Full) continue;
            const Interval ks = ray_box_up(ray, k.box);
            if (ks.is_empty() || ks.upper() < t0 || ks.lower() > t1) continue;
            s.children.push_back({ks.lower(), n.first_child + c});
        }
        std::sort(s.children.begin(), s.children.end());
        for (auto it = s.children.rbegin(); it != s.children.rend(); ++it) {
            s.stack.push_back(it->second);
        }
    }
}

RayResult Octree::certified(const Ray& ray, const solvers::CertifiedOptions& options) const {
    thread_local std::vector<Segment> segments;
    RayResult result;
    result.status = Status::Miss;
    bool found = false;
    double best_lo = kInf;
    // One piece of [tmin, tmax] with the tape valid on it; returns false when the budget is out.
    // Merges an answer for [a, …] that starts before the best so far: an earlier proven zero
    // replaces it; an earlier *possible* zero in front of a proven one gives a hit enclosing both
    // (a zero is proven in [best_lo, t_hi], and nothing is possible before lo).
    bool widened = false;
    auto merge = [&](Status status, double lo, double hi) {
        if (found && result.status == Status::Hit && status == Status::Unknown) {
            result.t_lo = lo;  // Hit [lo, t_hi]
            widened = true;
        } else {
            result.status = status;
            result.t_lo = lo;
            result.t_hi = hi;
        }
        found = true;
        best_lo = lo;
    };
    // [tmin, resume) has been decided by a window across a face (face_window): pieces start there.
    double resume = -kInf;
    auto piece = [&](const expr::Tape& tape, double a, double b) {
        if (b < resume) return true;
        a = std::max(a, resume);
        if (found && !(a < best_lo)) return true;
        const double hi = found ? std::min(b, best_lo) : b;
        if (result.evals.total() >= options.budget) {  // [a, …) unexamined
            merge(Status::Unknown, a, ray.tmax);
            return false;
        }
        solvers::CertifiedOptions o = options;
        o.budget = options.budget - result.evals.total();
        const RayResult r = solvers::certified_first_root(tape, Ray{ray.o, ray.d, a, hi}, o);
        result.evals += r.evals;
        if (r.status == Status::Miss) return true;
        if (found && !(r.t_lo < best_lo)) return result.evals.total() < options.budget;
        // Undecided at an end of the piece: re-decide across the face with the full tape.
        double wlo = 0, whi = 0;
        if (result.evals.total() < options.budget && face_window(ray, a, hi, r, wlo, whi)) {
            o.budget = options.budget - result.evals.total();
            const RayResult w =
                solvers::certified_first_root(tape_, Ray{ray.o, ray.d, wlo, whi}, o);
            result.evals += w.evals;
            if (w.status == Status::Miss) {
                resume = whi;
                return result.evals.total() < options.budget;
            }
            if (w.status == Status::Hit) {
                merge(Status::Hit, std::max(w.t_lo, r.t_lo), w.t_hi);
                resume = whi;
                return result.evals.total() < options.budget;
            }
        }
        merge(r.status, r.t_lo, r.t_hi);
        return result.evals.total() < options.budget;
    };
    auto finish = [&]() {
        if (result.status == Status::Miss) {
            result.t_lo = result.t_hi = result.t = std::numeric_limits<double>::quiet_NaN();
            return result;
        }
        // A hit widened by a merge: the full tape, restricted to it, narrows it again (its first
        // zero there is the first zero of the ray: nothing is possible before t_lo).
        if (widened && result.status == Status::Hit && result.evals.total() < options.budget) {
            solvers::CertifiedOptions o = options;
            o.budget = options.budget - result.evals.total();
            const RayResult r = solvers::certified_first_root(
                tape_, Ray{ray.o, ray.d, result.t_lo, result.t_hi}, o);
            result.evals += r.evals;
            if (r.status == Status::Hit) {
                result.t_lo = r.t_lo;
                result.t_hi = r.t_hi;
            }
        }
        result.t =
            std::isfinite(result.t_hi) ? midpoint(Interval(result.t_lo, result.t_hi)) : result.t_lo;
        return result;
    };
    const Interval in = ray_box(ray, bounds_);
    if (in.is_empty() || in.upper() < ray.tmin || in.lower() > ray.tmax) {
        piece(tape_, ray.tmin, ray.tmax);
        return finish();
    }
    if (ray.tmin < in.lower() && !piece(tape_, ray.tmin, in.lower())) return finish();
    walk(ray, std::max(ray.tmin, in.lower()), std::min(ray.tmax, in.upper()), segments);
    for (const Segment& s : segments) {
        const Node& n = nodes_[s.node];
        const bool inside = segment_inside(ray, s.t0, s.t1, inflate(n.box));
        if (!piece(inside ? *tapes_[n.tape] : tape_, s.t0, s.t1)) return finish();
    }
    if (in.upper() < ray.tmax) piece(tape_, in.upper(), ray.tmax);
    return finish();
}

namespace {

/// An enclosure of g over [t0, t1] (the box o + [t0, t1]·d, rounded outward).
Interval segment_value(const expr::Tape& tape, const Ray& ray, double t0, double t1) {
    thread_local expr::Evaluator<Interval> eval;
    std::array<Interval, 3> box;
    const Interval t(t0, t1);
    for (int i = 0; i < 3; ++i) box[i] = Interval(ray.o[i]) + t * Interval(ray.d[i]);
    return eval(tape, box);
}

}  // namespace

RayResult Octree::sphere(const Ray& ray, const TraceOptions& options) const {
    thread_local std::vector<Segment> segments;
    RayResult r;
    r.status = Status::Miss;
    auto unknown = [&](double lo) {
        r.status = Status::Unknown;
        r.t_lo = r.t = lo;
        r.t_hi = ray.tmax;
        return r;
    };
    const Interval in = ray_box(ray, bounds_);
    if (in.is_empty()) return r;
    walk(ray, std::max(ray.tmin, in.lower()), std::min(ray.tmax, in.upper()), segments);
    const Deadline deadline(options.seconds);
    // What is left of the ray's budgets, for a tracer of one piece; false when nothing is.
    TraceOptions opt = options;
    auto left = [&]() {
        if (r.evals.total() >= options.budget || deadline.passed()) return false;
        opt.budget = options.budget - r.evals.total();
        opt.seconds = deadline.seconds_left();
        return true;
    };
    // Each ambiguous leaf's segment is sphere traced (tracers/sphere_trace.h) with the leaf's
    // pruned tape and λ; empty and full cells are skipped. Where that cannot go on, segment
    // tracing takes over from where it stopped.
    detail::LocalBounds local;  // carried from cell to cell along the ray
    for (const Segment& seg : segments) {
        if (!left()) return unknown(seg.t0);
        const Node& n = nodes_[seg.node];
        const bool inside = segment_inside(ray, seg.t0, seg.t1, inflate(n.box));
        const expr::Tape& tape = inside ? *tapes_[n.tape] : tape_;
        // The enclosure of g over the leaf's segment first (one interval evaluation): where it
        // excludes 0 there is no zero on the segment (where g is defined), and nothing to trace.
        r.evals.interval += 1;
        if (!possibly_zero(segment_value(tape, ray, seg.t0, seg.t1))) continue;
        if (!left()) return unknown(seg.t0);
        RayResult p;
        p.status = Status::Unknown;
        p.t_lo = seg.t0;
        if (inside && n.lambda < kInf) {
            local.useful = true;  // a new cell, a new λ
            TraceOptions cell = opt;
            cell.budget = std::min(opt.budget, kSphereStepsPerCell);
            p = detail::sphere_trace(tape, Ray{ray.o, ray.d, seg.t0, seg.t1}, n.lambda, cell,
                                     local);
            r.evals += p.evals;
        }
        // Unknown (also after kSphereStepsPerCell): no root on [t0, p.t_lo); segment tracing on the
        // rest of the leaf's segment.
        if (p.status == Status::Unknown && std::isfinite(p.t_lo) && left()) {
            p = segment_trace(tape, Ray{ray.o, ray.d, p.t_lo, seg.t1}, opt);
            r.evals += p.evals;
        }
        if (p.status == Status::Miss) continue;
        if (p.status == Status::Unknown) return unknown(p.t_lo);
        r.status = Status::Hit;
        r.t_lo = p.t_lo;
        r.t_hi = p.t_hi;
        r.t = p.t;
        return r;
    }
    return r;
}

}  // namespace certray::tracers
