// tests/tracers/prune_ssa_test.cpp — expr::prune_ssa, the pruning the 2D quadtree does from the
// enclosures of an evaluation already made (tracers/tile_walker.cpp), and QuadInterval, the
// four-box evaluation it reads them from.
//
// Checked on random DAGs: the pruned list is the same real function on the box (MPFR at a point of
// the box: both empty or overlapping), its enclosure over the box is contained in the full one's,
// and — the property the quadtree's exactness rests on — when every intermediate enclosure over
// the box is bounded and defined, its double value at every point of the box is the full list's,
// bit for bit. Pruning a pruned list again (slots then no longer in list order) keeps all of that;
// a lane of a QuadInterval walk prunes exactly as a scalar walk over that lane's box.
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

}  // namespace
}  // namespace certray::expr
