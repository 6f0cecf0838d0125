// The MPFR oracle for tests: see mpfr_oracle.h.
#include "tests/support/mpfr_oracle.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "expr/eval.h"

namespace certray::testing {

bool encloses(double lo, double hi, const MpfrInterval& exact) {
    if (exact.is_empty()) {
        return true;
    }
    if (std::isnan(lo) || std::isnan(hi)) {
        return false;
    }
    // mpfr_cmp_d handles infinite operands exactly (−inf ≤ anything, +inf ≥ anything); it reads
    // the double with the FPU, so not under a host's denormals-are-zero.
    NearestScope env;
    return mpfr_cmp_d(exact.lo(), lo) >= 0 && mpfr_cmp_d(exact.hi(), hi) <= 0;
}

namespace {

std::string print_bound(mpfr_srcptr v, bool round_up) {
    const char* format = round_up ? "%.20RUg" : "%.20RDg";
    const int n = mpfr_snprintf(nullptr, 0, format, v);
    if (n < 0) {
        return "<unprintable>";
    }
    std::vector<char> buffer(static_cast<std::size_t>(n) + 1);
    mpfr_snprintf(buffer.data(), buffer.size(), format, v);
    return std::string(buffer.data(), static_cast<std::size_t>(n));
}

}  // namespace

std::string describe(const MpfrInterval& x) {
    // Built by appends: GCC 12 warns (-Wrestrict, a false positive) on "literal" + std::string&&.
    std::string out;
    if (x.is_empty()) {
        out.append("[empty] (prec ").append(std::to_string(x.precision())).append(")");
        return out;
    }
    out.append("[").append(print_bound(x.lo(), false)).append(", ");
    out.append(print_bound(x.hi(), true)).append("] (prec ");
    out.append(std::to_string(x.precision()));
    out.append(x.defined ? ", defined)" : ", undefined)");
    return out;
}

bool lipschitz_holds(const expr::Tape& tape, double lambda, const std::array<double, 3>& p,
                     const std::array<double, 3>& q) {
    auto at = [&](const std::array<double, 3>& s) {
        return expr::eval<MpfrInterval>(
            tape, {MpfrInterval(s[0]), MpfrInterval(s[1]), MpfrInterval(s[2])});
    };
    const MpfrInterval fp = at(p), fq = at(q);
    if (fp.is_empty() || fq.is_empty()) return false;
    const MpfrInterval diff = abs(fp - fq);
    MpfrInterval dist2(0.0);
    for (int i = 0; i < 3; ++i) dist2 = dist2 + square(MpfrInterval(p[i]) - MpfrInterval(q[i]));
    const MpfrInterval bound = MpfrInterval(lambda) * sqrt(dist2);
    // The difference's lower end must not exceed the bound's upper end.
    return mpfr_cmp(diff.lo(), bound.hi()) <= 0;
}

bool mean_value_form_holds(const expr::Tape& tape, const std::array<double, 3>& o,
                           const std::array<double, 3>& u, double t0, double t1,
                           const UpInterval& m, const UpInterval& g1) {
    const double tc = 0.5 * (t0 + t1);
    for (int k = 0; k <= 8; ++k) {
        const double tk = t0 + (t1 - t0) * k / 8.0;
        UpInterval form;
        {
            RoundingScope up;
            form = m + g1 * (UpInterval(tk) - UpInterval(tc));
        }
        const MpfrInterval exact = expr::eval<MpfrInterval>(
            tape, {MpfrInterval(o[0] + tk * u[0]), MpfrInterval(o[1] + tk * u[1]),
                   MpfrInterval(o[2] + tk * u[2])});
        if (exact.is_empty()) return false;
        const double size =
            std::max(1.0, std::max(std::fabs(exact.lower()), std::fabs(exact.upper())));
        if (!(exact.upper() - exact.lower() <= 0x1p-100 * size)) continue;
        if (!encloses(form.lower(), form.upper(), exact)) return false;
    }
    return true;
}

}  // namespace certray::testing
