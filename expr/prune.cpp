// expr/prune.cpp — pruning by min/max choices read from one interval evaluation of the SSA list.
//
// prune_ssa walks the list once, backwards from the output. A slot is live once a kept
// instruction reads it, and then has its slot in the output list (`bind`, numbered in the order
// slots become live: the output is 0). A live instruction is kept (written, back to front, with
// its operands bound), folded to a constant, or — a min/max whose other branch is inactive on the
// box — dropped, its chosen operand taking over its slot. prune() is the same on a fresh
// evaluation of a Tape's SSA, renumbered in list order for Tape::from_ssa.
#include "expr/prune.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "expr/eval.h"

namespace certray::expr {

namespace {

/// Per op: its arity (bits 0–1), whether it is min (bit 2) or max (bit 3), whether it may be
/// folded to a constant (bit 4: every op but Const), whether it is and/or (bit 5: a choice
/// by the first operand's zeroness), and whether it is add or sub (bit 6: x + 0, 0 + x and x − 0
/// are x).
constexpr unsigned kMin = 4, kMax = 8, kFoldable = 16, kSelect = 32, kAddSub = 64;
constexpr std::array<std::uint8_t, kOpCount> kInfo = [] {
    std::array<std::uint8_t, kOpCount> t{};
    for (int k = 0; k < kOpCount; ++k) {
        const auto op = static_cast<Op>(k);
        t[k] = static_cast<std::uint8_t>(
            arity(op) | (op == Op::Min ? kMin : 0) | (op == Op::Max ? kMax : 0) |
            (op == Op::And || op == Op::Or ? kSelect : 0) | (op != Op::Const ? kFoldable : 0) |
            (op == Op::Add || op == Op::Sub ? kAddSub : 0));
    }
    return t;
}();

/// What becomes of a live instruction.
enum Keep : unsigned { kBoth = 0, kA = 1, kB = 2, kConstant = 3 };

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// The decision for a live instruction (`info` = kInfo of its op) from its enclosure and its
/// operands' (the rules of prune.h); `v[s · Stride]` is slot s's enclosure.
template <std::size_t Stride>
[[gnu::always_inline]] inline Keep decide(const Instr& in, unsigned info, const UpInterval* v,
                                          std::size_t stride, unsigned fold) {
    const std::size_t step = Stride != 0 ? Stride : stride;
    const UpInterval& out = v[in.out * step];
    // One rarely taken branch (a point enclosure of an op that is not already a constant).
    const unsigned point = unsigned{out.lower() == out.upper()} & (info / kFoldable) & fold;
    if (point != 0) [[unlikely]] {
        if (out.defined && std::isfinite(out.lower())) return kConstant;
    }
    if ((info & (kMin | kMax | kSelect | kAddSub)) == 0) return kBoth;
    const UpInterval& a = v[in.a * step];
    const UpInterval& b = v[in.b * step];
    if (info & kAddSub) {
        // An operand that is 0 on the whole box (a constant, or a smooth blend's kernel folded
        // to one): x + 0 = 0 + x = x − 0 = x, as reals and as intervals; in double up to the
        // sign of a zero result (−0 + 0 = +0).
        auto zero = [](const UpInterval& x) {
            return x.defined && x.lower() == 0 && x.upper() == 0;
        };
        if (zero(b)) return kA;
        if (in.op == Op::Add && zero(a)) return kB;
        return kBoth;
    }
    if (info & kSelect) [[unlikely]] {
        // and(a, b) = a where a = 0, b where a ≠ 0; or(a, b) the other way round. Dropping a
        // (choosing b) needs a defined; choosing a never reads b.
        const bool nonzero = !a.is_empty() && (a.lower() > 0 || a.upper() < 0);
        const bool zero = a.lower() == 0 && a.upper() == 0;
        const bool is_and = in.op == Op::And;
        if (nonzero) return is_and ? (a.defined ? kB : kBoth) : kA;
        if (zero) return is_and ? kA : (a.defined ? kB : kBoth);
        return kBoth;
    }
    // below: a ≤ b everywhere on the box, above: a ≥ b (both when a and b are the same value).
    // min keeps a when a is below, b when a is above; max the other way round. A dropped branch
    // must be defined.
    const unsigned same = in.a == in.b;
    const unsigned below = unsigned{a.upper() <= b.lower()} | same;
    const unsigned above = unsigned{b.upper() <= a.lower()} | same;
    const unsigned a_wins = (info & kMin) != 0 ? below : above;
    const unsigned b_wins = (info & kMin) != 0 ? above : below;
    if (a_wins & unsigned{b.defined}) return kA;
    if (b_wins & unsigned{a.defined}) return kB;
    return kBoth;
}

/// On a pruned list (slots 0 … count − 1, each written before it is read): every max(x, −x),
/// seen through copies (min(y, y)), becomes |x| (see prune.h).
void absolute_values(std::vector<Instr>& out, std::uint32_t count, PruneWorkspace& ws) {
    // Every slot is written before it is read, so neither table needs clearing first.
    if (ws.alias.size() < count) ws.alias.resize(count);
    if (ws.neg_of.size() < count) ws.neg_of.resize(count);
    std::uint32_t* alias = ws.alias.data();
    std::uint32_t* neg_of = ws.neg_of.data();
    for (Instr& in : out) {
        const bool copy = in.op == Op::Min && in.a == in.b;
        alias[in.out] = copy ? alias[in.a] : in.out;
        neg_of[in.out] = copy ? neg_of[in.a] : (in.op == Op::Neg ? alias[in.a] : kNone);
        if (in.op != Op::Max) continue;
        const std::uint32_t x = alias[in.a], y = alias[in.b];
        if (neg_of[y] == x) {
            in = Instr{Op::Abs, in.out, in.a, 0, 0.0};
        } else if (neg_of[x] == y) {
            in = Instr{Op::Abs, in.out, in.b, 0, 0.0};
        }
    }
}

/// prune_ssa with the stride of `values` known at compile time (0: read `stride`).
template <std::size_t Stride>
bool prune_walk(const std::vector<Instr>& ssa, const UpInterval* values, PruneWorkspace& ws,
                std::vector<Instr>& out, std::size_t stride) {
    const std::size_t n = ssa.size();
    ws.bind.assign(n, kNone);
    if (ws.emitted.size() < n) ws.emitted.resize(n);
    std::uint32_t* bind = ws.bind.data();
    Instr* emitted = ws.emitted.data();
    std::size_t pos = n;      // emitted[pos, n) is the output list so far, written back to front
    std::uint32_t count = 1;  // slots of the output list handed out (0: the output)
    bool changed = false;
    const unsigned fold = ws.fold_points ? 1u : 0u;
    bind[ssa[n - 1].out] = 0;
    // The slot of the output list for input slot s, handed out if s is not live yet (without a
    // branch: whether an operand is read elsewhere too is as good as random).
    auto operand = [&](std::uint32_t s) {
        std::uint32_t b = bind[s];
        const bool fresh = b == kNone;
        b = fresh ? count : b;
        count += fresh;
        bind[s] = b;
        return b;
    };
    for (std::size_t i = n; i-- > 0;) {
        const Instr& in = ssa[i];
        const std::uint32_t slot = bind[in.out];
        if (slot == kNone) {  // not read by any kept instruction: dropped
            changed = true;
            continue;
        }
        const unsigned info = kInfo[static_cast<int>(in.op)];
        const Keep k = decide<Stride>(in, info, values, stride, fold);
        if (k == kBoth) [[likely]] {
            Instr e = in;
            e.out = slot;
            if ((info & 3u) >= 1) e.a = operand(in.a);
            if ((info & 3u) == 2) e.b = operand(in.b);
            emitted[--pos] = e;
            continue;
        }
        changed = true;
        if (k == kConstant) {
            emitted[--pos] = Instr{Op::Const, slot, 0, 0, values[in.out * stride].lower()};
            continue;
        }
        const std::uint32_t chosen = k == kA ? in.a : in.b;
        if (bind[chosen] == kNone) {
            bind[chosen] = slot;  // the chosen operand computes straight into this slot
        } else {
            // Already read by a kept instruction under its own slot: copy it, as min(x, x).
            emitted[--pos] = Instr{Op::Min, slot, bind[chosen], bind[chosen], 0.0};
        }
    }
    if (!changed) return false;
    out.assign(emitted + pos, emitted + n);
    if (ws.absolute_values) absolute_values(out, count, ws);
    return true;
}

}  // namespace

bool prune_ssa(const std::vector<Instr>& ssa, const UpInterval* values, PruneWorkspace& ws,
               std::vector<Instr>& out, std::size_t stride) {
    if (ssa.empty()) return false;
    // The strides the 2D quadtree uses, with constant multipliers; any other one read at run time.
    if (stride == 1) return prune_walk<1>(ssa, values, ws, out, stride);
    if (stride == 4) return prune_walk<4>(ssa, values, ws, out, stride);
    return prune_walk<0>(ssa, values, ws, out, stride);
}

std::size_t fold_ssa(const std::vector<Instr>& ssa, const UpInterval* values, double width,
                     FoldedList& out) {
    out.list.clear();
    out.fixed.clear();
    const std::size_t n = ssa.size();
    if (n < 2 || !(width >= 0)) return 0;
    // Per slot (slots are < n): 0 not read, 1 read by a kept instruction, 2 folded (an input).
    std::vector<std::uint8_t>& state = out.state;
    state.assign(n, 0);
    state[ssa[n - 1].out] = 1;
    std::size_t kept = 0, folded = 0;
    for (std::size_t i = n; i-- > 0;) {
        const Instr& in = ssa[i];
        if (state[in.out] == 0) continue;
        const UpInterval& v = values[in.out];
        if (i + 1 < n && in.op != Op::Const && v.defined && !v.is_empty() &&
            std::isfinite(v.lower()) && std::isfinite(v.upper()) &&
            v.upper() - v.lower() <= width) {
            state[in.out] = 2;
            ++folded;
            continue;
        }
        ++kept;
        const int k = arity(in.op);
        if (k >= 1 && state[in.a] == 0) state[in.a] = 1;
        if (k == 2 && state[in.b] == 0) state[in.b] = 1;
    }
    if (folded == 0) return 0;
    for (const Instr& in : ssa) {
        if (state[in.out] == 1) {
            out.list.push_back(in);
        } else if (state[in.out] == 2) {
            out.fixed.emplace_back(in.out, values[in.out]);
        }
    }
    return n - kept;
}

PruneResult prune(const Tape& tape, const std::array<Interval, 3>& box) {
    const std::vector<Instr>& ssa = tape.ssa();
    const std::size_t n = ssa.size();
    std::vector<UpInterval> v(n);
    {
        RoundingScope scope;
        const std::array<UpInterval, 3> p{UpInterval(box[0]), UpInterval(box[1]),
                                          UpInterval(box[2])};
        // The SSA list is itself a program whose registers are the SSA indices, so every
        // intermediate enclosure stays readable for the choices.
        detail::run<UpInterval>(ssa, p, v.data());
    }
    PruneResult result;
    result.before = n;
    result.value = Interval(v[n - 1]);
    PruneWorkspace ws;
    ws.absolute_values = true;
    std::vector<Instr> out;
    if (!prune_ssa(ssa, v.data(), ws, out)) {
        result.tape = tape;
        result.after = n;
        return result;
    }
    // Tape::from_ssa wants slot i = instruction i: renumber.
    std::vector<std::uint32_t> index(out.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
        Instr& in = out[i];
        const int k = arity(in.op);
        if (k >= 1) in.a = index[in.a];
        if (k == 2) in.b = index[in.b];
        index[in.out] = static_cast<std::uint32_t>(i);
        in.out = static_cast<std::uint32_t>(i);
    }
    result.tape = Tape::from_ssa(std::move(out));
    result.after = result.tape.size();
    return result;
}

}  // namespace certray::expr
