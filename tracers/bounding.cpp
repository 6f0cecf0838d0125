// tracers/bounding.cpp — bounding volumes over the CSG structure of f (see bounding.h).
#include "tracers/bounding.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "expr/derived.h"
#include "expr/eval.h"
#include "solvers/certified.h"
#include "tracers/octree.h"
#include "tracers/sphere_trace.h"

namespace certray::tracers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using Box = BoundedScene::Box;

/// Leaves longer than this many instructions get region-pruned tapes (a short leaf, a sphere or
/// a box, gains nothing worth a lookup).
constexpr std::size_t kRegionTapesAbove = 256;

/// The tape of the subexpression `root` of g alone (its nodes copied into a fresh graph).
expr::Tape sub_tape(const expr::Graph& g, expr::NodeId root) {
    expr::Graph out;
    out.set_output(out.copy(g, root, {out.var(0), out.var(1), out.var(2)}));
    return expr::Tape(out);
}

/// The graph of a tape's SSA form (the CSG structure is read from it).
expr::Graph graph_of(const expr::Tape& tape) {
    expr::Graph g;
    std::vector<expr::NodeId> id(tape.ssa().size());
    for (std::size_t i = 0; i < tape.ssa().size(); ++i) {
        const expr::Instr& in = tape.ssa()[i];
        const int arity = expr::arity(in.op);
        id[i] = g.add(in.op, arity >= 1 ? id[in.a] : expr::NodeId{},
                      arity == 2 ? id[in.b] : expr::NodeId{}, in.imm, in.b);
    }
    if (!id.empty()) g.set_output(id.back());
    return g;
}

/// Encloses the solid {f ≤ 0} (and wherever f may be undefined) inside `bounds` by a box, by
/// slab contraction: for each side of the box in turn, the thickest slab on which interval
/// evaluation proves f > 0 is cut off (bisection on its thickness; a thinner slab of a proven one
/// is proven too). Slabs shrink with the box, so later rounds are tighter. Sound for any f; tight
/// for sums of squares and their roots (a primitive's box up to 2⁻ⁱᵗᵉʳˢ of the current side).
void solid_box(const expr::Tape& tape, const Box& bounds, const BoundingOptions& o,
               std::array<double, 3>& lo, std::array<double, 3>& hi) {
    thread_local expr::Evaluator<Interval> eval;
    for (int i = 0; i < 3; ++i) {
        lo[i] = bounds[i].lower();
        hi[i] = bounds[i].upper();
    }
    auto positive_on = [&](int axis, double a, double b) {
        Box box;
        for (int i = 0; i < 3; ++i) box[i] = Interval(lo[i], hi[i]);
        box[axis] = Interval(a, b);
        const Interval v = eval(tape, box);
        return v.defined && !v.is_empty() && v.lower() > 0;
    };
    for (int round = 0; round < o.slab_rounds; ++round) {
        for (int axis = 0; axis < 3; ++axis) {
            if (positive_on(axis, lo[axis], hi[axis])) {  // no solid at all in the box
                lo.fill(kInf);
                hi.fill(-kInf);
                return;
            }
            // From below: the largest proven s with f > 0 on [lo, s]; the box keeps [s, hi].
            double keep = lo[axis], cut = hi[axis];  // proven-free up to keep; cut not proven
            for (int it = 0; it < o.slab_steps; ++it) {
                const double mid = 0.5 * keep + 0.5 * cut;
                if (!(mid > keep && mid < cut)) break;
                (positive_on(axis, lo[axis], mid) ? keep : cut) = mid;
            }
            lo[axis] = keep;
            // From above, symmetrically.
            keep = hi[axis];
            cut = lo[axis];
            for (int it = 0; it < o.slab_steps; ++it) {
                const double mid = 0.5 * keep + 0.5 * cut;
                if (!(mid < keep && mid > cut)) break;
                (positive_on(axis, mid, hi[axis]) ? keep : cut) = mid;
            }
            hi[axis] = keep;
        }
    }
}

}  // namespace

BoundedScene::BoundedScene(const expr::Tape& tape, const Box& bounds,
                           const BoundingOptions& options)
    : bounds_(bounds), tape_(tape), options_(options) {
    const auto start = std::chrono::steady_clock::now();
    double diag2 = 0;
    for (const Interval& b : bounds) {
        if (b.is_empty() || !std::isfinite(b.lower()) || !std::isfinite(b.upper())) {
            throw std::invalid_argument(
                "bounding volumes: the bounds must be finite and non-empty");
        }
        diag2 += (b.upper() - b.lower()) * (b.upper() - b.lower());
    }
    margin_ = options.margin * std::sqrt(diag2);
    const expr::Graph graph = graph_of(tape);
    if (!graph.output().valid()) throw std::invalid_argument("bounding volumes: empty tape");
    root_ = build(graph, graph.output(), 0);
    // A long leaf (a sum of many blobs, a primitive under a long expression) is evaluated on the
    // tape of the query box's region: the same function there, often far shorter. Built once
    // the leaves are in place (a RegionTapes refers to its leaf's tape).
    for (Leaf& l : leaves_) {
        if (l.tape.size() > kRegionTapesAbove) {
            l.regions = std::make_shared<const RegionTapes>(l.tape, bounds_);
        }
    }
    // f itself as its only leaf (a smooth union is not a min): the leaf's cells serve f's queries
    // too, built and stored once.
    auto same = [](const expr::Tape& a, const expr::Tape& b) {
        if (a.size() != b.size()) return false;
        for (std::size_t i = 0; i < a.size(); ++i) {
            const expr::Instr &x = a.ssa()[i], &y = b.ssa()[i];
            if (x.op != y.op || x.a != y.a || x.b != y.b ||
                std::bit_cast<std::uint64_t>(x.imm) != std::bit_cast<std::uint64_t>(y.imm)) {
                return false;
            }
        }
        return true;
    };
    if (leaves_.size() == 1 && leaves_[0].regions && same(leaves_[0].tape, tape_)) {
        regions_ = leaves_[0].regions;
    } else if (tape_.size() > kRegionTapesAbove) {
        regions_ = std::make_shared<const RegionTapes>(tape_, bounds_);
    }
    build_seconds_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::uint32_t BoundedScene::add(Node n) {
    nodes_.push_back(n);
    return static_cast<std::uint32_t>(nodes_.size() - 1);
}

std::uint32_t BoundedScene::build(const expr::Graph& g, expr::NodeId id, int nesting) {
    const expr::Node& n = g.node(id);
    if (nesting < options_.max_nesting) {
        if (n.op == expr::Op::Min || n.op == expr::Op::Max) return cluster(g, id, nesting);
        if (n.op == expr::Op::Neg) {
            const std::uint32_t child = build(g, n.a, nesting + 1);
            Node neg{Kind::Neg, {}, {}, child, 0};
            for (int i = 0; i < 3; ++i) {  // the complement's solid: anywhere in the bounds
                neg.lo[i] = bounds_[i].lower();
                neg.hi[i] = bounds_[i].upper();
            }
            return add(neg);
        }
    }
    return leaf(g, id);
}

std::uint32_t BoundedScene::cluster(const expr::Graph& g, expr::NodeId id, int nesting) {
    const expr::Op op = g.node(id).op;
    std::vector<std::uint32_t> parts;
    std::vector<expr::NodeId> stack{id};
    while (!stack.empty()) {
        const expr::NodeId k = stack.back();
        stack.pop_back();
        const expr::Node& n = g.node(k);
        if (n.op == op) {
            stack.push_back(n.b);
            stack.push_back(n.a);
        } else {
            parts.push_back(build(g, k, nesting + 1));
        }
    }
    return balance(parts, 0, parts.size(), op == expr::Op::Min ? Kind::Min : Kind::Max);
}

std::uint32_t BoundedScene::balance(std::vector<std::uint32_t>& parts, std::size_t lo,
                                    std::size_t hi, Kind kind) {
    if (hi - lo == 1) return parts[lo];
    // Split at the median of the box centres along the axis where they spread most.
    std::array<double, 3> cmin, cmax;
    cmin.fill(kInf);
    cmax.fill(-kInf);
    auto centre = [&](std::uint32_t k, int i) {
        const Node& n = nodes_[k];
        return n.lo[i] <= n.hi[i] ? 0.5 * n.lo[i] + 0.5 * n.hi[i] : 0.0;
    };
    for (std::size_t k = lo; k < hi; ++k) {
        for (int i = 0; i < 3; ++i) {
            cmin[i] = std::min(cmin[i], centre(parts[k], i));
            cmax[i] = std::max(cmax[i], centre(parts[k], i));
        }
    }
    int axis = 0;
    for (int i = 1; i < 3; ++i) {
        if (cmax[i] - cmin[i] > cmax[axis] - cmin[axis]) axis = i;
    }
    const std::size_t mid = lo + (hi - lo) / 2;
    std::nth_element(
        parts.begin() + static_cast<std::ptrdiff_t>(lo),
        parts.begin() + static_cast<std::ptrdiff_t>(mid),
        parts.begin() + static_cast<std::ptrdiff_t>(hi),
        [&](std::uint32_t a, std::uint32_t b) { return centre(a, axis) < centre(b, axis); });
    const std::uint32_t left = balance(parts, lo, mid, kind);
    const std::uint32_t right = balance(parts, mid, hi, kind);
    Node n{kind, {}, {}, left, right};
    const Node &a = nodes_[left], &b = nodes_[right];
    for (int i = 0; i < 3; ++i) {
        // Union: the hull of the solids' boxes; intersection: their intersection. An empty box
        // (lo > hi) is absorbed by the hull and absorbs the intersection.
        n.lo[i] = kind == Kind::Min ? std::min(a.lo[i], b.lo[i]) : std::max(a.lo[i], b.lo[i]);
        n.hi[i] = kind == Kind::Min ? std::max(a.hi[i], b.hi[i]) : std::min(a.hi[i], b.hi[i]);
    }
    return add(n);
}

std::uint32_t BoundedScene::leaf(const expr::Graph& g, expr::NodeId id) {
    Leaf l{sub_tape(g, id), kInf, nullptr};
    Node n{Kind::Leaf, {}, {}, static_cast<std::uint32_t>(leaves_.size()), 0};
    solid_box(l.tape, bounds_, options_, n.lo, n.hi);
    if (!n.empty()) {
        // λ over the box inflated by the margin: every point where the leaf is evaluated, and
        // the segment from it to its nearest surface point in the bounds, lie there.
        Box region;
        for (int i = 0; i < 3; ++i) {
            region[i] = Interval((Interval(n.lo[i]) - Interval(margin_)).lower(),
                                 (Interval(n.hi[i]) + Interval(margin_)).upper());
        }
        l.lambda = expr::lipschitz_bound(l.tape, region);
    }
    leaves_.push_back(std::move(l));
    return add(n);
}

double BoundedScene::box_distance(const Node& n, const Box& p) const {
    if (n.empty()) return kInf;
    // In round-to-nearest: the gaps (one rounding each), their squares, the sum and the root
    // carry a relative error below 6·2⁻⁵³ (squares that underflow only lower the result), so
    // scaling by 1 − 10⁻¹⁵ rounds the distance down; an overflow falls back to the largest gap.
    double sum = 0, largest = 0;
    for (int i = 0; i < 3; ++i) {
        double gap = 0;
        if (p[i].lower() > n.hi[i]) gap = p[i].lower() - n.hi[i];
        if (p[i].upper() < n.lo[i]) gap = n.lo[i] - p[i].upper();
        sum += gap * gap;
        largest = std::max(largest, gap);
    }
    const double d = std::sqrt(sum);
    return (std::isfinite(d) ? d : largest) * (1 - 1e-15);
}

namespace {

/// The distance bound of a node known to be outside its box by `db` > 0: the larger of the two.
Interval floor_at(const Interval& d, double db) {
    if (!(db > 0) || d.is_empty() || !d.defined) return d;
    return Interval(std::max(d.lower(), db), std::max(d.upper(), db));
}

Interval unknown_distance() {
    Interval r = Interval::entire();
    r.defined = false;
    return r;
}

}  // namespace

Interval BoundedScene::leaf_distance(const Leaf& l, const Box& p, double db, double rho,
                                     std::uint64_t& leaf_evals, LocalTries* tries) const {
    thread_local expr::Evaluator<Interval> eval;
    const Interval v = eval(l.regions ? l.regions->at(p) : l.tape, p);
    ++leaf_evals;
    if (!detail::usable(v)) return unknown_distance();
    Interval d =
        l.lambda < kInf ? floor_at(detail::distance_bound(v, l.lambda), db) : unknown_distance();
    const bool refine = !tries || tries->refine || !detail::usable(d);
    if (rho > 0 && refine && (!detail::usable(d) || detail::mignitude(d) < rho / 2) &&
        !contains(v, 0.0)) {
        unsigned slot = 0;
        if (tries) {
            const auto id = static_cast<std::uint32_t>(&l - leaves_.data());
            while (slot < tries->leaf.size() && tries->leaf[slot] != id) ++slot;
            if (slot == tries->leaf.size()) {
                slot = tries->next++ % tries->leaf.size();
                tries->leaf[slot] = id;
                tries->boxes[slot].valid = false;
                tries->probed[slot] = tries->tight[slot] = false;
            }
        }
        if (tries && tries->tight[slot]) return d;
        if (l.lambda < kInf && !(tries && tries->probed[slot])) {
            // A local λ over a box holding p is at least ‖∇f(p)‖: where that is ≥ λ/4 none can
            // beat the leaf's by 4×, and a smaller gain does not pay for a bound over a box (on
            // Lipschitz-Pruning's test scene, λ = 2.2 against ‖∇f‖ = 1: 0.80 → 0.62 s at 512²;
            // elsewhere within 7%). Probed once a ray and leaf (a gradient at a point costs a
            // tenth of a bound over a box on a long leaf); where it shows the leaf's λ tight, no
            // local bound is tried on that leaf for the rest of the ray.
            ++leaf_evals;
            const bool tight = 4 * detail::gradient_norm(l.regions ? l.regions->at(p) : l.tape,
                                                         detail::midpoint(p)) >=
                               l.lambda;
            if (tries) {
                tries->probed[slot] = true;
                tries->tight[slot] = tight;
            }
            if (tight) {
                if (tries) ++tries->tried;
                return d;
            }
        }
        Interval near;
        if (tries) {
            bool evaluated = false;
            near = detail::local_distance_bound(l.tape, p, v, rho, l.regions.get(), bounds_,
                                                tries->boxes[slot], evaluated);
            leaf_evals += evaluated;
        } else {
            ++leaf_evals;
            near = detail::local_distance_bound(l.tape, p, v, rho, l.regions.get(), &bounds_);
        }
        const double from_box = detail::usable(d) ? detail::mignitude(d) : 0.0;
        const bool usable = detail::usable(near);
        if (usable && (!detail::usable(d) || detail::mignitude(near) > from_box)) d = near;
        if (tries) {
            ++tries->tried;
            tries->won += usable && detail::mignitude(near) >= 2 * from_box;
        }
    }
    return d;
}

Interval BoundedScene::distance(const Box& p, std::uint64_t& leaf_evals, double rho,
                                LocalTries* tries) const {
    // Recursion depth: the CSG nesting (≤ max_nesting) times the BVH depth (log₂ of a cluster).
    // `best` is an upper bound of the union being computed by the callers (+inf elsewhere): a
    // node outside its box (db > 0) has a bound ≥ db, so with db ≥ best it cannot lower the
    // union and its box distance stands in for it (nearest-neighbour pruning).
    auto visit = [&](auto& self, std::uint32_t k, double best) -> Interval {
        const Node& n = nodes_[k];
        const double db = box_distance(n, p);
        if (db > margin_ || (db > 0 && db >= best)) return Interval(db);
        switch (n.kind) {
            case Kind::Leaf:
                return leaf_distance(leaves_[n.a], p, db, rho, leaf_evals, tries);
            case Kind::Neg:
                return -self(self, n.a, kInf);
            case Kind::Min: {
                // The nearer box first; its result bounds what the other may contribute.
                std::uint32_t first = n.a, second = n.b;
                if (box_distance(nodes_[first], p) > box_distance(nodes_[second], p)) {
                    std::swap(first, second);
                }
                const Interval d1 = self(self, first, best);
                const double b2 = d1.defined && !d1.is_empty() ? std::min(best, d1.upper()) : best;
                return floor_at(min(d1, self(self, second, b2)), db);
            }
            case Kind::Max:
                // Both operands: a certainly positive one alone would be a valid bound, but a
                // loose one (the face of a box carved away by the other operand) would stop the
                // tracer far from the surface.
                return floor_at(max(self(self, n.a, kInf), self(self, n.b, kInf)), db);
        }
        return unknown_distance();
    };
    return visit(visit, root_, kInf);
}

BoundedScene::Restricted BoundedScene::restrict_to(const Ray& ray) const {
    thread_local std::vector<expr::Instr> ssa;
    ssa.clear();
    Restricted out;
    // A node's restriction: +1 / −1 (constant sign on the segment) or 0 with the SSA index of its
    // value. Recursion depth as in distance().
    struct Part {
        int sign;
        std::uint32_t at;
    };
    auto emit = [&](expr::Op op, std::uint32_t a, std::uint32_t b) {
        const auto i = static_cast<std::uint32_t>(ssa.size());
        ssa.push_back(expr::Instr{op, i, a, b, 0.0});
        return i;
    };
    auto visit = [&](auto& self, std::uint32_t k) -> Part {
        const Node& n = nodes_[k];
        Interval hit = Interval::empty();
        if (!n.empty()) {
            hit = ray_box(ray, {Interval(n.lo[0], n.hi[0]), Interval(n.lo[1], n.hi[1]),
                                Interval(n.lo[2], n.hi[2])});
        }
        if (hit.is_empty() || hit.upper() < ray.tmin || hit.lower() > ray.tmax) {
            return {+1, 0};  // the solid's box is missed: f > 0 on the whole segment
        }
        switch (n.kind) {
            case Kind::Leaf: {
                const std::vector<expr::Instr>& leaf = leaves_[n.a].tape.ssa();
                const auto offset = static_cast<std::uint32_t>(ssa.size());
                for (expr::Instr in : leaf) {
                    const int arity = expr::arity(in.op);
                    if (arity >= 1) in.a += offset;
                    if (arity == 2) in.b += offset;
                    in.out += offset;
                    ssa.push_back(in);
                }
                ++out.leaves;
                return {0, static_cast<std::uint32_t>(ssa.size() - 1)};
            }
            case Kind::Neg: {
                const Part c = self(self, n.a);
                if (c.sign != 0) return {-c.sign, 0};
                return {0, emit(expr::Op::Neg, c.at, 0)};
            }
            case Kind::Min:
            case Kind::Max: {
                // min: a positive operand drops out, a negative one decides; max: the reverse.
                const int absorbing = n.kind == Kind::Min ? -1 : +1;
                const Part a = self(self, n.a);
                if (a.sign == absorbing) return a;
                const Part b = self(self, n.b);
                if (b.sign == absorbing) return b;
                if (a.sign != 0) return b;
                if (b.sign != 0) return a;
                return {0, emit(n.kind == Kind::Min ? expr::Op::Min : expr::Op::Max, a.at, b.at)};
            }
        }
        return {+1, 0};
    };
    const Part root = visit(visit, root_);
    out.sign = root.sign;
    if (root.sign == 0) {
        // Keep what the root's value depends on (an operand absorbed by a constant sign may have
        // emitted instructions first); renumbered, the root comes last.
        thread_local std::vector<bool> live;
        thread_local std::vector<std::uint32_t> renamed;
        live.assign(root.at + 1, false);
        live[root.at] = true;
        for (std::uint32_t j = root.at + 1; j-- > 0;) {
            if (!live[j]) continue;
            const int arity = expr::arity(ssa[j].op);
            if (arity >= 1) live[ssa[j].a] = true;
            if (arity == 2) live[ssa[j].b] = true;
        }
        renamed.assign(root.at + 1, 0);
        std::vector<expr::Instr> kept;  // moved into the tape
        for (std::uint32_t j = 0; j <= root.at; ++j) {
            if (!live[j]) continue;
            expr::Instr in = ssa[j];
            const int arity = expr::arity(in.op);
            if (arity >= 1) in.a = renamed[in.a];
            if (arity == 2) in.b = renamed[in.b];
            in.out = renamed[j] = static_cast<std::uint32_t>(kept.size());
            kept.push_back(in);
        }
        out.tape = expr::Tape::from_ssa(std::move(kept));
    }
    return out;
}

RayResult trace_in_parts(const Ray& r, const std::array<Interval, 3>& bounds, std::uint64_t budget,
                         const SegmentTracer& inside, const SegmentTracer& outside) {
    const Interval in = ray_box(r, bounds);
    RayResult out;
    out.status = Status::Miss;
    EvalCounts used;
    auto part = [&](double lo, double hi, bool within) {
        if (!(within ? lo <= hi : lo < hi) || out.status != Status::Miss) return;
        Ray seg = r;
        seg.tmin = lo;
        seg.tmax = hi;
        const std::uint64_t left = budget > used.total() ? budget - used.total() : 0;
        out = within ? inside(seg, left) : outside(seg, left);
        used += out.evals;
        if (out.status == Status::Unknown) out.t_hi = r.tmax;
    };
    if (in.is_empty() || in.upper() < r.tmin || in.lower() > r.tmax) {
        part(r.tmin, r.tmax, false);
    } else {
        part(r.tmin, in.lower(), false);
        part(std::max(r.tmin, in.lower()), std::min(r.tmax, in.upper()), true);
        part(in.upper(), r.tmax, false);
    }
    out.evals = used;
    return out;
}

RayResult bounded_certified(const BoundedScene& scene, const Ray& r, std::uint64_t budget) {
    auto certified = [](const expr::Tape& tape, const Ray& seg, std::uint64_t left) {
        solvers::CertifiedOptions opt;
        opt.budget = left;
        return solvers::certified_first_root(tape, seg, opt);
    };
    return trace_in_parts(
        r, scene.bounds(), budget,
        [&](const Ray& seg, std::uint64_t left) {
            const BoundedScene::Restricted f = scene.restrict_to(seg);
            if (f.sign == 0) return certified(f.tape, seg, left);
            RayResult miss;  // f has one sign on the whole segment
            miss.status = Status::Miss;
            return miss;
        },
        [&](const Ray& seg, std::uint64_t left) { return certified(scene.tape(), seg, left); });
}

RayResult bounded_sphere_trace(const BoundedScene& scene, const Ray& r, const TraceOptions& opt) {
    Ray ray = r;
    RayResult miss;
    miss.status = Status::Miss;
    const Interval in = ray_box(ray, scene.bounds());
    if (in.is_empty()) return miss;
    ray.tmin = std::max(ray.tmin, in.lower());
    ray.tmax = std::min(ray.tmax, in.upper());
    if (!(ray.tmin <= ray.tmax)) return miss;
    std::uint64_t leaf_evals = 0;
    // ρ of the first point: the margin (a local bound is tried wherever the box's λ gives less
    // than half of it); then twice the previous bound.
    double previous = scene.margin() / 2;
    // As sphere tracing does (sphere_trace.cpp): once the local bounds of a step have not beaten
    // the boxes' λ by 2×, they are tried again only where the bound has shrunk 16× since (ρ = 16 ×
    // the bound) or fallen below epsilon; where they win again, refining resumes.
    BoundedScene::LocalTries tries;
    double retry_below = 0;
    auto distance = [&](double t, EvalCounts&) {
        const Box p = detail::point_box(ray, t);
        const bool retry = !tries.refine && (previous < retry_below || previous < opt.epsilon);
        const double rho = tries.refine || !retry ? std::max(16 * opt.epsilon, 2 * previous)
                                                  : std::max(16 * opt.epsilon, 16 * previous);
        const bool refine = tries.refine;
        tries.refine = refine || retry;
        tries.tried = tries.won = 0;
        const Interval d = scene.distance(p, leaf_evals, rho, &tries);
        if (tries.tried > 0) {
            tries.refine = tries.won > 0;
            if (!tries.refine) retry_below = previous / 16;
        } else {
            tries.refine = refine;
        }
        if (d.defined && !d.is_empty()) previous = detail::mignitude(d);
        return d;
    };
    // The hit's sanity check on the tape restricted to the leaves this segment meets (built once,
    // on the first candidate hit): near its zeros it is f (same zeros and sign along the segment).
    // A long f (region_tapes()) is checked on the tape of the point's region instead: f itself
    // there, with no tape built per ray (particles: restrict_to copied 16,009 instructions).
    std::optional<BoundedScene::Restricted> restricted;
    auto estimate = [&](double t, EvalCounts& evals) {
        if (const RegionTapes* regions = scene.region_tapes()) {
            ++evals.gradient;
            return detail::first_order_distance(regions->at(detail::point_box(ray, t)), ray, t);
        }
        if (!restricted) restricted = scene.restrict_to(ray);
        if (restricted->sign != 0) return kInf;  // f has one sign on the whole segment
        ++evals.gradient;
        return detail::first_order_distance(restricted->tape, ray, t);
    };
    return detail::trace_distance(distance, estimate, scene.tape(), ray, opt, 0.0);
}

}  // namespace certray::tracers
