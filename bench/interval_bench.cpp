// bench/interval_bench.cpp — cost of each number-type operation relative to double (Google
// Benchmark).
//
// Two shapes per operation (+, ×, ÷, sqrt, square, exp, sin, min):
// - chain: a dependent chain of 256 steps y = op(y, x) (latency: what a tape evaluation of one
//   point or box pays along its critical path);
// - array: out[i] = op(a[i], b[i]) over 256 elements (throughput; double may vectorize).
// Number types: double; Interval (every operation saves, sets and restores the rounding mode);
// UpInterval inside one RoundingScope hoisted out of the timed loop; optional Dual and Affine
// types. The custom main runs every benchmark once, adds a counter `x_double` (this time / the
// double time of the same kernel and shape, measured in the same process) and prints a ratio table.
// Results and the command that produced them: docs/benchmarks.md, "Interval operations".
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "interval/interval.h"
#include "interval/number.h"

#ifdef CERTRAY_BENCH_DUAL  // set by bench/CMakeLists.txt when the header exists
#include "interval/dual.h"
#endif
#ifdef CERTRAY_BENCH_AFFINE  // likewise
#include "interval/affine.h"
#endif

namespace certray {
namespace {

constexpr int kLength = 256;

template <class T>
struct IsDual : std::false_type {};
template <class T>
struct IsAffine : std::false_type {};
#ifdef CERTRAY_BENCH_DUAL
template <class S, int N>
struct IsDual<Dual<S, N>> : std::true_type {};
#endif
#ifdef CERTRAY_BENCH_AFFINE
template <int N>
struct IsAffine<Affine<N>> : std::true_type {};
#endif

// ---- how to make a value of each type
// ------------------------------------------------------------

/// A narrow, non-degenerate enclosure of v (an input box); the point v for double.
template <class T>
T input(double v) {
    if constexpr (std::is_same_v<T, double>) {
        return v;
    } else if constexpr (std::is_same_v<T, Interval> || std::is_same_v<T, UpInterval>) {
        return T(v, v + std::ldexp(std::fabs(v) + 1.0, -40));
    } else if constexpr (IsDual<T>::value) {  // the variable x_0 at a narrow input
        return T::variable(input<std::remove_cvref_t<decltype(T{}.a)>>(v), 0);
    } else {
        static_assert(IsAffine<T>::value, "no input() for this type");
        return T::variable(input<Interval>(v), 0);
    }
}

/// The exact constant c.
template <class T>
T constant(double c) {
    return T(c);
}

// ---- kernels
// ------------------------------------------------------------------------------------- Each
// kernel: a chain step y ← step(y, x, c) that stays bounded for 256 steps from y0, and an
// element-wise op(a, b) with inputs spread over [a_lo, a_hi] × [b_lo, b_hi].

struct Add {
    static constexpr const char* kName = "add";
    static constexpr double y0 = 1.0, x = 1e-3, c = 0.0, a_lo = -4, a_hi = 4, b_lo = -4, b_hi = 4;
    template <class T>
    static T step(const T& y, const T& xx, const T&) {
        return y + xx;
    }
    template <class T>
    static T elem(const T& a, const T& b) {
        return a + b;
    }
};
/// The chain is y·x + c (contracting to 2), so a step costs one product and one sum.
struct Mul {
    static constexpr const char* kName = "mul";
    static constexpr double y0 = 1.0, x = 0.5, c = 1.0, a_lo = -4, a_hi = 4, b_lo = -4, b_hi = 4;
    template <class T>
    static T step(const T& y, const T& xx, const T& cc) {
        return y * xx + cc;
    }
    template <class T>
    static T elem(const T& a, const T& b) {
        return a * b;
    }
};
struct Div {
    static constexpr const char* kName = "div";
    static constexpr double y0 = 1.5, x = 2.0, c = 0.0, a_lo = -4, a_hi = 4, b_lo = 0.5, b_hi = 4;
    template <class T>
    static T step(const T& y, const T& xx, const T&) {
        return xx / y;
    }
    template <class T>
    static T elem(const T& a, const T& b) {
        return a / b;
    }
};
struct Sqrt {
    static constexpr const char* kName = "sqrt";
    static constexpr double y0 = 3.0, x = 0.0, c = 0.0, a_lo = 0.1, a_hi = 100, b_lo = 0, b_hi = 0;
    template <class T>
    static T step(const T& y, const T&, const T&) {
        return sqrt(y);
    }
    template <class T>
    static T elem(const T& a, const T&) {
        return sqrt(a);
    }
};
/// The chain y² stays at [1, 1] from y0 = 1 (no overflow, no subnormals).
struct Square {
    static constexpr const char* kName = "square";
    static constexpr double y0 = 1.0, x = 0.0, c = 0.0, a_lo = -4, a_hi = 4, b_lo = 0, b_hi = 0;
    template <class T>
    static T step(const T& y, const T&, const T&) {
        return square(y);
    }
    template <class T>
    static T elem(const T& a, const T&) {
        return square(a);
    }
};
/// The chain exp(−y) contracts to 0.567 (negation is exact and nearly free for every type).
struct Exp {
    static constexpr const char* kName = "exp";
    static constexpr double y0 = 0.5, x = 0.0, c = 0.0, a_lo = -4, a_hi = 4, b_lo = 0, b_hi = 0;
    template <class T>
    static T step(const T& y, const T&, const T&) {
        return exp(-y);
    }
    template <class T>
    static T elem(const T& a, const T&) {
        return exp(a);
    }
};
/// The chain sin(y) decays slowly from 1 (to about 0.1 after 256 steps).
struct Sin {
    static constexpr const char* kName = "sin";
    static constexpr double y0 = 1.0, x = 0.0, c = 0.0, a_lo = -3, a_hi = 3, b_lo = 0, b_hi = 0;
    template <class T>
    static T step(const T& y, const T&, const T&) {
        return sin(y);
    }
    template <class T>
    static T elem(const T& a, const T&) {
        return sin(a);
    }
};
/// The chain min(y, x) with x from memory (x > y0, so the comparison always keeps y).
struct Min {
    static constexpr const char* kName = "min";
    static constexpr double y0 = 1.0, x = 2.0, c = 0.0, a_lo = -4, a_hi = 4, b_lo = -4, b_hi = 4;
    template <class T>
    static T step(const T& y, const T& xx, const T&) {
        return min(y, xx);
    }
    template <class T>
    static T elem(const T& a, const T& b) {
        return min(a, b);
    }
};

/// Runs `body` inside one RoundingScope when T needs upward mode, else directly.
template <class T, class F>
void maybe_scoped(F&& body) {
    if constexpr (std::is_same_v<T, UpInterval>) {
        RoundingScope scope;
        body();
    } else {
        body();
    }
}

template <class K, class T>
void bm_chain(benchmark::State& state) {
    T y0 = input<T>(K::y0);
    T c = constant<T>(K::c);
    // x is read from memory at every step (off the critical path): with one x in a register,
    // g++ folded the 256 steps of min(min(y, x), x) … into one.
    const std::vector<T> xs(kLength, constant<T>(K::x));
    benchmark::DoNotOptimize(xs.data());
    maybe_scoped<T>([&] {
        for (auto _ : state) {
            // Opaque in every pass, or the chain (a pure function of loop-invariant values) may
            // be hoisted out of the timed loop. Free for double (a register), a store otherwise.
            benchmark::DoNotOptimize(y0);
            benchmark::DoNotOptimize(c);
            T y = y0;
            for (int i = 0; i < kLength; ++i) y = K::step(y, xs[i], c);
            benchmark::DoNotOptimize(y);
        }
    });
    state.SetItemsProcessed(state.iterations() * kLength);
}

template <class K, class T>
void bm_array(benchmark::State& state) {
    std::vector<T> a, b, out(kLength, constant<T>(0.0));
    for (int i = 0; i < kLength; ++i) {
        // A fixed permutation of the grid, so that sign cases do not come in long runs.
        const double s = ((i * 97) % kLength + 0.5) / kLength;
        a.push_back(input<T>(K::a_lo + (K::a_hi - K::a_lo) * s));
        b.push_back(input<T>(K::b_lo + (K::b_hi - K::b_lo) * (1.0 - s)));
    }
    benchmark::DoNotOptimize(a.data());  // escape the buffers: ClobberMemory then forces
    benchmark::DoNotOptimize(b.data());  // the loads and stores of every pass
    benchmark::DoNotOptimize(out.data());
    maybe_scoped<T>([&] {
        for (auto _ : state) {
            for (int i = 0; i < kLength; ++i) out[i] = K::elem(a[i], b[i]);
            benchmark::ClobberMemory();
        }
    });
    state.SetItemsProcessed(state.iterations() * kLength);
}

// ---- registration and the ratio table
// ------------------------------------------------------------

std::vector<std::string> g_types;    // in registration order, double first
std::vector<std::string> g_kernels;  // "chain/add", "array/add", ...

template <class K, class T>
void register_kernel(const std::string& type_name) {
    benchmark::RegisterBenchmark(("chain/" + std::string(K::kName) + "/" + type_name).c_str(),
                                 bm_chain<K, T>);
    benchmark::RegisterBenchmark(("array/" + std::string(K::kName) + "/" + type_name).c_str(),
                                 bm_array<K, T>);
}

template <class T>
void register_all(const std::string& type_name) {
    g_types.push_back(type_name);
    register_kernel<Add, T>(type_name);
    register_kernel<Mul, T>(type_name);
    register_kernel<Div, T>(type_name);
    register_kernel<Sqrt, T>(type_name);
    register_kernel<Square, T>(type_name);
    register_kernel<Exp, T>(type_name);
    register_kernel<Sin, T>(type_name);
    register_kernel<Min, T>(type_name);
}

/// "chain/add/Interval" → {"chain/add", "Interval"}.
std::pair<std::string, std::string> split_name(const std::string& name) {
    const auto slash = name.rfind('/');
    return {name.substr(0, slash), name.substr(slash + 1)};
}

/// The console reporter, plus: per run the counter x_double (time / time of the same kernel on
/// double, which runs first), and every time kept for the final table.
class RatioReporter : public benchmark::ConsoleReporter {
  public:
    std::map<std::string, std::map<std::string, double>> ns;  // kernel → type → ns per step

    void ReportRuns(const std::vector<Run>& runs) override {
        std::vector<Run> copy = runs;
        for (Run& run : copy) {
            if (run.run_type != Run::RT_Iteration || run.error_occurred) continue;
            const auto [kernel, type] = split_name(run.benchmark_name());
            // CPU time, not wall time: the machine is shared, and a descheduled benchmark
            // must not look slow.
            const double t = run.GetAdjustedCPUTime() / static_cast<double>(kLength);
            ns[kernel][type] = t;
            const auto base = ns[kernel].find("double");
            if (base != ns[kernel].end() && base->second > 0) {
                run.counters["x_double"] = benchmark::Counter(t / base->second);
            }
        }
        ConsoleReporter::ReportRuns(copy);
    }

    void print_table() const {
        std::printf("\nRatio to double (CPU time per step or element, same process):\n%-14s",
                    "kernel");
        for (const auto& type : g_types) std::printf(" %16s", type.c_str());
        std::printf("   (double CPU ns)\n");
        for (const auto& order : {"chain", "array"}) {
            for (const auto& [kernel, times] : ns) {
                if (kernel.rfind(order, 0) != 0) continue;
                std::printf("%-14s", kernel.c_str());
                const auto base = times.find("double");
                for (const auto& type : g_types) {
                    const auto it = times.find(type);
                    if (it == times.end() || base == times.end()) {
                        std::printf(" %16s", "-");
                    } else {
                        std::printf(" %15.2fx", it->second / base->second);
                    }
                }
                std::printf("   (%.3f)\n", base == times.end() ? 0.0 : base->second);
            }
        }
    }
};

}  // namespace
}  // namespace certray

int main(int argc, char** argv) {
    using namespace certray;
    register_all<double>("double");
    register_all<Interval>("Interval");
    register_all<UpInterval>("UpInterval");
#ifdef CERTRAY_BENCH_DUAL
    register_all<Dual<double, 3>>("Dual<double,3>");
    register_all<Dual<Interval, 3>>("Dual<Interval,3>");
#endif
#ifdef CERTRAY_BENCH_AFFINE
    register_all<Affine<1>>("Affine<1>");
#endif
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    RatioReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    reporter.print_table();
    benchmark::Shutdown();
    return 0;
}
