// tests/interval/poly_test.cpp — Poly<T>: arithmetic against hand expansion, the invalid paths,
// branch decisions on dom, the gallery's algebraic scenes, and enclosure of the MPFR value of
// f(o + t·d) over random polynomial DAGs (RapidCheck).
#include "interval/poly.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "expr/eval.h"
#include "expr/graph.h"
#include "expr/load.h"
#include "expr/parser.h"
#include "expr/tape.h"
#include "interval/interval.h"
#include "interval/mpfr_interval.h"
#include "tests/support/mpfr_oracle.h"
#include "tests/support/random_dag.h"

namespace certray {
namespace {

using P = Poly<Interval>;

/// The coefficient enclosure k is the point v.
void expect_point(const P& p, int k, double v) {
    EXPECT_EQ(p.c[k].lower(), v) << "coefficient " << k;
    EXPECT_EQ(p.c[k].upper(), v) << "coefficient " << k;
}

P ray_x(double o, double d, double lo = 0.0, double hi = 1.0) {
    return ray_coordinate<Interval>(o, d, Interval(lo, hi));
}

TEST(Poly, CubeOfALineExpandsExactly) {
    const P x = ray_x(1, 2);  // 1 + 2t
    const P p = pow(x, 3u);   // 1 + 6t + 12t² + 8t³
    ASSERT_TRUE(p.valid);
    ASSERT_EQ(p.degree, 3);
    expect_point(p, 0, 1);
    expect_point(p, 1, 6);
    expect_point(p, 2, 12);
    expect_point(p, 3, 8);
    const P q = x * x * x;
    for (int k = 0; k <= 3; ++k) expect_point(q, k, p.c[k].lower());
    const P s = square(x) - P(1.0);  // 4t + 4t²
    ASSERT_EQ(s.degree, 2);
    expect_point(s, 0, 0);
    expect_point(s, 1, 4);
    expect_point(s, 2, 4);
    const P n = -(x + P(3.0));  // −4 − 2t
    expect_point(n, 0, -4);
    expect_point(n, 1, -2);
    const P h = x / P(2.0);
    expect_point(h, 0, 0.5);
    expect_point(h, 1, 1.0);
}

TEST(Poly, RayCoordinateAndEvaluation) {
    const P x = ray_x(0.5, -0.25, -1, 3);
    EXPECT_TRUE(x.valid);
    EXPECT_TRUE(x.has_dom);
    EXPECT_EQ(x.degree, 1);
    EXPECT_EQ(ray_x(0.5, 0.0).degree, 0);
    const Interval v = horner(pow(ray_x(1, 2), 3u), Interval(0.5));  // (1 + 1)³ = 8
    EXPECT_EQ(v.lower(), 8.0);
    EXPECT_EQ(v.upper(), 8.0);
    // (1 + 2t)³ is increasing on [0, 1]: its range is [1, 27], attained exactly.
    const Interval r = range(pow(ray_x(1, 2), 3u));
    EXPECT_EQ(r.lower(), 1.0);
    EXPECT_EQ(r.upper(), 27.0);
    // t² − t on [0, 1] has range [−1/4, 0]; the centred form gives [−1/4, 1/4] at worst.
    const P t = ray_x(0, 1);
    const Interval r2 = range(square(t) - t);
    EXPECT_LE(r2.lower(), -0.25);
    EXPECT_GE(r2.lower(), -0.5);
    EXPECT_GE(r2.upper(), 0.0);
    EXPECT_LE(r2.upper(), 0.25);
}

TEST(Poly, InvalidPaths) {
    const P x = ray_x(0, 1);
    EXPECT_FALSE(sqrt(x).valid);
    EXPECT_FALSE(exp(x).valid);
    EXPECT_FALSE(log(x).valid);
    EXPECT_FALSE(sin(x).valid);
    EXPECT_FALSE(cos(x).valid);
    EXPECT_FALSE((P(1.0) / x).valid);             // non-constant divisor
    EXPECT_FALSE((x / (P(1.0) - P(1.0))).valid);  // divisor [0, 0]
    EXPECT_FALSE((x / (x - x + P(0.0))).valid);   // degree-1 divisor, even if ≡ 0
    EXPECT_FALSE(min(x, P(0.5)).valid);           // x − 0.5 changes sign on [0, 1]
    EXPECT_FALSE(abs(x - P(0.5)).valid);
    EXPECT_FALSE(pow(x, 17u).valid);  // degree 17 > 16
    EXPECT_TRUE(pow(x, 16u).valid);
    EXPECT_FALSE((pow(x, 9u) * pow(x, 8u)).valid);
    EXPECT_FALSE(square(pow(x, 9u)).valid);
    EXPECT_FALSE(sqrt(P(-1.0)).valid);  // undefined constant
    EXPECT_FALSE(log(P(0.0)).valid);
    EXPECT_FALSE(P(std::nan("")).valid);
    const P bad = sqrt(x);
    EXPECT_FALSE((bad * P(0.0) + P(1.0)).valid);  // stays invalid
    EXPECT_FALSE((-bad).valid);
    EXPECT_FALSE(square(bad).valid);
    EXPECT_FALSE(horner(bad, Interval(0.5)).defined);
}

TEST(Poly, ConstantsUseTheirEnclosures) {
    const P two = sqrt(P(4.0));
    ASSERT_TRUE(two.valid);
    expect_point(two, 0, 2.0);
    const P e = exp(P(0.0));
    expect_point(e, 0, 1.0);
    const P m = min(P(3.0), P(-2.0));
    expect_point(m, 0, -2.0);
    expect_point(abs(P(-5.0)), 0, 5.0);
    expect_point(pow(P(3.0), 2u), 0, 9.0);
}

TEST(Poly, BranchesDecidedOnDom) {
    const P x = ray_x(0, 1, 0, 0.4);  // x = t, t ∈ [0, 0.4]: x < 0.5 throughout
    const P lo = min(x, P(0.5));
    ASSERT_TRUE(lo.valid);
    EXPECT_EQ(lo.degree, 1);
    expect_point(lo, 1, 1.0);
    const P hi = max(x, P(0.5));
    ASSERT_TRUE(hi.valid);
    EXPECT_EQ(hi.degree, 0);
    expect_point(hi, 0, 0.5);
    EXPECT_TRUE(hi.has_dom);      // the choice only holds on dom
    const P a = abs(x - P(1.0));  // 1 − t
    ASSERT_TRUE(a.valid);
    expect_point(a, 0, 1.0);
    expect_point(a, 1, -1.0);
    // Touching is enough: t ≥ 0 on [0, 0.4], so max(t, 0) = t.
    const P touch = max(x, P(0.0));
    ASSERT_TRUE(touch.valid);
    EXPECT_EQ(touch.degree, 1);
    // Disjoint domains cannot be combined.
    EXPECT_FALSE((x + ray_x(0, 1, 2, 3)).valid);
}

TEST(Poly, MpfrCoefficients) {
    const auto x = ray_coordinate<MpfrInterval>(1, 2, MpfrInterval(0.0, 1.0));
    const auto p = pow(x, 3u);
    ASSERT_TRUE(p.valid);
    ASSERT_EQ(p.degree, 3);
    EXPECT_EQ(p.c[2].lower(), 12.0);
    EXPECT_EQ(p.c[2].upper(), 12.0);
    const MpfrInterval r = range(p);
    EXPECT_LE(r.lower(), 1.0);
    EXPECT_GE(r.upper(), 27.0);
    EXPECT_FALSE(sqrt(x).valid);
}

// ---- The gallery ----

int scene_degree(const expr::Graph& g) {
    const expr::Tape tape(g);
    expr::Evaluator<P> ev;
    const Interval dom(0.0, 4.0);
    // A generic direction, so that no leading coefficient vanishes.
    const P r = ev(
        tape, {ray_coordinate<Interval>(-1.3, 0.61, dom), ray_coordinate<Interval>(-0.9, 0.37, dom),
               ray_coordinate<Interval>(-1.1, 0.53, dom)});
    return r.valid ? r.degree : -1;
}

std::string scene(const char* name) { return std::string(CERTRAY_SOURCE_DIR) + "/scenes/" + name; }

TEST(Poly, AlgebraicScenesHaveTheirDegree) {
    EXPECT_EQ(scene_degree(expr::load_graph_file(scene("clebsch_cubic.vm"))), 3);
    EXPECT_EQ(scene_degree(expr::load_graph_file(scene("kummer_quartic.vm"))), 4);
    EXPECT_EQ(scene_degree(expr::load_graph_file(scene("mitchell.vm"))), 4);
    EXPECT_EQ(scene_degree(expr::load_graph_file(scene("steiner_roman.vm"))), 4);
    EXPECT_EQ(scene_degree(expr::load_graph_file(scene("tanglecube.vm"))), 4);
    EXPECT_EQ(scene_degree(expr::load_graph_file(scene("barth_sextic.vm"))), 6);
    EXPECT_EQ(scene_degree(expr::load_graph_file(scene("chmutov6.vm"))), 6);
    // sphere.expr and torus.expr are exact signed distances (sqrt of a non-constant): not
    // polynomial along a ray; their algebraic forms are.
    EXPECT_EQ(scene_degree(expr::load_graph_file(scene("sphere.expr"))), -1);
    EXPECT_EQ(scene_degree(expr::load_graph_file(scene("torus.expr"))), -1);
    EXPECT_EQ(scene_degree(expr::parse_expr("x^2 + y^2 + z^2 - 1")), 2);
    EXPECT_EQ(scene_degree(expr::parse_expr("(x^2 + y^2 + z^2 + 1 - 0.35^2)^2 - 4 * (x^2 + y^2)")),
              4);
}

// ---- Property: enclosure of the MPFR value along random rays ----

/// A random DAG over + − × square pow neg and constants (polynomial everywhere); with
/// `branches`, also min, max and abs (piecewise polynomial: valid only where decided).
rc::Gen<expr::Graph> gen_poly_dag(bool branches) {
    return rc::gen::exec([branches] {
        using expr::Op;
        expr::Graph g;
        std::vector<expr::NodeId> nodes;
        for (int axis = 0; axis < 3; ++axis) nodes.push_back(g.var(axis));
        const int constants = *rc::gen::inRange(1, 4);
        for (int i = 0; i < constants; ++i)
            nodes.push_back(g.constant(*rc::gen::oneOf(
                rc::gen::element(0.1, -3.0, 1.0 / 3.0, 1e-5, 7.25),
                rc::gen::map(rc::gen::inRange(-100, 100), [](int k) { return k / 8.0; }))));
        const int ops = *rc::gen::inRange(1, 14);
        for (int i = 0; i < ops; ++i) {
            const int n = static_cast<int>(nodes.size());
            auto pick = [&] { return nodes[*rc::gen::inRange(std::max(0, n - 5), n)]; };
            switch (*rc::gen::inRange(0, branches ? 9 : 6)) {
                case 0:
                    nodes.push_back(g.binary(Op::Add, pick(), pick()));
                    break;
                case 1:
                    nodes.push_back(g.binary(Op::Sub, pick(), pick()));
                    break;
                case 2:
                    nodes.push_back(g.binary(Op::Mul, pick(), pick()));
                    break;
                case 3:
                    nodes.push_back(g.unary(Op::Square, pick()));
                    break;
                case 4:
                    nodes.push_back(g.pow(pick(), *rc::gen::inRange(0u, 4u)));
                    break;
                case 5:
                    nodes.push_back(g.unary(Op::Neg, pick()));
                    break;
                case 6:
                    nodes.push_back(g.binary(Op::Min, pick(), pick()));
                    break;
                case 7:
                    nodes.push_back(g.binary(Op::Max, pick(), pick()));
                    break;
                default:
                    nodes.push_back(g.unary(Op::Abs, pick()));
                    break;
            }
        }
        if (branches) {  // end in a branch so that one is always on the output's path
            const int n = static_cast<int>(nodes.size());
            const expr::NodeId other = nodes[*rc::gen::inRange(0, n)];
            nodes.push_back(
                g.binary(*rc::gen::arbitrary<bool>() ? Op::Min : Op::Max, nodes.back(), other));
        }
        g.set_output(nodes.back());
        return g;
    });
}

void check_enclosure_on_ray(bool branches) {
    const expr::Graph g = *gen_poly_dag(branches);
    const expr::Tape tape(g);
    auto coord = [] { return *rc::gen::inRange(-2000, 2001) / 1000.0; };
    const std::array<double, 3> o{coord(), coord(), coord()}, d{coord(), coord(), coord()};
    const double t0 = *rc::gen::inRange(-3000, 3001) / 1000.0;
    const double t1 = t0 + *rc::gen::inRange(0, 3001) / 1000.0;
    const double t = t0 + (t1 - t0) * (*rc::gen::inRange(0, 1001) / 1000.0);
    const Interval dom(t0, t1);
    expr::Evaluator<P> ev;
    const P p = ev(
        tape, {ray_coordinate<Interval>(o[0], d[0], dom), ray_coordinate<Interval>(o[1], d[1], dom),
               ray_coordinate<Interval>(o[2], d[2], dom)});
    bool has_branch = false;
    for (const expr::Instr& in : tape.instrs())
        has_branch |= in.op == expr::Op::Min || in.op == expr::Op::Max || in.op == expr::Op::Abs;
    RC_TAG(p.valid ? "valid" : "invalid", has_branch ? "branch" : "no branch");
    if (!p.valid) return;  // a degree above kMaxPolyDegree, or an undecided branch
    // The reference: f at the exact point o + t·d in MPFR. 4096 bits make every value exact
    // (degree ≤ 16 products of ~110-bit coordinates and double constants), so the reference is
    // a point and enclosure is tested strictly.
    const Precision prec{4096};
    std::array<MpfrInterval, 3> q;
    for (int i = 0; i < 3; ++i)
        q[i] = MpfrInterval(o[i], prec) + MpfrInterval(t, prec) * MpfrInterval(d[i], prec);
    const MpfrInterval exact = expr::eval<MpfrInterval>(tape, q);
    const Interval h = horner(p, Interval(t));
    RC_ASSERT(testing::encloses(h.lower(), h.upper(), exact));
    const Interval r = range(p);
    RC_ASSERT(testing::encloses(r.lower(), r.upper(), exact));
    // The MPFR-coefficient polynomial encloses it too.
    expr::Evaluator<Poly<MpfrInterval>> evm;
    const MpfrInterval domm(t0, t1);
    const Poly<MpfrInterval> pm = evm(tape, {ray_coordinate<MpfrInterval>(o[0], d[0], domm),
                                             ray_coordinate<MpfrInterval>(o[1], d[1], domm),
                                             ray_coordinate<MpfrInterval>(o[2], d[2], domm)});
    if (!branches) RC_ASSERT(pm.valid);
    if (!pm.valid) return;
    const MpfrInterval hm = horner(pm, MpfrInterval(t));
    RC_ASSERT(testing::encloses(hm.lower(), hm.upper(), exact));
}

RC_GTEST_PROP(PolyProperty, HornerAndRangeEncloseTheMpfrValueOnTheRay, ()) {
    check_enclosure_on_ray(false);
}

/// Branches decided on dom: the chosen piece must be the function at every t of dom.
RC_GTEST_PROP(PolyProperty, DecidedBranchesEncloseTheMpfrValueOnTheRay, ()) {
    check_enclosure_on_ray(true);
}

}  // namespace
}  // namespace certray
