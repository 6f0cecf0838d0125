// bench/eval_bench.cpp — the cost of evaluating a tape, per number type and per scene (Google
// Benchmark).
//
// Scenes: unit sphere, torus (R = 1, r = 0.25), Barth sextic (.vm), a union of 1,001 spheres (the
// "molecule" of the Lipschitz-pruning paper, read from its JSON; a deterministic 1,000-sphere union
// when the file is absent) and prospero (.vm, 2D). Measured in one process:
// (a) `batch/<scene>`: Evaluator<Batch> over 256 points (2 walks of 128 lanes) with the copy of the
//     walk chosen for this CPU (expr/eval_batch.h); `double/<scene>`: Evaluator<double> point by
//     point; `native/<scene>`: the same function hand-written in C++ and compiled with the same
//     flags (generic x86-64; not for prospero);
// (a') `batch-<isa>/<scene>`: the batch walk forced to each copy the CPU runs (baseline SSE2,
//     AVX2, AVX-512), and `native-avx2/<scene>`: the hand-written function compiled for AVX2
//     (target attribute, no FMA: the batch's own instruction set);
// (b) `interval/<scene>`, `dual/<scene>`, `idual/<scene>`: Evaluator<Interval> on boxes of side
//     2e-3, Evaluator<Dual<double,3>> at points, Evaluator<Dual<Interval,3>> on the boxes;
// (c) after the benchmarks, outside Google Benchmark (skipped with --no_prune): prune() on boxes of
//     decreasing side around a point of the surface, with the tape lengths and the CPU time of one
//     interval evaluation of the full and the pruned tape;
// (d) outside Google Benchmark (skipped with --no_ops): the batch walk's cost per instruction on
//     synthetic chains of 1,000 instructions of one kind, per copy (what a Const, a unary op, a
//     result that must be stored cost).
// (e) `ibatch-scalar/<scene>`: detail::run<UpInterval> box by box inside one RoundingScope (the
//     certified renderer's walk); `ibatch-<n>/<scene>`: run_interval_batch over n boxes per walk
//     (expr/eval_interval_batch.h, the copy chosen for this CPU), `ibatch-ssa-<n>/<scene>` the
//     same over the tape's SSA form (a register per instruction: what the coherent renderer's
//     lists are), `ibatch-<isa>-64/<scene>` on
//     each copy; 128 boxes of side 2^-6 centred in [-1, 1]^3 per pass, on Barth's sextic
//     (scenes/barth_sextic.vm), bear and colonnade (scenes/fidget/); CPU ns per box and the
//     ratio scalar / batch, in table (e).
// (f) with (d), outside Google Benchmark: the interval batch walk's cost per instruction and lane,
//     on 500 independent instructions of one kind over 8 and 64 lanes (the copy chosen for this
//     CPU), operands in narrow intervals where each op is defined.
// The custom main prints the tables (CPU time; ratios from times of this process).
// Results and the command that produced them: docs/benchmarks.md, "Expression evaluation (issue
// 3)".
#include <benchmark/benchmark.h>
#include <immintrin.h>
#include <time.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <string>
#include <vector>

// eval.h and derived.h before builder.h: builder.h declares expr::min, sqrt, … which, seen first,
// would hide certray::min(double, double) etc. from the unqualified calls in detail::run.
#include "expr/builder.h"
#include "expr/derived.h"
#include "expr/eval.h"
#include "expr/eval_batch.h"
#include "expr/eval_interval_batch.h"
#include "expr/load.h"
#include "expr/prune.h"
#include "expr/tape.h"
#include "interval/batch.h"
#include "interval/dual.h"
#include "interval/interval.h"

namespace certray {
namespace {

using expr::Evaluator;
using expr::Tape;

constexpr int kPoints = 256;            // points per pass of batch/double/native
constexpr int kBoxes = 64;              // points or boxes per pass of interval/dual/idual
constexpr double kHalfBox = 1e-3;       // half side of the small boxes of (b)
constexpr int kIbatchBoxes = 128;       // boxes per pass of (e)
constexpr double kIbatchHalf = 0x1p-7;  // half side of the boxes of (e)
const std::array<int, 4> kIbatchLanes = {8, 16, 32, 64};  // lanes per walk in (e)

/// A hand-written f over arrays of points: out[i] = f(x[i], y[i], z[i]).
using Native = void (*)(const double*, const double*, const double*, double*, int);

struct Scene {
    std::string name;
    Tape tape;
    bool planar = false;     ///< 2D: z = 0
    double lo = -1, hi = 1;  ///< sampling cube (square when planar)
    Native native = nullptr;
    Native native_avx2 = nullptr;     ///< the same function compiled for AVX2 (no FMA)
    std::array<double, 3> surface{};  ///< a point on (or within 1e-15 of) f = 0
};

// ---- hand-written functions
// ----------------------------------------------------------------------

// native_<f>: compiled with the project's flags (generic x86-64; √ stays a scalar sqrtsd, since
// it may set errno). native_<f>_avx2: the same function on the batch walk's instruction set,
// AVX2 without FMA — Barth's body recompiled with target("avx2") (g++ vectorises it), the √
// scenes written with AVX intrinsics (vsqrtpd; the compiler would not vectorise std::sqrt), in
// the scalar version's order of operations: the strongest hand-written reference.

[[gnu::always_inline]] inline void sphere_body(const double* x, const double* y, const double* z,
                                               double* out, int n) {
    for (int i = 0; i < n; ++i) out[i] = std::sqrt(x[i] * x[i] + y[i] * y[i] + z[i] * z[i]) - 1.0;
}

[[gnu::always_inline]] inline void torus_body(const double* x, const double* y, const double* z,
                                              double* out, int n) {
    for (int i = 0; i < n; ++i) {
        const double q = std::sqrt(x[i] * x[i] + y[i] * y[i]) - 1.0;
        out[i] = std::sqrt(q * q + z[i] * z[i]) - 0.25;
    }
}

[[gnu::always_inline]] inline void barth_body(const double* x, const double* y, const double* z,
                                              double* out, int n) {
    constexpr double p2 = 2.618033988749895, c = 4.23606797749979;
    for (int i = 0; i < n; ++i) {
        const double x2 = x[i] * x[i], y2 = y[i] * y[i], z2 = z[i] * z[i];
        const double s = x2 + y2 + z2 - 1.0;
        out[i] = 4.0 * (p2 * x2 - y2) * (p2 * y2 - z2) * (p2 * z2 - x2) - c * (s * s);
    }
}

struct Spheres {
    std::vector<double> cx, cy, cz, r;
};
Spheres g_molecule;

/// Sphere-outer, point-inner: the inner loop runs over the points and vectorises, as the batch
/// evaluator does (the point-outer order would be a scalar min reduction).
[[gnu::always_inline]] inline void molecule_body(const double* x, const double* y, const double* z,
                                                 double* out, int n) {
    const Spheres& s = g_molecule;
    for (int i = 0; i < n; ++i) out[i] = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < s.r.size(); ++k) {
        const double cx = s.cx[k], cy = s.cy[k], cz = s.cz[k], r = s.r[k];
        for (int i = 0; i < n; ++i) {
            const double dx = x[i] - cx, dy = y[i] - cy, dz = z[i] - cz;
            out[i] = min(out[i], std::sqrt(dx * dx + dy * dy + dz * dz) - r);
        }
    }
}

__attribute__((noinline)) void native_sphere(const double* x, const double* y, const double* z,
                                             double* out, int n) {
    sphere_body(x, y, z, out, n);
}
__attribute__((noinline)) void native_torus(const double* x, const double* y, const double* z,
                                            double* out, int n) {
    torus_body(x, y, z, out, n);
}
__attribute__((noinline)) void native_barth(const double* x, const double* y, const double* z,
                                            double* out, int n) {
    barth_body(x, y, z, out, n);
}
__attribute__((noinline)) void native_molecule(const double* x, const double* y, const double* z,
                                               double* out, int n) {
    molecule_body(x, y, z, out, n);
}
__attribute__((noinline, target("avx2"))) void native_barth_avx2(const double* x, const double* y,
                                                                 const double* z, double* out,
                                                                 int n) {
    barth_body(x, y, z, out, n);
}

// The intrinsics versions take n a multiple of 4 (kPoints is).
#define CERTRAY_AVX2_FN [[gnu::noinline, gnu::target("avx2")]]
CERTRAY_AVX2_FN void native_sphere_avx2(const double* x, const double* y, const double* z,
                                        double* out, int n) {
    const __m256d one = _mm256_set1_pd(1.0);
    for (int i = 0; i < n; i += 4) {
        const __m256d X = _mm256_loadu_pd(x + i), Y = _mm256_loadu_pd(y + i),
                      Z = _mm256_loadu_pd(z + i);
        const __m256d s = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(X, X), _mm256_mul_pd(Y, Y)),
                                        _mm256_mul_pd(Z, Z));
        _mm256_storeu_pd(out + i, _mm256_sub_pd(_mm256_sqrt_pd(s), one));
    }
}

CERTRAY_AVX2_FN void native_torus_avx2(const double* x, const double* y, const double* z,
                                       double* out, int n) {
    const __m256d one = _mm256_set1_pd(1.0), r = _mm256_set1_pd(0.25);
    for (int i = 0; i < n; i += 4) {
        const __m256d X = _mm256_loadu_pd(x + i), Y = _mm256_loadu_pd(y + i),
                      Z = _mm256_loadu_pd(z + i);
        const __m256d q = _mm256_sub_pd(
            _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(X, X), _mm256_mul_pd(Y, Y))), one);
        const __m256d t = _mm256_add_pd(_mm256_mul_pd(q, q), _mm256_mul_pd(Z, Z));
        _mm256_storeu_pd(out + i, _mm256_sub_pd(_mm256_sqrt_pd(t), r));
    }
}

CERTRAY_AVX2_FN void native_molecule_avx2(const double* x, const double* y, const double* z,
                                          double* out, int n) {
    const Spheres& s = g_molecule;
    const __m256d inf = _mm256_set1_pd(std::numeric_limits<double>::infinity());
    for (int i = 0; i < n; i += 4) _mm256_storeu_pd(out + i, inf);
    for (std::size_t k = 0; k < s.r.size(); ++k) {
        const __m256d cx = _mm256_set1_pd(s.cx[k]), cy = _mm256_set1_pd(s.cy[k]),
                      cz = _mm256_set1_pd(s.cz[k]), r = _mm256_set1_pd(s.r[k]);
        for (int i = 0; i < n; i += 4) {
            const __m256d dx = _mm256_sub_pd(_mm256_loadu_pd(x + i), cx),
                          dy = _mm256_sub_pd(_mm256_loadu_pd(y + i), cy),
                          dz = _mm256_sub_pd(_mm256_loadu_pd(z + i), cz);
            const __m256d d2 = _mm256_add_pd(
                _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
            const __m256d d = _mm256_sub_pd(_mm256_sqrt_pd(d2), r);
            // certray::min without its NaN rule (no NaN here): (out < d) ? out : d.
            _mm256_storeu_pd(out + i, _mm256_min_pd(_mm256_loadu_pd(out + i), d));
        }
    }
}
#undef CERTRAY_AVX2_FN

// ---- scenes
// --------------------------------------------------------------------------------------

Tape sphere_tape() {
    expr::Graph g;
    auto [x, y, z] = expr::vars(g);
    g.set_output((sqrt(x * x + y * y + z * z) - 1.0).id);
    return Tape(g);
}

Tape torus_tape() {
    expr::Graph g;
    auto [x, y, z] = expr::vars(g);
    auto q = sqrt(x * x + y * y) - 1.0;
    g.set_output((sqrt(q * q + z * z) - 0.25).id);
    return Tape(g);
}

/// The molecule's spheres: primitives of type "sphere" under "union" operators whose matrices
/// are the identity; a primitive's centre is its matrix's translation column (mirrored if the file
/// stores the inverse transform — no timing depends on it). The file's unions carry a blend
/// radius (a smooth union); here the union is the plain min. Returns false if the file is absent
/// or holds anything else.
bool read_molecule(const std::string& path, Spheres& out) {
    std::ifstream in(path);
    if (!in) return false;
    const nlohmann::json doc = nlohmann::json::parse(in);
    std::vector<const nlohmann::json*> stack{&doc};  // explicit stack: the tree is 1,000 deep
    while (!stack.empty()) {
        const nlohmann::json& n = *stack.back();
        stack.pop_back();
        const auto& m = n.at("matrix");
        if (n.at("nodeType") == "binaryOperator") {
            if (n.at("blendMode") != "union") return false;
            for (int k = 0; k < 12; ++k) {
                if (m[k].get<double>() != ((k % 5 == 0) ? 1.0 : 0.0)) return false;
            }
            stack.push_back(&n.at("rightChild"));
            stack.push_back(&n.at("leftChild"));
        } else {
            if (n.at("primitiveType") != "sphere") return false;
            for (int k : {0, 1, 2, 4, 5, 6, 8, 9, 10}) {
                if (m[k].get<double>() != ((k % 5 == 0) ? 1.0 : 0.0)) return false;
            }
            // The matrix maps world to primitive space: the centre is minus its translation.
            out.cx.push_back(-m[3].get<double>());
            out.cy.push_back(-m[7].get<double>());
            out.cz.push_back(-m[11].get<double>());
            out.r.push_back(n.at("radius").get<double>());
        }
    }
    return true;
}

/// 1,000 spheres at deterministic pseudo-random centres in [-0.9, 0.9]³, radii in [0.02, 0.06].
void generate_molecule(Spheres& out) {
    std::mt19937_64 rng(20261123);
    std::uniform_real_distribution<double> c(-0.9, 0.9), r(0.02, 0.06);
    for (int k = 0; k < 1000; ++k) {
        out.cx.push_back(c(rng));
        out.cy.push_back(c(rng));
        out.cz.push_back(c(rng));
        out.r.push_back(r(rng));
    }
}

Tape molecule_tape(const Spheres& s) {
    expr::Graph g;
    auto [x, y, z] = expr::vars(g);
    expr::Expr f{};
    for (std::size_t k = 0; k < s.r.size(); ++k) {
        auto d = sqrt(square(x - s.cx[k]) + square(y - s.cy[k]) + square(z - s.cz[k])) - s.r[k];
        f = (k == 0) ? d : min(f, d);
    }
    g.set_output(f.id);
    return Tape(g);
}

/// A point where f changes sign on the segment a→b (first change of 4,096 samples, then 80
/// bisections); a if there is none.
std::array<double, 3> surface_point(const Tape& t, std::array<double, 3> a,
                                    std::array<double, 3> b) {
    Evaluator<double> e;
    auto at = [&](double s) {
        return std::array<double, 3>{a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]),
                                     a[2] + s * (b[2] - a[2])};
    };
    double s0 = 0, f0 = e(t, at(0));
    for (int k = 1; k <= 4096; ++k) {
        const double s1 = k / 4096.0, f1 = e(t, at(s1));
        if ((f0 < 0) != (f1 < 0)) {
            double l = s0, h = s1;
            for (int it = 0; it < 80; ++it) {
                const double m = 0.5 * (l + h);
                if ((e(t, at(m)) < 0) == (f0 < 0))
                    l = m;
                else
                    h = m;
            }
            return at(l);
        }
        s0 = s1;
        f0 = f1;
    }
    return a;
}

std::vector<Scene> g_scenes;
std::string g_molecule_source;

void make_scenes() {
    const std::string data = CERTRAY_SOURCE_DIR "/tests/data/models/";
    g_scenes.push_back({"sphere",
                        sphere_tape(),
                        false,
                        -1.5,
                        1.5,
                        native_sphere,
                        native_sphere_avx2,
                        {0.6, 0.48, 0.64}});
    g_scenes.push_back({"torus",
                        torus_tape(),
                        false,
                        -1.5,
                        1.5,
                        native_torus,
                        native_torus_avx2,
                        {0.8, 0.6, 0.25}});
    {
        Scene s{"barth",
                Tape(expr::load_graph_file(data + "algebraic/barth_sextic.vm")),
                false,
                -2.0,
                2.0,
                native_barth,
                native_barth_avx2,
                {}};
        s.surface = surface_point(s.tape, {0, 0, 0}, {2.0, 2.0, 2.0});
        g_scenes.push_back(std::move(s));
    }
    if (read_molecule(CERTRAY_MOLECULE_JSON, g_molecule)) {
        g_molecule_source = CERTRAY_MOLECULE_JSON;
    } else {
        g_molecule = Spheres{};
        generate_molecule(g_molecule);
        g_molecule_source = "generated (seed 20261123)";
    }
    {
        Scene s{"molecule",      molecule_tape(g_molecule), false, -1.0, 1.0,
                native_molecule, native_molecule_avx2,      {}};
        const auto& m = g_molecule;
        s.surface =
            surface_point(s.tape, {m.cx[0], m.cy[0], m.cz[0]}, {m.cx[0] + 1.0, m.cy[0], m.cz[0]});
        g_scenes.push_back(std::move(s));
    }
    {
        Scene s{"prospero", Tape(expr::load_graph_file(data + "prospero.vm")),
                true,       -1.0,
                1.0,        nullptr,
                nullptr,    {}};
        s.surface = surface_point(s.tape, {-1.0, 0.1, 0}, {1.0, 0.1, 0});
        g_scenes.push_back(std::move(s));
    }
}

// ---- inputs
// --------------------------------------------------------------------------------------

struct Inputs {
    std::vector<double> x, y, z;                // kPoints points
    std::vector<std::array<Batch, 3>> batches;  // the same points, 64 per batch
};

Inputs make_inputs(const Scene& s) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(s.lo, s.hi);
    Inputs in;
    for (int i = 0; i < kPoints; ++i) {
        in.x.push_back(u(rng));
        in.y.push_back(u(rng));
        in.z.push_back(s.planar ? 0.0 : u(rng));
    }
    for (int b = 0; b < kPoints / kBatch; ++b) {
        std::array<Batch, 3> p;
        for (int i = 0; i < kBatch; ++i) {
            p[0][i] = in.x[b * kBatch + i];
            p[1][i] = in.y[b * kBatch + i];
            p[2][i] = in.z[b * kBatch + i];
        }
        in.batches.push_back(p);
    }
    return in;
}

Interval around(double v, bool zero) {
    return zero ? Interval(0.0) : Interval(v - kHalfBox, v + kHalfBox);
}

// ---- benchmarks
// ----------------------------------------------------------------------------------

/// The batch walk over the scene's points; `isa` forces a copy of the walk (none: the one chosen
/// for this CPU).
void bm_batch_isa(benchmark::State& state, const Scene* s, std::optional<expr::BatchIsa> isa) {
    const Inputs in = make_inputs(*s);
    const expr::BatchIsa chosen = expr::batch_isa();
    if (isa) expr::set_batch_isa(*isa);
    Evaluator<Batch> e;
    for (auto _ : state) {
        for (const auto& p : in.batches) {
            Batch r = e(s->tape, p);
            benchmark::DoNotOptimize(r);
        }
    }
    expr::set_batch_isa(chosen);
}

void bm_batch(benchmark::State& state, const Scene* s) { bm_batch_isa(state, s, std::nullopt); }

void bm_double(benchmark::State& state, const Scene* s) {
    const Inputs in = make_inputs(*s);
    Evaluator<double> e;
    for (auto _ : state) {
        for (int i = 0; i < kPoints; ++i) {
            double r = e(s->tape, {in.x[i], in.y[i], in.z[i]});
            benchmark::DoNotOptimize(r);
        }
    }
}

void bm_native_fn(benchmark::State& state, const Scene* s, Native f) {
    const Inputs in = make_inputs(*s);
    std::vector<double> out(kPoints);
    benchmark::DoNotOptimize(out.data());
    for (auto _ : state) {
        f(in.x.data(), in.y.data(), in.z.data(), out.data(), kPoints);
        benchmark::ClobberMemory();
    }
}

void bm_native(benchmark::State& state, const Scene* s) { bm_native_fn(state, s, s->native); }

void bm_interval(benchmark::State& state, const Scene* s) {
    const Inputs in = make_inputs(*s);
    Evaluator<Interval> e;
    for (auto _ : state) {
        for (int i = 0; i < kBoxes; ++i) {
            Interval r = e(s->tape, {around(in.x[i], false), around(in.y[i], false),
                                     around(in.z[i], s->planar)});
            benchmark::DoNotOptimize(r);
        }
    }
}

void bm_dual(benchmark::State& state, const Scene* s) {
    using D = Dual<double, 3>;
    const Inputs in = make_inputs(*s);
    Evaluator<D> e;
    for (auto _ : state) {
        for (int i = 0; i < kBoxes; ++i) {
            D r = e(s->tape,
                    {D::variable(in.x[i], 0), D::variable(in.y[i], 1), D::variable(in.z[i], 2)});
            benchmark::DoNotOptimize(r);
        }
    }
}

void bm_idual(benchmark::State& state, const Scene* s) {
    using D = Dual<Interval, 3>;
    const Inputs in = make_inputs(*s);
    Evaluator<D> e;
    for (auto _ : state) {
        for (int i = 0; i < kBoxes; ++i) {
            D r = e(s->tape,
                    {D::variable(around(in.x[i], false), 0), D::variable(around(in.y[i], false), 1),
                     D::variable(around(in.z[i], s->planar), 2)});
            benchmark::DoNotOptimize(r);
        }
    }
}

// ---- (e) the interval batch walk
// --------------------------------------------------------------------

/// A scene of (e): a tape and kIbatchBoxes boxes, as UpInterval triples and as lanes of
/// IntervalLanes (kIntervalLanes boxes per group).
struct BoxScene {
    std::string name;
    Tape tape;
    std::vector<std::array<UpInterval, 3>> boxes;
};
std::vector<BoxScene> g_box_scenes;

void make_box_scenes() {
    const std::string dir = CERTRAY_SOURCE_DIR "/scenes/";
    const std::pair<const char*, const char*> files[] = {{"barth", "barth_sextic.vm"},
                                                         {"bear", "fidget/bear.vm"},
                                                         {"colonnade", "fidget/colonnade.vm"}};
    for (const auto& [name, file] : files) {
        BoxScene s{name, Tape(expr::load_graph_file(dir + file)), {}};
        std::mt19937_64 rng(13);
        std::uniform_real_distribution<double> u(-1.0 + kIbatchHalf, 1.0 - kIbatchHalf);
        for (int i = 0; i < kIbatchBoxes; ++i) {
            std::array<UpInterval, 3> b;
            for (auto& v : b) {
                const double c = u(rng);
                v = UpInterval(c - kIbatchHalf, c + kIbatchHalf);
            }
            s.boxes.push_back(b);
        }
        g_box_scenes.push_back(std::move(s));
    }
}

/// run<UpInterval> box by box, inside one RoundingScope per pass.
void bm_ibatch_scalar(benchmark::State& state, const BoxScene* s) {
    std::vector<UpInterval> regs(s->tape.registers());
    for (auto _ : state) {
        RoundingScope up;
        for (const auto& b : s->boxes) {
            expr::detail::run<UpInterval>(s->tape.instrs(), b, regs.data());
            benchmark::DoNotOptimize(regs[s->tape.output()]);
        }
    }
}

/// run_interval_batch over `lanes` boxes per walk (the inputs set once, outside the timing), on
/// the copy `isa` (none: the one chosen for this CPU), over the tape's registers or (`ssa`) its
/// SSA form.
void bm_ibatch(benchmark::State& state, const BoxScene* s, int lanes,
               std::optional<expr::BatchIsa> isa, bool ssa) {
    const int groups = kIbatchBoxes / lanes;
    std::vector<std::array<expr::IntervalLanes, 3>> in(groups);
    for (int i = 0; i < kIbatchBoxes; ++i) {
        for (int k = 0; k < 3; ++k) expr::set_lane(in[i / lanes][k], i % lanes, s->boxes[i][k]);
    }
    std::vector<expr::IntervalLanes> regs(ssa ? s->tape.ssa().size() : s->tape.registers());
    const expr::BatchIsa chosen = expr::batch_isa();
    if (isa) expr::set_batch_isa(*isa);
    const std::vector<expr::Instr>& list = ssa ? s->tape.ssa() : s->tape.instrs();
    for (auto _ : state) {
        RoundingScope up;
        for (const auto& p : in) {
            expr::run_interval_batch(list.data(), list.data() + list.size(), p.data(), regs.data(),
                                     lanes);
            benchmark::DoNotOptimize(regs[list.back().out]);
        }
    }
    expr::set_batch_isa(chosen);
}

/// Evaluations (points, boxes) per pass of each kind.
int per_pass(const std::string& kind) {
    if (kind.starts_with("ibatch")) return kIbatchBoxes;
    return (kind.starts_with("batch") || kind == "double" || kind.starts_with("native")) ? kPoints
                                                                                         : kBoxes;
}

/// Keeps CPU ns per evaluation of every run: kind → scene → ns.
class TableReporter : public benchmark::ConsoleReporter {
  public:
    std::map<std::string, std::map<std::string, double>> ns;

    void ReportRuns(const std::vector<Run>& runs) override {
        std::vector<Run> copy = runs;
        for (Run& run : copy) {
            if (run.run_type != Run::RT_Iteration || run.error_occurred) continue;
            const std::string name = run.benchmark_name();
            const auto slash = name.find('/');
            const std::string kind = name.substr(0, slash), scene = name.substr(slash + 1);
            // CPU time: the machine is shared.
            const double t = run.GetAdjustedCPUTime() / per_pass(kind);
            ns[kind][scene] = t;
            run.counters["ns_per_eval"] = benchmark::Counter(t);
        }
        ConsoleReporter::ReportRuns(copy);
    }

    double get(const std::string& kind, const std::string& scene) const {
        const auto k = ns.find(kind);
        if (k == ns.end()) return NAN;
        const auto s = k->second.find(scene);
        return s == k->second.end() ? NAN : s->second;
    }

    void print_tables() const {
        std::printf(
            "\n(a) Point evaluation, CPU ns (per point; per op = per point / tape length):\n");
        std::printf("%-10s %6s %12s %12s %14s %12s %14s %12s\n", "scene", "ops", "native/pt",
                    "batch/pt", "batch/op/pt", "batch/native", "double/op/pt", "double/native");
        for (const Scene& s : g_scenes) {
            const double n = static_cast<double>(s.tape.size());
            const double nat = get("native", s.name), b = get("batch", s.name),
                         d = get("double", s.name);
            std::printf("%-10s %6zu %12.3f %12.3f %14.4f %11.2fx %14.4f %11.2fx\n", s.name.c_str(),
                        s.tape.size(), nat, b, b / n, b / nat, d / n, d / nat);
        }
        std::printf("batch: the %s copy of the walk (expr/eval_batch.h)\n",
                    expr::batch_isa_name(expr::batch_isa()));
        std::printf(
            "\n(a') The batch walk per copy, CPU ns per op per point; against native-avx2, the "
            "hand-written\nfunction compiled for AVX2 without FMA (per point; nan: the CPU lacks "
            "the copy):\n");
        std::printf("%-10s %6s %15s %15s %12s %14s %18s %18s\n", "scene", "ops", "native-avx2/pt",
                    "baseline/op/pt", "avx2/op/pt", "avx512/op/pt", "avx2/native-avx2",
                    "avx512/native-avx2");
        for (const Scene& s : g_scenes) {
            const double n = static_cast<double>(s.tape.size());
            const double nat = get("native-avx2", s.name), b0 = get("batch-baseline", s.name),
                         b1 = get("batch-avx2", s.name), b2 = get("batch-avx512", s.name);
            std::printf("%-10s %6zu %15.3f %15.4f %12.4f %14.4f %17.2fx %17.2fx\n", s.name.c_str(),
                        s.tape.size(), nat, b0 / n, b1 / n, b2 / n, b1 / nat, b2 / nat);
        }
        std::printf("\n(b) One evaluation against one scalar double evaluation (CPU ns, ratio):\n");
        std::printf("%-10s %12s %16s %16s %18s\n", "scene", "double ns", "Interval",
                    "Dual<double,3>", "Dual<Interval,3>");
        for (const Scene& s : g_scenes) {
            const double d = get("double", s.name);
            std::printf("%-10s %12.1f %15.2fx %15.2fx %17.2fx\n", s.name.c_str(), d,
                        get("interval", s.name) / d, get("dual", s.name) / d,
                        get("idual", s.name) / d);
        }
        print_ibatch_table();
    }

    void print_ibatch_table() const {
        if (g_box_scenes.empty() || std::isnan(get("ibatch-scalar", g_box_scenes[0].name))) return;
        std::printf(
            "\n(e) Interval enclosures of %d boxes of side 2^-6 in [-1, 1]^3, CPU ns per box: "
            "run<UpInterval>\nbox by box against run_interval_batch over n boxes per walk (%s "
            "copy; last columns n = 64 on each copy); ratio = scalar / batch:\n",
            kIbatchBoxes, expr::batch_isa_name(expr::batch_isa()));
        std::printf("%-10s %6s %10s", "scene", "instrs", "scalar");
        for (int n : kIbatchLanes)
            std::printf(" %12s %7s", ("n=" + std::to_string(n)).c_str(), "ratio");
        std::printf(" %10s %10s %10s\n", "baseline", "avx2", "avx512");
        for (const BoxScene& s : g_box_scenes) {
            const double sc = get("ibatch-scalar", s.name);
            std::printf("%-10s %6zu %10.1f", s.name.c_str(), s.tape.size(), sc);
            for (int n : kIbatchLanes) {
                const double b = get("ibatch-" + std::to_string(n), s.name);
                std::printf(" %12.1f %6.2fx", b, sc / b);
            }
            for (const char* isa : {"baseline", "avx2", "avx512"}) {
                std::printf(" %10.1f", get(std::string("ibatch-") + isa + "-64", s.name));
            }
            std::printf("\n");
        }
    }
};

// ---- (c) pruning
// ---------------------------------------------------------------------------------

double cpu_ns() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e9 + ts.tv_nsec;
}

/// CPU ns per call of f, over at least 20 ms.
double time_ns(const std::function<void()>& f) {
    long n = 0;
    const double t0 = cpu_ns();
    double t1 = t0;
    while (t1 - t0 < 2e7) {
        for (int i = 0; i < 8; ++i) f();
        n += 8;
        t1 = cpu_ns();
    }
    return (t1 - t0) / static_cast<double>(n);
}

void print_prune_table() {
    std::printf(
        "\n(c) prune() on boxes of side s centred at a point of the surface "
        "(CPU ns per interval evaluation):\n");
    std::printf("%-10s %6s %8s %8s %12s %12s %8s %12s\n", "scene", "side", "before", "after",
                "full ns", "pruned ns", "speedup", "prune ns");
    for (const Scene& s : g_scenes) {
        for (double side : {2.0, 1.0, 0.5, 0.25, 0.1, 0.05, 0.01}) {
            const double h = side / 2;
            const auto& c = s.surface;
            const std::array<Interval, 3> box{
                Interval(c[0] - h, c[0] + h), Interval(c[1] - h, c[1] + h),
                s.planar ? Interval(0.0) : Interval(c[2] - h, c[2] + h)};
            const expr::PruneResult p = expr::prune(s.tape, box);
            Evaluator<Interval> e;
            const double full = time_ns([&] {
                Interval r = e(s.tape, box);
                benchmark::DoNotOptimize(r);
            });
            const double pruned = time_ns([&] {
                Interval r = e(p.tape, box);
                benchmark::DoNotOptimize(r);
            });
            const double pt = time_ns([&] {
                expr::PruneResult q = expr::prune(s.tape, box);
                benchmark::DoNotOptimize(q);
            });
            std::printf("%-10s %6.2f %8zu %8zu %12.0f %12.0f %7.1fx %12.0f\n", s.name.c_str(), side,
                        p.before, p.after, full, pruned, full / pruned, pt);
        }
    }
}

// ---- (d) the batch walk per kind of instruction
// -----------------------------------------------------------------

/// A chain of `links` links of one kind, each reading the previous link's result: the batch walk
/// keeps that result in registers (except "add, stored": the Fibonacci sum reads each result
/// twice, so every result is stored).
Tape chain_tape(const std::string& kind, int links) {
    expr::Graph g;
    auto [x, y, z] = expr::vars(g);
    expr::Expr e = x, before = y;
    for (int i = 0; i < links; ++i) {
        if (kind == "add") e = e + y;
        if (kind == "mul") e = e * y;
        if (kind == "min") e = min(e, y);
        if (kind == "square") e = square(e);
        if (kind == "sqrt") e = sqrt(e);
        if (kind == "const + add") e = e + (1.0 + std::ldexp(i, -20));  // distinct constants
        if (kind == "sin") e = sin(e);
        if (kind == "add, stored") {
            const expr::Expr next = e + before;
            before = e;
            e = next;
        }
    }
    g.set_output(e.id);
    return Tape(g);
}

void print_ops_table() {
    constexpr int kLinks = 1000;
    const std::vector<std::string> kinds = {"add",  "mul",         "min", "square",
                                            "sqrt", "const + add", "sin", "add, stored"};
    std::printf(
        "\n(d) The batch walk per kind of instruction: chains of %d links, each reading the "
        "previous result\n(x in [1, 2], y in [0.999, 1.001]); CPU ns per link per point (nan: the "
        "CPU lacks the copy):\n",
        kLinks);
    std::printf("%-12s %10s %10s %10s %10s\n", "link", "instr", "baseline", "avx2", "avx512");
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> ux(1.0, 2.0), uy(0.999, 1.001);
    std::vector<std::array<Batch, 3>> points(kPoints / kBatch);
    for (auto& p : points) {
        for (int i = 0; i < kBatch; ++i) {
            p[0][i] = ux(rng);
            p[1][i] = uy(rng);
            p[2][i] = 0.0;
        }
    }
    const expr::BatchIsa chosen = expr::batch_isa();
    for (const std::string& kind : kinds) {
        const Tape t = chain_tape(kind, kLinks);
        const double per_link = static_cast<double>(t.size() - 2) / kLinks;  // less x and y
        std::printf("%-12s %10.2f", kind.c_str(), per_link);
        for (expr::BatchIsa isa :
             {expr::BatchIsa::Baseline, expr::BatchIsa::Avx2, expr::BatchIsa::Avx512}) {
            if (!expr::set_batch_isa(isa)) {
                std::printf(" %10s", "nan");
                continue;
            }
            Evaluator<Batch> e;
            const double ns = time_ns([&] {
                for (const auto& p : points) {
                    Batch r = e(t, p);
                    benchmark::DoNotOptimize(r);
                }
            });
            std::printf(" %10.4f", ns / kPoints / kLinks);
        }
        std::printf("\n");
    }
    expr::set_batch_isa(chosen);
}

/// Table (f): run_interval_batch over lists of kOps instructions of one kind, each reading the
/// inputs x and y (so no chain: the cost of the kernel, not its latency).
void print_interval_ops_table() {
    struct Kind {
        const char* name;
        expr::Op op;
        double lo, hi;  // x's lanes: [lo, hi] + 0.001·lane; y's: [1, 1.001] + 0.001·lane
    };
    const Kind kinds[] = {{"add", expr::Op::Add, 1, 2},      {"mul", expr::Op::Mul, 1, 2},
                          {"div", expr::Op::Div, 1, 2},      {"max", expr::Op::Max, 1, 2},
                          {"neg", expr::Op::Neg, 1, 2},      {"square", expr::Op::Square, -1, 2},
                          {"sqrt", expr::Op::Sqrt, 1, 2},    {"exp", expr::Op::Exp, -3, -2.99},
                          {"log", expr::Op::Log, 1.5, 1.51}, {"sin", expr::Op::Sin, 1, 1.01}};
    constexpr int kOps = 500;
    std::printf(
        "\n(f) The interval batch walk per kind of instruction (%s copy): %d independent "
        "instructions;\nCPU ns per instruction per lane:\n%-8s %10s %10s\n",
        expr::batch_isa_name(expr::batch_isa()), kOps, "op", "8 lanes", "64 lanes");
    for (const Kind& k : kinds) {
        std::vector<expr::Instr> list;
        list.push_back({expr::Op::VarX, 0, 0, 0, 0});
        list.push_back({expr::Op::VarY, 1, 0, 0, 0});
        for (std::uint32_t i = 0; i < kOps; ++i) list.push_back({k.op, 2 + i, 0, 1, 0});
        std::array<expr::IntervalLanes, 3> in{};
        for (int l = 0; l < expr::kIntervalLanes; ++l) {
            expr::set_lane(in[0], l, UpInterval(k.lo + 0.001 * l, k.hi + 0.001 * l));
            expr::set_lane(in[1], l, UpInterval(1 + 0.001 * l, 1.001 + 0.001 * l));
            expr::set_lane(in[2], l, UpInterval(0.0));
        }
        std::vector<expr::IntervalLanes> regs(list.size());
        std::printf("%-8s", k.name);
        for (int lanes : {8, 64}) {
            const double ns = time_ns([&] {
                RoundingScope up;
                expr::run_interval_batch(list.data(), list.data() + list.size(), in.data(),
                                         regs.data(), lanes);
                benchmark::DoNotOptimize(regs.back());
            });
            std::printf(" %10.3f", ns / kOps / lanes);
        }
        std::printf("\n");
    }
}

}  // namespace
}  // namespace certray

int main(int argc, char** argv) {
    using namespace certray;
    // --no_prune, --no_ops (ours, removed before Google Benchmark sees the arguments): skip
    // table (c), table (d).
    bool prune_table = true, ops_table = true;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--no_prune" || arg == "--no_ops") {
            (arg == "--no_prune" ? prune_table : ops_table) = false;
            for (int j = i; j + 1 < argc; ++j) argv[j] = argv[j + 1];
            --argc;
            --i;
        }
    }
    make_scenes();
    for (const Scene& s : g_scenes) {
        const Scene* p = &s;
        if (s.native) benchmark::RegisterBenchmark(("native/" + s.name).c_str(), bm_native, p);
        if (s.native_avx2 && __builtin_cpu_supports("avx2")) {
            benchmark::RegisterBenchmark(("native-avx2/" + s.name).c_str(), bm_native_fn, p,
                                         s.native_avx2);
        }
        benchmark::RegisterBenchmark(("batch/" + s.name).c_str(), bm_batch, p);
        for (expr::BatchIsa isa :
             {expr::BatchIsa::Baseline, expr::BatchIsa::Avx2, expr::BatchIsa::Avx512}) {
            if (!expr::batch_isa_supported(isa)) continue;
            const std::string name =
                std::string("batch-") + expr::batch_isa_name(isa) + "/" + s.name;
            benchmark::RegisterBenchmark(name.c_str(), bm_batch_isa, p,
                                         std::optional<expr::BatchIsa>(isa));
        }
        benchmark::RegisterBenchmark(("double/" + s.name).c_str(), bm_double, p);
        benchmark::RegisterBenchmark(("interval/" + s.name).c_str(), bm_interval, p);
        benchmark::RegisterBenchmark(("dual/" + s.name).c_str(), bm_dual, p);
        benchmark::RegisterBenchmark(("idual/" + s.name).c_str(), bm_idual, p);
    }
    make_box_scenes();
    for (const BoxScene& s : g_box_scenes) {
        const BoxScene* p = &s;
        benchmark::RegisterBenchmark(("ibatch-scalar/" + s.name).c_str(), bm_ibatch_scalar, p);
        for (int n : kIbatchLanes) {
            benchmark::RegisterBenchmark(("ibatch-" + std::to_string(n) + "/" + s.name).c_str(),
                                         bm_ibatch, p, n, std::optional<expr::BatchIsa>(), false);
            benchmark::RegisterBenchmark(("ibatch-ssa-" + std::to_string(n) + "/" + s.name).c_str(),
                                         bm_ibatch, p, n, std::optional<expr::BatchIsa>(), true);
        }
        for (expr::BatchIsa isa :
             {expr::BatchIsa::Baseline, expr::BatchIsa::Avx2, expr::BatchIsa::Avx512}) {
            if (!expr::batch_isa_supported(isa)) continue;
            const std::string name =
                std::string("ibatch-") + expr::batch_isa_name(isa) + "-64/" + s.name;
            benchmark::RegisterBenchmark(name.c_str(), bm_ibatch, p, 64,
                                         std::optional<expr::BatchIsa>(isa), false);
        }
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    std::printf("molecule: %zu spheres from %s\n", g_molecule.r.size(), g_molecule_source.c_str());
    for (const Scene& s : g_scenes) {
        std::printf("%-10s tape %zu instructions, %u registers; surface point (%.6g, %.6g, %.6g)\n",
                    s.name.c_str(), s.tape.size(), s.tape.registers(), s.surface[0], s.surface[1],
                    s.surface[2]);
    }
    TableReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    reporter.print_tables();
    if (prune_table) print_prune_table();
    if (ops_table) print_ops_table();
    if (ops_table) print_interval_ops_table();
    benchmark::Shutdown();
    return 0;
}
