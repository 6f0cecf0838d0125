// bench/walk_bench.cpp — what one walk of the interval batch evaluator costs, by the number of
// lanes it carries, in double and in binary32 bounds (Google Benchmark).
//
// The coherent renderer (tracers/coherent_*.cpp) walks short SSA lists over a few lanes at a time:
// a node's four quarters, a scan's pieces and points, the mean value forms' lanes of a tangent
// list. A walk of one vector of lanes is paid whole, whatever its lanes (docs/benchmarks.md,
// session 24), so the cost that matters is that of a walk, not of a lane. Lists: the SSA form of
// Barth's sextic (scenes/barth_sextic.vm, 25 instructions) and its tangent list (expr/tangent.h),
// and Fidget's bear (scenes/fidget/bear.vm, 662 instructions). Boxes of side 2^-6 around points of
// [-1, 1]^3; n lanes per walk, 1 to 64; `f32` the binary32 walk (IntervalLanesF), else double
// (IntervalLanes); the copy of the walk chosen for this CPU. CPU time per walk.
// Command: build/bench/walk_bench [--benchmark_filter=…]; results in docs/benchmarks.md,
// "The walk of one vector" (session 25).
#include <benchmark/benchmark.h>

#include <array>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "expr/eval_interval_batch.h"
#include "expr/load.h"
#include "expr/tangent.h"
#include "expr/tape.h"
#include "interval/interval.h"

namespace certray {
namespace {

struct List {
    std::vector<expr::Instr> instrs;
    std::uint32_t slots = 0;
    std::array<std::uint32_t, 3> seeds{};  ///< tangent list: the seed slots (else unused)
    bool tangent = false;
};

List list_of(const char* path, bool tangent, bool registers = false) {
    const expr::Tape tape(expr::load_graph_file(path));
    List l;
    if (registers) {
        l.instrs = tape.instrs();
        l.slots = static_cast<std::uint32_t>(tape.registers());
        return l;
    }
    if (!tangent) {
        l.instrs = tape.ssa();
        l.slots = static_cast<std::uint32_t>(l.instrs.size());
        return l;
    }
    const auto tl = expr::tangent_list(tape.ssa());
    l.instrs = tl->list;
    l.slots = tl->slots;
    l.seeds = {tl->seed[0], tl->seed[1], tl->seed[2]};
    l.tangent = true;
    return l;
}

const List& list(int k) {
    static const std::vector<List> lists = {
        list_of(CERTRAY_SCENES_DIR "/barth_sextic.vm", false),
        list_of(CERTRAY_SCENES_DIR "/barth_sextic.vm", true),
        list_of(CERTRAY_SCENES_DIR "/fidget/bear.vm", false),
        list_of(CERTRAY_SCENES_DIR "/fidget/bear.vm", false, true)};
    return lists[k];
}

/// n lanes per walk of list `k`, in binary32 (`f32`) or double bounds.
template <class L>
void bm_walk(benchmark::State& state) {
    const List& l = list(static_cast<int>(state.range(0)));
    const int n = static_cast<int>(state.range(1));
    std::vector<L> regs(l.slots);
    std::array<L, 3> in{};
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            const double x = u(rng);
            using B = std::remove_cvref_t<decltype(in[c].lo[0])>;
            in[c].lo[i] = static_cast<B>(x);
            in[c].hi[i] = static_cast<B>(x + 0x1p-6);
        }
    }
    for (auto& x : in) x.defined[0] = ~std::uint64_t{0};
    if (l.tangent) {  // the seeds: a direction (the same in every lane)
        for (int c = 0; c < 3; ++c) {
            L& s = regs[l.seeds[c]];
            for (int i = 0; i < n; ++i) s.lo[i] = s.hi[i] = c == 2 ? 1.0f : 0.5f;
            s.defined[0] = ~std::uint64_t{0};
        }
    }
    RoundingScope up;
    for (auto _ : state) {
        expr::run_interval_batch(l.instrs.data(), l.instrs.data() + l.instrs.size(), in.data(),
                                 regs.data(), n);
        benchmark::DoNotOptimize(regs[l.instrs.back().out]);
    }
    state.SetLabel(std::to_string(l.instrs.size()) + " instructions, " + std::to_string(l.slots) +
                   " registers");
}

void lanes(benchmark::internal::Benchmark* b) {
    b->ArgNames({"list", "lanes"});
    for (int k = 0; k < 4; ++k) {
        for (int n : {1, 4, 8, 16, 32, 64}) b->Args({k, n});
    }
}

BENCHMARK(bm_walk<expr::IntervalLanes>)->Name("double")->Apply(lanes);
BENCHMARK(bm_walk<expr::IntervalLanesF>)->Name("f32")->Apply(lanes);

}  // namespace
}  // namespace certray

BENCHMARK_MAIN();
