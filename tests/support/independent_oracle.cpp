// The independent oracle for certified answers: see independent_oracle.h.
//
// Only the evaluator (expr::eval<MpfrInterval>) and the exact oracle (solvers/exact.h) are shared
// with the library; every decision (subdivision, signs, continuity, hit/miss) is made here.
#include "tests/support/independent_oracle.h"

#include <mpfr.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <utility>
#include <vector>

#include "expr/eval.h"
#include "interval/dual.h"
#include "interval/mpfr_interval.h"
#include "solvers/exact.h"

namespace certray::testing {

std::string_view name(Verdict v) noexcept {
    switch (v) {
        case Verdict::Confirmed:
            return "confirmed";
        case Verdict::Unverified:
            return "unverified";
        case Verdict::Refuted:
            return "refuted";
        case Verdict::NotApplicable:
            return "n/a";
    }
    return "?";
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Pieces are [A + (B − A)·k/2ⁿ, A + (B − A)·(k+1)/2ⁿ] with n ≤ kMaxDepth (k exact in a double).
constexpr int kMaxDepth = 52;

std::string fmt(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

/// g over sets of t, in MPFR.
class G {
  public:
    G(const expr::Tape& tape, const Ray& ray, long precision)
        : tape_(tape), ray_(ray), prec_(precision) {}

    /// The enclosure of g over T (an MpfrInterval of t).
    MpfrInterval over(const MpfrInterval& t) const {
        std::array<MpfrInterval, 3> p;
        for (int i = 0; i < 3; ++i) p[i] = mi(ray_.o[i]) + t * mi(ray_.d[i]);
        return expr::eval<MpfrInterval>(tape_, p);
    }
    /// g at the double t; `exact_point` says whether o + t·d was computed without rounding.
    MpfrInterval at(double t, bool* exact_point) const {
        std::array<MpfrInterval, 3> p;
        bool exact = true;
        for (int i = 0; i < 3; ++i) {
            p[i] = mi(ray_.o[i]) + mi(t) * mi(ray_.d[i]);
            exact = exact && !p[i].is_empty() && mpfr_equal_p(p[i].lo(), p[i].hi()) != 0;
        }
        *exact_point = exact;
        return expr::eval<MpfrInterval>(tape_, p);
    }
    /// The piece (k, n) of [a, b]: a + (b − a)·[k, k+1]·2⁻ⁿ, rounded outward (exact in practice).
    MpfrInterval piece(double a, double b, double k, int n) const {
        const MpfrInterval width = mi(b) - mi(a);
        const MpfrInterval u = MpfrInterval(k, k + 1, Precision{prec_}) * mi(std::ldexp(1.0, -n));
        return mi(a) + width * u;
    }
    /// g is continuous on T and its derivative (every one-sided one) is bounded away from 0.
    bool monotone_over(const MpfrInterval& t) const {
        using M1 = Dual<MpfrInterval, 1>;
        std::array<M1, 3> p;
        for (int i = 0; i < 3; ++i) p[i] = M1(mi(ray_.o[i]) + t * mi(ray_.d[i]), {mi(ray_.d[i])});
        const M1 r = expr::eval<M1>(tape_, p);
        const MpfrInterval& d = r.v[0];
        return !r.a.is_empty() && r.a.defined && !d.is_empty() &&
               (mpfr_sgn(d.lo()) > 0 || mpfr_sgn(d.hi()) < 0);
    }
    /// The end a + (b − a)·k·2⁻ⁿ of a piece, as a (degenerate in practice) MPFR interval.
    MpfrInterval node(double a, double b, double k, int n) const {
        return mi(a) + (mi(b) - mi(a)) * (mi(k) * mi(std::ldexp(1.0, -n)));
    }
    /// [a, b] with a finite and b possibly +inf.
    MpfrInterval span(double a, double b) const { return MpfrInterval(a, b, Precision{prec_}); }

  private:
    MpfrInterval mi(double x) const { return MpfrInterval(x, Precision{prec_}); }
    const expr::Tape& tape_;
    const Ray& ray_;
    long prec_;
};

bool excludes_zero(const MpfrInterval& v) {
    // Empty: no point of the piece is in f's domain, so no zero there.
    return v.is_empty() || mpfr_sgn(v.lo()) > 0 || mpfr_sgn(v.hi()) < 0;
}

/// +1 / −1 when g(t) is proven positive / negative, 0 when proven exactly zero (o + t·d exact,
/// g defined there, enclosure [0, 0]), 2 when undecided or undefined.
int sign_at(const G& g, double t) {
    bool exact = false;
    const MpfrInterval v = g.at(t, &exact);
    if (v.is_empty()) return 2;
    if (mpfr_sgn(v.lo()) > 0) return 1;
    if (mpfr_sgn(v.hi()) < 0) return -1;
    if (exact && v.defined && mpfr_zero_p(v.lo()) && mpfr_zero_p(v.hi())) return 0;
    return 2;
}

/// Every piece of a cover of [a, b] (a ≤ b finite) has an enclosure decorated defined (g defined
/// and continuous on [a, b]).
bool continuous_on(const G& g, double a, double b, long budget) {
    std::vector<std::pair<double, int>> stack{{0.0, 0}};
    while (!stack.empty()) {
        const auto [k, n] = stack.back();
        stack.pop_back();
        if (--budget < 0) return false;
        const MpfrInterval v = g.over(g.piece(a, b, k, n));
        if (!v.is_empty() && v.defined) continue;
        if (n >= 40) return false;  // a discontinuity (or a domain edge) inside
        stack.push_back({2 * k + 1, n + 1});
        stack.push_back({2 * k, n + 1});
    }
    return true;
}

/// A zero of g proven in [a, b] (finite doubles, a ≤ b): an exact zero at one of `samples` + 1
/// double points, or strict opposite signs at consecutive points with g continuous between them.
/// Writes the points that prove it into `where`.
bool prove_zero(const G& g, double a, double b, int samples, long continuity_budget,
                std::string* where) {
    double prev_t = a;
    int prev_s = sign_at(g, a);
    if (prev_s == 0) {
        *where = "g(" + fmt(a) + ") = 0 exactly";
        return true;
    }
    for (int i = 1; i <= samples; ++i) {
        double t = i == samples ? b : a + (b - a) * (static_cast<double>(i) / samples);
        if (!(t > prev_t) || t > b) continue;
        const int s = sign_at(g, t);
        if (s == 0) {
            *where = "g(" + fmt(t) + ") = 0 exactly";
            return true;
        }
        if ((s == 1 && prev_s == -1) || (s == -1 && prev_s == 1)) {
            if (continuous_on(g, prev_t, t, continuity_budget)) {
                *where = "g changes sign continuously on [" + fmt(prev_t) + ", " + fmt(t) + "]";
                return true;
            }
        }
        if (s != 2) {
            prev_t = t;
            prev_s = s;
        }
    }
    return false;
}

/// Where an exclusion stopped: the hull of the piece it could not exclude (or where it proved a
/// zero), in doubles.
struct Stuck {
    double lo = 0, hi = 0;
};

enum class Cover {
    Excluded,  // no zero
    GaveUp,    // budget or depth spent
    Zero,      // a zero proven (in [lo, hi] of Stuck)
};

/// +1 / −1 when every member of v is positive / negative, else 0.
int strict_sign(const MpfrInterval& v) {
    if (v.is_empty()) return 0;
    return mpfr_sgn(v.lo()) > 0 ? 1 : mpfr_sgn(v.hi()) < 0 ? -1 : 0;
}

/// No zero of g on [a, b] (or [a, b) when open_right; a ≤ b finite) by adaptive subdivision.
/// A piece T = [c, d] is done when g's enclosure over it excludes 0, or when g is monotone on it
/// (continuous, g′ — both one-sided derivatives at kinks — bounded away from 0) and g(c), g(d)
/// have the same strict sign, or, for [a, b) with g(b) = 0 exactly, when T ends at b and g is
/// monotone on it (b its only zero). When g is continuous on T with g(c), g(d) of opposite strict
/// signs, a zero is proven in T (for [a, b), unless T ends at b and g(b) is not proven ≠ 0).
/// Spends `*budget`; `*stuck` is the piece where it gave up or proved a zero.
Cover exclude_segment(const G& g, double a, double b, bool open_right, long* budget, Stuck* stuck) {
    if (open_right && a == b) return Cover::Excluded;  // [a, a) is empty
    const int sign_b = open_right ? sign_at(g, b) : 2;
    std::vector<std::pair<double, int>> stack{{0.0, 0}};
    while (!stack.empty()) {
        const auto [k, n] = stack.back();
        stack.pop_back();
        const MpfrInterval t = g.piece(a, b, k, n);
        *stuck = {t.lower(), t.upper()};
        if ((*budget -= 4) < 0) return Cover::GaveUp;
        const MpfrInterval v = g.over(t);
        if (excludes_zero(v)) continue;
        const bool rightmost = open_right && k + 1 == std::ldexp(1.0, n);
        const int sl = strict_sign(g.over(g.node(a, b, k, n)));
        const int sr = strict_sign(g.over(g.node(a, b, k + 1, n)));
        if (sl * sr < 0 && v.defined && (!rightmost || sign_b == 1 || sign_b == -1)) {
            return Cover::Zero;
        }
        if (((sl != 0 && sl == sr) || (rightmost && sign_b == 0)) && g.monotone_over(t)) continue;
        if (n >= kMaxDepth) return Cover::GaveUp;
        stack.push_back({2 * k + 1, n + 1});
        stack.push_back({2 * k, n + 1});
    }
    return Cover::Excluded;
}

/// exclude_segment on [a, b] closed, b possibly +inf: [a, a + 1], then pieces doubling in length
/// up to 2⁶⁴ past a, then one unbounded tail (its enclosure must exclude 0).
Cover exclude_range(const G& g, double a, double b, long* budget, Stuck* stuck) {
    *stuck = {a, b};
    if (b < kInf) return exclude_segment(g, a, b, false, budget, stuck);
    double lo = a;
    for (int j = 0; j <= 64; ++j) {
        const double hi = a + std::ldexp(1.0, j);
        if (hi > lo) {
            const Cover c = exclude_segment(g, lo, hi, false, budget, stuck);
            if (c != Cover::Excluded) return c;
            lo = hi;
        }
    }
    *stuck = {lo, std::numeric_limits<double>::max()};
    if (--*budget < 0) return Cover::GaveUp;
    return excludes_zero(g.over(g.span(lo, kInf))) ? Cover::Excluded : Cover::GaveUp;
}

// ---- the exact route ---------------------------------------------------------------------------

enum class Tri { No, Yes, Unsure };

RayResult exact_on(const expr::Tape& tape, const Ray& ray, double lo, double hi,
                   const OracleOptions& opt) {
    Ray r = ray;
    r.tmin = lo;
    r.tmax = hi;
    solvers::ExactOptions eo;
    eo.budget = opt.exact_budget;
    return solvers::exact_first_root(tape, r, eo);
}

/// g has no zero in [tmin, a), given e, the exact answer on [tmin, tmax].
Tri exact_none_before(const expr::Tape& tape, const Ray& ray, const RayResult& e, double a,
                      const OracleOptions& opt) {
    if (e.status == Status::Miss) return Tri::Yes;
    if (e.status != Status::Hit) return Tri::Unsure;
    if (e.t_lo >= a) return Tri::Yes;  // the first root r ≥ e.t_lo
    if (e.t_hi < a) return Tri::No;    // r ≤ e.t_hi < a
    const RayResult before = exact_on(tape, ray, ray.tmin, a, opt);
    if (before.status == Status::Miss) return Tri::Yes;
    if (before.status == Status::Hit && before.t_lo == a) return Tri::Yes;  // r = a exactly
    if (before.status == Status::Hit && before.t_hi < a) return Tri::No;
    return Tri::Unsure;
}

Verdict exact_route(const expr::Tape& tape, const Ray& ray, const RayResult& claim,
                    const OracleOptions& opt, std::string* why) {
    const RayResult e = exact_on(tape, ray, ray.tmin, ray.tmax, opt);
    *why += "exact: " + std::string(certray::name(e.status));
    if (e.status == Status::Hit) *why += " [" + fmt(e.t_lo) + ", " + fmt(e.t_hi) + "]";
    *why += "; ";
    if (claim.status == Status::Miss) {
        if (e.status == Status::Miss) return Verdict::Confirmed;
        return e.status == Status::Hit ? Verdict::Refuted : Verdict::Unverified;
    }
    const double a = claim.t_lo, b = claim.t_hi;
    const Tri none_before = exact_none_before(tape, ray, e, a, opt);
    if (none_before == Tri::No) return Verdict::Refuted;
    if (claim.status == Status::Unknown) return Verdict::Confirmed;  // not refuted
    Tri root_in = Tri::Unsure;
    if (e.status == Status::Miss) {
        root_in = Tri::No;
    } else if (e.status == Status::Hit && a <= e.t_lo && e.t_hi <= b) {
        root_in = Tri::Yes;
    } else if (e.status == Status::Hit && e.t_lo > b) {
        root_in = Tri::No;
    } else {
        const RayResult in = exact_on(tape, ray, a, b, opt);
        root_in = in.status == Status::Hit    ? Tri::Yes
                  : in.status == Status::Miss ? Tri::No
                                              : Tri::Unsure;
    }
    if (root_in == Tri::No) return Verdict::Refuted;
    if (none_before == Tri::Yes && root_in == Tri::Yes) return Verdict::Confirmed;
    return Verdict::Unverified;
}

// ---- the MPFR route ----------------------------------------------------------------------------

Verdict mpfr_route(const expr::Tape& tape, const Ray& ray, const RayResult& claim,
                   const OracleOptions& opt, std::string* why) {
    const G g(tape, ray, opt.precision);
    long budget = opt.exclusion_budget;
    std::string where;
    Stuck stuck;
    // Refutation where an exclusion gave up: a proven zero in the stuck piece, or in [tmin, the
    // stuck piece's end], before `end` (or at it, when closed).
    auto zero_before = [&](double end, bool closed) {
        const double last = closed ? end : std::nextafter(end, -kInf);
        if (!(last >= ray.tmin) || !std::isfinite(last)) return false;
        const double hi = std::min(last, stuck.hi), lo = std::max(ray.tmin, std::min(stuck.lo, hi));
        return prove_zero(g, lo, hi, opt.refute_samples / 4, opt.continuity_budget, &where) ||
               prove_zero(g, ray.tmin, hi, opt.refute_samples, opt.continuity_budget, &where);
    };
    // Built by appends: GCC 12 warns (-Wrestrict, a false positive) on "literal" + std::string&&.
    auto at = [&] {
        std::string s = "[";
        s.append(fmt(stuck.lo)).append(", ").append(fmt(stuck.hi)).append("]");
        return s;
    };
    if (claim.status == Status::Miss) {
        const Cover c = exclude_range(g, ray.tmin, ray.tmax, &budget, &stuck);
        if (c == Cover::Excluded) {
            *why += "mpfr: [tmin, tmax] excluded; ";
            return Verdict::Confirmed;
        }
        if (c == Cover::Zero) {
            *why += "mpfr: a sign change with continuity on " + at() + "; ";
            return Verdict::Refuted;
        }
        if (zero_before(std::min(ray.tmax, std::numeric_limits<double>::max()), true)) {
            *why += "mpfr: " + where + "; ";
            return Verdict::Refuted;
        }
        *why += "mpfr: exclusion of [tmin, tmax] gave up at " + at() + "; ";
        return Verdict::Unverified;
    }
    const double a = claim.t_lo, b = claim.t_hi;
    stuck = {ray.tmin, a};
    const Cover before = exclude_segment(g, ray.tmin, a, true, &budget, &stuck);
    if (before == Cover::Zero) {
        *why += "mpfr: zero before t_lo: a sign change with continuity on " + at() + "; ";
        return Verdict::Refuted;
    }
    if (before == Cover::GaveUp && zero_before(a, false)) {
        *why += "mpfr: zero before t_lo: " + where + "; ";
        return Verdict::Refuted;
    }
    const bool excluded = before == Cover::Excluded;
    const std::string gave_up = at();
    if (claim.status == Status::Unknown) return Verdict::Confirmed;  // not refuted
    bool exists = prove_zero(g, a, b, opt.existence_samples, opt.continuity_budget, &where);
    if (!exists) {
        long rest = std::max(budget, opt.continuity_budget);
        const Cover c = exclude_segment(g, a, b, false, &rest, &stuck);
        if (c == Cover::Excluded) {
            *why += "mpfr: no zero in [t_lo, t_hi]; ";
            return Verdict::Refuted;
        }
        if (c == Cover::Zero) {
            exists = true;
            where = "a sign change with continuity on " + at();
        }
    }
    *why += "mpfr: [tmin, t_lo) " +
            (excluded ? std::string("excluded") : "not excluded (gave up at " + gave_up + ")") +
            ", zero in [t_lo, t_hi] " + (exists ? "proven (" + where + ")" : "not proven") + "; ";
    return excluded && exists ? Verdict::Confirmed : Verdict::Unverified;
}

}  // namespace

Judgement judge_claim(const expr::Tape& tape, const Ray& ray, const RayResult& claim,
                      const OracleOptions& options) {
    Judgement j;
    if (claim.status != Status::Miss) {
        const bool unknown_without_range =
            claim.status == Status::Unknown && !(claim.t_lo == claim.t_lo);
        if (unknown_without_range) {
            j.verdict = Verdict::Confirmed;
            j.why = "unknown without a range";
            return j;
        }
        // The enclosure must be a nonempty part of the ray's range.
        if (!(ray.tmin <= claim.t_lo && claim.t_lo <= claim.t_hi && claim.t_hi <= ray.tmax)) {
            j.verdict = Verdict::Refuted;
            j.why = "[t_lo, t_hi] not within [tmin, tmax]";
            return j;
        }
    }
    if (options.use_exact && solvers::is_polynomial(tape)) {
        j.exact = exact_route(tape, ray, claim, options, &j.why);
    }
    if (options.use_mpfr) j.mpfr = mpfr_route(tape, ray, claim, options, &j.why);
    if (j.exact == Verdict::Refuted || j.mpfr == Verdict::Refuted) {
        j.verdict = Verdict::Refuted;
    } else if (j.exact == Verdict::Confirmed || j.mpfr == Verdict::Confirmed) {
        j.verdict = Verdict::Confirmed;
    } else {
        j.verdict = Verdict::Unverified;
    }
    return j;
}

void OracleTally::add(const RayResult& claim, const Judgement& j) {
    switch (claim.status) {
        case Status::Hit:
            ++hits;
            break;
        case Status::Miss:
            ++misses;
            break;
        case Status::Unknown:
            ++unknowns;
            break;
    }
    if (j.verdict == Verdict::Refuted) ++refuted;
    if (claim.status == Status::Unknown) return;
    if (j.verdict == Verdict::Confirmed) ++confirmed;
    if (j.verdict == Verdict::Unverified) ++unverified;
    if (j.exact == Verdict::Confirmed) ++exact_confirmed;
    if (j.mpfr == Verdict::Confirmed) ++mpfr_confirmed;
    if (j.exact != Verdict::NotApplicable && j.mpfr == Verdict::Unverified) {
        ++mpfr_unverified_polynomial;
    }
}

Judgement OracleTally::judge(const expr::Tape& tape, const Ray& ray, const RayResult& claim,
                             const OracleOptions& options) {
    Judgement j = judge_claim(tape, ray, claim, options);
    add(claim, j);
    if (j.verdict == Verdict::Unverified && claim.status != Status::Unknown &&
        std::getenv("CERTRAY_ORACLE_VERBOSE") != nullptr) {
        std::printf("unverified: %s: %s\n", describe(ray, claim).c_str(), j.why.c_str());
    }
    return j;
}

std::string OracleTally::summary(std::string_view what) const {
    char buf[400];
    std::snprintf(
        buf, sizeof buf,
        "%.*s: %llu hits, %llu misses, %llu unknowns; confirmed %llu (exact %llu, mpfr "
        "%llu), unverified %llu, refuted %llu; mpfr unverified on polynomials %llu",
        static_cast<int>(what.size()), what.data(), static_cast<unsigned long long>(hits),
        static_cast<unsigned long long>(misses), static_cast<unsigned long long>(unknowns),
        static_cast<unsigned long long>(confirmed),
        static_cast<unsigned long long>(exact_confirmed),
        static_cast<unsigned long long>(mpfr_confirmed),
        static_cast<unsigned long long>(unverified), static_cast<unsigned long long>(refuted),
        static_cast<unsigned long long>(mpfr_unverified_polynomial));
    return buf;
}

std::string describe(const Ray& ray, const RayResult& r) {
    std::string s = "ray o (" + fmt(ray.o[0]) + ", " + fmt(ray.o[1]) + ", " + fmt(ray.o[2]) +
                    ") d (" + fmt(ray.d[0]) + ", " + fmt(ray.d[1]) + ", " + fmt(ray.d[2]) +
                    ") t [" + fmt(ray.tmin) + ", " + fmt(ray.tmax) +
                    "]: " + std::string(certray::name(r.status));
    if (r.status != Status::Miss) s += " [" + fmt(r.t_lo) + ", " + fmt(r.t_hi) + "]";
    return s;
}

}  // namespace certray::testing
