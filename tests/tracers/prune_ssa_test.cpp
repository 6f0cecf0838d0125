// tests/tracers/prune_ssa_test.cpp — expr::prune_ssa, the pruning the 2D quadtree does from the
// enclosures of an evaluation already made (tracers/tile_walker.cpp), and QuadInterval, the
// four-box evaluation it reads them from.
//
// Checked on random DAGs: the pruned list is the same real function on the box (MPFR at a point of
// the box: both empty or overlapping), its enclosure over the box is contained in the full one's,
// and — the property the quadtree's exactness rests on — when every intermediate enclosure over
// the box is bounded and defined, its double value at every point of the box is the full list's,
// bit for bit. Pruning a pruned list again (slots then no longer in list order) keeps all of that;
// a lane of a QuadInterval walk prunes exactly as a scalar walk over that lane's box. fold_ssa:
// the folded list, its fixed slots filled, encloses f's MPFR value at points of sub-boxes of the
// box (and is well formed), and its tangent list's mean value forms hold for f along segments.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <vector>

#include "expr/eval.h"
#include "expr/graph.h"
#include "expr/prune.h"
#include "expr/tangent.h"
#include "expr/tape.h"
#include "interval/dual.h"
#include "interval/interval.h"
#include "interval/mpfr_interval.h"
#include "tests/support/generators.h"
#include "tests/support/mpfr_oracle.h"
#include "tests/support/random_dag.h"
#include "tracers/quad_interval.h"

namespace certray::expr {
namespace {

using Ssa = std::vector<Instr>;
using Box = std::array<std::pair<double, double>, 3>;

/// A box: half the time from gen_bounds (any magnitude, unbounded sides), half the time small
/// boxes around moderate centres (where every enclosure is often bounded: the quadtree's case).
rc::Gen<Box> gen_box() {
    auto moderate = rc::gen::apply(
        [](int c, int e) {
            const double centre = c / 16.0, half = std::ldexp(1.0, -e);
            return std::pair<double, double>{centre - half, centre + half};
        },
        rc::gen::inRange(-64, 65), rc::gen::inRange(0, 12));
    return rc::gen::exec([moderate] {
        const bool wide = *rc::gen::arbitrary<bool>();
        Box b;
        for (auto& side : b) side = wide ? *testing::gen_bounds() : *moderate;
        return b;
    });
}

/// A point of the box.
std::array<double, 3> gen_point(const Box& b) {
    std::array<double, 3> p;
    for (int i = 0; i < 3; ++i) p[i] = *testing::gen_point_in(b[i].first, b[i].second);
    return p;
}

/// The box `inner` scaled into `outer` (a sub-box containing `p`): each side shrunk towards p.
Box sub_box(const Box& outer, const std::array<double, 3>& p) {
    Box b = outer;
    for (int i = 0; i < 3; ++i) {
        const bool lower_half = *rc::gen::arbitrary<bool>();
        if (lower_half && std::isfinite(outer[i].first)) b[i].second = p[i];
        if (!lower_half && std::isfinite(outer[i].second)) b[i].first = p[i];
    }
    return b;
}

/// Number of slots the list uses (one past the largest).
std::size_t slot_count(const Ssa& list) {
    std::uint32_t m = 0;
    for (const Instr& in : list) m = std::max(m, in.out);
    return m + 1;
}

/// An SSA list in prune_ssa's sense: slots distinct and < size, operands written before.
bool well_formed(const Ssa& list) {
    std::vector<bool> written(list.size(), false);
    for (const Instr& in : list) {
        if (in.out >= list.size() || written[in.out]) return false;
        const int k = arity(in.op);
        if (k >= 1 && (in.a >= list.size() || !written[in.a])) return false;
        if (k == 2 && (in.b >= list.size() || !written[in.b])) return false;
        written[in.out] = true;
    }
    return !list.empty();
}

/// Enclosures of every slot over the box; `finite`: all bounded and defined.
std::vector<UpInterval> enclose(const Ssa& list, const Box& b, bool& finite) {
    std::vector<UpInterval> v(slot_count(list));
    RoundingScope scope;
    const std::array<UpInterval, 3> box{UpInterval(b[0].first, b[0].second),
                                        UpInterval(b[1].first, b[1].second),
                                        UpInterval(b[2].first, b[2].second)};
    finite = true;
    detail::run<UpInterval>(list, box, v.data(), [&](const Instr& in, const UpInterval* r) {
        const UpInterval& x = r[in.out];
        finite = finite && x.defined && std::isfinite(x.lower()) && std::isfinite(x.upper());
    });
    return v;
}

Interval output(const Ssa& list, const std::vector<UpInterval>& v) {
    return Interval(v[list.back().out]);
}

double at(const Ssa& list, const std::array<double, 3>& p) {
    std::vector<double> r(slot_count(list));
    detail::run<double>(list, p, r.data());
    return r[list.back().out];
}

MpfrInterval at_mpfr(const Ssa& list, const std::array<double, 3>& p) {
    std::vector<MpfrInterval> r(slot_count(list));
    detail::run<MpfrInterval>(list, {MpfrInterval(p[0]), MpfrInterval(p[1]), MpfrInterval(p[2])},
                              r.data());
    return r[list.back().out];
}

/// Everything the pruned list `pruned` must satisfy against `full` on box b at point p.
void check_same_function(const Ssa& full, const Ssa& pruned, const Box& b,
                         const std::array<double, 3>& p) {
    RC_ASSERT(well_formed(pruned));
    const MpfrInterval exact = at_mpfr(full, p), exact_pruned = at_mpfr(pruned, p);
    RC_ASSERT(exact.is_empty() == exact_pruned.is_empty());
    if (!exact.is_empty()) RC_ASSERT(!intersect(exact, exact_pruned).is_empty());
    bool finite = false, finite_pruned = false;
    const std::vector<UpInterval> v = enclose(full, b, finite);
    const std::vector<UpInterval> w = enclose(pruned, b, finite_pruned);
    RC_ASSERT(contains(output(full, v), output(pruned, w)));
    if (finite) {
        // The quadtree's rule: every double intermediate lies in its enclosure, so the dropped
        // branches are dropped in double arithmetic too. Equal as numbers: a constant folded from
        // the point enclosure [−0, 0] may carry the other sign of zero, which no op of a finite
        // walk turns into different nonzero values (a division by an enclosure holding 0 is never
        // defined), and f < 0 reads the same for both.
        const double d = at(full, p), e = at(pruned, p);
        RC_ASSERT(d == e || (std::isnan(d) && std::isnan(e)));
    }
}

RC_GTEST_PROP(PruneSsa, PrunedListIsTheSameFunctionOnTheBox, ()) {
    const Tape t(*testing::gen_dag(40));
    const Box b = *gen_box();
    const std::array<double, 3> p = gen_point(b);
    bool finite = false;
    const std::vector<UpInterval> v = enclose(t.ssa(), b, finite);
    PruneWorkspace ws;
    ws.absolute_values = *rc::gen::arbitrary<bool>();
    Ssa out;
    const bool changed = prune_ssa(t.ssa(), v.data(), ws, out);
    RC_TAG(changed ? "pruned" : "unchanged", finite ? "bounded" : "unbounded");
    if (!changed) return;
    RC_ASSERT(out.size() <= t.ssa().size());
    check_same_function(t.ssa(), out, b, p);
}

RC_GTEST_PROP(PruneSsa, PruningAPrunedListOnASubBoxKeepsTheFunction, ()) {
    const Tape t(*testing::gen_dag(40));
    const Box b = *gen_box();
    const std::array<double, 3> p = gen_point(b);
    bool finite = false;
    PruneWorkspace ws;
    ws.absolute_values = *rc::gen::arbitrary<bool>();
    Ssa once, twice;
    const std::vector<UpInterval> v = enclose(t.ssa(), b, finite);
    const Ssa& first = prune_ssa(t.ssa(), v.data(), ws, once) ? once : t.ssa();
    const Box inner = sub_box(b, p);
    const std::vector<UpInterval> w = enclose(first, inner, finite);
    const Ssa& second = prune_ssa(first, w.data(), ws, twice) ? twice : first;
    check_same_function(t.ssa(), second, inner, p);
}

RC_GTEST_PROP(PruneSsa, QuadLaneEvaluatesAndPrunesAsAScalarWalk, ()) {
    const Tape t(*testing::gen_dag(40));
    std::array<Box, 4> boxes;
    for (Box& b : boxes) b = *gen_box();
    const Ssa& list = t.ssa();
    std::vector<tracers::QuadInterval> q(list.size());
    std::array<bool, 4> finite{true, true, true, true};
    {
        RoundingScope scope;
        std::array<tracers::QuadInterval, 3> box;
        for (int k = 0; k < 4; ++k) {
            for (int i = 0; i < 3; ++i) {
                box[i].v[k] = UpInterval(boxes[k][i].first, boxes[k][i].second);
            }
        }
        detail::run<tracers::QuadInterval>(
            list, box, q.data(), [&](const Instr& in, const tracers::QuadInterval* r) {
                for (int k = 0; k < 4; ++k) {
                    const UpInterval& x = r[in.out].v[k];
                    finite[k] = finite[k] && x.defined && std::isfinite(x.lower()) &&
                                std::isfinite(x.upper());
                }
            });
    }
    PruneWorkspace ws;
    for (int k = 0; k < 4; ++k) {
        bool scalar_finite = false;
        const std::vector<UpInterval> v = enclose(list, boxes[k], scalar_finite);
        RC_ASSERT(finite[k] == scalar_finite);
        for (std::size_t s = 0; s < list.size(); ++s) {  // the same bounds, bit for bit
            const UpInterval& a = q[s].v[k];
            RC_ASSERT(a.is_empty() == v[s].is_empty());
            RC_ASSERT(a.defined == v[s].defined);
            if (!a.is_empty()) {
                RC_ASSERT(std::bit_cast<std::uint64_t>(a.lower()) ==
                          std::bit_cast<std::uint64_t>(v[s].lower()));
                RC_ASSERT(std::bit_cast<std::uint64_t>(a.upper()) ==
                          std::bit_cast<std::uint64_t>(v[s].upper()));
            }
        }
        Ssa from_lane, from_scalar;
        const bool l = prune_ssa(list, &q[0].v[k], ws, from_lane, tracers::lane_stride);
        const bool s = prune_ssa(list, v.data(), ws, from_scalar);
        RC_ASSERT(l == s);
        if (!l) continue;
        RC_ASSERT(from_lane.size() == from_scalar.size());
        for (std::size_t i = 0; i < from_lane.size(); ++i) {
            const Instr &x = from_lane[i], &y = from_scalar[i];
            RC_ASSERT(x.op == y.op && x.out == y.out && x.a == y.a && x.b == y.b);
            RC_ASSERT(std::bit_cast<std::uint64_t>(x.imm) == std::bit_cast<std::uint64_t>(y.imm));
        }
    }
}

/// The list pruned to the box `b` with the settings of `ws` (which must drop something).
Ssa pruned(const Ssa& list, const Box& b, PruneWorkspace ws = {}) {
    bool finite = false;
    const std::vector<UpInterval> v = enclose(list, b, finite);
    Ssa out;
    EXPECT_TRUE(prune_ssa(list, v.data(), ws, out));
    EXPECT_TRUE(well_formed(out));
    return out;
}

TEST(PruneSsa, AChosenOperandReadElsewhereIsCopiedOnce) {
    // f = max(a, y) + a with a = x + 1: on x ∈ [2, 3], y ∈ [−1, 0], max picks a, which the sum
    // also reads, so the max becomes the copy min(a, a) (Fidget's CopyReg); pruning again keeps
    // that one copy (the sum still reads a) and adds none.
    Graph g;
    const NodeId a = g.binary(Op::Add, g.var(0), g.constant(1.0));
    g.set_output(g.binary(Op::Add, g.binary(Op::Max, a, g.var(1)), a));
    const Tape t(g);
    const Box b{{{2.0, 3.0}, {-1.0, 0.0}, {0.0, 0.0}}};
    const Ssa once = pruned(t.ssa(), b);
    auto copies = [](const Ssa& list) {
        return std::count_if(list.begin(), list.end(), [](const Instr& in) {
            return (in.op == Op::Min || in.op == Op::Max) && in.a == in.b;
        });
    };
    EXPECT_EQ(copies(once), 1);
    EXPECT_EQ(
        std::count_if(once.begin(), once.end(), [](const Instr& in) { return in.op == Op::VarY; }),
        0);
    EXPECT_EQ(at(once, {2.5, -0.5, 0.0}), 7.0);  // (2.5 + 1) + (2.5 + 1)
    bool finite = false;
    const std::vector<UpInterval> v = enclose(once, b, finite);
    PruneWorkspace ws;
    Ssa twice;
    EXPECT_TRUE(prune_ssa(once, v.data(), ws, twice));  // the copy counts as a choice
    EXPECT_EQ(copies(twice), 1);
    EXPECT_EQ(twice.size(), once.size());
    EXPECT_EQ(at(twice, {2.5, -0.5, 0.0}), 7.0);
    EXPECT_TRUE(well_formed(twice));
}

TEST(PruneSsa, NothingToDropReturnsFalse) {
    Graph g;
    g.set_output(g.binary(Op::Min, g.var(0), g.var(1)));
    const Tape t(g);
    bool finite = false;
    const Box b{{{-1.0, 1.0}, {-1.0, 1.0}, {0.0, 0.0}}};
    const std::vector<UpInterval> v = enclose(t.ssa(), b, finite);
    PruneWorkspace ws;
    Ssa out;
    EXPECT_FALSE(prune_ssa(t.ssa(), v.data(), ws, out));
}

TEST(PruneSsa, NeverDropsAnUndefinedBranch) {
    // min(x, sqrt(y)) with x ∈ [−2, −1]: x wins wherever sqrt(y) exists, but for y < 0 f is
    // undefined, and dropping sqrt(y) would define it.
    Graph g;
    g.set_output(g.binary(Op::Min, g.var(0), g.unary(Op::Sqrt, g.var(1))));
    const Tape t(g);
    bool finite = false;
    PruneWorkspace ws;
    Ssa out;
    const Box straddles{{{-2.0, -1.0}, {-1.0, 1.0}, {0.0, 0.0}}};
    std::vector<UpInterval> v = enclose(t.ssa(), straddles, finite);
    EXPECT_FALSE(prune_ssa(t.ssa(), v.data(), ws, out));
    const Box nonnegative{{{-2.0, -1.0}, {0.0, 1.0}, {0.0, 0.0}}};
    v = enclose(t.ssa(), nonnegative, finite);
    ASSERT_TRUE(prune_ssa(t.ssa(), v.data(), ws, out));
    EXPECT_EQ(out.size(), 1u);
    EXPECT_EQ(out.back().op, Op::VarX);
}

TEST(PruneSsa, APointEnclosureBecomesAConstant) {
    // sqrt(x) · y on x = 4 (a degenerate box): sqrt(x) is the point 2.
    Graph g;
    g.set_output(g.binary(Op::Mul, g.unary(Op::Sqrt, g.var(0)), g.var(1)));
    const Tape t(g);
    const Ssa out = pruned(t.ssa(), Box{{{4.0, 4.0}, {-1.0, 1.0}, {0.0, 0.0}}});
    EXPECT_TRUE(well_formed(out));
    EXPECT_EQ(std::count_if(out.begin(), out.end(),
                            [](const Instr& in) { return in.op == Op::Const && in.imm == 2.0; }),
              1);
    EXPECT_EQ(at(out, {4.0, 0.5, 0.0}), 1.0);
}

TEST(PruneSsa, WithoutFoldingPointsAPrunedListKeepsTheDerivatives) {
    // max(sqrt(x) · y, y − 10) on x = 4 (a degenerate box, as a heightmap ray's), y ∈ [−1, 1]:
    // the max keeps sqrt(x) · y ∈ [−2, 2] (y − 10 ≤ −9). Without folding sqrt(x) to 2, the
    // list's gradient at (4, 1/2, 0) is f's: (y/(2√x), √x, 0) = (1/8, 2, 0).
    Graph g;
    const NodeId y = g.var(1);
    g.set_output(g.binary(Op::Max, g.binary(Op::Mul, g.unary(Op::Sqrt, g.var(0)), y),
                          g.binary(Op::Sub, y, g.constant(10.0))));
    const Tape t(g);
    const Box b{{{4.0, 4.0}, {-1.0, 1.0}, {0.0, 0.0}}};
    const auto gradient_at = [](const Ssa& list) {
        using D = Dual<double, 3>;
        std::vector<D> r(list.size());
        detail::run<D>(list, {D::variable(4.0, 0), D::variable(0.5, 1), D::variable(0.0, 2)},
                       r.data());
        return r[list.back().out];
    };
    PruneWorkspace no_folding;
    no_folding.fold_points = false;
    const Ssa out = pruned(t.ssa(), b, no_folding);
    EXPECT_EQ(
        std::count_if(out.begin(), out.end(), [](const Instr& in) { return in.op == Op::Max; }), 0);
    const Dual<double, 3> f = gradient_at(out);
    EXPECT_EQ(f.a, 1.0);
    EXPECT_EQ(f.v[0], 0.125);
    EXPECT_EQ(f.v[1], 2.0);
    EXPECT_EQ(f.v[2], 0.0);
    // Folded (the default), sqrt(x) is the constant 2 and ∂/∂x is lost.
    EXPECT_EQ(gradient_at(pruned(t.ssa(), b)).v[0], 0.0);
}

TEST(PruneSsa, MaxOfXAndMinusXBecomesAbsoluteValue) {
    // f = max(max(u, y − 10), −min(u, y + 10)) with u = x − 1/2, on x ∈ [0.4, 0.6], y ∈ [−1, 1]:
    // both inner choices pick u, so f = max(u, −u) = |u| there. As a max the enclosure is
    // [−0.1, 0.1]; as |u|, [0, 0.1]: f ≥ 0 is proven on the box (a model that touches 0 along
    // the plane x = 1/2, as Fidget's colonnade does).
    Graph g;
    const NodeId u = g.binary(Op::Sub, g.var(0), g.constant(0.5));
    const NodeId left = g.binary(Op::Max, u, g.binary(Op::Sub, g.var(1), g.constant(10.0)));
    const NodeId right =
        g.unary(Op::Neg, g.binary(Op::Min, u, g.binary(Op::Add, g.var(1), g.constant(10.0))));
    g.set_output(g.binary(Op::Max, left, right));
    const Tape t(g);
    const Box b{{{0.4, 0.6}, {-1.0, 1.0}, {0.0, 0.0}}};
    bool finite = false;
    EXPECT_LT(output(t.ssa(), enclose(t.ssa(), b, finite)).lower(), 0.0);
    auto abs_count = [](const Ssa& list) {
        return std::count_if(list.begin(), list.end(),
                             [](const Instr& in) { return in.op == Op::Abs; });
    };
    EXPECT_EQ(abs_count(pruned(t.ssa(), b)), 0);  // off by default
    PruneWorkspace ws;
    ws.absolute_values = true;
    const Ssa out = pruned(t.ssa(), b, ws);
    EXPECT_EQ(abs_count(out), 1);
    const Interval f = output(out, enclose(out, b, finite));
    EXPECT_EQ(f.lower(), 0.0);
    EXPECT_GE(f.upper(), 0.6 - 0.5);  // the largest |u| on the box (the doubles 0.6 and 0.4)
    EXPECT_LE(f.upper(), 0.1 + 1e-15);
    for (double x : {0.4, 0.45, 0.5, 0.55, 0.6}) {
        EXPECT_EQ(at(out, {x, 0.25, 0.0}), std::fabs(x - 0.5)) << x;
        EXPECT_EQ(at(out, {x, 0.25, 0.0}), at(t.ssa(), {x, 0.25, 0.0})) << x;
    }
}

// ---- fold_ssa -----------------------------------------------------------------------------------

/// The folded list's walk over b (fixed slots filled), every slot's enclosure.
std::vector<UpInterval> enclose_folded(const FoldedList& f, std::size_t slots, const Box& b) {
    std::vector<UpInterval> v(slots);
    for (const auto& [slot, x] : f.fixed) v[slot] = x;
    RoundingScope scope;
    const std::array<UpInterval, 3> box{UpInterval(b[0].first, b[0].second),
                                        UpInterval(b[1].first, b[1].second),
                                        UpInterval(b[2].first, b[2].second)};
    detail::run<UpInterval>(f.list, box, v.data());
    return v;
}

/// `folded` of `ssa` (enclosures `v`, width `width`): the output kept last, every operand written
/// before it is read or fixed, no fixed slot written, each fixed value the slot's enclosure,
/// defined, bounded and at most `width` wide.
void check_folded_form(const Ssa& ssa, const std::vector<UpInterval>& v, double width,
                       const FoldedList& folded) {
    RC_ASSERT(!folded.list.empty());
    RC_ASSERT(folded.list.back().out == ssa.back().out);
    std::vector<bool> ready(ssa.size(), false);
    for (const auto& [slot, x] : folded.fixed) {
        RC_ASSERT(slot < ssa.size());
        RC_ASSERT(!ready[slot]);
        ready[slot] = true;
        RC_ASSERT(x.lower() == v[slot].lower() && x.upper() == v[slot].upper());
        RC_ASSERT(x.defined && std::isfinite(x.lower()) && std::isfinite(x.upper()));
        RC_ASSERT(x.upper() - x.lower() <= width);
    }
    for (const Instr& in : folded.list) {
        const int k = arity(in.op);
        if (k >= 1) RC_ASSERT(in.a < ssa.size() && ready[in.a]);
        if (k == 2) RC_ASSERT(in.b < ssa.size() && ready[in.b]);
        RC_ASSERT(in.out < ssa.size() && !ready[in.out]);
        ready[in.out] = true;
    }
}

/// A width to fold at: a power of two times the output's width, or an absolute one.
double gen_fold_width(const std::vector<UpInterval>& v, const Ssa& ssa) {
    const UpInterval& f = v[ssa.back().out];
    const double w = f.upper() - f.lower();
    if (*rc::gen::arbitrary<bool>() && std::isfinite(w)) {
        return std::ldexp(w, -*rc::gen::inRange(0, 30));
    }
    return *rc::gen::element(0.0, 1e-9, 1e-3, 1.0, 1e300);
}

RC_GTEST_PROP(FoldSsa, FoldedListEnclosesTheFunctionOnSubBoxes, ()) {
    const Tape t(*testing::gen_dag(40));
    const Box b = *gen_box();
    bool finite = false;
    std::vector<UpInterval> v = enclose(t.ssa(), b, finite);
    // Half the time a pruned list (slots not in list order), as the renderer folds.
    PruneWorkspace ws;
    Ssa pruned_list;
    const Ssa& ssa = *rc::gen::arbitrary<bool>() && prune_ssa(t.ssa(), v.data(), ws, pruned_list)
                         ? pruned_list
                         : t.ssa();
    if (&ssa == &pruned_list) v = enclose(ssa, b, finite);
    const double width = gen_fold_width(v, ssa);
    FoldedList folded;
    const std::size_t dropped = fold_ssa(ssa, v.data(), width, folded);
    RC_TAG(dropped > 0 ? "folded" : "nothing to fold");
    if (dropped == 0) {
        RC_ASSERT(folded.list.empty() && folded.fixed.empty());
        return;
    }
    RC_ASSERT(dropped == ssa.size() - folded.list.size());
    check_folded_form(ssa, v, width, folded);
    // At a point p of the box, over a sub-box holding p and over p itself: f's exact value lies
    // in the enclosure, and a defined enclosure means f is defined there.
    const std::array<double, 3> p = gen_point(b);
    const MpfrInterval exact = at_mpfr(ssa, p);
    for (const Box& inner : {sub_box(b, p), Box{{{p[0], p[0]}, {p[1], p[1]}, {p[2], p[2]}}}}) {
        const std::vector<UpInterval> w = enclose_folded(folded, ssa.size(), inner);
        const UpInterval& e = w[ssa.back().out];
        if (e.defined) RC_ASSERT(!exact.is_empty());
        if (exact.is_empty()) continue;
        const double size =
            std::max(1.0, std::max(std::fabs(exact.lower()), std::fabs(exact.upper())));
        if (!(exact.upper() - exact.lower() <= 0x1p-100 * size)) continue;  // beyond MPFR's bits
        RC_ASSERT(testing::encloses(e.lower(), e.upper(), exact));
    }
}

/// The renderer's mean value form on a folded list (tracers/coherent_segments.cpp): over a segment
/// {o + t·u : t ∈ [t0, t1]} inside the box the list was folded to, g(t) ∈ g(tc) + G′·(t − tc),
/// with g(tc) and G′ from the folded list's tangent list (the fixed inputs' derivatives 0),
/// wherever its value over the segment is defined and G′ finite. Dyadic o, u and t keep every
/// point exact.
RC_GTEST_PROP(FoldSsa, MeanValueFormsOfAFoldedListHoldAlongSegments, ()) {
    const Tape t(*testing::gen_dag(16, /*smooth=*/*rc::gen::arbitrary<bool>()));
    const auto [o, u, t0, t1] = *testing::gen_dyadic_segment();
    const double tc = 0.5 * (t0 + t1);
    // Folded to a box around the segment (the renderer's node box holds its rays' segments).
    Box b, seg, centre;
    for (int c = 0; c < 3; ++c) {
        const double e0 = o[c] + t0 * u[c], e1 = o[c] + t1 * u[c];  // exact: dyadic, few bits
        const double margin = *rc::gen::inRange(0, 9) / 8.0;
        seg[c] = {std::min(e0, e1), std::max(e0, e1)};
        b[c] = {seg[c].first - margin, seg[c].second + margin};
        centre[c] = {o[c] + tc * u[c], o[c] + tc * u[c]};
    }
    bool finite = false;
    const std::vector<UpInterval> v = enclose(t.ssa(), b, finite);
    FoldedList folded;
    if (fold_ssa(t.ssa(), v.data(), gen_fold_width(v, t.ssa()), folded) == 0) return;
    const std::optional<TangentList> tl = tangent_list(folded.list);
    RC_ASSERT(tl.has_value());
    const auto run = [&](const Box& x) {
        std::vector<UpInterval> r(tl->slots);
        for (const auto& [slot, fx] : folded.fixed) r[slot] = fx;
        RoundingScope up;
        for (int c = 0; c < 3; ++c) r[tl->seed[c]] = UpInterval(u[c]);
        detail::run<UpInterval>(
            tl->list,
            {UpInterval(x[0].first, x[0].second), UpInterval(x[1].first, x[1].second),
             UpInterval(x[2].first, x[2].second)},
            r.data());
        return std::pair{r[tl->value], r[tl->derivative]};
    };
    const auto [e, g1] = run(seg);
    const auto [m, unused] = run(centre);
    if (!e.defined || !m.defined || !std::isfinite(g1.lower()) || !std::isfinite(g1.upper())) {
        return;
    }
    RC_TAG(tl->smooth ? "smooth" : "kinks");
    RC_ASSERT(testing::mean_value_form_holds(t, o, u, t0, t1, m, g1));
}

TEST(FoldSsa, ANarrowSubexpressionBecomesAnInput) {
    // x + exp(y − 100) over [0, 1]²: exp(y − 100) ∈ [e⁻¹⁰⁰, e⁻⁹⁹], about 6e−44 wide, folds at
    // width 1e−3; y, 100, y − 100 and exp drop, and the list is x + [e⁻¹⁰⁰, e⁻⁹⁹].
    Graph g;
    const NodeId e = g.unary(Op::Exp, g.binary(Op::Sub, g.var(1), g.constant(100.0)));
    g.set_output(g.binary(Op::Add, g.var(0), e));
    const Tape t(g);
    const Box b{{{0.0, 1.0}, {0.0, 1.0}, {0.0, 0.0}}};
    bool finite = false;
    const std::vector<UpInterval> v = enclose(t.ssa(), b, finite);
    FoldedList folded;
    EXPECT_EQ(fold_ssa(t.ssa(), v.data(), 1e-3, folded), 4u);
    ASSERT_EQ(folded.list.size(), 2u);
    EXPECT_EQ(folded.list[0].op, Op::VarX);
    EXPECT_EQ(folded.list[1].op, Op::Add);
    ASSERT_EQ(folded.fixed.size(), 1u);
    EXPECT_LE(folded.fixed[0].second.lower(), std::exp(-100.0));
    EXPECT_GE(folded.fixed[0].second.upper(), std::exp(-99.0));
    EXPECT_LT(folded.fixed[0].second.upper(), 1e-42);
    // At x = 1/2 the folded list encloses 1/2 + e^(y − 100) for every y: [1/2, 1/2 + 1e−42].
    const std::vector<UpInterval> w =
        enclose_folded(folded, t.ssa().size(), Box{{{0.5, 0.5}, {0.0, 1.0}, {0.0, 0.0}}});
    EXPECT_EQ(w[t.ssa().back().out].lower(), 0.5);
    EXPECT_LE(w[t.ssa().back().out].upper(), 0.5 + 1e-15);
    // Width 0 folds only subexpressions that are points on the box (none here).
    EXPECT_EQ(fold_ssa(t.ssa(), v.data(), 0.0, folded), 0u);
    EXPECT_TRUE(folded.list.empty());
}

TEST(FoldSsa, AnUndefinedOrUnboundedSubexpressionStays) {
    // sqrt(y) + x over y ∈ [−1, 0] (sqrt(y) defined at y = 0 only) and log(y) + x over
    // y ∈ [0, 0] (log 0 = −∞): however wide the width, the square root and the log stay in the
    // list (their operand y, defined and bounded, may become an input).
    for (Op op : {Op::Sqrt, Op::Log}) {
        Graph g;
        g.set_output(g.binary(Op::Add, g.unary(op, g.var(1)), g.var(0)));
        const Tape t(g);
        const double lo = op == Op::Sqrt ? -1.0 : 0.0;
        bool finite = false;
        const std::vector<UpInterval> v =
            enclose(t.ssa(), Box{{{0.0, 1.0}, {lo, 0.0}, {0.0, 0.0}}}, finite);
        FoldedList folded;
        EXPECT_GT(fold_ssa(t.ssa(), v.data(), 1e300, folded), 0u);
        EXPECT_EQ(std::count_if(folded.list.begin(), folded.list.end(),
                                [op](const Instr& in) { return in.op == op; }),
                  1)
            << static_cast<int>(op);
        for (const auto& [slot, x] : folded.fixed) {
            EXPECT_TRUE(x.defined && std::isfinite(x.lower()) && std::isfinite(x.upper()));
        }
    }
}

}  // namespace
}  // namespace certray::expr
