// tests/interval/dual_test.cpp — Dual<T, N>: closed-form derivatives, MPFR-checked properties,
// kinks.
//
// Expected values come from the closed-form derivative of each function, evaluated with MPFR at
// 256 bits (plain mpfr_* calls through the small `Big` wrapper below). Doubles are compared to the
// round-to-nearest reference within a few ulps; interval partials must contain the reference
// computed once with every operation rounded down and once rounded up. RapidCheck runs are
// reproducible with RC_PARAMS="seed=N".
#include "interval/dual.h"

#include <gtest/gtest.h>
#include <mpfr.h>
#include <rapidcheck.h>

#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>

#include "interval/interval.h"
#include "tests/support/generators.h"

namespace certray {

static_assert(Number<Dual<double, 3>>);
static_assert(Number<Dual<Interval, 3>>);
static_assert(Number<Dual<UpInterval, 3>>);
static_assert(Number<Dual<Dual<double, 1>, 1>>);
static_assert(!Enclosure<Dual<Interval, 3>>);
static_assert(std::is_trivially_copyable_v<Dual<double, 3>>);

namespace {

// ---- MPFR reference ----------------------------------------------------------------------------

constexpr mpfr_prec_t kPrec = 256;
/// The rounding direction of every Big operation (RNDN, RNDD or RNDU for a whole formula).
mpfr_rnd_t g_rnd = MPFR_RNDN;

/// A 256-bit MPFR number with value semantics; operations round in direction g_rnd.
class Big {
  public:
    Big() { mpfr_init2(x_, kPrec), mpfr_set_zero(x_, 1); }
    explicit Big(double d) { mpfr_init2(x_, kPrec), mpfr_set_d(x_, d, MPFR_RNDN); }  // exact
    Big(const Big& o) { mpfr_init2(x_, kPrec), mpfr_set(x_, o.x_, MPFR_RNDN); }
    Big& operator=(const Big& o) {
        mpfr_set(x_, o.x_, MPFR_RNDN);
        return *this;
    }
    ~Big() { mpfr_clear(x_); }
    mpfr_ptr get() { return x_; }
    mpfr_srcptr get() const { return x_; }

  private:
    mpfr_t x_;
};

namespace ref {
using Fn2 = int (*)(mpfr_ptr, mpfr_srcptr, mpfr_srcptr, mpfr_rnd_t);
using Fn1 = int (*)(mpfr_ptr, mpfr_srcptr, mpfr_rnd_t);
Big apply(Fn2 f, const Big& a, const Big& b) {
    Big r;
    f(r.get(), a.get(), b.get(), g_rnd);
    return r;
}
Big apply(Fn1 f, const Big& a) {
    Big r;
    f(r.get(), a.get(), g_rnd);
    return r;
}
Big sin(const Big& a) { return apply(mpfr_sin, a); }
Big cos(const Big& a) { return apply(mpfr_cos, a); }
Big exp(const Big& a) { return apply(mpfr_exp, a); }
Big log(const Big& a) { return apply(mpfr_log, a); }
Big sqrt(const Big& a) { return apply(mpfr_sqrt, a); }
int sgn(const Big& a) { return mpfr_sgn(a.get()); }
int cmp(const Big& a, const Big& b) { return mpfr_cmp(a.get(), b.get()); }
double to_double(const Big& a) { return mpfr_get_d(a.get(), MPFR_RNDN); }
bool is_finite(const Big& a) { return mpfr_number_p(a.get()) != 0; }
std::string str(const Big& a) {
    char buf[64];
    mpfr_snprintf(buf, sizeof buf, "%.25Rg", a.get());
    return buf;
}
}  // namespace ref

Big operator+(const Big& a, const Big& b) { return ref::apply(mpfr_add, a, b); }
Big operator-(const Big& a, const Big& b) { return ref::apply(mpfr_sub, a, b); }
Big operator*(const Big& a, const Big& b) { return ref::apply(mpfr_mul, a, b); }
Big operator/(const Big& a, const Big& b) { return ref::apply(mpfr_div, a, b); }
Big operator-(const Big& a) { return ref::apply(mpfr_neg, a); }
Big operator*(double c, const Big& b) { return Big(c) * b; }
Big operator+(double c, const Big& b) { return Big(c) + b; }

/// xⁿ by repeated multiplication (n small).
Big big_pow(const Big& x, unsigned n) {
    Big r(1.0);
    for (unsigned i = 0; i < n; ++i) r = r * x;
    return r;
}

// ---- generators --------------------------------------------------------------------------------

/// Moderate doubles in [−16, 16] on a fine grid, mixed with the extreme-value generator.
rc::Gen<double> gen_point() {
    auto moderate = rc::gen::map(
        rc::gen::inRange<std::int64_t>(-(std::int64_t{1} << 40), (std::int64_t{1} << 40) + 1),
        [](std::int64_t k) { return std::ldexp(static_cast<double>(k), -36); });
    // resize: rc::gen::inRange scales with the case size, which would pin early cases to −16.
    return rc::gen::resize(
        100, rc::gen::weightedOneOf<double>({{3, moderate}, {1, testing::gen_finite_double()}}));
}

/// Finite boxes of moderate magnitude: centre in [−8, 8], half-width 0, a few ulps' worth, or up
/// to 4; occasionally a bounded box from the shared gen_bounds().
rc::Gen<std::pair<double, double>> gen_box() {
    using Bounds = std::pair<double, double>;
    auto centred = rc::gen::apply(
        [](int c, int kind, int m) {
            const double centre = std::ldexp(static_cast<double>(c), -8);
            const double half =
                kind == 0 ? 0.0 : std::ldexp(static_cast<double>(m), kind == 1 ? -40 : -8);
            return Bounds{centre - half, centre + half};  // exact: dyadics of bounded size
        },
        rc::gen::inRange(-2048, 2049), rc::gen::inRange(0, 3), rc::gen::inRange(1, 1025));
    auto shared = rc::gen::suchThat(testing::gen_bounds(), [](const Bounds& b) {
        return std::fabs(b.first) <= 1e6 && std::fabs(b.second) <= 1e6;
    });
    return rc::gen::resize(100, rc::gen::weightedOneOf<Bounds>({{4, centred}, {1, shared}}));
}

// ---- checkers ----------------------------------------------------------------------------------

template <int N>
using BigPoint = std::array<Big, N>;

template <int N>
BigPoint<N> to_big(const std::array<double, N>& p) {
    BigPoint<N> b;
    for (int i = 0; i < N; ++i) b[i] = Big(p[i]);
    return b;
}

template <int N>
std::string show(const std::array<double, N>& p) {
    std::ostringstream s;
    s.precision(17);
    for (double x : p) s << x << ' ';
    return s.str();
}

/// The references that were in range (finite, not subnormal-small): false means skip the case.
template <int N>
bool usable(const BigPoint<N>& g) {
    for (const Big& x : g) {
        if (!ref::is_finite(x)) return false;
        const double d = std::fabs(ref::to_double(x));
        if (d > 1e300 || (d != 0 && d < 1e-290)) return false;
    }
    return true;
}

/// Property over Dual<double, N>: at random points p where ok(p), the partials of f match the
/// MPFR gradient within `ulps` relative ulps. Requires at least a fifth of the cases to be checked.
template <int N, class F, class G, class Ok>
void check_double(const std::string& name, F f, G grad, Ok ok, double ulps) {
    int total = 0, checked = 0;
    const bool passed = rc::check("Dual<double> " + name, [&] {
        std::array<double, N> p;
        for (int i = 0; i < N; ++i) p[i] = *gen_point();
        ++total;
        const BigPoint<N> bp = to_big<N>(p);
        if (!ok(bp)) return;
        g_rnd = MPFR_RNDN;
        const BigPoint<N> g = grad(bp);
        if (!usable<N>(g)) return;
        std::array<Dual<double, N>, N> x;
        for (int i = 0; i < N; ++i) x[i] = Dual<double, N>::variable(p[i], i);
        const Dual<double, N> r = f(x);
        ++checked;
        for (int i = 0; i < N; ++i) {
            const double e = ref::to_double(g[i]);
            if (!(std::fabs(r.v[i] - e) <= ulps * DBL_EPSILON * std::fabs(e))) {
                RC_FAIL(name + " at " + show<N>(p) + ": partial " + std::to_string(i) + " = " +
                        std::to_string(r.v[i]) + ", exact " + ref::str(g[i]));
            }
        }
    });
    EXPECT_TRUE(passed) << name;
    EXPECT_GE(5 * checked, total) << name << ": too many points skipped";
}

/// g ∈ [lo, hi], up to 2⁻²⁰⁰·|g| beyond a bound. A formula evaluated with every operation rounded
/// one way bounds the exact derivative only to its 256-bit precision, so where the exact derivative
/// is a double and a tight interval ends at it (z/3 with z divisible by 3), the RNDU value may pass
/// the bound by ~2⁻²⁵⁰ relative. A wrong double bound misses by far more.
bool inside(const Big& g, double lo, double hi) {
    if (std::isnan(lo) || std::isnan(hi)) return false;
    if (mpfr_cmp_d(g.get(), lo) >= 0 && mpfr_cmp_d(g.get(), hi) <= 0) return true;
    const double bound = mpfr_cmp_d(g.get(), lo) < 0 ? lo : hi;
    if (!std::isfinite(bound)) return false;
    Big gap;
    mpfr_sub_d(gap.get(), g.get(), bound, MPFR_RNDN);
    mpfr_abs(gap.get(), gap.get(), MPFR_RNDN);
    Big slack;
    mpfr_abs(slack.get(), g.get(), MPFR_RNDN);
    mpfr_mul_2si(slack.get(), slack.get(), -200, MPFR_RNDN);
    return mpfr_cmp(gap.get(), slack.get()) <= 0;
}

/// Property over Dual<T, N> for an enclosure T: on random boxes, at random points p inside where
/// ok(p), every partial of f over the box contains the MPFR gradient at p computed rounded down
/// and rounded up. `Scope` is constructed around the evaluation (a RoundingScope for UpInterval).
template <int N, class T, class Scope, class F, class G, class Ok>
void check_enclosure(const std::string& name, F f, G grad, Ok ok) {
    int total = 0, checked = 0;
    const bool passed = rc::check("Dual<interval> " + name, [&] {
        std::array<std::pair<double, double>, N> box;
        std::array<double, N> p;
        for (int i = 0; i < N; ++i) {
            box[i] = *gen_box();
            p[i] = *testing::gen_point_in(box[i].first, box[i].second);
        }
        ++total;
        const BigPoint<N> bp = to_big<N>(p);
        if (!ok(bp)) return;
        g_rnd = MPFR_RNDD;
        const BigPoint<N> gd = grad(bp);
        g_rnd = MPFR_RNDU;
        const BigPoint<N> gu = grad(bp);
        if (!usable<N>(gd) || !usable<N>(gu)) return;
        std::array<double, N> lo, hi;
        {
            [[maybe_unused]] Scope scope;
            std::array<Dual<T, N>, N> x;
            for (int i = 0; i < N; ++i) {
                x[i] = Dual<T, N>::variable(T(box[i].first, box[i].second), i);
            }
            const Dual<T, N> r = f(x);
            for (int i = 0; i < N; ++i) lo[i] = lower(r.v[i]), hi[i] = upper(r.v[i]);
        }
        ++checked;
        for (int i = 0; i < N; ++i) {
            for (const Big* g : {&gd[i], &gu[i]}) {
                if (!inside(*g, lo[i], hi[i])) {
                    std::ostringstream s;
                    s.precision(17);
                    s << name << " partial " << i << " = [" << lo[i] << ", " << hi[i] << "] misses "
                      << ref::str(*g) << " at " << show<N>(p) << "box";
                    for (const auto& b : box) s << " [" << b.first << ", " << b.second << "]";
                    RC_FAIL(s.str());
                }
            }
        }
    });
    EXPECT_TRUE(passed) << name;
    EXPECT_GE(5 * checked, total) << name << ": too many points skipped";
}

struct NoScope {};

/// A unary op: f on a Dual, its derivative d on a Big, ok(u) where it is differentiable.
/// Checked over Dual<double, 1>, Dual<Interval, 1> and, composed as op(x + y·z), Dual<Interval, 3>.
template <class F, class D, class Ok>
void check_unary(const std::string& name, F f, D d, Ok ok, double ulps = 4) {
    auto f1 = [f](const auto& x) { return f(x[0]); };
    auto g1 = [d](const BigPoint<1>& p) { return BigPoint<1>{d(p[0])}; };
    auto ok1 = [ok](const BigPoint<1>& p) { return ok(p[0]); };
    check_double<1>(name, f1, g1, ok1, ulps);
    check_enclosure<1, Interval, NoScope>(name, f1, g1, ok1);
    // op(x + y·z): gradient op'(u)·(1, z, y).
    auto f3 = [f](const auto& x) { return f(x[0] + x[1] * x[2]); };
    auto u_of = [](const BigPoint<3>& p) { return p[0] + p[1] * p[2]; };
    auto g3 = [d, u_of](const BigPoint<3>& p) {
        const Big du = d(u_of(p));
        return BigPoint<3>{du, du * p[2], du * p[1]};
    };
    auto ok3 = [ok, u_of](const BigPoint<3>& p) {
        g_rnd = MPFR_RNDN;
        // u is exact at 256 bits for doubles of moderate exponent range; reject if inexact.
        Big u;
        Big yz;
        if (mpfr_mul(yz.get(), p[1].get(), p[2].get(), MPFR_RNDN) != 0) return false;
        if (mpfr_add(u.get(), p[0].get(), yz.get(), MPFR_RNDN) != 0) return false;
        return ok(u);
    };
    check_enclosure<3, Interval, NoScope>(name + " of x+y*z", f3, g3, ok3);
}

/// A binary op over Dual<double, 2> and Dual<Interval, 2>: grad gives both partials.
template <class F, class G, class Ok>
void check_binary(const std::string& name, F f, G grad, Ok ok, double ulps = 4) {
    auto f2 = [f](const auto& x) { return f(x[0], x[1]); };
    check_double<2>(name, f2, grad, ok, ulps);
    check_enclosure<2, Interval, NoScope>(name, f2, grad, ok);
}

auto always = [](const auto&) { return true; };
auto nonzero = [](const Big& u) { return ref::sgn(u) != 0; };
auto positive = [](const Big& u) { return ref::sgn(u) > 0; };

// ---- RapidCheck properties: every op ------------------------------------------------------------

TEST(DualProperty, UnaryOpsMatchMpfrDerivative) {
    check_unary(
        "neg", [](const auto& x) { return -x; }, [](const Big&) { return Big(-1.0); }, always);
    check_unary(
        "abs", [](const auto& x) { return abs(x); },
        [](const Big& u) { return Big(ref::sgn(u) > 0 ? 1.0 : -1.0); }, nonzero);
    check_unary(
        "square", [](const auto& x) { return square(x); }, [](const Big& u) { return 2.0 * u; },
        always);
    check_unary(
        "sqrt", [](const auto& x) { return sqrt(x); },
        [](const Big& u) { return Big(0.5) / ref::sqrt(u); }, positive);
    check_unary(
        "exp", [](const auto& x) { return exp(x); }, [](const Big& u) { return ref::exp(u); },
        always);
    check_unary(
        "log", [](const auto& x) { return log(x); }, [](const Big& u) { return Big(1.0) / u; },
        positive);
    check_unary(
        "sin", [](const auto& x) { return sin(x); }, [](const Big& u) { return ref::cos(u); },
        always);
    check_unary(
        "cos", [](const auto& x) { return cos(x); }, [](const Big& u) { return -ref::sin(u); },
        always);
}

TEST(DualProperty, PowMatchesMpfrDerivative) {
    for (unsigned n : {0u, 1u, 2u, 3u, 4u, 7u, 12u}) {
        check_unary(
            "pow " + std::to_string(n), [n](const auto& x) { return pow(x, n); },
            [n](const Big& u) {
                return n == 0 ? Big(0.0) : static_cast<double>(n) * big_pow(u, n - 1);
            },
            always, 16);
    }
}

TEST(DualProperty, MixedWithDoubleMatchesMpfrDerivative) {
    check_unary(
        "x + 2.5", [](const auto& x) { return x + 2.5; }, [](const Big&) { return Big(1.0); },
        always);
    check_unary(
        "2.5 + x", [](const auto& x) { return 2.5 + x; }, [](const Big&) { return Big(1.0); },
        always);
    check_unary(
        "x - 0.1", [](const auto& x) { return x - 0.1; }, [](const Big&) { return Big(1.0); },
        always);
    check_unary(
        "0.1 - x", [](const auto& x) { return 0.1 - x; }, [](const Big&) { return Big(-1.0); },
        always);
    check_unary(
        "x * 0.1", [](const auto& x) { return x * 0.1; }, [](const Big&) { return Big(0.1); },
        always);
    check_unary(
        "-3 * x", [](const auto& x) { return -3.0 * x; }, [](const Big&) { return Big(-3.0); },
        always);
    check_unary(
        "x / 3", [](const auto& x) { return x / 3.0; },
        [](const Big&) { return Big(1.0) / Big(3.0); }, always);
    check_unary(
        "0.7 / x", [](const auto& x) { return 0.7 / x; },
        [](const Big& u) { return -Big(0.7) / (u * u); }, nonzero);
}

TEST(DualProperty, BinaryOpsMatchMpfrDerivative) {
    check_binary(
        "x + y", [](const auto& x, const auto& y) { return x + y; },
        [](const BigPoint<2>&) {
            return BigPoint<2>{Big(1.0), Big(1.0)};
        },
        always);
    check_binary(
        "x - y", [](const auto& x, const auto& y) { return x - y; },
        [](const BigPoint<2>&) {
            return BigPoint<2>{Big(1.0), Big(-1.0)};
        },
        always);
    check_binary(
        "x * y", [](const auto& x, const auto& y) { return x * y; },
        [](const BigPoint<2>& p) {
            return BigPoint<2>{p[1], p[0]};
        },
        always);
    check_binary(
        "x / y", [](const auto& x, const auto& y) { return x / y; },
        [](const BigPoint<2>& p) {
            return BigPoint<2>{Big(1.0) / p[1], -p[0] / (p[1] * p[1])};
        },
        [](const BigPoint<2>& p) { return ref::sgn(p[1]) != 0; });
    auto distinct = [](const BigPoint<2>& p) { return ref::cmp(p[0], p[1]) != 0; };
    check_binary(
        "min", [](const auto& x, const auto& y) { return min(x, y); },
        [](const BigPoint<2>& p) {
            const bool first = ref::cmp(p[0], p[1]) < 0;
            return BigPoint<2>{Big(first ? 1.0 : 0.0), Big(first ? 0.0 : 1.0)};
        },
        distinct);
    check_binary(
        "max", [](const auto& x, const auto& y) { return max(x, y); },
        [](const BigPoint<2>& p) {
            const bool first = ref::cmp(p[0], p[1]) > 0;
            return BigPoint<2>{Big(first ? 1.0 : 0.0), Big(first ? 0.0 : 1.0)};
        },
        distinct);
}

TEST(DualProperty, CompositesEncloseMpfrGradient) {
    // exp(sin x)·y: (cos x·exp(sin x)·y, exp(sin x)).
    check_enclosure<2, Interval, NoScope>(
        "exp(sin x)*y", [](const auto& x) { return exp(sin(x[0])) * x[1]; },
        [](const BigPoint<2>& p) {
            const Big e = ref::exp(ref::sin(p[0]));
            return BigPoint<2>{ref::cos(p[0]) * e * p[1], e};
        },
        always);
    // min(x, y²): e_x where x < y², (0, 2y) where y² < x.
    check_enclosure<2, Interval, NoScope>(
        "min(x, y^2)", [](const auto& x) { return min(x[0], square(x[1])); },
        [](const BigPoint<2>& p) {
            const Big y2 = p[1] * p[1];
            if (ref::cmp(p[0], y2) < 0) return BigPoint<2>{Big(1.0), Big(0.0)};
            return BigPoint<2>{Big(0.0), 2.0 * p[1]};
        },
        [](const BigPoint<2>& p) {
            g_rnd = MPFR_RNDN;
            return ref::cmp(p[0], p[1] * p[1]) != 0;
        });
    // |x − y|: sign(x − y)·(1, −1).
    check_enclosure<2, Interval, NoScope>(
        "abs(x - y)", [](const auto& x) { return abs(x[0] - x[1]); },
        [](const BigPoint<2>& p) {
            const double s = ref::cmp(p[0], p[1]) > 0 ? 1.0 : -1.0;
            return BigPoint<2>{Big(s), Big(-s)};
        },
        [](const BigPoint<2>& p) { return ref::cmp(p[0], p[1]) != 0; });
    // √(x² + y² + z²): p/|p|.
    auto norm_grad = [](const BigPoint<3>& p) {
        const Big r = ref::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        return BigPoint<3>{p[0] / r, p[1] / r, p[2] / r};
    };
    auto norm_ok = [](const BigPoint<3>& p) {
        return ref::sgn(p[0]) != 0 || ref::sgn(p[1]) != 0 || ref::sgn(p[2]) != 0;
    };
    auto norm = [](const auto& x) { return sqrt(square(x[0]) + square(x[1]) + square(x[2])); };
    check_enclosure<3, Interval, NoScope>("norm", norm, norm_grad, norm_ok);
    check_enclosure<3, UpInterval, RoundingScope>("norm (UpInterval)", norm, norm_grad, norm_ok);
    // x·y/(1 + z²) − log(1 + x²)·cos y.
    auto mixed = [](const auto& x) {
        return x[0] * x[1] / (1.0 + square(x[2])) - log(1.0 + square(x[0])) * cos(x[1]);
    };
    auto mixed_grad = [](const BigPoint<3>& p) {
        const Big q = 1.0 + p[2] * p[2];
        const Big s = 1.0 + p[0] * p[0];
        return BigPoint<3>{p[1] / q - 2.0 * p[0] / s * ref::cos(p[1]),
                           p[0] / q + ref::log(s) * ref::sin(p[1]),
                           -(p[0] * p[1]) * (2.0 * p[2]) / (q * q)};
    };
    check_enclosure<3, Interval, NoScope>("x*y/(1+z^2) - log(1+x^2)*cos(y)", mixed, mixed_grad,
                                          always);
    check_enclosure<3, UpInterval, RoundingScope>("x*y/(1+z^2) - log(1+x^2)*cos(y) (Up)", mixed,
                                                  mixed_grad, always);
    // max(x·y, z)·exp(−z) + pow(x − z, 3).
    check_enclosure<3, Interval, NoScope>(
        "max(x*y, z)*exp(-z) + pow(x-z, 3)",
        [](const auto& x) { return max(x[0] * x[1], x[2]) * exp(-x[2]) + pow(x[0] - x[2], 3u); },
        [](const BigPoint<3>& p) {
            const Big e = ref::exp(-p[2]);
            const Big c = 3.0 * (p[0] - p[2]) * (p[0] - p[2]);
            if (ref::cmp(p[0] * p[1], p[2]) > 0) {  // x·y·e^{−z}
                return BigPoint<3>{p[1] * e + c, p[0] * e, -(p[0] * p[1]) * e - c};
            }
            // z·e^{−z}
            return BigPoint<3>{c, Big(0.0), e - p[2] * e - c};
        },
        [](const BigPoint<3>& p) {
            g_rnd = MPFR_RNDN;
            return ref::cmp(p[0] * p[1], p[2]) != 0;
        });
}

// ---- closed-form derivatives at points
// -------------------------------------------------------------

/// |got − exact| ≤ ulps·ulp-sized relative error, exact from MPFR at 256 bits.
void expect_near_exact(double got, const Big& exact, double ulps) {
    const double e = ref::to_double(exact);
    EXPECT_LE(std::fabs(got - e), ulps * DBL_EPSILON * std::fabs(e))
        << "got " << got << ", exact " << ref::str(exact);
}

/// Both the RNDD and RNDU evaluations of `formula` lie in x.
template <class F>
void expect_encloses(const Interval& x, F formula) {
    for (mpfr_rnd_t r : {MPFR_RNDD, MPFR_RNDU}) {
        g_rnd = r;
        const Big e = formula();
        EXPECT_GE(mpfr_cmp_d(e.get(), lower(x)), 0) << ref::str(e) << " below " << lower(x);
        EXPECT_LE(mpfr_cmp_d(e.get(), upper(x)), 0) << ref::str(e) << " above " << upper(x);
    }
    g_rnd = MPFR_RNDN;
}

TEST(DualClosedForm, XSinXAtHalf) {
    auto f = [](const auto& x) { return x * sin(x); };
    auto exact = [] {
        const Big h(0.5);
        return ref::sin(h) + h * ref::cos(h);
    };
    g_rnd = MPFR_RNDN;
    const auto d = f(Dual<double, 1>::variable(0.5, 0));
    expect_near_exact(d.v[0], exact(), 2);
    const auto di = f(Dual<Interval, 1>::variable(Interval(0.5), 0));
    expect_encloses(di.v[0], exact);
    EXPECT_LT(width(di.v[0]), 1e-14);
}

TEST(DualClosedForm, GradientOfNormAt122) {
    using D = Dual<double, 3>;
    const D x = D::variable(1, 0), y = D::variable(2, 1), z = D::variable(2, 2);
    const D r = sqrt(x * x + y * y + z * z);
    EXPECT_EQ(r.a, 3.0);
    g_rnd = MPFR_RNDN;
    expect_near_exact(r.v[0], Big(1.0) / Big(3.0), 2);
    expect_near_exact(r.v[1], Big(2.0) / Big(3.0), 2);
    expect_near_exact(r.v[2], Big(2.0) / Big(3.0), 2);

    using DI = Dual<Interval, 3>;
    const DI xi = DI::variable(Interval(1), 0), yi = DI::variable(Interval(2), 1),
             zi = DI::variable(Interval(2), 2);
    const DI ri = sqrt(square(xi) + square(yi) + square(zi));
    expect_encloses(ri.v[0], [] { return Big(1.0) / Big(3.0); });
    expect_encloses(ri.v[1], [] { return Big(2.0) / Big(3.0); });
    expect_encloses(ri.v[2], [] { return Big(2.0) / Big(3.0); });
    EXPECT_GT(lower(ri.v[0]), 0.33);  // not trivially wide
    EXPECT_LT(upper(ri.v[0]), 0.34);
}

TEST(DualClosedForm, QuotientRule) {
    using D = Dual<double, 2>;
    const D q = D::variable(3, 0) / D::variable(4, 1);  // ∂/∂x = 1/4, ∂/∂y = −3/16 (exact)
    EXPECT_EQ(q.a, 0.75);
    EXPECT_EQ(q.v[0], 0.25);
    EXPECT_EQ(q.v[1], -0.1875);
    const D r = 1.0 / D::variable(8, 0);  // −1/64
    EXPECT_EQ(r.v[0], -1.0 / 64);
    EXPECT_EQ(r.v[1], 0.0);
}

TEST(DualClosedForm, ChainRule) {
    g_rnd = MPFR_RNDN;
    // d/dx exp(sin x) at 1 = cos 1 · exp(sin 1).
    const auto e = exp(sin(Dual<double, 1>::variable(1.0, 0)));
    expect_near_exact(e.v[0], ref::cos(Big(1.0)) * ref::exp(ref::sin(Big(1.0))), 4);
    // d/dx log(x² + 1) at 2 = 2x/(x² + 1) = 4/5.
    const auto l = log(square(Dual<double, 1>::variable(2.0, 0)) + 1.0);
    expect_near_exact(l.v[0], Big(4.0) / Big(5.0), 2);
    // d/dx cos(3x) at 0.25 = −3 sin(0.75).
    const auto c = cos(3.0 * Dual<double, 1>::variable(0.25, 0));
    expect_near_exact(c.v[0], -3.0 * ref::sin(Big(0.75)), 2);
}

TEST(DualClosedForm, PowFiveIsExactForSmallIntegers) {
    for (int k = -6; k <= 10; ++k) {
        const double x = k;
        const auto p = pow(Dual<double, 1>::variable(x, 0), 5u);
        EXPECT_EQ(p.a, x * x * x * x * x) << x;
        EXPECT_EQ(p.v[0], 5 * x * x * x * x) << x;
        const auto pi = pow(Dual<Interval, 1>::variable(Interval(x), 0), 5u);
        EXPECT_EQ(lower(pi.v[0]), 5 * x * x * x * x) << x;
        EXPECT_EQ(upper(pi.v[0]), 5 * x * x * x * x) << x;
    }
    const auto p0 = pow(Dual<double, 1>::variable(3.0, 0), 0u);
    EXPECT_EQ(p0.a, 1.0);
    EXPECT_EQ(p0.v[0], 0.0);
}

TEST(DualClosedForm, SecondDerivativeThroughNestedDual) {
    using D1 = Dual<double, 1>;
    using D2 = Dual<D1, 1>;
    const D2 x(D1::variable(0.5, 0), {D1(1.0)});
    const D2 s = sin(x);  // s.v[0].v[0] = d²/dx² sin x = −sin x
    EXPECT_EQ(s.v[0].a, std::cos(0.5));
    EXPECT_EQ(s.v[0].v[0], -std::sin(0.5));
}

// ---- construction
// --------------------------------------------------------------------------------

TEST(DualConstruction, ConstantsAndVariables) {
    const Dual<double, 3> c(2.0);
    EXPECT_EQ(c.a, 2.0);
    for (double d : c.v) EXPECT_EQ(d, 0.0);
    const auto x = Dual<double, 3>::variable(5.0, 1);
    EXPECT_EQ(x.a, 5.0);
    EXPECT_EQ(x.v[0], 0.0);
    EXPECT_EQ(x.v[1], 1.0);
    EXPECT_EQ(x.v[2], 0.0);
    const Dual<Interval, 2> ci(Interval(1.0, 2.0));
    EXPECT_EQ(lower(ci.a), 1.0);
    EXPECT_EQ(upper(ci.a), 2.0);
    EXPECT_EQ(lower(ci.v[1]), 0.0);
    EXPECT_EQ(upper(ci.v[1]), 0.0);
    const Dual<Interval, 2> d = 3.0;
    EXPECT_EQ(lower(d.a), 3.0);
}

// ---- kinks and singular points
// -------------------------------------------------------------------

TEST(DualKink, AbsOverSignChangeIsHullOfBothSides) {
    const auto r = abs(Dual<Interval, 1>::variable(Interval(-1, 2), 0));
    EXPECT_LE(lower(r.v[0]), -1.0);
    EXPECT_GE(upper(r.v[0]), 1.0);
    EXPECT_EQ(lower(r.v[0]), -1.0);  // exactly [−1, 1]
    EXPECT_EQ(upper(r.v[0]), 1.0);
    EXPECT_EQ(lower(r.a), 0.0);
    EXPECT_EQ(upper(r.a), 2.0);
    // Certain signs take one branch.
    const auto n = abs(Dual<Interval, 1>::variable(Interval(-3, -1), 0));
    EXPECT_EQ(lower(n.v[0]), -1.0);
    EXPECT_EQ(upper(n.v[0]), -1.0);
    const auto p = abs(Dual<Interval, 1>::variable(Interval(1, 3), 0));
    EXPECT_EQ(lower(p.v[0]), 1.0);
    EXPECT_EQ(upper(p.v[0]), 1.0);
}

TEST(DualKink, DoubleAtExactKinkTakesTheDocumentedBranch) {
    EXPECT_EQ(abs(Dual<double, 1>::variable(0.0, 0)).v[0], 1.0);  // right-hand branch
    EXPECT_EQ(abs(Dual<double, 1>::variable(-0.5, 0)).v[0], -1.0);
    using D = Dual<double, 2>;
    const D x = D::variable(1, 0), y = D::variable(1, 1);
    EXPECT_EQ(min(x, y).v[0], 1.0);  // tie: the first operand's derivative
    EXPECT_EQ(min(x, y).v[1], 0.0);
    EXPECT_EQ(max(y, x).v[1], 1.0);
    EXPECT_EQ(max(y, x).v[0], 0.0);
}

TEST(DualKink, MinMaxOverOverlapIsHullOfBothGradients) {
    using DI = Dual<Interval, 2>;
    const DI x = DI::variable(Interval(0, 2), 0), y = DI::variable(Interval(1, 3), 1);
    for (const DI& m : {min(x, y), max(x, y)}) {
        EXPECT_EQ(lower(m.v[0]), 0.0);
        EXPECT_EQ(upper(m.v[0]), 1.0);
        EXPECT_EQ(lower(m.v[1]), 0.0);
        EXPECT_EQ(upper(m.v[1]), 1.0);
    }
    const DI mn = min(x, y);
    EXPECT_EQ(lower(mn.a), 0.0);
    EXPECT_EQ(upper(mn.a), 2.0);
    // Certainly ordered: one gradient.
    const DI far = DI::variable(Interval(5, 6), 1);
    const DI m2 = min(x, far), M2 = max(x, far);
    EXPECT_EQ(lower(m2.v[0]), 1.0);
    EXPECT_EQ(upper(m2.v[1]), 0.0);
    EXPECT_EQ(lower(M2.v[1]), 1.0);
    EXPECT_EQ(upper(M2.v[0]), 0.0);
}

TEST(DualKink, MinKeepsTheDecorationOfBothOperands) {
    using DI = Dual<Interval, 1>;
    const DI x = DI::variable(Interval(0, 1), 0);
    const DI s = sqrt(DI(Interval(-1, 100))) + 10.0;  // [10, 20], not defined on the whole box
    const DI m = min(x, s);                           // certainly x: the gradient of x …
    EXPECT_EQ(lower(m.v[0]), 1.0);
    EXPECT_EQ(upper(m.v[0]), 1.0);
    EXPECT_FALSE(is_defined(m.a));  // … but the decoration of both operands
}

TEST(DualSingular, SqrtTouchingZeroHasEntireDerivative) {
    const auto r = sqrt(Dual<Interval, 1>::variable(Interval(0, 4), 0));
    EXPECT_EQ(lower(r.v[0]), -INFINITY);
    EXPECT_EQ(upper(r.v[0]), INFINITY);
    EXPECT_EQ(upper(r.a), 2.0);
    EXPECT_TRUE(is_defined(r.a));  // √ is continuous on [0, 4] but not differentiable at 0
    const auto s = sqrt(Dual<Interval, 1>::variable(Interval(-1, 4), 0));
    EXPECT_EQ(lower(s.v[0]), -INFINITY);
    EXPECT_FALSE(is_defined(s.a));
    EXPECT_TRUE(std::isnan(sqrt(Dual<double, 1>::variable(0.0, 0)).v[0]));
    const auto t = sqrt(Dual<Interval, 1>::variable(Interval(1, 4), 0));  // [1/4, 1/2]
    EXPECT_EQ(lower(t.v[0]), 0.25);
    EXPECT_EQ(upper(t.v[0]), 0.5);
}

TEST(DualSingular, DivisionByBoxWithZeroFollowsIntervalDivision) {
    const auto r = 1.0 / Dual<Interval, 1>::variable(Interval(-1, 1), 0);
    EXPECT_FALSE(is_defined(r.a));
    EXPECT_EQ(lower(r.v[0]), -INFINITY);
    EXPECT_EQ(upper(r.v[0]), INFINITY);
    const auto s = Dual<Interval, 1>(1.0) / Dual<Interval, 1>::variable(Interval(0, 2), 0);
    EXPECT_FALSE(is_defined(s.a));
    EXPECT_EQ(upper(s.v[0]), -0.25);  // −1/x² ≤ −1/4 on (0, 2]
    EXPECT_EQ(lower(s.v[0]), -INFINITY);
}

TEST(DualUpInterval, SameBoundsAsIntervalInsideRoundingScope) {
    auto f = [](const auto& x, const auto& y) { return exp(sin(x)) * y / (1.0 + square(x)); };
    using DI = Dual<Interval, 2>;
    using DU = Dual<UpInterval, 2>;
    const DI r = f(DI::variable(Interval(0.1, 0.3), 0), DI::variable(Interval(2, 3), 1));
    double lo[2], hi[2];
    {
        RoundingScope scope;
        const DU u = f(DU::variable(UpInterval(0.1, 0.3), 0), DU::variable(UpInterval(2, 3), 1));
        for (int i = 0; i < 2; ++i) lo[i] = lower(u.v[i]), hi[i] = upper(u.v[i]);
    }
    for (int i = 0; i < 2; ++i) {
        EXPECT_EQ(lo[i], lower(r.v[i]));
        EXPECT_EQ(hi[i], upper(r.v[i]));
    }
}

}  // namespace
}  // namespace certray
