// apps/inspect.cpp — the scene report: sizes, enclosures, Lipschitz bound and pruning per level.
#include "apps/inspect.h"

#include <chrono>
#include <cstdio>
#include <random>
#include <vector>

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
    const expr::Graph graph = expr::load_graph_file(path);
    const Tape tape(graph);
    const bool is3d = tape.uses_var(2);
    const std::array<double, 2> bounds =
        options.bounds.value_or(is3d ? std::array{-2.0, 2.0} : std::array{-1.0, 1.0});
    const double lo = bounds[0], hi = bounds[1];
    const Interval side(lo, hi);
    const std::array<Interval, 3> box{side, side, is3d ? side : Interval(0.0)};

    out << path << "\n";
    out << "  graph nodes " << graph.size() << ", tape length " << tape.size() << ", registers "
        << tape.registers() << ", " << (is3d ? "3D" : "2D") << " over [" << lo << ", " << hi << "]^"
        << (is3d ? 3 : 2) << "\n";

    const Interval f = expr::eval(tape, box);
    out << fmt("  f over the bounds: [%.6g, %.6g]\n", f.lower(), f.upper());
    out << "  defined and continuous on the whole box: " << (f.defined ? "yes" : "no") << "\n";
    out << fmt("  Lipschitz bound over the bounds: %.6g\n", expr::lipschitz_bound(tape, box));

    // Speed of one evaluation, double and interval, on random points / small boxes.
    {
        std::mt19937_64 rng(1);
        std::uniform_real_distribution<double> u(lo, hi);
        constexpr int kPoints = 2000;
        std::vector<std::array<double, 3>> pts(kPoints);
        for (auto& q : pts) q = {u(rng), u(rng), is3d ? u(rng) : 0.0};
        expr::Evaluator<double> ed;
        expr::Evaluator<Interval> ei;
        volatile double sink = 0;  // keeps the evaluations from being optimised away
        auto t0 = std::chrono::steady_clock::now();
        for (const auto& q : pts) sink = sink + ed(tape, q);
        auto t1 = std::chrono::steady_clock::now();
        for (const auto& q : pts) {
            const double w = (hi - lo) / 64;
            sink = sink + ei(tape, {Interval(q[0], q[0] + w), Interval(q[1], q[1] + w),
                                    Interval(q[2], q[2] + w)})
                              .lower();
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
        const double step = (hi - lo) / k;
        long empty = 0, filled = 0, ambiguous = 0;
        double pruned_sum = 0;
        const int kz = is3d ? k : 1;
        for (int i = 0; i < k; ++i) {
            for (int j = 0; j < k; ++j) {
                for (int l = 0; l < kz; ++l) {
                    const std::array<Interval, 3> cell{
                        Interval(lo + i * step, lo + (i + 1) * step),
                        Interval(lo + j * step, lo + (j + 1) * step),
                        is3d ? Interval(lo + l * step, lo + (l + 1) * step) : Interval(0.0)};
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
