// tests/expr/interval_batch_test.cpp — the interval batch walk (expr/eval_interval_batch.h)
// against the scalar detail::run<UpInterval>, lane by lane, bit for bit: both bounds, the
// decoration, emptiness.
//
// Every test runs each copy of the walk this CPU supports (set_batch_isa), and the walk is called
// as a host in the run's floating-point state would call it (testing::as_host; the suite also
// runs under each host state, tests/CMakeLists.txt), while the expected values are computed in
// the default state. Cases: every op on every pair of special boxes (signed zeros, infinite and
// empty bounds, subnormals, undefined operands), in place and not; random DAGs of every op over
// random boxes per lane for a random number of lanes, as tapes (registers reused), as SSA lists
// and as lists written by prune_ssa.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "expr/eval.h"
#include "expr/eval_batch.h"
#include "expr/eval_interval_batch.h"
#include "expr/graph.h"
#include "expr/prune.h"
#include "expr/tape.h"
#include "interval/mpfr_interval.h"
#include "tests/support/batch_isa.h"
#include "tests/support/generators.h"
#include "tests/support/mpfr_oracle.h"
#include "tests/support/random_dag.h"

namespace certray::expr {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Same bounds bit for bit (NaN payloads included), same decoration, same emptiness.
bool same(const UpInterval& a, const UpInterval& b) {
    return std::bit_cast<std::uint64_t>(a.lower()) == std::bit_cast<std::uint64_t>(b.lower()) &&
           std::bit_cast<std::uint64_t>(a.upper()) == std::bit_cast<std::uint64_t>(b.upper()) &&
           a.defined == b.defined && a.is_empty() == b.is_empty();
}

std::string show(const UpInterval& v) {
    std::ostringstream os;
    os.precision(17);
    os << "[" << v.lower() << ", " << v.upper() << "]" << (v.defined ? " def" : " undef")
       << (v.is_empty() ? " empty" : "") << " (0x" << std::hex
       << std::bit_cast<std::uint64_t>(v.lower()) << ", 0x"
       << std::bit_cast<std::uint64_t>(v.upper()) << ")";
    return os.str();
}

using testing::batch_isas;
using IsaGuard = testing::BatchIsaGuard;

/// One box per lane.
using Boxes = std::vector<std::array<UpInterval, 3>>;

/// The registers `list` writes.
std::set<std::uint32_t> written_by(const std::vector<Instr>& list) {
    std::set<std::uint32_t> written;
    for (const Instr& in : list) written.insert(in.out);
    return written;
}

/// The batch walk of `list` over lanes 0 … n − 1 of p into r (L: IntervalLanes or IntervalLanesF)
/// on the copy `isa`, called as a host in this run's floating-point state would call it, after
/// stale values in every register, so that a lane the walk forgets to write shows.
template <class L>
void walk_as_host(BatchIsa isa, const std::vector<Instr>& list, const std::array<L, 3>& p,
                  std::vector<L>& r, int n) {
    set_batch_isa(isa);
    for (L& reg : r) {
        for (int i = 0; i < kIntervalLanes; ++i) set_lane(reg, i, UpInterval(-12345.0));
    }
    testing::as_host([&] {
        RoundingScope up;
        run_interval_batch(list.data(), list.data() + list.size(), p.data(), r.data(), n);
        return 0;
    });
}

/// Runs `list` over `boxes` with the scalar walk (default environment, its own RoundingScope) and
/// with the batch walk on every copy (as the host of this run), and compares every register the
/// list writes in every lane. Returns a description of the first mismatch, or "".
std::string mismatch(const std::vector<Instr>& list, const Boxes& boxes) {
    const int n = static_cast<int>(boxes.size());
    const std::set<std::uint32_t> written = written_by(list);
    const std::uint32_t registers = *written.rbegin() + 1;
    // Expected: want[i][reg].
    std::vector<std::vector<UpInterval>> want(n, std::vector<UpInterval>(registers));
    {
        RoundingScope up;
        for (int i = 0; i < n; ++i) detail::run<UpInterval>(list, boxes[i], want[i].data());
    }
    std::array<IntervalLanes, 3> p{};
    for (int i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) set_lane(p[k], i, boxes[i][k]);
    }
    IsaGuard guard;
    std::vector<IntervalLanes> r(registers);
    for (BatchIsa isa : batch_isas()) {
        walk_as_host(isa, list, p, r, n);
        for (std::uint32_t reg : written) {
            for (int i = 0; i < n; ++i) {
                const UpInterval got = lane(r[reg], i);
                if (!same(got, want[i][reg])) {
                    std::ostringstream os;
                    os << batch_isa_name(isa) << " n=" << n << " lane " << i << " register " << reg
                       << ": batch " << show(got) << ", scalar " << show(want[i][reg]) << "; box x "
                       << show(boxes[i][0]) << " y " << show(boxes[i][1]) << " z "
                       << show(boxes[i][2]);
                    return os.str();
                }
            }
        }
    }
    return "";
}

/// Boxes at the corners of every kernel: signed zeros (also [0, −0] and [−0, +0]), infinite and
/// half-infinite bounds, [+inf, +inf], subnormals, huge values, the empty box, an undefined box.
std::vector<UpInterval> special_boxes() {
    const double sub = std::ldexp(1.0, -1074), tiny = std::ldexp(3.0, -1060);
    return {UpInterval(0.0),
            UpInterval(-0.0),
            UpInterval(-0.0, 0.0),
            UpInterval(0.0, -0.0),
            UpInterval(-kInf, kInf),
            UpInterval(kInf, kInf),
            UpInterval(-kInf, -kInf),
            UpInterval(1.0, kInf),
            UpInterval(-kInf, -1.0),
            UpInterval(0.0, kInf),
            UpInterval(-kInf, -0.0),
            UpInterval(1.0, 2.0),
            UpInterval(-2.0, -1.0),
            UpInterval(-1.0, 1.0),
            UpInterval(-3.0, 0.0),
            UpInterval(0.0, 5.0),
            UpInterval(sub, tiny),
            UpInterval(-tiny, sub),
            UpInterval(-DBL_MAX, DBL_MAX),
            UpInterval(DBL_MAX),
            UpInterval(0.1, 0.30000000000000004),
            UpInterval(1e300, 1e301),
            UpInterval(1.5707963267948966),
            UpInterval(-7.5, 7.25),
            UpInterval(2.0),
            UpInterval(-1.0),
            UpInterval::empty(),
            UpInterval{UpInterval(2.0, 3.0).iv, false},
            UpInterval{UpInterval(-0.5, 0.25).iv, false}};
}

/// Every op of the .vm language (Pow with exponents 0 … 9, 16 and 31: the vector kernel's chains of
/// one to five squarings, with and without the odd factor).
std::vector<Instr> every_op_instrs(std::uint32_t out, std::uint32_t a, std::uint32_t b) {
    std::vector<Instr> v;
    for (int code = 0; code < kOpCount; ++code) {
        const Op op = static_cast<Op>(code);
        if (arity(op) == 0) continue;
        if (op == Op::Pow) {
            for (std::uint32_t e : {0u, 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 16u, 31u}) {
                v.push_back({op, out, a, e, 0.0});
            }
        } else {
            v.push_back({op, out, a, b, 0.0});
        }
    }
    return v;
}

TEST(IntervalBatch, LanesRoundTrip) {
    IntervalLanes x;
    for (int i = 0; i < kIntervalLanes; ++i) set_lane(x, i, UpInterval(1.0));
    for (const UpInterval& v : special_boxes()) {
        for (int i : {0, 1, 31, 63, kIntervalLanes - 1}) {
            set_lane(x, i, v);
            EXPECT_TRUE(same(lane(x, i), v)) << i << " " << show(v);
        }
    }
}

/// Every op on every pair of special boxes (x, y; one pair per lane, in batches of lanes), written
/// to a new register and in place (the output register is x's, then y's): `failure(list, boxes)`
/// of each, "" where it passes.
template <class Failure>
void every_op_on_special_pairs(Failure failure) {
    const std::vector<UpInterval> s = special_boxes();
    std::vector<Boxes> batches(1);
    for (std::size_t i = 0; i < s.size(); ++i) {
        for (std::size_t j = 0; j < s.size(); ++j) {
            if (batches.back().size() == static_cast<std::size_t>(kIntervalLanes)) {
                batches.emplace_back();
            }
            batches.back().push_back({s[i], s[j], s[(i + j) % s.size()]});
        }
    }
    for (std::uint32_t out : {2u, 0u, 1u}) {
        for (const Instr& op : every_op_instrs(out, 0, 1)) {
            const std::vector<Instr> list = {
                {Op::VarX, 0, 0, 0, 0.0}, {Op::VarY, 1, 0, 0, 0.0}, op};
            for (const Boxes& b : batches) {
                EXPECT_EQ(failure(list, b), "") << name(op.op) << " into register " << out;
            }
        }
    }
}

/// x ∘ y for every op on every pair of special boxes, bit for bit as the scalar walk.
TEST(IntervalBatch, EveryOpOnEveryPairOfSpecialBoxes) { every_op_on_special_pairs(mismatch); }

/// Constants, and an op whose operands are one register (x ∘ x).
TEST(IntervalBatch, ConstantsAndSharedOperands) {
    const std::vector<UpInterval> s = special_boxes();
    Boxes boxes;
    for (std::size_t i = 0; i < s.size(); ++i) boxes.push_back({s[i], s[i], s[i]});
    for (double c : {0.0, -0.0, 1.0, -3.5, 1e-310, DBL_MAX, 0.1}) {
        for (const Instr& op : every_op_instrs(2, 0, 1)) {
            const std::vector<Instr> list = {
                {Op::Const, 0, 0, 0, c}, {Op::VarZ, 1, 0, 0, 0.0}, op, {op.op, 1, 1, 1, 0.0}};
            EXPECT_EQ(mismatch(list, boxes), "") << name(op.op) << " with " << c;
        }
    }
}

// ---- random expressions --------------------------------------------------------------------

/// A random DAG over every op (random_dag.h's gen_dag draws the first 19 only).
rc::Gen<Graph> gen_any_dag(int max_ops) {
    return rc::gen::exec([max_ops] {
        Graph g;
        std::vector<NodeId> nodes;
        for (int axis = 0; axis < 3; ++axis) nodes.push_back(g.var(axis));
        const int constants = *rc::gen::inRange(1, 4);
        for (int i = 0; i < constants; ++i) {
            nodes.push_back(g.constant(*rc::gen::oneOf(
                rc::gen::element(0.5, 1.0, 2.0, -3.0, 0.1, 0.0, 1e-300, 1e300, -7.25),
                rc::gen::map(rc::gen::inRange(-1000, 1000), [](int k) { return k / 8.0; }))));
        }
        const int ops = *rc::gen::inRange(1, max_ops);
        for (int i = 0; i < ops; ++i) {
            const int n = static_cast<int>(nodes.size());
            const auto pick = [&] { return nodes[*rc::gen::inRange(std::max(0, n - 6), n)]; };
            const Op op = static_cast<Op>(*rc::gen::inRange(4, kOpCount));
            if (op == Op::Pow) {
                nodes.push_back(g.pow(pick(), *rc::gen::inRange(0u, 12u)));
            } else if (arity(op) == 1) {
                nodes.push_back(g.unary(op, pick()));
            } else {
                nodes.push_back(g.binary(op, pick(), pick()));
            }
        }
        g.set_output(nodes.back());
        return g;
    });
}

/// A box for one lane: gen_bounds' corners (points, unbounded, huge, a few ulps, subnormal and
/// signed-zero bounds), small boxes in [−1, 1] as a renderer makes them, rarely empty or
/// undefined.
rc::Gen<UpInterval> gen_box() {
    namespace gen = rc::gen;
    auto any = gen::map(testing::gen_bounds(),
                        [](std::pair<double, double> b) { return UpInterval(b.first, b.second); });
    auto small = gen::apply(
        [](int c, int w) {
            const double lo = std::ldexp(static_cast<double>(c), -10);
            return UpInterval(lo, lo + std::ldexp(static_cast<double>(w), -12));
        },
        gen::inRange(-1024, 1024), gen::inRange(0, 64));
    auto undefined = gen::map(testing::gen_bounds(), [](std::pair<double, double> b) {
        return UpInterval{UpInterval(b.first, b.second).iv, false};
    });
    return gen::weightedOneOf<UpInterval>(
        {{30, any}, {20, small}, {1, gen::just(UpInterval::empty())}, {1, undefined}});
}

/// n ∈ [1, kIntervalLanes] lanes of boxes.
rc::Gen<Boxes> gen_boxes() {
    return rc::gen::exec([] {
        const int n = *rc::gen::inRange(1, kIntervalLanes + 1);
        Boxes b(n);
        for (auto& box : b) {
            for (auto& v : box) v = *gen_box();
        }
        return b;
    });
}

RC_GTEST_PROP(IntervalBatchProperty, TapesMatchTheScalarWalk, ()) {
    const Tape t(*gen_any_dag(40));
    const std::string m = mismatch(t.instrs(), *gen_boxes());
    RC_ASSERT(m == "");
}

RC_GTEST_PROP(IntervalBatchProperty, BasicOpTapesMatchTheScalarWalk, ()) {
    const Tape t(*testing::gen_dag(40));  // the ops of the renderer's scenes, more of each
    const std::string m = mismatch(t.instrs(), *gen_boxes());
    RC_ASSERT(m == "");
}

RC_GTEST_PROP(IntervalBatchProperty, SsaListsMatchTheScalarWalk, ()) {
    const Tape t(*gen_any_dag(40));
    const std::string m = mismatch(t.ssa(), *gen_boxes());
    RC_ASSERT(m == "");
}

/// n lanes of boxes for sin and cos: every width up to past a period, near the extrema kπ/2, and
/// across a kernel's edge |x| = `edge`, so that each lane's side of each end is chosen per lane.
Boxes trig_boxes(double edge) {
    const int n = *rc::gen::inRange(1, kIntervalLanes + 1);
    Boxes boxes(n);
    for (auto& box : boxes) {
        const int kind = *rc::gen::inRange(0, 4);
        double lo = 0, width = 0;
        if (kind == 0) {
            lo = *rc::gen::inRange(-20000, 20001) * 1e-3;
            width = *rc::gen::inRange(0, 7000) * 1e-3;
        } else if (kind == 1) {  // an extremum near an end
            lo = *rc::gen::inRange(-100, 101) * 1.5707963267948966 +
                 *rc::gen::inRange(-8, 9) * std::ldexp(1.0, *rc::gen::inRange(-52, -10));
            width = std::ldexp(1.0, *rc::gen::inRange(-50, 2));
        } else if (kind == 2) {  // the kernel's edge
            lo = (*rc::gen::arbitrary<bool>() ? 1 : -1) * edge + *rc::gen::inRange(-4, 2);
            width = *rc::gen::inRange(0, 4);
        } else {
            box[0] = *gen_box();
        }
        if (kind != 3) box[0] = UpInterval(lo, lo + width);
        box[1] = box[2] = box[0];
    }
    return boxes;
}

/// sin and cos (interval/trig_kernel.h on the lanes, the scalar sin() and cos() on one box) over
/// trig_boxes, the kernel's edge at 2¹⁹: bit for bit.
RC_GTEST_PROP(IntervalBatchProperty, SinAndCosMatchTheScalarWalk, ()) {
    const Boxes boxes = trig_boxes(0x1p19);
    for (const Op op : {Op::Sin, Op::Cos}) {
        const std::vector<Instr> list = {{Op::VarX, 0, 0, 0, 0.0}, {op, 1, 0, 0, 0.0}};
        const std::string m = mismatch(list, boxes);
        RC_ASSERT(m == "");
    }
}

/// Lists written by prune_ssa (slots numbered from the output backwards), pruned to a box.
RC_GTEST_PROP(IntervalBatchProperty, PrunedSsaListsMatchTheScalarWalk, ()) {
    const Tape t(*gen_any_dag(40));
    const std::vector<Instr>& ssa = t.ssa();
    std::array<UpInterval, 3> region;
    for (auto& v : region) v = *gen_box();
    std::vector<UpInterval> values(ssa.size());
    PruneWorkspace ws;
    std::vector<Instr> pruned;
    bool shorter = false;
    {
        RoundingScope up;
        detail::run<UpInterval>(ssa, region, values.data());
        shorter = prune_ssa(ssa, values.data(), ws, pruned);
    }
    RC_CLASSIFY(shorter);
    const std::string m = mismatch(shorter ? pruned : ssa, *gen_boxes());
    RC_ASSERT(m == "");
}

// ---- the binary32 walk -----------------------------------------------------------------------

TEST(IntervalBatchF32, OutwardRounding) {
    const float fmax = std::numeric_limits<float>::max();
    const float fsub = std::numeric_limits<float>::denorm_min();
    const float finf = std::numeric_limits<float>::infinity();
    // binary32 numbers are kept exactly, signed zeros included.
    for (double x : {0.0, 1.0, -2.5, 0.375, static_cast<double>(fmax), static_cast<double>(fsub)}) {
        EXPECT_EQ(lower_f32(x), static_cast<float>(x)) << x;
        EXPECT_EQ(upper_f32(x), static_cast<float>(x)) << x;
    }
    EXPECT_TRUE(std::signbit(lower_f32(-0.0)) && std::signbit(upper_f32(-0.0)));
    EXPECT_EQ(lower_f32(kInf), finf);
    EXPECT_EQ(upper_f32(-kInf), -finf);
    // 0.1 lies strictly between two binary32 neighbours 2⁻²⁷ apart (its exponent is −4).
    EXPECT_LT(static_cast<double>(lower_f32(0.1)), 0.1);
    EXPECT_GT(static_cast<double>(upper_f32(0.1)), 0.1);
    EXPECT_EQ(std::nextafter(lower_f32(0.1), finf), upper_f32(0.1));
    EXPECT_EQ(upper_f32(-0.1), -lower_f32(0.1));
    // Past the largest binary32 number and below the smallest subnormal.
    EXPECT_EQ(lower_f32(DBL_MAX), fmax);
    EXPECT_EQ(upper_f32(DBL_MAX), finf);
    EXPECT_EQ(lower_f32(-DBL_MAX), -finf);
    EXPECT_EQ(lower_f32(1e-300), 0.0f);
    EXPECT_EQ(upper_f32(1e-300), fsub);
    EXPECT_EQ(lower_f32(-1e-300), -fsub);
    EXPECT_TRUE(std::isnan(lower_f32(std::nan(""))) && std::isnan(upper_f32(std::nan(""))));
    // The same in upward mode, where the conversion itself rounds up.
    RoundingScope up;
    EXPECT_LT(static_cast<double>(lower_f32(0.1)), 0.1);
    EXPECT_EQ(lower_f32(-1e-300), -fsub);
    EXPECT_EQ(upper_f32(1e-300), fsub);
}

// In upward mode the branch-free roundings are lower_f32 and upper_f32, bit for bit: on binary32
// numbers, between them, past them and below them, at signed zeros, subnormals of both formats,
// infinities and NaN.
RC_GTEST_PROP(IntervalBatchF32Property, BranchFreeRoundingIsTheOutwardOne, ()) {
    const auto x = *rc::gen::oneOf(
        rc::gen::arbitrary<double>(),
        rc::gen::map(rc::gen::arbitrary<std::uint64_t>(),
                     [](std::uint64_t b) { return std::bit_cast<double>(b); }),
        rc::gen::map(rc::gen::arbitrary<float>(), [](float f) { return static_cast<double>(f); }),
        rc::gen::element(0.0, -0.0, 1e-300, -1e-300, 4.9e-324, -4.9e-324, 1.4e-45, 7e-46, -7e-46,
                         3.4028234663852886e38, 3.4028235e38 * 1.0000001, DBL_MAX, -DBL_MAX, kInf,
                         -kInf, std::nan("")));
    const float lo = lower_f32(x), hi = upper_f32(x);  // in the default mode
    float lo_up, hi_up;
    {
        RoundingScope up;
        lo_up = lower_f32_upward(x);
        hi_up = upper_f32_upward(x);
    }
    if (std::isnan(x)) {
        RC_ASSERT(std::isnan(lo_up) && std::isnan(hi_up));
        return;
    }
    RC_ASSERT(std::bit_cast<std::uint32_t>(lo_up) == std::bit_cast<std::uint32_t>(lo));
    RC_ASSERT(std::bit_cast<std::uint32_t>(hi_up) == std::bit_cast<std::uint32_t>(hi));
    RC_ASSERT(static_cast<double>(lo_up) <= x && x <= static_cast<double>(hi_up));
}

/// Runs `list` over `boxes` with the binary32 walk on every copy (as the host of this run) and
/// with the scalar double walk over the same boxes rounded outward to binary32 (the boxes the
/// binary32 walk sees). When `each_op`, every register of the binary32 walk must hold the scalar
/// one's interval (and be empty only where it is, defined only where it is): what one op over the
/// same operands must satisfy, since each binary32 bound is an operation rounded outward to
/// binary32 or a double bound rounded outward. Otherwise only the output is compared, by
/// `check(lane, got)`. Returns a description of the first failure, or "".
template <class Check>
std::string f32_failure(const std::vector<Instr>& list, const Boxes& boxes, bool each_op,
                        Check check) {
    const int n = static_cast<int>(boxes.size());
    const std::set<std::uint32_t> written = written_by(list);
    const std::uint32_t registers = *written.rbegin() + 1;
    std::array<IntervalLanesF, 3> p{};
    for (int i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) set_lane(p[k], i, boxes[i][k]);
    }
    std::vector<std::vector<UpInterval>> want(n, std::vector<UpInterval>(registers));
    {
        RoundingScope up;
        for (int i = 0; i < n; ++i) {
            const std::array<UpInterval, 3> box = {lane(p[0], i), lane(p[1], i), lane(p[2], i)};
            detail::run<UpInterval>(list, box, want[i].data());
        }
    }
    IsaGuard guard;
    std::vector<IntervalLanesF> r(registers);
    for (BatchIsa isa : batch_isas()) {
        walk_as_host(isa, list, p, r, n);
        for (std::uint32_t reg : written) {
            if (!each_op && reg != list.back().out) continue;
            for (int i = 0; i < n; ++i) {
                const UpInterval got = lane(r[reg], i), w = want[i][reg];
                std::string why;
                if (!each_op) {
                    why = check(i, got);
                } else if (!w.is_empty() && got.is_empty()) {
                    why = "empty";
                } else if (!w.is_empty() &&
                           !(got.lower() <= w.lower() && w.upper() <= got.upper())) {
                    why = "narrower";
                } else if (got.defined && !w.defined) {
                    why = "defined";
                }
                if (!why.empty()) {
                    std::ostringstream os;
                    os << batch_isa_name(isa) << " n=" << n << " lane " << i << " register " << reg
                       << ": " << why << ": binary32 " << show(got) << ", double " << show(w)
                       << "; box x " << show(boxes[i][0]) << " y " << show(boxes[i][1]) << " z "
                       << show(boxes[i][2]);
                    return os.str();
                }
            }
        }
    }
    return "";
}

std::string f32_op_failure(const std::vector<Instr>& list, const Boxes& boxes) {
    return f32_failure(list, boxes, true, [](int, const UpInterval&) { return std::string(); });
}

/// x ∘ y for every op on every pair of special boxes: the double walk's interval over the same
/// binary32 operands, or wider.
TEST(IntervalBatchF32, EveryOpOnEveryPairOfSpecialBoxes) {
    every_op_on_special_pairs(f32_op_failure);
}

/// Constants (rounded outward to binary32, exactly where they are binary32 numbers), and x ∘ x.
/// (An op on a constant is not compared with the double walk's: that one takes the constant
/// itself, and exp(1e−310) widened by its ulps is wider than exp([0, 2⁻¹⁴⁹]) = [1, …].)
TEST(IntervalBatchF32, ConstantsAndSharedOperands) {
    const std::vector<UpInterval> s = special_boxes();
    Boxes boxes;
    for (std::size_t i = 0; i < s.size(); ++i) boxes.push_back({s[i], s[i], s[i]});
    for (const Instr& op : every_op_instrs(2, 1, 1)) {
        const std::vector<Instr> list = {{Op::VarZ, 1, 0, 0, 0.0}, op, {op.op, 1, 1, 1, 0.0}};
        EXPECT_EQ(f32_op_failure(list, boxes), "") << name(op.op);
    }
    for (double c : {0.0, -0.0, 1.0, -3.5, 1e-310, DBL_MAX, 0.1}) {
        const std::vector<Instr> one = {{Op::Const, 0, 0, 0, c}};
        const std::string m = f32_failure(one, boxes, false, [c](int, const UpInterval& got) {
            const bool exact = got.lower() == static_cast<double>(lower_f32(c)) &&
                               got.upper() == static_cast<double>(upper_f32(c)) && got.defined;
            return exact ? std::string() : std::string("not the constant rounded outward");
        });
        EXPECT_EQ(m, "") << c;
    }
}

/// Constants to multiply by in the binary32 walk: not binary32 numbers (their lanes are no point),
/// binary32 ones (points), both signs, either zero, a subnormal (its lower bound rounds to 0), and
/// bounds that round to infinity.
const std::vector<double>& mul_constants() {
    static const std::vector<double> c = {
        2.618033988749895, 4.0,     0.1,      -0.1,  -3.5, 0.0, -0.0, 1e-310,
        -1e-310,           DBL_MAX, -DBL_MAX, 1e300, 0.5};
    return c;
}

/// c·x and x·c for each such constant c over every special box x (signed zeros, infinite and
/// empty bounds, subnormals, undefined), and c·(c·x): the binary32 result holds the double one.
TEST(IntervalBatchF32, ProductsByConstants) {
    const std::vector<UpInterval> s = special_boxes();
    Boxes boxes;
    for (const UpInterval& x : s) boxes.push_back({x, x, x});
    for (double c : mul_constants()) {
        for (bool first : {true, false}) {
            const std::uint32_t ka = first ? 0 : 1, kb = first ? 1 : 0;
            const std::vector<Instr> list = {{Op::Const, 0, 0, 0, c},
                                             {Op::VarX, 1, 0, 0, 0.0},
                                             {Op::Mul, 2, ka, kb, 0.0},
                                             {Op::Mul, 3, first ? 0u : 2u, first ? 2u : 0u, 0.0}};
            EXPECT_EQ(f32_op_failure(list, boxes), "") << c << (first ? " c·x" : " x·c");
        }
    }
}

/// A register that a Const wrote and then an op wrote again: products by it are those of the op's
/// lanes (a walk that took the register for the constant still would multiply wrongly).
TEST(IntervalBatchF32, ProductsByARegisterAConstLeft) {
    const std::vector<UpInterval> s = special_boxes();
    Boxes pairs;  // every pair (x, y) of special boxes
    for (const UpInterval& x : s) {
        for (const UpInterval& y : s) pairs.push_back({x, y, x});
    }
    for (double c : mul_constants()) {
        const std::vector<Instr> list = {{Op::Const, 0, 0, 0, c}, {Op::VarX, 1, 0, 0, 0.0},
                                         {Op::Mul, 2, 1, 0, 0.0}, {Op::VarY, 0, 0, 0, 0.0},
                                         {Op::Mul, 3, 1, 0, 0.0}, {Op::Mul, 0, 0, 2, 0.0}};
        for (std::size_t k = 0; k < pairs.size(); k += kIntervalLanes) {
            const Boxes boxes(pairs.begin() + static_cast<std::ptrdiff_t>(k),
                              pairs.begin() + static_cast<std::ptrdiff_t>(
                                                  std::min(pairs.size(), k + kIntervalLanes)));
            EXPECT_EQ(f32_op_failure(list, boxes), "") << c;
        }
    }
}

/// Random constants in either slot of a product over random boxes: the binary32 result holds
/// the double one over the same binary32 operands.
RC_GTEST_PROP(IntervalBatchF32Property, ProductsByRandomConstantsHoldTheDoubleInterval, ()) {
    const Boxes boxes = *gen_boxes();
    const double c = *testing::gen_finite_double();
    const bool first = *rc::gen::arbitrary<bool>();
    const std::vector<Instr> list = {{Op::VarX, 0, 0, 0, 0.0},
                                     {Op::Const, 1, 0, 0, c},
                                     {Op::Mul, 2, first ? 1u : 0u, first ? 0u : 1u, 0.0}};
    const std::string m = f32_op_failure(list, boxes);
    RC_ASSERT(m == "");
}

/// Every op over random boxes (the operands x and y of each lane), to a new register and in
/// place: the binary32 result holds the double one over the same binary32 operands.
RC_GTEST_PROP(IntervalBatchF32Property, EachOpHoldsTheDoubleIntervalOnRandomBoxes, ()) {
    const Boxes boxes = *gen_boxes();
    const std::uint32_t out = *rc::gen::inRange(0u, 3u);
    for (const Instr& op : every_op_instrs(out, 0, 1)) {
        const std::vector<Instr> list = {{Op::VarX, 0, 0, 0, 0.0}, {Op::VarY, 1, 0, 0, 0.0}, op};
        const std::string m = f32_op_failure(list, boxes);
        RC_ASSERT(m == "");
    }
}

/// sin and cos by the binary32 kernel (interval/trig_kernel_f32.h) over trig_boxes, the kernel's
/// edge at 2⁹: the double walk's interval over the same binary32 boxes, or wider.
RC_GTEST_PROP(IntervalBatchF32Property, SinAndCosHoldTheDoubleInterval, ()) {
    const Boxes boxes = trig_boxes(0x1p9);
    for (const Op op : {Op::Sin, Op::Cos}) {
        const std::vector<Instr> list = {{Op::VarX, 0, 0, 0, 0.0}, {op, 1, 0, 0, 0.0}};
        const std::string m = f32_op_failure(list, boxes);
        RC_ASSERT(m == "");
    }
}

/// Random DAGs of every op, at a random point of each lane's box: the binary32 walk's enclosure
/// over the box holds f's value there by MPFR at 256 bits, and where it says defined, f is.
RC_GTEST_PROP(IntervalBatchF32Property, EnclosesMpfrAtPointsOfTheBoxes, ()) {
    const Tape t(*gen_any_dag(24));
    const int n = *rc::gen::inRange(1, kIntervalLanes + 1);
    Boxes boxes(n);
    std::vector<std::array<double, 3>> points(n);
    for (int i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            const auto [lo, hi] = *testing::gen_bounds();
            boxes[i][k] = UpInterval(lo, hi);
            points[i][k] = *testing::gen_point_in(lo, hi);
        }
    }
    const bool ssa = *rc::gen::arbitrary<bool>();
    const std::string m =
        f32_failure(ssa ? t.ssa() : t.instrs(), boxes, false, [&](int i, const UpInterval& got) {
            const MpfrInterval exact =
                eval<MpfrInterval>(t, {MpfrInterval(points[i][0]), MpfrInterval(points[i][1]),
                                       MpfrInterval(points[i][2])});
            if (!testing::encloses(got.lower(), got.upper(), exact)) {
                return "misses " + testing::describe(exact);
            }
            if (got.defined && exact.is_empty()) return std::string("defined where f is not");
            return std::string();
        });
    RC_ASSERT(m == "");
}

}  // namespace
}  // namespace certray::expr
