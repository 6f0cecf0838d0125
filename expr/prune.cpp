// expr/prune.cpp — pruning by min/max choices recorded during one interval evaluation of the SSA.
#include "expr/prune.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "expr/eval.h"

namespace certray::expr {

namespace {

enum class Keep : std::uint8_t { Both, A, B, Constant };

}  // namespace

PruneResult prune(const Tape& tape, const std::array<Interval, 3>& box) {
    const std::vector<Instr>& ssa = tape.ssa();
    const std::size_t n = ssa.size();
    std::vector<UpInterval> v(n);
    std::vector<Keep> keep(n, Keep::Both);
    {
        RoundingScope scope;
        const std::array<UpInterval, 3> p{UpInterval(box[0]), UpInterval(box[1]),
                                          UpInterval(box[2])};
        // The SSA list is itself a program whose registers are the SSA indices, so every
        // intermediate enclosure stays readable for the choices.
        detail::run<UpInterval>(ssa, p, v.data(), [&](const Instr& in, const UpInterval* r) {
            const UpInterval& out = r[in.out];
            if (in.op == Op::Min || in.op == Op::Max) {
                const UpInterval& a = r[in.a];
                const UpInterval& b = r[in.b];
                const bool a_wins =
                    in.op == Op::Min ? a.upper() <= b.lower() : a.lower() >= b.upper();
                const bool b_wins =
                    in.op == Op::Min ? b.upper() <= a.lower() : b.lower() >= a.upper();
                if (a_wins && b.defined)
                    keep[in.out] = Keep::A;
                else if (b_wins && a.defined)
                    keep[in.out] = Keep::B;
            }
            if (in.op != Op::Const && out.defined && out.lower() == out.upper() &&
                std::isfinite(out.lower())) {
                keep[in.out] = Keep::Constant;
            }
        });
    }
    // Nothing to drop or fold (every instruction of a compiled tape is live): the tape as it is.
    if (std::all_of(keep.begin(), keep.end(), [](Keep k) { return k == Keep::Both; })) {
        return PruneResult{tape, n, n, Interval(v[n - 1])};
    }
    // alias[i]: the SSA index whose value instruction i's value equals on the box.
    std::vector<std::uint32_t> alias(n);
    for (std::size_t i = 0; i < n; ++i) {
        alias[i] = static_cast<std::uint32_t>(i);
        if (keep[i] == Keep::A) alias[i] = alias[ssa[i].a];
        if (keep[i] == Keep::B) alias[i] = alias[ssa[i].b];
    }
    // Liveness from the output backwards, through aliases.
    std::vector<bool> live(n, false);
    live[alias[n - 1]] = true;
    for (std::size_t j = n; j-- > 0;) {
        if (!live[j] || keep[j] == Keep::Constant) continue;
        const int k = arity(ssa[j].op);
        if (k >= 1) live[alias[ssa[j].a]] = true;
        if (k == 2) live[alias[ssa[j].b]] = true;
    }
    // Emit the live instructions, operands renamed to new indices.
    std::vector<std::uint32_t> renamed(n, 0);
    std::vector<Instr> out;
    for (std::size_t i = 0; i < n; ++i) {
        if (!live[i]) continue;
        Instr in = ssa[i];
        if (keep[i] == Keep::Constant) {
            in = Instr{Op::Const, 0, 0, 0, v[i].lower()};
        } else {
            const int k = arity(in.op);
            if (k >= 1) in.a = renamed[alias[in.a]];
            if (k == 2) in.b = renamed[alias[in.b]];
        }
        renamed[i] = static_cast<std::uint32_t>(out.size());
        in.out = renamed[i];
        out.push_back(in);
    }
    PruneResult result;
    result.before = n;
    result.value = Interval(v[n - 1]);
    result.tape = Tape::from_ssa(std::move(out));
    result.after = result.tape.size();
    return result;
}

}  // namespace certray::expr
