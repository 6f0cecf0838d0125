// tests/tracers/region_tapes_test.cpp — region-pruned tapes (tracers/region_tapes.h): the tape
// at a point is f there, bit for bit in double, on a min/max-heavy scene (eagerly and lazily built
// cells); an enclosure over a box on its region's tape lies in the full tape's; cells built on
// demand, from one thread or several at once, are the eager tree's; the budget holds; and every
// approximate tracer, which now evaluates on those tapes, answers a sphere union whose first roots
// are known by hand.
#include "tracers/region_tapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "expr/eval.h"
#include "expr/parser.h"
#include "expr/prune.h"
#include "expr/tape.h"
#include "tracers/methods.h"

namespace certray::tracers {
namespace {

using expr::Tape;
using Box = RegionTapes::Box;

/// Two spheres, |p| − 0.5 and |p − (1, 0, 0)| − 0.3, united with 64 small spheres of radius 0.05
/// on the plane z = 1.5 and cut by max with the slab |z| ≤ 1.9 (a min/max-heavy tape: 66 sqrt,
/// 65 min, one max). No small sphere reaches z < 1.45, so the rays below at z = 0 meet only the
/// first two spheres.
std::string scene_text() {
    std::string s = "min(sqrt(x^2 + y^2 + z^2) - 0.5, sqrt((x - 1)^2 + y^2 + z^2) - 0.3)";
    for (int i = 0; i < 8; ++i) {
        for (int j = 0; j < 8; ++j) {
            const double cx = -1.75 + 0.5 * i, cy = -1.75 + 0.5 * j;
            s = "min(" + s + ", sqrt((x - " + std::to_string(cx) + ")^2 + (y - " +
                std::to_string(cy) + ")^2 + (z - 1.5)^2) - 0.05)";
        }
    }
    return "max(" + s + ", abs(z) - 1.9)";
}

const Box kBounds{Interval(-2, 2), Interval(-2, 2), Interval(-2, 2)};

bool same_bits(double a, double b) {
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

TEST(RegionTapes, ShorterTapesThatEqualTheFullTapeAtRandomPointsOfRandomCells) {
    const Tape tape(expr::parse_expr(scene_text()));
    const RegionTapes regions(tape, kBounds);
    const RegionStats& st = regions.stats();
    // Not vacuous: the tree was split and its leaves hold far shorter tapes.
    ASSERT_GT(st.cells, 1u);
    EXPECT_LT(st.mean_leaf_instructions, tape.size() / 4.0);
    std::mt19937_64 rng(20261124);
    std::uniform_int_distribution<int> level_of(0, 5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    expr::Evaluator<double> full_eval, region_eval;
    int shorter = 0;
    for (int cell = 0; cell < 400; ++cell) {
        // A random cell of a random level (5: deeper than the tree), then points inside it.
        const int level = level_of(rng);
        const double side = 4.0 / (1 << level);
        std::array<double, 3> lo;
        for (int i = 0; i < 3; ++i) {
            lo[i] = -2 + side * std::floor(unit(rng) * (1 << level));
        }
        for (int k = 0; k < 20; ++k) {
            std::array<double, 3> p;
            for (int i = 0; i < 3; ++i) p[i] = lo[i] + side * unit(rng);
            const Tape& t = regions.at(p);
            shorter += t.size() < tape.size();
            const double want = full_eval(tape, p), got = region_eval(t, p);
            ASSERT_TRUE(same_bits(want, got))
                << "at (" << p[0] << ", " << p[1] << ", " << p[2] << "): full " << want
                << ", region tape (" << t.size() << " instructions) " << got;
        }
    }
    EXPECT_GT(shorter, 7000);  // of 8,000 points, nearly all get a pruned tape
}

TEST(RegionTapes, EnclosuresOverBoxesLieInTheFullTapesAndPointsOutsideUseTheFullTape) {
    const Tape tape(expr::parse_expr(scene_text()));
    const RegionTapes regions(tape, kBounds);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> coord(-2.2, 2.2), size(0.0, 0.6);
    expr::Evaluator<Interval> full_eval, region_eval;
    for (int k = 0; k < 2000; ++k) {
        Box b;
        for (int i = 0; i < 3; ++i) {
            const double a = coord(rng);
            b[i] = Interval(a, a + size(rng));
        }
        const Tape& t = regions.at(b);
        const Interval want = full_eval(tape, b), got = region_eval(t, b);
        EXPECT_TRUE(want.lower() <= got.lower() && got.upper() <= want.upper())
            << "full [" << want.lower() << ", " << want.upper() << "], region [" << got.lower()
            << ", " << got.upper() << "]";
        bool outside = false;
        for (int i = 0; i < 3; ++i) outside = outside || b[i].upper() > 2.0 || b[i].lower() < -2.0;
        if (outside) {
            EXPECT_EQ(&t, &tape);
        }
    }
    EXPECT_EQ(&regions.at(std::array<double, 3>{3.0, 0.0, 0.0}), &tape);
}

/// Options that build the tree to `depth` up front (eager) or nothing below the root (lazy), with
/// budgets that the test scene does not reach.
RegionOptions tree_options(int depth, bool eager) {
    RegionOptions o;
    o.max_depth = depth;
    o.eager_depth = eager ? depth : 0;
    o.max_cells = std::size_t{1} << 20;
    o.max_instructions = o.eager_instructions = std::size_t{1} << 30;
    return o;
}

bool same_list(const Tape& a, const Tape& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const expr::Instr &x = a.ssa()[i], &y = b.ssa()[i];
        if (x.op != y.op || x.a != y.a || x.b != y.b || !same_bits(x.imm, y.imm)) return false;
    }
    return true;
}

/// Random query boxes over kBounds (and a little beyond): points, and boxes from 2⁻¹² to 1 wide.
std::vector<Box> random_queries(std::uint64_t seed, int n) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> coord(-2.1, 2.1), unit(0.0, 1.0);
    std::vector<Box> q(n);
    for (Box& b : q) {
        const bool point = unit(rng) < 0.5;
        const double w = point ? 0.0 : std::ldexp(1.0, -static_cast<int>(12 * unit(rng)));
        for (int i = 0; i < 3; ++i) {
            const double a = coord(rng);
            b[i] = Interval(a, a + w);
        }
    }
    return q;
}

TEST(RegionTapes, LazilyBuiltCellsAreTheEagerTreesCells) {
    const Tape tape(expr::parse_expr(scene_text()));
    const RegionTapes eager(tape, kBounds, tree_options(5, true));
    const RegionTapes lazy(tape, kBounds, tree_options(5, false));
    ASSERT_EQ(lazy.stats().cells, 1u);  // nothing below the root yet
    const RegionStats before = eager.stats();
    int deeper = 0;
    for (const Box& q : random_queries(11, 4000)) {
        const Tape &want = eager.at(q), &got = lazy.at(q);
        deeper += got.size() < lazy.tape().size();
        ASSERT_TRUE(same_list(want, got))
            << "query box at (" << q[0].lower() << ", " << q[1].lower() << ", " << q[2].lower()
            << ") width " << width(q[0]) << ": eager " << want.size() << " instructions, lazy "
            << got.size();
    }
    EXPECT_GT(deeper, 2000);
    const RegionStats st = lazy.stats();
    EXPECT_GT(st.lazy_cells, 100u);
    EXPECT_EQ(st.lazy_cells + 1, st.cells);
    EXPECT_LT(st.cells, before.cells);             // only the cells the queries needed
    EXPECT_EQ(eager.stats().cells, before.cells);  // the eager tree had every cell already
    EXPECT_EQ(eager.stats().lazy_cells, 0u);
}

TEST(RegionTapes, LazilyBuiltDeepCellsEqualTheFullTapeAtRandomPoints) {
    const Tape tape(expr::parse_expr(scene_text()));
    const RegionTapes regions(tape, kBounds, tree_options(7, false));
    std::mt19937_64 rng(20261125);
    std::uniform_int_distribution<int> level_of(3, 8);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    expr::Evaluator<double> full_eval, region_eval;
    expr::Evaluator<Interval> full_box, region_box;
    for (int cell = 0; cell < 300; ++cell) {
        const int level = level_of(rng);
        const double side = 4.0 / (1 << level);
        Box c;
        for (int i = 0; i < 3; ++i) {
            const double lo = -2 + side * std::floor(unit(rng) * (1 << level));
            c[i] = Interval(lo, lo + side);
        }
        // The cell's own box: its enclosure on the region tape lies in the full tape's.
        const Tape& tc = regions.at(c);
        const Interval want = full_box(tape, c), got = region_box(tc, c);
        EXPECT_TRUE(want.lower() <= got.lower() && got.upper() <= want.upper());
        for (int k = 0; k < 20; ++k) {
            std::array<double, 3> p;
            for (int i = 0; i < 3; ++i) p[i] = c[i].lower() + side * unit(rng);
            const Tape& t = regions.at(p);
            const double f = full_eval(tape, p), g = region_eval(t, p);
            ASSERT_TRUE(same_bits(f, g))
                << "at (" << p[0] << ", " << p[1] << ", " << p[2] << "): full " << f
                << ", region tape (" << t.size() << " instructions) " << g;
        }
    }
    const RegionStats st = regions.stats();
    EXPECT_EQ(st.depth, 7);  // the points reached the deepest level
    EXPECT_LT(st.mean_leaf_instructions, tape.size());
}

TEST(RegionTapes, ThreadsQueryingAtOnceBuildOneTree) {
    // Four threads ask the same queries of one lazy tree in different orders (each child is
    // built by one of them, the others waiting for it): every answer is the eager tree's, the
    // same cell's tape for every thread, and equal to f at the points.
    const Tape tape(expr::parse_expr(scene_text()));
    const RegionTapes eager(tape, kBounds, tree_options(6, true));
    const RegionTapes lazy(tape, kBounds, tree_options(6, false));
    const std::vector<Box> queries = random_queries(5, 3000);
    constexpr int kThreads = 4;
    std::vector<std::vector<const Tape*>> got(kThreads, std::vector<const Tape*>(queries.size()));
    std::vector<int> wrong(kThreads, 0);
    std::vector<std::thread> threads;
    for (int k = 0; k < kThreads; ++k) {
        threads.emplace_back([&, k] {
            expr::Evaluator<double> full_eval, region_eval;
            std::vector<std::size_t> order(queries.size());
            for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
            std::shuffle(order.begin(), order.end(), std::mt19937_64(k));
            for (std::size_t i : order) {
                const Tape& t = lazy.at(queries[i]);
                got[k][i] = &t;
                const std::array<double, 3> p{queries[i][0].lower(), queries[i][1].lower(),
                                              queries[i][2].lower()};
                wrong[k] += !same_bits(full_eval(tape, p), region_eval(t, p));
            }
        });
    }
    for (std::thread& t : threads) t.join();
    for (int k = 0; k < kThreads; ++k) {
        EXPECT_EQ(wrong[k], 0) << "thread " << k;
        for (std::size_t i = 0; i < queries.size(); ++i) {
            ASSERT_EQ(got[k][i], got[0][i]) << "query " << i << ", thread " << k;
            ASSERT_TRUE(same_list(*got[k][i], eager.at(queries[i]))) << "query " << i;
        }
    }
    EXPECT_GT(lazy.stats().lazy_cells, 100u);
}

TEST(RegionTapes, BudgetBoundsTheStoredInstructions) {
    const Tape tape(expr::parse_expr(scene_text()));
    RegionOptions o = tree_options(7, false);
    o.max_instructions = 20 * tape.size();
    o.max_cells = 300;
    const RegionTapes regions(tape, kBounds, o);
    expr::Evaluator<double> full_eval, region_eval;
    for (const Box& q : random_queries(3, 5000)) {
        const Tape& t = regions.at(q);
        const std::array<double, 3> p{q[0].lower(), q[1].lower(), q[2].lower()};
        ASSERT_TRUE(same_bits(full_eval(tape, p), region_eval(t, p)));
    }
    const RegionStats st = regions.stats();
    EXPECT_LE(st.instructions, o.max_instructions);
    EXPECT_LE(st.cells, o.max_cells);
    EXPECT_GT(st.cells, 20u);  // it did build until the budget ran out
}

TEST(RegionTapes, PolynomialKeepsOneCell) {
    // Nothing to prune in x⁴ − 5x² + …: no cell is split.
    const Tape tape(expr::parse_expr("x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8"));
    const RegionTapes regions(tape, kBounds);
    EXPECT_EQ(regions.stats().cells, 1u);
}

TEST(RegionTapes, SmoothUnionKernelFoldedToZeroLeavesTheNearSphereAlone) {
    // A smooth union (Lipschitz-Pruning's blend, expr/csg_shapes.cpp) of two spheres 5 apart:
    // min(a, b) − max(k − |a − b|, 0)²/(4k). Near the first one |a − b| > k, so the kernel is 0
    // and min(a, b) = a there: pruning leaves exactly a's instructions (the `− 0` dropped too).
    const std::string a = "sqrt(x^2 + y^2 + z^2) - 0.5";
    const std::string b = "sqrt((x - 5)^2 + y^2 + z^2) - 0.5";
    const Tape blend(expr::parse_expr("a = " + a + "\nb = " + b +
                                      "\nmin(a, b) - square(max(0.2 - abs(a - b), 0)) / 0.8"));
    const Tape alone(expr::parse_expr(a));
    const Box near{Interval(-0.1, 0.1), Interval(-0.1, 0.1), Interval(-0.1, 0.1)};
    const expr::PruneResult p = expr::prune(blend, near);
    EXPECT_EQ(p.after, alone.size());
    expr::Evaluator<double> e1, e2;
    for (double x : {-0.1, -0.03, 0.0, 0.07, 0.1}) {
        const std::array<double, 3> q{x, 0.05, -0.02};
        EXPECT_TRUE(same_bits(e1(blend, q), e2(p.tape, q))) << x;
    }
}

/// A ray along +x at height y from x = x0 (‖d‖ = 1, so t is a distance).
Ray along_x(double x0, double y) { return Ray{{x0, y, 0}, {1, 0, 0}, 0, 10}; }

TEST(RegionTapes, EveryApproximateTracerAnswersTheSphereUnion) {
    // First roots by hand (z = 0, the small spheres are at z ≥ 1.45):
    //   from (−3, 0): the sphere |p| = 0.5 at x = −0.5, t = 2.5;
    //   from (−3, 0.4): x = −√(0.25 − 0.16) = −0.3, t = 2.7;
    //   from (0.6, 0.2): outside the first sphere (0.6² + 0.2² > 0.25), the second one at
    //   x = 1 − √(0.09 − 0.04), t = 0.4 − √0.05;
    //   from (−3, 0.6): above both spheres (0.6 > 0.5 > 0.3): no root in the bounds or beyond.
    const Tape tape(expr::parse_expr(scene_text()));
    struct Case {
        Ray ray;
        Status status;
        double root;
    };
    const Case cases[] = {
        {along_x(-3, 0), Status::Hit, 2.5},
        {along_x(-3, 0.4), Status::Hit, 2.7},
        {along_x(0.6, 0.2), Status::Hit, 0.4 - std::sqrt(0.05)},
        {along_x(-3, 0.6), Status::Miss, 0},
    };
    MethodOptions o;
    o.bounds = kBounds;
    for (const char* m : {"sphere", "enhanced", "segment", "octree", "bvh", "march"}) {
        const RayFunction fn = make_method(m, tape, o);
        for (const Case& c : cases) {
            const RayResult r = fn(c.ray);
            ASSERT_EQ(r.status, c.status)
                << m << " from (" << c.ray.o[0] << ", " << c.ray.o[1] << ")";
            if (c.status != Status::Hit) continue;
            // Within 10⁻⁴ of the root; past it only by march's bracket (ε = 10⁻⁶).
            EXPECT_LE(r.t_lo, c.root) << m;
            EXPECT_LE(r.t, c.root + 1e-6) << m;
            EXPECT_GE(r.t, c.root - 1e-4) << m;
        }
    }
}

}  // namespace
}  // namespace certray::tracers
