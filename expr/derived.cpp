// expr/derived.cpp — Lipschitz bounds from the interval gradient and root forms.
#include "expr/derived.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "interval/grad_bound.h"

namespace certray::expr {

// One evaluator per thread, so that the per-region queries of tracers allocate nothing.
Dual<double, 3> gradient(const Tape& tape, const std::array<double, 3>& p) {
    using D = Dual<double, 3>;
    thread_local Evaluator<D> e;
    return e(tape, {D::variable(p[0], 0), D::variable(p[1], 1), D::variable(p[2], 2)});
}

Dual<Interval, 3> interval_gradient(const Tape& tape, const std::array<Interval, 3>& box) {
    using D = Dual<Interval, 3>;
    thread_local Evaluator<D> e;
    return e(tape, {D::variable(box[0], 0), D::variable(box[1], 1), D::variable(box[2], 2)});
}

double norm_bound(const std::array<Interval, 3>& grad) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::array<double, 3> mag{};
    double m = 0;
    for (int i = 0; i < 3; ++i) {
        const Interval& g = grad[i];
        if (g.is_empty() || !g.defined) return kInf;
        mag[i] = std::max(std::fabs(g.lower()), std::fabs(g.upper()));
        if (!std::isfinite(mag[i])) return kInf;
        m = std::max(m, mag[i]);
    }
    if (m == 0) return 0;
    if (m > 0x1p-400 && m < 0x1p400) {
        // No square can overflow, and any that underflows is below 2⁻⁸⁰⁰·m²: rounding everything
        // upward in one scope bounds the norm directly (the common case, no rescaling).
        RoundingScope scope;
        const double sum = mag[0] * mag[0] + mag[1] * mag[1] + mag[2] * mag[2];
        return std::sqrt(sum);
    }
    // ‖g‖ = 2^e ‖g / 2^e‖ with 2^e near the largest component, so that the squares neither
    // underflow (a gradient of 1e-300 would otherwise give a bound of 1e-162) nor overflow.
    const int e = std::ilogb(m);
    Interval sum(0.0);
    for (double g : mag) {
        Interval x(g);
        // 2^-e in at most two exact factors (2^1074 alone would overflow).
        for (int k = -e; k != 0;) {
            const int step = std::clamp(k, -1000, 1000);
            x = x * Interval(std::ldexp(1.0, step));
            k -= step;
        }
        sum = sum + square(x);
    }
    return (sqrt(sum) * Interval(std::ldexp(1.0, e))).upper();
}

namespace {

/// The instructions of an SSA list by the slot they write.
class BySlot {
  public:
    explicit BySlot(const std::vector<Instr>& ssa) : ssa_(ssa) {
        thread_local std::vector<std::uint32_t> index;
        index.assign(ssa.size(), kNone);
        for (std::uint32_t i = 0; i < ssa.size(); ++i) {
            if (ssa[i].out < index.size()) index[ssa[i].out] = i;
        }
        index_ = &index;
    }
    /// The instruction writing slot `s`, if it has op `op`.
    const Instr* as(std::uint32_t s, Op op) const {
        if (s >= index_->size() || (*index_)[s] == kNone) return nullptr;
        const Instr& in = ssa_[(*index_)[s]];
        return in.op == op ? &in : nullptr;
    }
    /// Whether slot `s` is the constant `v` (0 matches either sign of zero).
    bool is_const(std::uint32_t s, double v) const {
        const Instr* c = as(s, Op::Const);
        return c != nullptr && c->imm == v;
    }

  private:
    static constexpr std::uint32_t kNone = 0xffffffffu;
    const std::vector<Instr>& ssa_;
    const std::vector<std::uint32_t>* index_;
};

/// Whether slot `kern` is max(k − |d|, 0)² / (4k), k > 0, with d = a − b or b − a.
bool is_kernel(const BySlot& at, std::uint32_t kern, std::uint32_t a, std::uint32_t b) {
    const Instr* div = at.as(kern, Op::Div);
    if (div == nullptr) return false;
    const Instr* c = at.as(div->b, Op::Const);
    const Instr* sq = at.as(div->a, Op::Square);
    if (c == nullptr || sq == nullptr) return false;
    const Instr* mx = at.as(sq->a, Op::Max);
    if (mx == nullptr) return false;
    std::uint32_t inner = mx->a;
    if (!at.is_const(mx->b, 0.0)) {
        if (!at.is_const(mx->a, 0.0)) return false;
        inner = mx->b;
    }
    const Instr* sub = at.as(inner, Op::Sub);
    if (sub == nullptr) return false;
    const Instr* k = at.as(sub->a, Op::Const);
    const Instr* ab = at.as(sub->b, Op::Abs);
    if (k == nullptr || ab == nullptr || !(k->imm > 0) || c->imm != 4 * k->imm) return false;
    const Instr* d = at.as(ab->a, Op::Sub);
    return d != nullptr && ((d->a == a && d->b == b) || (d->a == b && d->b == a));
}

}  // namespace

void smooth_blends(const std::vector<Instr>& ssa, std::vector<SmoothBlend>& out) {
    out.clear();
    bool any = false;  // no Div, no blend: skip the map (most tapes)
    for (const Instr& in : ssa) any = any || in.op == Op::Div;
    if (!any) return;
    const BySlot at(ssa);
    for (const Instr& in : ssa) {
        if (in.op == Op::Sub) {
            const Instr* hard = at.as(in.a, Op::Min);
            if (hard != nullptr && is_kernel(at, in.b, hard->a, hard->b)) {
                out.push_back({in.out, hard->a, hard->b});
            }
        } else if (in.op == Op::Add) {
            for (const auto& [h, k] : {std::pair{in.a, in.b}, std::pair{in.b, in.a}}) {
                const Instr* hard = at.as(h, Op::Max);
                if (hard != nullptr && is_kernel(at, k, hard->a, hard->b)) {
                    out.push_back({in.out, hard->a, hard->b});
                    break;
                }
            }
        }
    }
}

std::vector<SmoothBlend> smooth_blends(const std::vector<Instr>& ssa) {
    std::vector<SmoothBlend> out;
    smooth_blends(ssa, out);
    return out;
}

namespace {

/// After each blend's root: the operands' hull and max(λ_a, λ_b), its value kept (see the file
/// contract of derived.h).
struct BlendRule {
    const std::vector<SmoothBlend>& blends;
    std::size_t next = 0;
    void operator()(const Instr& in, GradBound* r) {
        if (next >= blends.size() || in.out != blends[next].root) return;
        const SmoothBlend& b = blends[next++];
        GradBound& g = r[in.out];
        if (!g.d.a.defined) return;  // no Lipschitz bound claimed where f is not proven defined
        const GradBound& x = r[b.a];
        const GradBound& y = r[b.b];
        for (int i = 0; i < 3; ++i) g.d.v[i] = hull(x.d.v[i], y.d.v[i]);
        g.lip = std::max(x.lip, y.lip);
        g.has_form = false;
        g = certray::detail::finish(g);
    }
};

}  // namespace

double lipschitz_bound(const Tape& tape, const std::array<Interval, 3>& box) {
    thread_local std::vector<GradBound> regs;
    std::array<Interval, 3> parts;
    double lip = 0;
    // The blends and whether there is a square root, found once per tape (a tracer asks for
    // bounds on one tape many times in a row; Tape::serial names its instructions).
    thread_local std::vector<SmoothBlend> blends;
    thread_local std::uint64_t scanned = 0;
    thread_local bool roots = false;
    if (tape.serial() == 0 || tape.serial() != scanned) {
        smooth_blends(tape.ssa(), blends);
        roots = std::any_of(tape.instrs().begin(), tape.instrs().end(),
                            [](const Instr& in) { return in.op == Op::Sqrt; });
        scanned = tape.serial();
    }
    // Without a square root there is no root form to find (interval/grad_bound.h), and without a
    // blend no rule to apply: the norm of the interval gradient is the bound, at half the cost of
    // GradBound's per-operation bookkeeping (the same steps on the particles, the Barth sextic
    // and the tanglecube, 1.6× faster sphere tracing).
    if (!roots && blends.empty()) {
        using D = Dual<UpInterval, 3>;
        thread_local std::vector<D> dregs;
        if (dregs.size() < tape.registers()) dregs.resize(tape.registers());
        {
            RoundingScope scope;
            detail::run<D>(tape.instrs(),
                           {D::variable(UpInterval(box[0]), 0), D::variable(UpInterval(box[1]), 1),
                            D::variable(UpInterval(box[2]), 2)},
                           dregs.data());
            const D& out = dregs[tape.output()];
            if (!out.a.defined) return std::numeric_limits<double>::infinity();
            for (int i = 0; i < 3; ++i) parts[i] = Interval(out.v[i]);
        }
        return norm_bound(parts);
    }
    {
        RoundingScope scope;
        const std::array<GradBound, 3> p{GradBound::variable(UpInterval(box[0]), 0),
                                         GradBound::variable(UpInterval(box[1]), 1),
                                         GradBound::variable(UpInterval(box[2]), 2)};
        const GradBound* out = nullptr;
        if (blends.empty()) {
            if (regs.size() < tape.registers()) regs.resize(tape.registers());
            detail::run<GradBound>(tape.instrs(), p, regs.data());
            out = &regs[tape.output()];
        } else {
            // The SSA form, so that each blend's operands are still there at its root.
            const std::vector<Instr>& ssa = tape.ssa();
            if (regs.size() < ssa.size()) regs.resize(ssa.size());
            detail::run<GradBound>(ssa, p, regs.data(), BlendRule{blends});
            out = &regs[ssa.back().out];
        }
        if (!out->d.a.defined) return std::numeric_limits<double>::infinity();
        lip = out->lip;
        for (int i = 0; i < 3; ++i) parts[i] = Interval(out->d.v[i]);
    }
    // The components' norm scaled against underflow (GradBound's own is only rounded up).
    return std::min(lip, norm_bound(parts));
}

double lipschitz_bound_segment(const Tape& tape, const std::array<double, 3>& p,
                               const std::array<double, 3>& q) {
    std::array<Interval, 3> box;
    for (int i = 0; i < 3; ++i) box[i] = Interval(std::min(p[i], q[i]), std::max(p[i], q[i]));
    return lipschitz_bound(tape, box);
}

}  // namespace certray::expr
