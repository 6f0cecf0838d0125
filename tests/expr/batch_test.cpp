// tests/expr/batch_test.cpp — Evaluator<Batch> against eval<double>, lane by lane, bit for bit.
#include "interval/batch.h"
// eval.h before builder.h: builder.h declares expr::min, sqrt, … which, seen first, would hide
// certray::min(double, double) etc. from the unqualified calls in detail::run.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "expr/builder.h"
#include "expr/eval.h"
#include "expr/graph.h"
#include "expr/tape.h"
#include "tests/support/generators.h"
#include "tests/support/random_dag.h"

namespace certray::expr {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Same bits, or both NaN (the payload of a NaN is not part of the contract).
bool same(double a, double b) {
    return (std::isnan(a) && std::isnan(b)) ||
           std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

/// kBatch points: the special values first (zeros of both signs, ±inf, NaN, tiny, huge), then
/// pseudo-random points in [-span, span]³.
std::array<Batch, 3> points(unsigned seed, double span) {
    const std::vector<double> special = {0.0,  -0.0,   1.0,     -1.0,  kInf,   -kInf,
                                         kNaN, 1e-310, -1e-310, 1e300, -1e300, 0.5};
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-span, span);
    std::array<Batch, 3> p;
    for (int i = 0; i < kBatch; ++i) {
        for (int k = 0; k < 3; ++k) {
            const std::size_t j = static_cast<std::size_t>(i * 3 + k);
            p[k][i] =
                (i < 24) ? special[(j * 7 + static_cast<std::size_t>(i)) % special.size()] : u(rng);
        }
    }
    return p;
}

/// Checks every lane of Evaluator<Batch> against eval<double> at that lane's point.
void expect_lanes_match(const Graph& g, const std::array<Batch, 3>& p) {
    const Tape t(g);
    Evaluator<Batch> eb;
    const Batch r = eb(t, p);
    Evaluator<double> ed;
    for (int i = 0; i < kBatch; ++i) {
        const double d = ed(t, {p[0][i], p[1][i], p[2][i]});
        EXPECT_TRUE(same(r[i], d)) << "lane " << i << " at (" << p[0][i] << ", " << p[1][i] << ", "
                                   << p[2][i] << "): batch " << r[i] << ", double " << d;
    }
}

void expect_lanes_match(const Graph& g) {
    for (unsigned seed : {1u, 2u, 3u}) {
        expect_lanes_match(g, points(seed, 2.0));
        expect_lanes_match(g, points(seed + 10, 50.0));
    }
}

TEST(Batch, IsANumber) { static_assert(Number<Batch>); }

TEST(Batch, Sphere) {
    Graph g;
    auto [x, y, z] = vars(g);
    g.set_output((sqrt(x * x + y * y + z * z) - 1.0).id);
    expect_lanes_match(g);
}

TEST(Batch, MinMaxCsg) {
    // (sphere ∪ box) minus a smaller sphere: max(min(s1, b), −s2).
    Graph g;
    auto [x, y, z] = vars(g);
    auto s1 = sqrt(square(x - 0.5) + square(y) + square(z)) - 1.0;
    auto b = max(max(abs(x + 0.5) - 0.7, abs(y) - 0.7), abs(z) - 0.7);
    auto s2 = sqrt(square(x) + square(y - 0.25) + square(z)) - 0.5;
    g.set_output(max(min(s1, b), -s2).id);
    expect_lanes_match(g);
}

TEST(Batch, NaNFromSqrtAndLogOfNegatives) {
    // sqrt(x) and log(y) are NaN for negative inputs; min/max must keep the NaN in either slot.
    Graph g;
    auto [x, y, z] = vars(g);
    g.set_output(max(min(sqrt(x), z), min(z, log(y))).id);
    expect_lanes_match(g);
    Evaluator<Batch> e;
    const Batch r = e(Tape(g), {Batch(-1.0), Batch(2.0), Batch(0.0)});
    for (int i = 0; i < kBatch; ++i) EXPECT_TRUE(std::isnan(r[i]));
}

TEST(Batch, SignedZeroTiesOfMinAndMax) {
    // certray::min(−0, +0) = +0 and min(+0, −0) = −0 (the second operand on a tie); the batch
    // must give the same signs.
    for (const bool use_max : {false, true}) {
        Graph g;
        auto [x, y, z] = vars(g);
        g.set_output((use_max ? max(x, y) : min(x, y)).id);
        Batch a(0.0), b(0.0);
        for (int i = 0; i < kBatch; i += 2) a[i] = -0.0;
        for (int i = 1; i < kBatch; i += 2) b[i] = -0.0;
        expect_lanes_match(g, {a, b, Batch(0.0)});
    }
}

TEST(Batch, EveryOp) {
    Graph g;
    auto [x, y, z] = vars(g);
    auto f = exp(sin(x) * cos(y)) + log(abs(z) + 0.5) - pow(x, 5) / (square(y) + 1.0);
    f = f + pow(z, 0) * pow(y, 1) * pow(x, 2) - (-sqrt(abs(x * y)));
    f = max(min(f, 3.0 * x), -(y / z));  // y / z: ±inf and NaN at z = ±0
    g.set_output(f.id);
    expect_lanes_match(g);
}

RC_GTEST_PROP(BatchProperty, RandomDagsMatchDoubleLaneByLane, ()) {
    const Graph g = *testing::gen_dag();
    const Tape t(g);
    std::array<Batch, 3> p;
    for (int i = 0; i < kBatch; ++i) {
        for (int k = 0; k < 3; ++k) p[k][i] = *testing::gen_double();
    }
    Evaluator<Batch> eb;
    const Batch r = eb(t, p);
    Evaluator<double> ed;
    for (int i = 0; i < kBatch; ++i) {
        const double d = ed(t, {p[0][i], p[1][i], p[2][i]});
        RC_ASSERT(same(r[i], d));
    }
}

}  // namespace
}  // namespace certray::expr
