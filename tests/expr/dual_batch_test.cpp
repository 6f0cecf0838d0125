// tests/expr/dual_batch_test.cpp — the Dual<double, 3> walk over lanes (expr/eval_dual_batch.h)
// against detail::run<Dual<double, 3>> point by point, bit for bit: every register's value and
// partials in every lane, signed zeros included (a NaN for a NaN), on every copy of the walk this
// CPU runs. Cases: random DAGs of the renderer's ops (as SSA lists) at random points (gen_double's
// mix: zeros of both signs, subnormals, huge values, infinities) for 1 to kDualLanes lanes; and
// every op of the .vm language on every pair of special values.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

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
#include "expr/eval_dual_batch.h"
#include "expr/graph.h"
#include "expr/tape.h"
#include "interval/dual.h"
#include "tests/support/batch_isa.h"
#include "tests/support/generators.h"
#include "tests/support/random_dag.h"

namespace certray::expr {
namespace {

using D3 = Dual<double, 3>;
using Points = std::vector<std::array<double, 3>>;

/// The same bits, or both NaN (a NaN's sign and payload follow which operand the compiler puts
/// first, in either walk).
bool same_bits(double a, double b) {
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b) ||
           (std::isnan(a) && std::isnan(b));
}

/// Runs the SSA list `list` at `points` with run<D3> point by point and with run_dual_batch on
/// every copy, and compares every register written in every lane. Returns the first mismatch, or
/// "".
std::string mismatch(const std::vector<Instr>& list, const Points& points) {
    const int n = static_cast<int>(points.size());
    std::set<std::uint32_t> written;
    for (const Instr& in : list) written.insert(in.out);
    const std::size_t registers = *written.rbegin() + 1;
    std::vector<std::vector<D3>> want(n, std::vector<D3>(registers));
    for (int k = 0; k < n; ++k) {
        const auto& q = points[static_cast<std::size_t>(k)];
        detail::run<D3>(list, {D3::variable(q[0], 0), D3::variable(q[1], 1), D3::variable(q[2], 2)},
                        want[static_cast<std::size_t>(k)].data());
    }
    testing::BatchIsaGuard guard;
    std::vector<DualLanes> r(registers);
    for (BatchIsa isa : testing::batch_isas()) {
        set_batch_isa(isa);
        for (DualLanes& x : r) {  // stale values, so that a lane left unwritten shows
            for (int k = 0; k < kDualLanes; ++k) {
                x.v[k] = -12345.0;
                for (auto& g : x.g) g[k] = -12345.0;
            }
        }
        run_dual_batch(list.data(), list.data() + list.size(), points.data(), n, r.data());
        for (std::uint32_t reg : written) {
            for (int k = 0; k < n; ++k) {
                const D3& w = want[static_cast<std::size_t>(k)][reg];
                const DualLanes& x = r[reg];
                bool ok = same_bits(x.v[k], w.a);
                for (int i = 0; i < 3; ++i) ok = ok && same_bits(x.g[i][k], w.v[i]);
                if (!ok) {
                    std::ostringstream os;
                    os.precision(17);
                    os << batch_isa_name(isa) << " n=" << n << " lane " << k << " register " << reg
                       << " (" << name(list[reg].op) << "): batch (" << x.v[k] << "; " << x.g[0][k]
                       << ", " << x.g[1][k] << ", " << x.g[2][k] << "), scalar (" << w.a << "; "
                       << w.v[0] << ", " << w.v[1] << ", " << w.v[2] << ")";
                    return os.str();
                }
            }
        }
    }
    return "";
}

rc::Gen<Points> gen_points() {
    return rc::gen::exec([] {
        const int n = *rc::gen::inRange(1, kDualLanes + 1);
        Points p(static_cast<std::size_t>(n));
        for (auto& q : p) {
            for (double& c : q) {
                c = *rc::gen::weightedOneOf<double>(
                    {{3, testing::gen_double()},
                     {3, rc::gen::map(rc::gen::inRange(-2000, 2001),
                                      [](int k) { return k / 1000.0; })}});
            }
        }
        return p;
    });
}

RC_GTEST_PROP(DualBatchProperty, SsaListsMatchTheScalarWalk, ()) {
    const Tape t(*testing::gen_dag(40));
    const std::string m = mismatch(t.ssa(), *gen_points());
    RC_ASSERT(m == "");
}

TEST(DualBatch, EveryOpOnEveryPairOfSpecialValues) {
    const double inf = std::numeric_limits<double>::infinity();
    const std::vector<double> special = {0.0, -0.0, 1.0,     -1.0,      2.5,   -0.75,
                                         inf, -inf, DBL_MAX, 0x1p-1074, 1e300, 3.0};
    Points all;
    for (double a : special) {
        for (double b : special) all.push_back({a, b, 0.5});
    }
    for (int code = 0; code < kOpCount; ++code) {
        const Op op = static_cast<Op>(code);
        if (arity(op) == 0) continue;
        // x, y, then one op reading x·y and y (so that both operands carry partials); Pow with
        // exponents 0 … 5, 16 and 31 (its vector loop's zero, odd, even and long chains).
        const std::vector<std::uint32_t> exponents =
            op == Op::Pow ? std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5, 16, 31}
                          : std::vector<std::uint32_t>{1};
        for (const std::uint32_t e : exponents) {
            std::vector<Instr> list = {{Op::VarX, 0, 0, 0, 0.0},
                                       {Op::VarY, 1, 0, 0, 0.0},
                                       {Op::Mul, 2, 0, 1, 0.0},
                                       {op, 3, 2, e, 0.0}};
            for (std::size_t k = 0; k < all.size(); k += kDualLanes) {
                const Points chunk(all.begin() + static_cast<std::ptrdiff_t>(k),
                                   all.begin() + static_cast<std::ptrdiff_t>(
                                                     std::min(all.size(), k + kDualLanes)));
                EXPECT_EQ(mismatch(list, chunk), "") << name(op) << " " << e;
            }
        }
    }
}

TEST(DualBatch, GradientOfAKnownFunction) {
    // f = x·y + sin(z): at (2, 3, 0) the value 6 and the gradient (3, 2, cos 0 = 1).
    const std::vector<Instr> list = {{Op::VarX, 0, 0, 0, 0.0}, {Op::VarY, 1, 0, 0, 0.0},
                                     {Op::VarZ, 2, 0, 0, 0.0}, {Op::Mul, 3, 0, 1, 0.0},
                                     {Op::Sin, 4, 2, 0, 0.0},  {Op::Add, 5, 3, 4, 0.0}};
    const Points p = {{2.0, 3.0, 0.0}};
    std::vector<DualLanes> r(list.size());
    run_dual_batch(list.data(), list.data() + list.size(), p.data(), 1, r.data());
    EXPECT_EQ(r[5].v[0], 6.0);
    EXPECT_EQ(r[5].g[0][0], 3.0);
    EXPECT_EQ(r[5].g[1][0], 2.0);
    EXPECT_EQ(r[5].g[2][0], 1.0);
}

}  // namespace
}  // namespace certray::expr
