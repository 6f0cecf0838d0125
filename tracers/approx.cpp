// tracers/approx.cpp — per-cell Taylor models on the octree and the ray queries over them (see
// approx.h).
#include "tracers/approx.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "expr/eval.h"
#include "interval/poly.h"
#include "interval/taylor.h"
#include "solvers/closed_form.h"

namespace certray::tracers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::uint32_t kNoSlot = std::numeric_limits<std::uint32_t>::max();

/// One bisection item of a segment, in the model's parameter.
struct Item {
    double lo, hi;
    int depth;
};

void bump(std::atomic<std::uint64_t>& c, std::uint64_t n = 1) {
    c.fetch_add(n, std::memory_order_relaxed);
}

/// A ray model's polynomial (degree ≤ 3) in upward-mode intervals, for cheap ranges: every
/// function below must run inside a live RoundingScope.
struct Cubic {
    std::array<UpInterval, 4> c;
    int degree = 0;
};

UpInterval horner_up(const Cubic& p, const UpInterval& t) {
    UpInterval r = p.c[p.degree];
    for (int k = p.degree - 1; k >= 0; --k) r = r * t + p.c[k];
    return r;
}

/// Encloses p over [lo, hi] (finite): Horner over the interval intersected with the centred form
/// Σ q_k (T − m)^k, q the coefficients shifted to m (as interval/poly.h's range()).
UpInterval range_up(const Cubic& p, double lo, double hi) {
    const UpInterval t(lo, hi);
    if (p.degree == 0) return p.c[0];
    const UpInterval direct = horner_up(p, t);
    const UpInterval m(0.5 * lo + 0.5 * hi);  // any point of [lo, hi]
    std::array<UpInterval, 4> q = p.c;
    for (int i = 0; i < p.degree; ++i)
        for (int k = p.degree - 1; k >= i; --k) q[k] = q[k] + m * q[k + 1];
    const UpInterval s = t - m;
    UpInterval centred = q[0];
    for (int k = 1; k <= p.degree; ++k) centred = centred + q[k] * pow(s, static_cast<unsigned>(k));
    return intersect(direct, centred);
}

}  // namespace

Approx::Approx(const expr::Tape& tape, const std::array<Interval, 3>& bounds,
               const ApproxOptions& options)
    : tree_(tape, bounds, options.octree), options_(options) {
    slot_of_.assign(tree_.node_count(), kNoSlot);
    for (std::uint32_t n = 0; n < tree_.node_count(); ++n)
        if (tree_.state(n) == Octree::State::Ambiguous)
            slot_of_[n] = static_cast<std::uint32_t>(slot_count_++);
    slots_ = std::make_unique<Slot[]>(slot_count_);
    built_ = std::make_unique<std::atomic<bool>[]>(slot_count_);
    for (std::size_t i = 0; i < slot_count_; ++i) built_[i].store(false);
}

void Approx::build(std::uint32_t node, CellModel& out) const {
    const std::array<Interval, 3>& box = tree_.box(node);
    const TaylorDomain<3> dom(inflate(box));
    thread_local expr::Evaluator<TaylorModel<3>> ev;
    const TaylorModel<3> m = ev(tree_.leaf_tape(node),
                                {TaylorModel<3>::variable(dom, 0), TaylorModel<3>::variable(dom, 1),
                                 TaylorModel<3>::variable(dom, 2)});
    double size = 0, root = 0;
    for (int i = 0; i < 3; ++i) {
        size = std::max(size, width(box[i]));
        root = std::max(root, width(tree_.bounds()[i]));
    }
    out.size = size;
    out.level = static_cast<std::uint8_t>(std::max(0.0, std::round(std::log2(root / size))));
    out.c = dom.c;
    // R_d = R_{d+1} + the bound over the cell of the degree-(d+1) terms: a valid degree-d model.
    std::array<Interval, 4> rd;
    rd[3] = m.r;
    {
        RoundingScope scope;
        for (int d = 2; d >= 1; --d) {
            UpInterval s(rd[d + 1]);
            for (int k = detail::taylor_terms(d); k < detail::taylor_terms(d + 1); ++k)
                if (m.a[k] != 0) s = s + UpInterval(m.a[k]) * dom.bound[k];
            rd[d] = Interval(s);
            rd[d].defined = rd[d + 1].defined && !rd[d].is_empty();
        }
    }
    const double slope = std::hypot(m.a[1], m.a[2], m.a[3]);
    int degree = 3;
    for (int d = 1; d <= 2; ++d)
        if (width(rd[d]) <= options_.tolerance * size * slope) {
            degree = d;
            break;
        }
    out.degree = static_cast<std::uint8_t>(degree);
    out.r = rd[degree];
    for (int k = 0; k < detail::taylor_terms(degree); ++k) out.a[k] = m.a[k];
}

const CellModel& Approx::model(std::uint32_t node) const {
    const std::uint32_t s = slot_of_[node];
    Slot& slot = slots_[s];
    std::call_once(slot.once, [&] {
        build(node, slot.model);
        built_[s].store(true, std::memory_order_release);
        bump(models_built_);
        bump(by_degree_[slot.model.degree]);
    });
    return slot.model;
}

void Approx::build_all() const {
    for (std::uint32_t n = 0; n < slot_of_.size(); ++n)
        if (slot_of_[n] != kNoSlot) model(n);
}

std::vector<std::pair<std::uint32_t, const CellModel*>> Approx::built_models() const {
    std::vector<std::pair<std::uint32_t, const CellModel*>> out;
    for (std::uint32_t n = 0; n < slot_of_.size(); ++n)
        if (slot_of_[n] != kNoSlot && built_[slot_of_[n]].load(std::memory_order_acquire))
            out.emplace_back(n, &slots_[slot_of_[n]].model);
    return out;
}

ApproxStats Approx::stats() const {
    ApproxStats s;
    s.segments = segments_.load();
    s.excluded = excluded_.load();
    s.proven = proven_.load();
    s.fallback = fallback_.load();
    s.full_tape = full_tape_.load();
    s.model_ranges = model_ranges_.load();
    s.models_built = models_built_.load();
    for (int d = 0; d < 4; ++d) s.by_degree[d] = by_degree_[d].load();
    s.model_bytes = slot_count_ * (sizeof(Slot) + sizeof(std::atomic<bool>)) +
                    slot_of_.size() * sizeof(std::uint32_t);
    return s;
}

RayResult Approx::certified(const Ray& ray, const solvers::CertifiedOptions& options) const {
    thread_local std::vector<Octree::Segment> segments;
    RayResult result;
    result.status = Status::Miss;
    bool found = false;
    double best_lo = kInf;
    auto out_of_budget = [&](double a) {
        if (result.evals.total() < options.budget) return false;
        result.status = Status::Unknown;
        result.t_lo = a;
        result.t_hi = ray.tmax;
        result.t = a;
        return true;
    };
    // [tmin, resume) has been decided by a window across a face (face_window, tracers/octree.h):
    // pieces and candidates start there.
    double resume = -kInf;
    auto take = [&](Status status, double lo, double hi) {
        found = true;
        best_lo = lo;
        result.status = status;
        result.t_lo = lo;
        result.t_hi = hi;
        result.t = std::isfinite(hi) ? midpoint(Interval(lo, hi)) : lo;
    };
    // The certified solver on [a, b] with `tape` (valid there); false: stop the ray.
    auto solve = [&](const expr::Tape& tape, double a, double b) {
        if (b < resume) return true;
        a = std::max(a, resume);
        if (found && !(a < best_lo)) return true;
        const double hi = found ? std::min(b, best_lo) : b;
        if (out_of_budget(a)) return false;
        solvers::CertifiedOptions o = options;
        o.budget = options.budget - result.evals.total();
        const RayResult r = solvers::certified_first_root(tape, Ray{ray.o, ray.d, a, hi}, o);
        result.evals += r.evals;
        if (r.status == Status::Miss) return true;
        if (found && !(r.t_lo < best_lo)) {
            return r.status == Status::Hit || result.evals.total() < options.budget;
        }
        // Undecided at an end of the piece (a cell face, or a split point of the model's
        // bisection): re-decide across it with the full tape.
        double wlo = 0, whi = 0;
        if (result.evals.total() < options.budget && face_window(ray, a, hi, r, wlo, whi)) {
            o.budget = options.budget - result.evals.total();
            const RayResult w =
                solvers::certified_first_root(tree_.tape(), Ray{ray.o, ray.d, wlo, whi}, o);
            result.evals += w.evals;
            if (w.status == Status::Miss) {
                resume = whi;
                return result.evals.total() < options.budget;
            }
            if (w.status == Status::Hit) {
                take(Status::Hit, std::max(w.t_lo, r.t_lo), w.t_hi);
                resume = whi;
                return true;
            }
        }
        take(r.status, r.t_lo, r.t_hi);
        result.t = r.t;
        return r.status == Status::Hit || result.evals.total() < options.budget;
    };
    auto full = [&](double a, double b) {
        bump(full_tape_);
        return solve(tree_.tape(), a, b);
    };
    // One leaf segment with the cell's model; false: stop the ray.
    auto leaf = [&](std::uint32_t node, double a, double b) {
        if (b < resume) return true;
        a = std::max(a, resume);
        if (found && !(a < best_lo)) return true;
        const double hi = found ? std::min(b, best_lo) : b;
        if (out_of_budget(a)) return false;
        bump(segments_);
        const CellModel& cm = model(node);
        ++result.evals.interval;
        RayModel rm =
            compose_ray(cm.a.data(), cm.degree, cm.c, cm.r, ray.o, ray.d, Interval(a, hi));
        const double rw = width(rm.r);
        Cubic cub;
        cub.degree = rm.p.degree;
        for (int k = 0; k <= cub.degree; ++k) cub.c[k] = UpInterval(rm.p.c[k]);
        const UpInterval r_up(rm.r);
        Item stack[64];
        int n = 0;
        stack[n++] = {a, hi, 0};
        bool candidate = false;
        std::uint64_t ranges = 0;
        bool go_on = true;
        while (n > 0 && go_on) {
            Item it = stack[--n];
            if (found && !(it.lo < best_lo)) break;
            if (it.hi < resume) continue;  // decided across a face
            it.lo = std::max(it.lo, resume);
            double pr_width;
            bool excluded;
            {
                RoundingScope scope;
                const UpInterval pr = range_up(cub, it.lo, it.hi);
                const UpInterval enc = pr + r_up;
                excluded = enc.is_empty() || !possibly_zero(enc);
                pr_width = width(pr);
            }
            ++ranges;
            if (excluded) continue;  // 0 ∉ p(T) + r ⊇ g(T): no zero of f on this part
            const double mid = 0.5 * it.lo + 0.5 * it.hi;
            if (it.depth < options_.max_split_depth && pr_width > 2 * rw && mid > it.lo &&
                mid < it.hi && n + 2 <= 64) {
                stack[n++] = {mid, it.hi, it.depth + 1};
                stack[n++] = {it.lo, mid, it.depth + 1};
                continue;
            }
            candidate = true;
            bool sign_change;
            {
                RoundingScope scope;
                const UpInterval vl = horner_up(cub, UpInterval(it.lo)) + r_up;
                const UpInterval vh = horner_up(cub, UpInterval(it.hi)) + r_up;
                sign_change = rm.r.defined && ((vl.lower() > 0 && vh.upper() < 0) ||
                                               (vl.upper() < 0 && vh.lower() > 0));
            }
            bump(sign_change ? proven_ : fallback_);
            go_on = solve(tree_.leaf_tape(node), it.lo, it.hi);
            if (found && result.status == Status::Hit) break;
        }
        bump(model_ranges_, ranges);
        if (!candidate) bump(excluded_);
        return go_on && !(found && result.status == Status::Hit);
    };
    auto finish = [&]() {
        if (result.status == Status::Miss)
            result.t_lo = result.t_hi = result.t = std::numeric_limits<double>::quiet_NaN();
        return result;
    };
    const Interval in = ray_box(ray, tree_.bounds());
    if (in.is_empty() || in.upper() < ray.tmin || in.lower() > ray.tmax) {
        full(ray.tmin, ray.tmax);
        return finish();
    }
    if (ray.tmin < in.lower() && !full(ray.tmin, in.lower())) return finish();
    tree_.walk(ray, std::max(ray.tmin, in.lower()), std::min(ray.tmax, in.upper()), segments);
    for (const Octree::Segment& s : segments) {
        const bool inside = segment_inside(ray, s.t0, s.t1, inflate(tree_.box(s.node)));
        if (!(inside ? leaf(s.node, s.t0, s.t1) : full(s.t0, s.t1))) return finish();
    }
    if (in.upper() < ray.tmax) full(in.upper(), ray.tmax);
    return finish();
}

RayResult Approx::plain(const Ray& ray) const {
    thread_local std::vector<Octree::Segment> segments;
    RayResult r;
    r.status = Status::Miss;
    const Interval in = ray_box(ray, tree_.bounds());
    if (in.is_empty() || in.upper() < ray.tmin || in.lower() > ray.tmax) return r;
    tree_.walk(ray, std::max(ray.tmin, in.lower()), std::min(ray.tmax, in.upper()), segments);
    for (const Octree::Segment& s : segments) {
        const CellModel& cm = model(s.node);
        ++r.evals.interval;
        // In the local parameter τ = t − t0 (better conditioned): origin o + t0·d, rounded.
        const std::array<double, 3> o{ray.o[0] + s.t0 * ray.d[0], ray.o[1] + s.t0 * ray.d[1],
                                      ray.o[2] + s.t0 * ray.d[2]};
        const double len = s.t1 - s.t0;
        const RayModel rm =
            compose_ray(cm.a.data(), cm.degree, cm.c, Interval(0.0), o, ray.d, Interval(0.0, len));
        std::array<double, 4> m{};
        for (int k = 0; k <= 3; ++k) m[k] = k <= rm.p.degree ? midpoint(rm.p.c[k]) : 0.0;
        double roots[3];
        bool all_zero = false;
        const int count = solvers::solve_cubic(m[3], m[2], m[1], m[0], roots, &all_zero);
        double hit = kInf;
        if (all_zero) hit = 0;
        for (int i = 0; i < count && hit == kInf; ++i)
            if (roots[i] >= 0 && roots[i] <= len) hit = roots[i];
        if (hit < kInf) {
            r.status = Status::Hit;
            r.t = r.t_lo = r.t_hi = s.t0 + hit;
            return r;
        }
    }
    return r;
}

}  // namespace certray::tracers
