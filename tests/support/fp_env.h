// tests/support/fp_env.h — the raw floating-point control words, and hosts that set them.
//
// A library is called from hosts whose floating-point environment it does not control: flush-to-
// zero (FTZ, MXCSR bit 15) and denormals-are-zero (DAZ, bit 6), set by game engines and by any
// object built with -ffast-math, or a rounding direction other than to-nearest. These helpers read
// the whole control state (MXCSR and the x87 control word, not just fegetround(), which reads the
// x87 field alone on x86-64 glibc), and set a host's state for a scope or a whole test run
// (tests/support/main.cpp: CERTRAY_HOST_FPENV).
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

namespace certray::testing {

/// MXCSR and the x87 control word as read by stmxcsr / fnstcw (zeros where there is no x86-64).
struct FpWords {
    std::uint32_t mxcsr = 0;
    std::uint16_t x87 = 0;
    bool operator==(const FpWords&) const = default;
};

/// True when a and b hold the same control state: every bit of both words but MXCSR's six sticky
/// exception flags (bits 0-5, status raised by any inexact operation).
inline bool same_control(const FpWords& a, const FpWords& b) {
    return (a.mxcsr & ~0x3fu) == (b.mxcsr & ~0x3fu) && a.x87 == b.x87;
}

inline FpWords read_fp_words() {
    FpWords w;
#if defined(__GNUC__) && defined(__x86_64__)
    asm volatile("stmxcsr %0" : "=m"(w.mxcsr));
    asm volatile("fnstcw %0" : "=m"(w.x87));
#endif
    return w;
}

inline void write_fp_words(const FpWords& w) {
#if defined(__GNUC__) && defined(__x86_64__)
    asm volatile("ldmxcsr %0" : : "m"(w.mxcsr) : "memory");
    asm volatile("fldcw %0" : : "m"(w.x87) : "memory");
#else
    (void)w;
#endif
}

inline std::string describe(const FpWords& w) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "mxcsr=0x%04x x87=0x%04x", static_cast<unsigned>(w.mxcsr),
                  static_cast<unsigned>(w.x87));
    return buf;
}

inline constexpr std::uint32_t kFtz = 1u << 15;
inline constexpr std::uint32_t kDaz = 1u << 6;

/// The host states the suites are run under: "" or "default" (what the process starts with),
/// "ftz-daz" (both bits set, to-nearest), "upward", "downward", "toward-zero" (that rounding
/// direction in both units). Returns false for any other name.
inline bool host_fp_words(std::string_view name, FpWords base, FpWords& out) {
    out = base;
    unsigned rc = 0;
    if (name.empty() || name == "default") return true;
    if (name == "ftz-daz") {
        out.mxcsr |= kFtz | kDaz;
        return true;
    }
    if (name == "downward") {
        rc = 1;
    } else if (name == "upward") {
        rc = 2;
    } else if (name == "toward-zero") {
        rc = 3;
    } else {
        return false;
    }
    out.mxcsr = (out.mxcsr & ~0x6000u) | (rc << 13);
    out.x87 = static_cast<std::uint16_t>((out.x87 & ~0x0c00u) | (rc << 10));
    return true;
}

/// Sets a host's floating-point state for its lifetime (see host_fp_words), restoring the words
/// it found.
class HostFpEnv {
  public:
    explicit HostFpEnv(std::string_view name) : saved_(read_fp_words()) {
        FpWords w;
        if (!host_fp_words(name, saved_, w)) std::abort();
        write_fp_words(w);
    }
    ~HostFpEnv() { write_fp_words(saved_); }
    HostFpEnv(const HostFpEnv&) = delete;
    HostFpEnv& operator=(const HostFpEnv&) = delete;

  private:
    FpWords saved_;
};

/// The host state of this run: CERTRAY_HOST_FPENV, or "" (tests/support/main.cpp checks it).
inline const char* host_state_name() {
    static const char* name = [] {
        const char* v = std::getenv("CERTRAY_HOST_FPENV");
        return v ? v : "";
    }();
    return name;
}

/// f() called as a host in this run's state (host_state_name()) would call the library: the
/// state is set around the call only, so the test's own arithmetic (generators, the MPFR oracle,
/// expected values) runs in the default environment.
template <class F>
auto as_host(F&& f) {
    HostFpEnv host(host_state_name());
    return f();
}

}  // namespace certray::testing
