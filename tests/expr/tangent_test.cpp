// tests/expr/tangent_test.cpp — the tangent list (expr/tangent.h): derivatives along a direction
// that calculus gives, enclosures of the MPFR derivative at random points of random boxes, the
// same bits in the lanes as in the scalar walk, Clarke's branches at the kinks (min, max, abs), the
// mean value form along segments against MPFR, no list for ops with jumps, and the second-order
// list made shorter by share_instructions with the same bits.
#include "expr/tangent.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "expr/builder.h"
#include "expr/eval.h"
#include "expr/eval_interval_batch.h"
#include "expr/tape.h"
#include "interval/dual.h"
#include "interval/interval.h"
#include "interval/mpfr_interval.h"
#include "tests/support/generators.h"
#include "tests/support/mpfr_oracle.h"
#include "tests/support/random_dag.h"

namespace certray::expr {
namespace {

/// f and ∇f·u over the box, by the tangent list in the scalar walk.
struct Slope {
    UpInterval value, derivative;
};
Slope run_tangent(const TangentList& t, const std::array<UpInterval, 3>& box,
                  const std::array<double, 3>& u) {
    RoundingScope up;
    std::vector<UpInterval> r(t.slots);
    for (int c = 0; c < 3; ++c) r[t.seed[c]] = UpInterval(u[c]);
    detail::run<UpInterval>(t.list, box, r.data());
    return {r[t.value], r[t.derivative]};
}

/// The same bounds, bit for bit, and the same decoration.
bool same_bits(const UpInterval& a, const UpInterval& b) {
    return std::bit_cast<std::uint64_t>(a.lower()) == std::bit_cast<std::uint64_t>(b.lower()) &&
           std::bit_cast<std::uint64_t>(a.upper()) == std::bit_cast<std::uint64_t>(b.upper()) &&
           a.defined == b.defined;
}

Tape tape_of(const Expr& f) {
    f.graph->set_output(f.id);
    return Tape(*f.graph);
}

std::array<UpInterval, 3> point(double x, double y, double z) {
    return {UpInterval(x), UpInterval(y), UpInterval(z)};
}

/// [lo, hi] holds v and is at most a few ulps of v wide.
void expect_tight(const UpInterval& d, double v) {
    EXPECT_LE(d.lower(), v);
    EXPECT_GE(d.upper(), v);
    EXPECT_LE(d.upper() - d.lower(), 1e-13 * std::max(1.0, std::fabs(v)));
}

TEST(Tangent, DerivativesAlongADirectionAreTheCalculusOnes) {
    Graph g;
    auto [x, y, z] = vars(g);
    // f = x²·y − z/x + eˣ: ∂f/∂x = 2xy + z/x² + eˣ, ∂f/∂y = x², ∂f/∂z = −1/x.
    const Tape t = tape_of(square(x) * y - z / x + exp(x));
    const std::optional<TangentList> tl = tangent_list(t.ssa());
    ASSERT_TRUE(tl.has_value());
    // At (1, 2, 3) along (1, 0, 0): 4 + 3 + e; along (0, 1, 0): 1; along (0, 0, 1): −1; along
    // (1, 1, 1): their sum.
    const double e = std::exp(1.0);
    expect_tight(run_tangent(*tl, point(1, 2, 3), {1, 0, 0}).derivative, 7 + e);
    expect_tight(run_tangent(*tl, point(1, 2, 3), {0, 1, 0}).derivative, 1);
    expect_tight(run_tangent(*tl, point(1, 2, 3), {0, 0, 1}).derivative, -1);
    expect_tight(run_tangent(*tl, point(1, 2, 3), {1, 1, 1}).derivative, 7 + e);
    // The value slot is f: 2 − 3 + e.
    expect_tight(run_tangent(*tl, point(1, 2, 3), {1, 0, 0}).value, e - 1);

    // √(x² + y²) at (3, 4) along (3, 4)/5 (the radial direction): 1; log(y)·sin(z) + cos(x)·x³
    // at (0, 1, 0) along (0, 0, 1): log 1·cos 0 = 0; along (1, 0, 0): −sin 0·0 + cos 0·0 = 0.
    const Tape r = tape_of(sqrt(square(x) + square(y)));
    const std::optional<TangentList> tr = tangent_list(r.ssa());
    ASSERT_TRUE(tr.has_value());
    expect_tight(run_tangent(*tr, point(3, 4, 0), {0.6, 0.8, 0}).derivative, 1);
    const Tape s = tape_of(log(y) * sin(z) + cos(x) * (x * x * x) + recip(y));
    const std::optional<TangentList> ts = tangent_list(s.ssa());
    ASSERT_TRUE(ts.has_value());
    // Along (0, 1, 0) at (0, 1, 0): sin 0 / y − 1/y² = −1.
    expect_tight(run_tangent(*ts, point(0, 1, 0), {0, 1, 0}).derivative, -1);
    // Along (1, 0, 0) at (1, 1, 0): −sin 1 + 3 cos 1.
    expect_tight(run_tangent(*ts, point(1, 1, 0), {1, 0, 0}).derivative,
                 -std::sin(1.0) + 3 * std::cos(1.0));
}

TEST(Tangent, SquareRootAtZeroHasAnUnboundedDerivative) {
    Graph g;
    auto [x, y, z] = vars(g);
    const Tape t = tape_of(sqrt(square(x) + square(y)) + z);
    const std::optional<TangentList> tl = tangent_list(t.ssa());
    ASSERT_TRUE(tl.has_value());
    // Over a box through the axis x = y = 0 the slope of the cone is ±1 along x but √ cannot
    // bound it there: the derivative enclosure must not be finite (the mean value form is then
    // not taken).
    const Slope s =
        run_tangent(*tl, {UpInterval(-0.5, 0.5), UpInterval(-0.5, 0.5), UpInterval(0)}, {1, 0, 0});
    EXPECT_FALSE(std::isfinite(s.derivative.lower()) && std::isfinite(s.derivative.upper()));
}

TEST(Tangent, KinksTakeOneBranchWhereItIsCertainAndBothAtATie) {
    Graph g;
    auto [x, y, z] = vars(g);
    // min(x, y)·z at z = 1 along u = (3, 5, 0): u_x where x < y, u_y where y < x.
    const Tape m = tape_of(min(x, y) * z);
    const std::optional<TangentList> tm = tangent_list(m.ssa());
    ASSERT_TRUE(tm.has_value());
    EXPECT_FALSE(tm->smooth);
    EXPECT_EQ(tangent_kind(m.ssa()), TangentKind::Kinked);
    const std::array<double, 3> u = {3, 5, 0};
    Slope s = run_tangent(*tm, point(1, 2, 1), u);
    EXPECT_EQ(s.derivative.lower(), 3.0);
    EXPECT_EQ(s.derivative.upper(), 3.0);
    s = run_tangent(*tm, point(2, 1, 1), u);
    EXPECT_EQ(s.derivative.lower(), 5.0);
    EXPECT_EQ(s.derivative.upper(), 5.0);
    // A box where either may be the least (x ∈ [0, 2], y = 1): both slopes, 3 and 5, inside.
    s = run_tangent(*tm, {UpInterval(0, 2), UpInterval(1), UpInterval(1)}, u);
    EXPECT_LE(s.derivative.lower(), 3.0);
    EXPECT_GE(s.derivative.upper(), 5.0);
    // max(x, y) − z along (3, 5, 7): u_y − 7 where y > x, u_x − 7 where x > y.
    const Tape mx = tape_of(max(x, y) - z);
    const std::optional<TangentList> tx = tangent_list(mx.ssa());
    ASSERT_TRUE(tx.has_value());
    s = run_tangent(*tx, point(1, 2, 0), {3, 5, 7});
    EXPECT_EQ(s.derivative.lower(), -2.0);
    EXPECT_EQ(s.derivative.upper(), -2.0);
    s = run_tangent(*tx, point(2, 1, 0), {3, 5, 7});
    EXPECT_EQ(s.derivative.lower(), -4.0);
    EXPECT_EQ(s.derivative.upper(), -4.0);
    // A gap of one ulp still counts as certain, even between subnormals.
    s = run_tangent(*tx, point(1, std::nextafter(1.0, 2.0), 0), {3, 5, 7});
    EXPECT_EQ(s.derivative.lower(), -2.0);
    EXPECT_EQ(s.derivative.upper(), -2.0);
    s = run_tangent(*tx, point(0, 0x1p-1074, 0), {3, 5, 7});
    EXPECT_EQ(s.derivative.lower(), -2.0);
    EXPECT_EQ(s.derivative.upper(), -2.0);
    // |x| + y along (3, 1, 0): −3 + 1 at x < 0, 3 + 1 at x > 0, ⊇ [−2, 4] over x ∈ [−1, 1]; 1
    // where x ≡ 0 on the box (along the y axis |x| stays 0).
    const Tape a = tape_of(abs(x) + y);
    const std::optional<TangentList> ta = tangent_list(a.ssa());
    ASSERT_TRUE(ta.has_value());
    const std::array<double, 3> v = {3, 1, 0};
    s = run_tangent(*ta, point(-2, 0, 0), v);
    EXPECT_EQ(s.derivative.lower(), -2.0);
    EXPECT_EQ(s.derivative.upper(), -2.0);
    s = run_tangent(*ta, point(2, 0, 0), v);
    EXPECT_EQ(s.derivative.lower(), 4.0);
    EXPECT_EQ(s.derivative.upper(), 4.0);
    s = run_tangent(*ta, point(0x1p-1074, 0, 0), v);
    EXPECT_EQ(s.derivative.lower(), 4.0);
    EXPECT_EQ(s.derivative.upper(), 4.0);
    s = run_tangent(*ta, {UpInterval(-1, 1), UpInterval(0), UpInterval(0)}, v);
    EXPECT_LE(s.derivative.lower(), -2.0);
    EXPECT_GE(s.derivative.upper(), 4.0);
    s = run_tangent(*ta, {UpInterval(0), UpInterval(-1, 1), UpInterval(0)}, {0, 1, 0});
    EXPECT_EQ(s.derivative.lower(), 1.0);
    EXPECT_EQ(s.derivative.upper(), 1.0);
    // Smooth lists are marked so; ops with jumps have no list.
    EXPECT_TRUE(tangent_list(tape_of(x * y - z).ssa())->smooth);
    EXPECT_EQ(tangent_kind(tape_of(x * y - z).ssa()), TangentKind::Smooth);
    EXPECT_FALSE(tangent_list(tape_of(floor(x) + y).ssa()).has_value());
    EXPECT_EQ(tangent_kind(tape_of(floor(x) + y).ssa()), TangentKind::None);
    // A constant function: derivative 0.
    const std::optional<TangentList> c = tangent_list(tape_of(constant(g, 2.5) * 2.0).ssa());
    ASSERT_TRUE(c.has_value());
    s = run_tangent(*c, point(1, 2, 3), {1, 1, 1});
    EXPECT_EQ(s.derivative.lower(), 0.0);
    EXPECT_EQ(s.derivative.upper(), 0.0);
}

/// The mean value form the renderer takes (tracers/coherent_segments.cpp): over the segment
/// {o + t·u : t ∈ [t0, t1]}, g(t) ∈ g(tc) + G′·(t − tc) for g(t) = f(o + t·u), with G′ the tangent
/// list's derivative over the segment's box, wherever f is defined and continuous there and G′
/// is finite (Lebourg's theorem at the kinks). Dyadic o, u and t keep every point exact, so f is
/// taken there by MPFR.
RC_GTEST_PROP(TangentProperty, MeanValueFormHoldsAlongSegments, ()) {
    const Tape t(*testing::gen_dag(16, /*smooth=*/*rc::gen::arbitrary<bool>()));
    const std::optional<TangentList> tl = tangent_list(t.ssa());
    RC_ASSERT(tl.has_value());
    const auto [o, u, t0, t1] = *testing::gen_dyadic_segment();
    const double tc = 0.5 * (t0 + t1);
    std::array<UpInterval, 3> box, centre;
    {
        RoundingScope up;
        for (int c = 0; c < 3; ++c) {
            box[c] = UpInterval(o[c]) + UpInterval(t0, t1) * UpInterval(u[c]);
            centre[c] = UpInterval(o[c] + tc * u[c]);  // exact: dyadic with few bits
        }
    }
    const Slope s = run_tangent(*tl, box, u);
    const Slope c = run_tangent(*tl, centre, u);
    if (!s.value.defined || !c.value.defined || !std::isfinite(s.derivative.lower()) ||
        !std::isfinite(s.derivative.upper())) {
        return;
    }
    RC_TAG(tl->smooth ? "smooth" : "kinks");
    RC_ASSERT(testing::mean_value_form_holds(t, o, u, t0, t1, c.value, s.derivative));
}

RC_GTEST_PROP(TangentProperty, EnclosesTheMpfrDerivativeAtPointsOfTheBox, ()) {
    const Tape t(*testing::gen_dag(24, /*smooth=*/*rc::gen::arbitrary<bool>()));
    const std::optional<TangentList> tl = tangent_list(t.ssa());
    RC_ASSERT(tl.has_value());
    std::array<UpInterval, 3> box;
    std::array<double, 3> p, u;
    for (int c = 0; c < 3; ++c) {
        const auto [lo, hi] = *testing::gen_bounds();
        box[c] = UpInterval(lo, hi);
        p[c] = *testing::gen_point_in(lo, hi);
        u[c] = *testing::gen_finite_double();
    }
    const Slope s = run_tangent(*tl, box, u);
    // The value slot is the plain walk's enclosure, bit for bit.
    std::vector<UpInterval> plain(t.size());
    {
        RoundingScope up;
        detail::run<UpInterval>(t.ssa(), box, plain.data());
    }
    RC_ASSERT(same_bits(plain[t.ssa().back().out], s.value));
    // Where f is defined and continuous on the box, ∇f(p)·u lies in the derivative's enclosure
    // (where it exists: a square root at 0 has none; at a kink of p, where the MPFR Dual's rule
    // gives the hull of both branches, the list's is asked only along segments: the next
    // property).
    if (!s.value.defined) return;
    using M = Dual<MpfrInterval, 1>;
    const M exact = eval<M>(t, {M(MpfrInterval(p[0]), {MpfrInterval(u[0])}),
                                M(MpfrInterval(p[1]), {MpfrInterval(u[1])}),
                                M(MpfrInterval(p[2]), {MpfrInterval(u[2])})});
    if (exact.a.is_empty() || exact.v[0].is_empty()) return;
    if (!std::isfinite(exact.v[0].lower()) || !std::isfinite(exact.v[0].upper())) return;
    const double width = exact.v[0].upper() - exact.v[0].lower();
    const double size = std::max(std::fabs(exact.v[0].lower()), std::fabs(exact.v[0].upper()));
    if (!tl->smooth && !(width <= 0x1p-100 * size)) return;  // p at a kink
    // An empty enclosure (0.5/√0 where a square root is [0, 0], behind a max that picks the
    // other branch at p) claims nothing: the renderer takes no form from it.
    if (s.derivative.is_empty()) return;
    RC_TAG(std::isfinite(s.derivative.lower()) && std::isfinite(s.derivative.upper())
               ? "finite derivative"
               : "unbounded");
    RC_ASSERT(testing::encloses(s.derivative.lower(), s.derivative.upper(), exact.v[0]));
}

RC_GTEST_PROP(TangentProperty, LanesGiveTheScalarWalksBits, ()) {
    const Tape t(*testing::gen_dag(16, /*smooth=*/*rc::gen::arbitrary<bool>()));
    const std::optional<TangentList> tl = tangent_list(t.ssa());
    RC_ASSERT(tl.has_value());
    const int n = *rc::gen::inRange(1, kIntervalLanes + 1);
    std::vector<std::array<UpInterval, 3>> boxes(n);
    std::vector<std::array<double, 3>> dirs(n);
    std::array<IntervalLanes, 3> in{};
    std::vector<IntervalLanes> regs(tl->slots);
    for (int k = 0; k < n; ++k) {
        for (int c = 0; c < 3; ++c) {
            const auto [lo, hi] = *testing::gen_bounds();
            boxes[k][c] = UpInterval(lo, hi);
            dirs[k][c] = *testing::gen_finite_double();
            set_lane(in[c], k, boxes[k][c]);
            set_lane(regs[tl->seed[c]], k, UpInterval(dirs[k][c]));
        }
    }
    {
        RoundingScope up;
        run_interval_batch(tl->list.data(), tl->list.data() + tl->list.size(), in.data(),
                           regs.data(), n);
    }
    for (int k = 0; k < n; ++k) {
        const Slope s = run_tangent(*tl, boxes[k], dirs[k]);
        RC_ASSERT(same_bits(lane(regs[tl->value], k), s.value));
        RC_ASSERT(same_bits(lane(regs[tl->derivative], k), s.derivative));
    }
}

/// The tangent list of tl taken again with its seeds shared (as the renderer's second-order
/// list): tl's list with its derivative copied into a last slot (two negations), differentiated.
/// `shared`: made shorter by share_instructions, its second seeds read as tl's.
struct Twice {
    TangentList list;
    std::size_t dropped = 0;
};
std::optional<Twice> tangent_twice(const TangentList& tl, bool shared) {
    std::vector<Instr> list = tl.list;
    Instr n{};
    n.op = Op::Neg;
    n.a = tl.derivative;
    n.out = tl.slots;
    list.push_back(n);
    n.a = tl.slots;
    n.out = tl.slots + 1;
    list.push_back(n);
    std::optional<TangentList> second = tangent_list(list);
    if (!second) return std::nullopt;
    Twice t{*second, 0};
    if (shared) {
        const std::pair<std::uint32_t, std::uint32_t> same[3] = {{second->seed[0], tl.seed[0]},
                                                                 {second->seed[1], tl.seed[1]},
                                                                 {second->seed[2], tl.seed[2]}};
        const std::uint32_t keep[3] = {tl.value, tl.derivative, second->derivative};
        t.dropped = share_instructions(t.list.list, same, keep);
    }
    return t;
}

/// tl's value and derivative and the second list's derivative over a box, every seed holding u,
/// by the scalar walk.
std::array<UpInterval, 3> run_twice(const TangentList& tl, const TangentList& second,
                                    const std::array<UpInterval, 3>& box,
                                    const std::array<double, 3>& u) {
    RoundingScope up;
    std::vector<UpInterval> r(second.slots);
    for (int c = 0; c < 3; ++c) r[tl.seed[c]] = r[second.seed[c]] = UpInterval(u[c]);
    detail::run<UpInterval>(second.list, box, r.data());
    return {r[tl.value], r[tl.derivative], r[second.derivative]};
}

TEST(Tangent, SharedInstructionsDropRepeatsAndWhatNothingReads) {
    // x·y twice, a dead product and a repeated constant: the repeats read as the first, the dead
    // one gone, the kept slots where they were.
    std::vector<Instr> list = {
        {Op::VarX, 0, 0, 0, 0},   {Op::VarY, 1, 0, 0, 0},  {Op::Mul, 2, 0, 1, 0},
        {Op::Mul, 3, 0, 1, 0},    {Op::Const, 4, 0, 0, 2}, {Op::Const, 5, 0, 0, 2},
        {Op::Mul, 6, 3, 5, 0},    {Op::Add, 7, 2, 6, 0},   {Op::Mul, 8, 7, 7, 0},
        {Op::Const, 9, 0, 0, -2}, {Op::Mul, 10, 0, 0, 0},
    };
    const std::vector<Instr> before = list;
    const std::uint32_t keep[2] = {8, 3};               // 3 repeats 2, and is kept as it is
    EXPECT_EQ(share_instructions(list, {}, keep), 3u);  // 5 (a repeat), 9 and 10 (dead), none else
    ASSERT_EQ(list.size(), 8u);
    for (const Instr& in : list) {
        EXPECT_NE(in.out, 5u);
        EXPECT_NE(in.out, 9u);
        EXPECT_NE(in.out, 10u);
        if (in.out == 6u) {
            EXPECT_EQ(in.b, 4u);  // read the first 2
        }
    }
    // The kept slots, bit for bit, over a box.
    const std::array<UpInterval, 3> box = {UpInterval(-1.5, 0.25), UpInterval(0.1, 3.0),
                                           UpInterval(0.0)};
    std::vector<UpInterval> a(11), b(11);
    {
        RoundingScope up;
        detail::run<UpInterval>(before, box, a.data());
        detail::run<UpInterval>(list, box, b.data());
    }
    EXPECT_TRUE(same_bits(a[8], b[8]));
    EXPECT_TRUE(same_bits(a[3], b[3]));
    // (x·y + x·y·2)² = 9x²y², 36 at (−1, 2), a point of the box.
    EXPECT_LE(b[8].lower(), 36.0);
    EXPECT_GE(b[8].upper(), 36.0);
}

TEST(Tangent, SharedSeedsShortenTheSecondOrderList) {
    // g″ of f = x·y·z + x³ along u twice: with the second seeds read as the first, the second
    // list's derivatives of the values along them are the first list's (dropped), and so is the
    // second of each product's a′·b′; the calculus value of g″ at a point is in both lists'
    // enclosures, bit for bit the same.
    Graph g;
    auto [x, y, z] = vars(g);
    const Tape t = tape_of(x * y * z + x * x * x);
    const std::optional<TangentList> tl = tangent_list(t.ssa());
    ASSERT_TRUE(tl.has_value());
    const std::optional<Twice> plain = tangent_twice(*tl, false);
    const std::optional<Twice> shared = tangent_twice(*tl, true);
    ASSERT_TRUE(plain && shared);
    EXPECT_GT(shared->dropped, 0u);
    EXPECT_EQ(shared->list.list.size() + shared->dropped, plain->list.list.size());
    const std::array<double, 3> u = {0.5, -2.0, 1.25};
    const std::array<UpInterval, 3> p = point(0.75, 1.5, -0.5);
    const auto e = run_twice(*tl, plain->list, p, u);
    const auto s = run_twice(*tl, shared->list, p, u);
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(same_bits(e[k], s[k])) << k;
    // g″ = 2·(ux·uy·z + ux·y·uz + x·uy·uz) + 6·x·ux² at the point.
    const double g2 =
        2 * (u[0] * u[1] * -0.5 + u[0] * 1.5 * u[2] + 0.75 * u[1] * u[2]) + 6 * 0.75 * u[0] * u[0];
    EXPECT_LE(s[2].lower(), g2);
    EXPECT_GE(s[2].upper(), g2);
}

/// Over random lists, boxes and directions, the second-order list with shared seeds gives the
/// unshared one's g, g′ and g″ bit for bit, in the scalar walk and in binary32 lanes.
RC_GTEST_PROP(TangentProperty, SharedSeedsKeepTheSecondOrderBits, ()) {
    const Tape t(*testing::gen_dag(16, /*smooth=*/true));
    const std::optional<TangentList> tl = tangent_list(t.ssa());
    RC_ASSERT(tl.has_value());
    const std::optional<Twice> plain = tangent_twice(*tl, false);
    const std::optional<Twice> shared = tangent_twice(*tl, true);
    RC_ASSERT(plain.has_value() && shared.has_value());
    RC_TAG(shared->dropped > 0 ? "instructions dropped" : "none dropped");
    const int n = *rc::gen::inRange(1, kIntervalLanes + 1);
    std::array<IntervalLanesF, 3> in{};
    std::vector<IntervalLanesF> ra(plain->list.slots), rb(shared->list.slots);
    for (int k = 0; k < n; ++k) {
        std::array<UpInterval, 3> box;
        std::array<double, 3> u;
        for (int c = 0; c < 3; ++c) {
            const auto [lo, hi] = *testing::gen_bounds();
            box[c] = UpInterval(lo, hi);
            u[c] = *testing::gen_finite_double();
            set_lane(in[c], k, box[c]);
            for (auto* r : {&ra, &rb}) {
                set_lane((*r)[tl->seed[c]], k, UpInterval(u[c]));
                set_lane((*r)[plain->list.seed[c]], k, UpInterval(u[c]));
            }
        }
        const auto e = run_twice(*tl, plain->list, box, u);
        const auto s = run_twice(*tl, shared->list, box, u);
        for (int j = 0; j < 3; ++j) RC_ASSERT(same_bits(e[j], s[j]));
    }
    {
        RoundingScope up;
        run_interval_batch(plain->list.list.data(),
                           plain->list.list.data() + plain->list.list.size(), in.data(), ra.data(),
                           n);
        run_interval_batch(shared->list.list.data(),
                           shared->list.list.data() + shared->list.list.size(), in.data(),
                           rb.data(), n);
    }
    for (int k = 0; k < n; ++k) {
        for (const std::uint32_t slot : {tl->value, tl->derivative, plain->list.derivative}) {
            RC_ASSERT(same_bits(lane(ra[slot], k), lane(rb[slot], k)));
        }
    }
}

}  // namespace
}  // namespace certray::expr
