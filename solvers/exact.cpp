// solvers/exact.cpp — g(t) exactly over the rationals, and its first root by a Sturm sequence.
//
// Steps (docs/theory/exact.md): the tape is walked over polynomials in t with GMP rational
// coefficients; g is scaled to a primitive integer polynomial g_0; the chain g_{k+1} =
// gcd(g_k, g_k′) gives the square-free part p = g_0 / g_1 (same distinct roots as g, all simple)
// and, lazily, the multiplicity of the root found. The Sturm sequence of p counts its distinct
// roots in (a, b] exactly; bisection on the order of the doubles (not on their values: at most 64
// halvings reach adjacent doubles from any two doubles) isolates the leftmost root, then the sign
// of p alone narrows it to two adjacent doubles or to the double it equals. Every sign is the
// sign of an exact integer: p(m·2^−k)·2^{k·deg p} by Horner's rule in GMP integers.
#include "solvers/exact.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "interval/interval.h"
#include "solvers/polynomial_check.h"
#include "solvers/width.h"

namespace certray::solvers {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using QPoly = std::vector<mpq_class>;
using ZPoly = std::vector<mpz_class>;

// ---------------------------------------------------------------------------------------------
// Polynomials over Q: the tape walk.

template <class P>
void trim(P& p) {
    while (!p.empty() && sgn(p.back()) == 0) p.pop_back();
}

QPoly q_add(const QPoly& a, const QPoly& b, bool subtract) {
    QPoly r(std::max(a.size(), b.size()));
    for (std::size_t i = 0; i < r.size(); ++i) {
        if (i < a.size()) r[i] = a[i];
        if (i < b.size()) {
            if (subtract) {
                r[i] -= b[i];
            } else {
                r[i] += b[i];
            }
        }
    }
    trim(r);
    return r;
}

QPoly q_mul(const QPoly& a, const QPoly& b) {
    if (a.empty() || b.empty()) return {};
    QPoly r(a.size() + b.size() - 1);
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (sgn(a[i]) == 0) continue;
        for (std::size_t j = 0; j < b.size(); ++j) r[i + j] += a[i] * b[j];
    }
    trim(r);
    return r;
}

int q_degree(const QPoly& p) { return static_cast<int>(p.size()) - 1; }

/// Bits of the largest numerator plus the largest denominator (a size guard, not exact).
long q_bits(const QPoly& p) {
    long num = 0, den = 0;
    for (const mpq_class& c : p) {
        num = std::max(num, static_cast<long>(mpz_sizeinbase(c.get_num_mpz_t(), 2)));
        den = std::max(den, static_cast<long>(mpz_sizeinbase(c.get_den_mpz_t(), 2)));
    }
    return num + den;
}

bool too_big(const QPoly& p) { return q_degree(p) > kMaxExactDegree || q_bits(p) > kMaxExactBits; }

/// base^n by squaring; false when the result would exceed the limits.
bool q_pow(const QPoly& base, std::uint32_t n, QPoly& out) {
    if (n == 0) {
        out = {mpq_class(1)};
        return true;
    }
    if (base.empty()) {
        out = {};
        return true;
    }
    const int d = q_degree(base);
    if (d > 0 && static_cast<long>(d) * n > kMaxExactDegree) return false;
    if (d == 0) {
        const mpq_class& c = base[0];
        const long bits = static_cast<long>(mpz_sizeinbase(c.get_num_mpz_t(), 2)) - 1 +
                          static_cast<long>(mpz_sizeinbase(c.get_den_mpz_t(), 2)) - 1;
        if (bits > 0 && bits * static_cast<long>(n) > kMaxExactBits) return false;
        mpq_class r;
        mpz_pow_ui(r.get_num_mpz_t(), c.get_num_mpz_t(), n);
        mpz_pow_ui(r.get_den_mpz_t(), c.get_den_mpz_t(), n);
        r.canonicalize();
        out = {r};
        return true;
    }
    QPoly result{mpq_class(1)};
    QPoly sq = base;
    for (std::uint32_t k = n;;) {
        if (k & 1u) result = q_mul(result, sq);
        k >>= 1;
        if (k == 0) break;
        sq = q_mul(sq, sq);
        if (too_big(sq)) return false;
    }
    out = std::move(result);
    return !too_big(out);
}

/// The constant value of p (p has degree ≤ 0).
mpq_class q_const(const QPoly& p) { return p.empty() ? mpq_class(0) : p[0]; }

// ---------------------------------------------------------------------------------------------
// Polynomials over Z: gcd, Sturm, exact signs.

int z_degree(const ZPoly& p) { return static_cast<int>(p.size()) - 1; }

/// p divided by the (positive) gcd of its coefficients.
void make_primitive(ZPoly& p) {
    trim(p);
    if (p.empty()) return;
    mpz_class g = 0;
    for (const mpz_class& c : p) {
        mpz_gcd(g.get_mpz_t(), g.get_mpz_t(), c.get_mpz_t());
        if (g == 1) return;
    }
    for (mpz_class& c : p) mpz_divexact(c.get_mpz_t(), c.get_mpz_t(), g.get_mpz_t());
}

ZPoly z_derivative(const ZPoly& p) {
    ZPoly r;
    for (std::size_t i = 1; i < p.size(); ++i) r.push_back(p[i] * static_cast<unsigned long>(i));
    trim(r);
    return r;
}

/// The pseudo-remainder r = lc(b)^s · (a mod b) (deg r < deg b), with s the number of reduction
/// steps: each step r ← lc(b)·r − lc(r)·t^(deg r − deg b)·b.
ZPoly z_prem(ZPoly r, const ZPoly& b, int& steps) {
    steps = 0;
    const int db = z_degree(b);
    const mpz_class& lb = b.back();
    while (z_degree(r) >= db && !r.empty()) {
        const int shift = z_degree(r) - db;
        const mpz_class lr = r.back();
        for (mpz_class& c : r) c *= lb;
        for (int i = 0; i <= db; ++i) r[i + shift] -= lr * b[i];
        trim(r);
        ++steps;
    }
    return r;
}

/// A greatest common divisor of a and b, primitive (primitive pseudo-remainder sequence).
ZPoly z_gcd(ZPoly a, ZPoly b) {
    make_primitive(a);
    make_primitive(b);
    if (z_degree(a) < z_degree(b)) std::swap(a, b);
    while (!b.empty()) {
        int steps = 0;
        ZPoly r = z_prem(a, b, steps);
        make_primitive(r);
        a = std::move(b);
        b = std::move(r);
    }
    return a;
}

/// Whether p (of degree ≥ 1) is proven square-free by its image modulo the prime 2⁶¹ − 1: if
/// gcd(p mod q, p′ mod q) = 1 and q divides neither the leading coefficient nor deg p, p is
/// square-free over Q (a repeated factor h would keep its degree mod q, lc(h) dividing lc(p), and
/// divide both images). False means "not proven", not "not square-free".
bool square_free_mod_prime(const ZPoly& p) {
    using u64 = std::uint64_t;
    __extension__ using u128 = unsigned __int128;  // GCC and Clang; products below 2^122
    constexpr u64 q = (u64{1} << 61) - 1;
    const auto mul = [](u64 a, u64 b) { return static_cast<u64>(static_cast<u128>(a) * b % q); };
    const auto inv = [&](u64 a) {  // a^(q−2)
        u64 r = 1, e = q - 2;
        for (; e; e >>= 1, a = mul(a, a)) {
            if (e & 1) r = mul(r, a);
        }
        return r;
    };
    const auto trim_mod = [](std::vector<u64>& v) {
        while (!v.empty() && v.back() == 0) v.pop_back();
    };
    std::vector<u64> a(p.size()), b;
    for (std::size_t i = 0; i < p.size(); ++i) a[i] = mpz_fdiv_ui(p[i].get_mpz_t(), q);
    if (a.back() == 0 || (p.size() - 1) % q == 0) return false;
    for (std::size_t i = 1; i < a.size(); ++i) b.push_back(mul(a[i], i % q));
    trim_mod(b);
    while (!b.empty()) {  // Euclid over GF(q)
        const u64 lb = inv(b.back());
        while (a.size() >= b.size()) {
            const u64 f = mul(a.back(), lb);
            const std::size_t shift = a.size() - b.size();
            for (std::size_t i = 0; i < b.size(); ++i) {
                a[i + shift] = (a[i + shift] + q - mul(f, b[i])) % q;
            }
            trim_mod(a);
            if (a.empty()) break;
        }
        std::swap(a, b);
    }
    return a.size() == 1;  // the gcd is a nonzero constant
}

/// a / b for b dividing a in Q[t], a and b primitive: the quotient is in Z[t] (Gauss's lemma),
/// so every leading-coefficient division is exact.
ZPoly z_divexact(ZPoly a, const ZPoly& b) {
    const int db = z_degree(b);
    const int dq = z_degree(a) - db;
    if (dq < 0) return {};
    ZPoly q(dq + 1);
    for (int k = dq; k >= 0; --k) {
        mpz_divexact(q[k].get_mpz_t(), a[k + db].get_mpz_t(), b.back().get_mpz_t());
        for (int i = 0; i <= db; ++i) a[i + k] -= q[k] * b[i];
    }
    trim(q);
    return q;
}

/// The Sturm sequence p, p′, −rem(p, p′), … up to a constant, each term scaled by a positive
/// factor (so that the signs are those of the classical sequence).
std::vector<ZPoly> sturm_sequence(const ZPoly& p) {
    std::vector<ZPoly> s{p, z_derivative(p)};
    make_primitive(s[1]);
    while (z_degree(s.back()) > 0) {
        const ZPoly& a = s[s.size() - 2];
        const ZPoly& b = s.back();
        int steps = 0;
        ZPoly r = z_prem(a, b, steps);
        if (r.empty()) break;  // p square-free: cannot happen; the sequence ends anyway
        // r = lc(b)^steps · rem(a, b); the next term is −rem(a, b), up to a positive factor.
        const bool flip = !(sgn(b.back()) < 0 && (steps & 1));
        if (flip) {
            for (mpz_class& c : r) c = -c;
        }
        make_primitive(r);
        s.push_back(std::move(r));
    }
    return s;
}

/// A double point x = m·2^−k exactly (k ≥ 0, m an integer), or ±∞ (inf = ±1).
struct Point {
    mpz_class m;
    unsigned long k = 0;
    int inf = 0;
    double value = 0;
};

Point make_point(double x) {
    Point pt;
    pt.value = x;
    if (std::isinf(x)) {
        pt.inf = x > 0 ? 1 : -1;
        return pt;
    }
    if (x == 0) return pt;
    int e = 0;
    const double f = std::frexp(x, &e);  // x = f·2^e, 0.5 ≤ |f| < 1
    auto mant = static_cast<std::int64_t>(std::ldexp(f, 53));
    e -= 53;
    while (e < 0 && (mant & 1) == 0) {  // the fewest bits of 2^−k
        mant /= 2;
        ++e;
    }
    pt.m = static_cast<long>(mant);
    if (e >= 0) {
        mpz_mul_2exp(pt.m.get_mpz_t(), pt.m.get_mpz_t(), static_cast<unsigned long>(e));
    } else {
        pt.k = static_cast<unsigned long>(-e);
    }
    return pt;
}

/// The sign of p(x), exactly: Σ a_i m^i 2^{k(n−i)} = p(x)·2^{kn} by Horner's rule; at ±∞, the
/// sign of the leading term.
int sign_at(const ZPoly& p, const Point& x, mpz_class& v, mpz_class& tmp) {
    if (p.empty()) return 0;
    const int n = z_degree(p);
    if (x.inf != 0) {
        const int s = sgn(p.back());
        return (x.inf < 0 && (n & 1)) ? -s : s;
    }
    v = p.back();
    for (int i = n - 1; i >= 0; --i) {
        v *= x.m;
        if (x.k == 0) {
            v += p[i];
        } else {
            mpz_mul_2exp(tmp.get_mpz_t(), p[i].get_mpz_t(),
                         x.k * static_cast<unsigned long>(n - i));
            v += tmp;
        }
    }
    return sgn(v);
}

// ---------------------------------------------------------------------------------------------
// The order of the doubles: a key per double with −0 and +0 one key, so that the midpoint of two
// keys is a double between the two, and equal keys of neighbours mean adjacent doubles.

constexpr std::uint64_t kZeroKey = std::uint64_t{1} << 63;

std::uint64_t key(double x) {
    const std::uint64_t mag = std::bit_cast<std::uint64_t>(x) & ~kZeroKey;
    return std::signbit(x) ? kZeroKey - mag : kZeroKey + mag;
}

double from_key(std::uint64_t k) {
    if (k >= kZeroKey) return std::bit_cast<double>(k - kZeroKey);
    return -std::bit_cast<double>(kZeroKey - k);
}

/// A double strictly between a < b in their order, or a when they are adjacent.
double mid(double a, double b) {
    const std::uint64_t ka = key(a), kb = key(b);
    return from_key(ka + (kb - ka) / 2);
}

// ---------------------------------------------------------------------------------------------

/// The search along one ray.
class Search {
  public:
    Search(const ExactOptions& options, ExactRoot& out) : options_(options), out_(out) {}

    void run(const Ray& ray, const ExactPoly& g);

  private:
    RayResult& res() { return out_.result; }
    bool out_of_budget() const { return out_.result.evals.value >= options_.budget; }
    int sign(const ZPoly& p, const Point& x) {
        ++res().evals.value;
        return sign_at(p, x, v_, tmp_);
    }
    /// Sign variations of the Sturm sequence at x (zeros skipped).
    int variations(const Point& x) {
        ++res().evals.value;
        int count = 0, last = 0;
        for (const ZPoly& q : sturm_) {
            const int s = sign_at(q, x, v_, tmp_);
            if (s == 0) continue;
            if (last != 0 && s != last) ++count;
            last = s;
        }
        return count;
    }
    void finish(Status status, double lo, double hi) {
        res().status = status;
        if (status != Status::Miss) {
            res().t_lo = lo;
            res().t_hi = hi;
            res().t = lo == hi || !std::isfinite(hi) || !std::isfinite(lo) ? lo : mid(lo, hi);
        }
    }
    /// The multiplicity of the only root of p in [a, b] (a = b: the root is a; a < b: it lies in
    /// (a, b), p(a), p(b) ≠ 0). A root of g_k is a root of p, so g_k has the root iff its
    /// square-free part g_k / g_{k+1} (simple roots only) changes sign over [a, b] or, for a = b,
    /// iff g_k(a) = 0.
    int multiplicity(double a, double b);

    const ExactOptions& options_;
    ExactRoot& out_;
    std::vector<ZPoly> chain_;  // g_0, g_1 = gcd(g_0, g_0′), … as far as computed
    std::vector<ZPoly> sturm_;
    mpz_class v_, tmp_;
};

int Search::multiplicity(double a, double b) {
    const Point pa = make_point(a), pb = make_point(b);
    int m = 1;
    for (std::size_t k = 1;; ++k) {
        if (z_degree(chain_[k]) <= 0) break;  // g_k constant: no root
        if (chain_.size() == k + 1) {
            ZPoly d = z_derivative(chain_[k]);
            chain_.push_back(z_gcd(chain_[k], std::move(d)));
        }
        bool root = false;
        if (a == b) {
            root = sign(chain_[k], pa) == 0;
        } else {
            const ZPoly q = z_divexact(chain_[k], chain_[k + 1]);
            root = sign(q, pa) * sign(q, pb) < 0;
        }
        if (!root) break;
        ++m;
    }
    return m;
}

void Search::run(const Ray& ray, const ExactPoly& g) {
    if (g.degree() < 0) {  // g ≡ 0: every t is a root
        finish(Status::Hit, ray.tmin, ray.tmin);
        return;
    }
    if (g.degree() == 0) {
        finish(Status::Miss, 0, 0);
        return;
    }
    // g_0: g times the lcm of its denominators, primitive.
    mpz_class den = 1;
    for (const mpq_class& c : g.c) mpz_lcm(den.get_mpz_t(), den.get_mpz_t(), c.get_den_mpz_t());
    ZPoly g0;
    g0.reserve(g.c.size());
    for (const mpq_class& c : g.c) {
        mpz_class z = c.get_num() * (den / c.get_den());
        g0.push_back(std::move(z));
    }
    make_primitive(g0);
    chain_.clear();
    chain_.push_back(g0);
    if (square_free_mod_prime(g0)) {  // the common case: no gcd over Z needed
        chain_.push_back(ZPoly{mpz_class(1)});
    } else {
        chain_.push_back(z_gcd(g0, z_derivative(g0)));
    }
    const ZPoly p = z_degree(chain_[1]) == 0 ? g0 : z_divexact(g0, chain_[1]);

    // Cauchy: every root r of p has |r| ≤ 1 + max_{i<n} |a_i / a_n| < 2^(max(c, 0) + 1), with
    // c = bits(max |a_i|) − bits(|a_n|) + 1.
    long max_bits = 0;
    for (int i = 0; i < z_degree(p); ++i) {
        if (sgn(p[i]) != 0) {
            max_bits = std::max(max_bits, static_cast<long>(mpz_sizeinbase(p[i].get_mpz_t(), 2)));
        }
    }
    const long c = max_bits - static_cast<long>(mpz_sizeinbase(p.back().get_mpz_t(), 2)) + 1;
    const long e = std::max(c, 0L) + 1;
    const double bound = e > 1023 ? kInf : std::ldexp(1.0, static_cast<int>(e));
    const double lo = std::max(ray.tmin, -bound);
    const double hi = std::min(ray.tmax, bound);
    if (lo > hi) {  // [tmin, tmax] beyond every root
        finish(Status::Miss, 0, 0);
        return;
    }
    const Point plo = make_point(lo);
    if (options_.budget < 4) {  // not even the first count
        finish(Status::Unknown, ray.tmin, ray.tmax);
        return;
    }
    if (lo == ray.tmin && std::isfinite(lo) && sign(p, plo) == 0) {
        out_.multiplicity = multiplicity(lo, lo);
        finish(Status::Hit, lo, lo);
        return;
    }
    if (lo == hi) {  // p(lo) ≠ 0 (checked, or lo = ±bound)
        finish(Status::Miss, 0, 0);
        return;
    }
    if (out_of_budget()) {
        finish(Status::Unknown, ray.tmin, ray.tmax);
        return;
    }
    sturm_ = sturm_sequence(p);

    // Sturm phase: (a, b] holds count ≥ 1 distinct roots, (tmin, a] none, p(a) ≠ 0.
    double a = lo, b = hi;
    int va = variations(plo);
    int vb = variations(make_point(hi));
    int count = va - vb;
    if (count <= 0) {
        finish(Status::Miss, 0, 0);
        return;
    }
    while (count > 1) {
        const double m = mid(a, b);
        if (m == a || out_of_budget()) {  // proven, not isolated
            finish(Status::Hit, a, b);
            return;
        }
        const int vm = variations(make_point(m));
        if (va - vm == 0) {
            a = m;
            va = vm;
            count = vm - vb;
        } else {
            b = m;
            vb = vm;
            count = va - vm;
        }
    }
    // Sign phase: exactly one root in (a, b], simple in p; p(a) ≠ 0.
    const int sa = sign(p, make_point(a));
    if (sign(p, make_point(b)) == 0) {
        out_.multiplicity = multiplicity(b, b);
        finish(Status::Hit, b, b);
        return;
    }
    for (;;) {
        const double m = mid(a, b);
        if (m == a) break;
        if (out_of_budget()) {
            out_.multiplicity = multiplicity(a, b);
            finish(Status::Hit, a, b);
            return;
        }
        const int sm = sign(p, make_point(m));
        if (sm == 0) {
            out_.multiplicity = multiplicity(m, m);
            finish(Status::Hit, m, m);
            return;
        }
        if (sm == sa) {
            a = m;
        } else {
            b = m;
        }
    }
    out_.multiplicity = multiplicity(a, b);
    finish(Status::Hit, a, b);
}

}  // namespace

namespace {

/// The exact oracle's rule: g is a polynomial with rational coefficients along every ray when only
/// + − × square, integer powers, division by constants and abs/min/max of constants appear.
/// (sqrt, exp, … are refused even of constants: their values are not rational.)
OpRule exact_polynomial_rule(expr::Op op) {
    switch (op) {
        case expr::Op::Sqrt:
        case expr::Op::Exp:
        case expr::Op::Log:
        case expr::Op::Sin:
        case expr::Op::Cos:
        case expr::Op::Floor:
        case expr::Op::Ceil:
        case expr::Op::Round:
        case expr::Op::Tan:
        case expr::Op::Asin:
        case expr::Op::Acos:
        case expr::Op::Atan:
        case expr::Op::Recip:
        case expr::Op::Not:
        case expr::Op::Atan2:
        case expr::Op::Compare:
        case expr::Op::Mod:
        case expr::Op::And:
        case expr::Op::Or:
            return {Along::Never, Along::Never};
        case expr::Op::Div:
            return {Along::Passes, Along::Refused};
        case expr::Op::Abs:
        case expr::Op::Min:
        case expr::Op::Max:
            return {Along::Refused, Along::Refused};
        case expr::Op::Const:
        case expr::Op::VarX:
        case expr::Op::VarY:
        case expr::Op::VarZ:
        case expr::Op::Neg:
        case expr::Op::Square:
        case expr::Op::Add:
        case expr::Op::Sub:
        case expr::Op::Mul:
        case expr::Op::Pow:
            return {};
    }
    return {Along::Never, Along::Never};
}

}  // namespace

std::string why_not_exact_polynomial(const expr::Tape& tape) {
    return why_not_along(tape, &exact_polynomial_rule);
}

bool is_polynomial(const expr::Tape& tape) {
    thread_local std::uint64_t serial = 0;
    thread_local bool answer = false;
    if (tape.serial() == 0 || tape.serial() != serial) {
        answer = why_not_exact_polynomial(tape).empty();
        serial = tape.serial();
    }
    return answer;
}

std::optional<ExactPoly> exact_polynomial(const expr::Tape& tape, const Ray& ray) {
    NearestScope env;  // GMP reads doubles with the FPU: not under a caller's DAZ
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(ray.o[i]) || !std::isfinite(ray.d[i])) return std::nullopt;
    }
    if (!is_polynomial(tape) || tape.size() == 0) return std::nullopt;
    std::vector<QPoly> r(tape.registers());
    auto coordinate = [&](int axis) {
        QPoly q{mpq_class(ray.o[axis]), mpq_class(ray.d[axis])};
        trim(q);
        return q;
    };
    for (const expr::Instr& in : tape.instrs()) {
        QPoly out;
        switch (in.op) {
            case expr::Op::Const:
                out = {mpq_class(in.imm)};
                trim(out);
                break;
            case expr::Op::VarX:
            case expr::Op::VarY:
            case expr::Op::VarZ:
                out = coordinate(static_cast<int>(in.op) - static_cast<int>(expr::Op::VarX));
                break;
            case expr::Op::Neg:
                out = r[in.a];
                for (mpq_class& c : out) c = -c;
                break;
            case expr::Op::Square:
                out = q_mul(r[in.a], r[in.a]);
                if (too_big(out)) return std::nullopt;
                break;
            case expr::Op::Pow:
                if (!q_pow(r[in.a], in.b, out)) return std::nullopt;
                break;
            case expr::Op::Add:
                out = q_add(r[in.a], r[in.b], false);
                break;
            case expr::Op::Sub:
                out = q_add(r[in.a], r[in.b], true);
                break;
            case expr::Op::Mul:
                if (q_degree(r[in.a]) + q_degree(r[in.b]) > kMaxExactDegree) return std::nullopt;
                out = q_mul(r[in.a], r[in.b]);
                if (too_big(out)) return std::nullopt;
                break;
            case expr::Op::Div: {  // by a constant (is_polynomial)
                if (q_degree(r[in.b]) > 0 || r[in.b].empty()) return std::nullopt;
                const mpq_class inv = 1 / r[in.b][0];
                out = r[in.a];
                for (mpq_class& c : out) c *= inv;
                if (too_big(out)) return std::nullopt;
                break;
            }
            case expr::Op::Abs:
                if (q_degree(r[in.a]) > 0) return std::nullopt;
                out = {abs(q_const(r[in.a]))};
                trim(out);
                break;
            case expr::Op::Min:
            case expr::Op::Max: {
                if (q_degree(r[in.a]) > 0 || q_degree(r[in.b]) > 0) return std::nullopt;
                const mpq_class x = q_const(r[in.a]), y = q_const(r[in.b]);
                out = {in.op == expr::Op::Min ? (x < y ? x : y) : (x < y ? y : x)};
                trim(out);
                break;
            }
            case expr::Op::Sqrt:
            case expr::Op::Exp:
            case expr::Op::Log:
            case expr::Op::Sin:
            case expr::Op::Cos:
            case expr::Op::Floor:
            case expr::Op::Ceil:
            case expr::Op::Round:
            case expr::Op::Tan:
            case expr::Op::Asin:
            case expr::Op::Acos:
            case expr::Op::Atan:
            case expr::Op::Recip:
            case expr::Op::Not:
            case expr::Op::Atan2:
            case expr::Op::Compare:
            case expr::Op::Mod:
            case expr::Op::And:
            case expr::Op::Or:
                return std::nullopt;  // excluded by is_polynomial
        }
        r[in.out] = std::move(out);
    }
    ExactPoly g;
    g.c = std::move(r[tape.output()]);
    return g;
}

ExactRoot exact_root(const expr::Tape& tape, const Ray& ray, const ExactOptions& options) {
    NearestScope env;  // GMP reads and writes doubles with the FPU: not under FTZ|DAZ
    ExactRoot out;
    ++out.result.evals.interval;
    const std::optional<ExactPoly> g =
        ray.tmin <= ray.tmax ? exact_polynomial(tape, ray) : std::nullopt;
    if (!g) {
        out.result.status = Status::Unknown;
        out.result.t_lo = ray.tmin;
        out.result.t_hi = ray.tmax;
        out.result.t = ray.tmin;
        return out;
    }
    Search(options, out).run(ray, *g);
    return out;
}

RayResult exact_first_root(const expr::Tape& tape, const Ray& ray, const ExactOptions& options) {
    return exact_root(tape, ray, options).result;
}

RayResult exact_fallback(const expr::Tape& tape, const Ray& ray, RayResult r, std::uint64_t budget,
                         bool tighten) {
    const bool decided = r.status == Status::Miss ||
                         (r.status == Status::Hit && (!tighten || narrow(r.t_lo, r.t_hi)));
    if (decided) return r;
    const std::uint64_t spent = r.evals.total();
    if (spent >= budget || !is_polynomial(tape)) return r;
    ExactOptions exact;
    exact.budget = budget - spent;
    RayResult e = exact_first_root(tape, ray, exact);
    e.evals += r.evals;
    if (e.status == Status::Unknown) {
        r.evals = e.evals;
        return r;
    }
    return e;
}

}  // namespace certray::solvers
