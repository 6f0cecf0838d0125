// apps/inspect.cpp — the scene report: sizes, enclosures, Lipschitz bound and pruning per level.
#include "apps/inspect.h"

#include <chrono>
#include <cstdio>
#include <random>
#include <vector>

#include "certray/scene.h"
#include "expr/derived.h"
#include "expr/eval.h"
#include "expr/load.h"
#include "expr/prune.h"
#include "expr/tape.h"

namespace certray::apps {

namespace {

std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
    char buf[256];
    std::snprintf(buf, sizeof buf, f, a, b, c, d);
    return buf;
}

}  // namespace

void inspect_scene(const std::string& path, const InspectOptions& options, std::ostream& out) {
    using expr::Tape;
    const Scene scene = Scene::load(path);
    const expr::Graph& graph = scene.graph();
    const Tape& tape = scene.tape();
    const bool is3d = tape.uses_var(2);
    // The bounds render uses: --bounds, else the file's own (a .vm's view, a CSG tree's aabb),
    // else [-2, 2]^3 in 3D and [-1, 1]^2 in 2D.
    std::array<std::array<double, 2>, 3> b{};
    if (options.bounds) {
        b = {*options.bounds, *options.bounds, *options.bounds};
    } else if (scene.bounds()) {
        b = *scene.bounds();
    } else {
        const std::array<double, 2> cube = is3d ? std::array{-2.0, 2.0} : std::array{-1.0, 1.0};
        b = {cube, cube, cube};
    }
    const int axes = is3d ? 3 : 2;
    const std::array<Interval, 3> box{Interval(b[0][0], b[0][1]), Interval(b[1][0], b[1][1]),
                                      is3d ? Interval(b[2][0], b[2][1]) : Interval(0.0)};

    out << path << "\n";
    out << "  graph nodes " << graph.size() << ", tape length " << tape.size() << ", registers "
        << tape.registers() << ", " << (is3d ? "3D" : "2D") << " over ";
    const bool cube = b[1] == b[0] && (!is3d || b[2] == b[0]);
    if (cube) {
        out << "[" << b[0][0] << ", " << b[0][1] << "]^" << axes;
    } else {
        for (int a = 0; a < axes; ++a) {
            out << (a ? " x " : "") << "[" << b[a][0] << ", " << b[a][1] << "]";
        }
    }
    out << (options.bounds ? "" : scene.bounds() ? " (the file's bounds)" : "") << "\n";

    const Interval f = expr::eval(tape, box);
    out << fmt("  f over the bounds: [%.6g, %.6g]\n", f.lower(), f.upper());
    out << "  defined and continuous on the whole box: " << (f.defined ? "yes" : "no") << "\n";
    out << fmt("  Lipschitz bound over the bounds: %.6g\n", expr::lipschitz_bound(tape, box));

    // Speed of one evaluation, double and interval, on random points / small boxes.
    {
        std::mt19937_64 rng(1);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        const auto at = [&](int a) { return b[a][0] + u(rng) * (b[a][1] - b[a][0]); };
        constexpr int kPoints = 2000;
        std::vector<std::array<double, 3>> pts(kPoints);
        for (auto& q : pts) q = {at(0), at(1), is3d ? at(2) : 0.0};
        expr::Evaluator<double> ed;
        expr::Evaluator<Interval> ei;
        volatile double sink = 0;  // keeps the evaluations from being optimised away
        auto t0 = std::chrono::steady_clock::now();
        for (const auto& q : pts) sink = sink + ed(tape, q);
        auto t1 = std::chrono::steady_clock::now();
        for (const auto& q : pts) {
            const auto side = [&](int a) {
                return Interval(q[a], q[a] + (b[a][1] - b[a][0]) / 64);
            };
            sink = sink + ei(tape, {side(0), side(1), side(2)}).lower();
        }
        auto t2 = std::chrono::steady_clock::now();
        const double nd = std::chrono::duration<double, std::nano>(t1 - t0).count() / kPoints;
        const double ni = std::chrono::duration<double, std::nano>(t2 - t1).count() / kPoints;
        out << fmt("  one evaluation: double %.0f ns, interval %.0f ns (%.1fx)\n", nd, ni, ni / nd);
    }

    // Pruning per level: cells where f is proven positive (empty), negative (filled), or
    // ambiguous, and the tape length that ambiguous cells need.
    out << "  level  cells  empty  filled  ambiguous  mean pruned tape (of " << tape.size()
        << ")\n";
    for (int level = 1; level <= options.levels; ++level) {
        const int k = 1 << level;
        const auto cell_of = [&](int a, int i) {
            const double step = (b[a][1] - b[a][0]) / k;
            return Interval(b[a][0] + i * step, i + 1 == k ? b[a][1] : b[a][0] + (i + 1) * step);
        };
        long empty = 0, filled = 0, ambiguous = 0;
        double pruned_sum = 0;
        const int kz = is3d ? k : 1;
        for (int i = 0; i < k; ++i) {
            for (int j = 0; j < k; ++j) {
                for (int l = 0; l < kz; ++l) {
                    const std::array<Interval, 3> cell{cell_of(0, i), cell_of(1, j),
                                                       is3d ? cell_of(2, l) : Interval(0.0)};
                    const expr::PruneResult p = expr::prune(tape, cell);
                    if (p.value.defined && p.value.lower() > 0) {
                        ++empty;
                    } else if (p.value.defined && p.value.upper() < 0) {
                        ++filled;
                    } else {
                        ++ambiguous;
                        pruned_sum += static_cast<double>(p.after);
                    }
                }
            }
        }
        const long cells = empty + filled + ambiguous;
        out << fmt("  %5.0f  %5.0f  %5.0f", level, cells, empty)
            << fmt("  %6.0f  %9.0f  %.1f\n", filled, ambiguous,
                   ambiguous ? pruned_sum / ambiguous : 0.0);
    }
}

}  // namespace certray::apps
