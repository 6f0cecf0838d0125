// expr/tangent.cpp — forward-mode derivative along a direction, written as plain instructions.
#include "expr/tangent.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <unordered_map>

namespace certray::expr {
namespace {

constexpr std::uint32_t kZero = std::numeric_limits<std::uint32_t>::max();

/// Writes the tangent list: each emit() takes a fresh slot.
class Writer {
  public:
    explicit Writer(std::uint32_t first) : next_(first) {}
    std::uint32_t emit(Op op, std::uint32_t a = 0, std::uint32_t b = 0, double imm = 0) {
        out.push_back({op, next_, a, b, imm});
        return next_++;
    }
    std::uint32_t constant(double c) { return emit(Op::Const, 0, 0, c); }
    /// A slot that no instruction writes (a seed).
    std::uint32_t reserve() { return next_++; }
    std::uint32_t slots() const { return next_; }
    std::vector<Instr> out;

  private:
    std::uint32_t next_;
};

/// Whether op has a kink (its rule in tangent_list encloses Clarke's derivative).
bool kink(Op op) { return op == Op::Min || op == Op::Max || op == Op::Abs; }

/// Whether tangent_list has a rule for op.
bool has_rule(Op op) {
    switch (op) {
        case Op::Const:
        case Op::VarX:
        case Op::VarY:
        case Op::VarZ:
        case Op::Neg:
        case Op::Add:
        case Op::Sub:
        case Op::Mul:
        case Op::Square:
        case Op::Div:
        case Op::Recip:
        case Op::Sqrt:
        case Op::Exp:
        case Op::Log:
        case Op::Sin:
        case Op::Cos:
        case Op::Pow:
        case Op::Min:
        case Op::Max:
        case Op::Abs:
            return true;
        default:
            return false;
    }
}

}  // namespace

TangentKind tangent_kind(const std::vector<Instr>& list) {
    if (list.empty()) return TangentKind::None;
    bool kinked = false;
    for (const Instr& in : list) {
        if (!has_rule(in.op)) return TangentKind::None;
        kinked = kinked || kink(in.op);
    }
    return kinked ? TangentKind::Kinked : TangentKind::Smooth;
}

std::optional<TangentList> tangent_list(const std::vector<Instr>& list) {
    // Most lists without a tangent list hold a min or max: found before anything is built.
    if (list.empty() ||
        !std::all_of(list.begin(), list.end(), [](const Instr& in) { return has_rule(in.op); })) {
        return std::nullopt;
    }
    // Slots past every slot the list writes or reads (an operand that no instruction writes is
    // an input: its derivative is 0).
    std::uint32_t end = 0;
    for (const Instr& in : list) {
        end = std::max(end, in.out + 1);
        if (arity(in.op) >= 1) end = std::max(end, in.a + 1);
        if (arity(in.op) == 2) end = std::max(end, in.b + 1);
    }
    TangentList t;
    t.smooth = std::none_of(list.begin(), list.end(), [](const Instr& in) { return kink(in.op); });
    Writer w(end);
    for (std::uint32_t& s : t.seed) s = w.reserve();
    std::vector<std::uint32_t> d(end, kZero);  // per slot of the list: its derivative's slot
    std::uint32_t one = kZero, zero = kZero, minus_one = kZero, big = kZero;
    const auto constant = [&](std::uint32_t& slot, double c) {
        if (slot == kZero) slot = w.constant(c);
        return slot;
    };
    // clamp(v·2⁶⁰⁰·2⁶⁰⁰, lo, 1): 1 where v > 0 on the box (the least positive double times 2¹²⁰⁰
    // exceeds 1; large ones overflow to +inf), lo where v < 0, 0 where v = 0 on the box, and an
    // interval holding [lo, 1]'s part on either side of 0 where v's sign is not certain.
    const auto gate = [&](std::uint32_t v, double lo) {
        const std::uint32_t big_v = w.emit(Op::Mul, v, constant(big, 0x1p600));
        const std::uint32_t s = w.emit(Op::Mul, big_v, big);
        const std::uint32_t top = w.emit(Op::Min, constant(one, 1.0), s);
        return w.emit(Op::Max, lo == 0 ? constant(zero, 0.0) : constant(minus_one, -1.0), top);
    };
    for (const Instr& in : list) {
        w.out.push_back(in);
        const std::uint32_t da = arity(in.op) >= 1 ? d[in.a] : kZero;
        const std::uint32_t db = arity(in.op) == 2 ? d[in.b] : kZero;
        std::uint32_t r = kZero;
        switch (in.op) {
            case Op::Const:
                break;
            case Op::VarX:
            case Op::VarY:
            case Op::VarZ:
                r = t.seed[static_cast<int>(in.op) - static_cast<int>(Op::VarX)];
                break;
            case Op::Neg:
                if (da != kZero) r = w.emit(Op::Neg, da);
                break;
            case Op::Add:
                if (da != kZero && db != kZero) {
                    r = w.emit(Op::Add, da, db);
                } else {
                    r = da != kZero ? da : db;
                }
                break;
            case Op::Sub:
                if (da != kZero && db != kZero) {
                    r = w.emit(Op::Sub, da, db);
                } else if (da != kZero) {
                    r = da;
                } else if (db != kZero) {
                    r = w.emit(Op::Neg, db);
                }
                break;
            case Op::Mul:  // a′·b + a·b′
                if (da != kZero && db != kZero) {
                    r = w.emit(Op::Add, w.emit(Op::Mul, da, in.b), w.emit(Op::Mul, in.a, db));
                } else if (da != kZero) {
                    r = w.emit(Op::Mul, da, in.b);
                } else if (db != kZero) {
                    r = w.emit(Op::Mul, in.a, db);
                }
                break;
            case Op::Square:  // a·a′ doubled (exact): a sum where a product by 2 cost more
                if (da != kZero) {
                    const std::uint32_t p = w.emit(Op::Mul, in.a, da);
                    r = w.emit(Op::Add, p, p);
                }
                break;
            case Op::Div:  // (a′ − q·b′)/b with q = a/b
                if (db != kZero) {
                    const std::uint32_t qb = w.emit(Op::Mul, in.out, db);
                    const std::uint32_t num =
                        da != kZero ? w.emit(Op::Sub, da, qb) : w.emit(Op::Neg, qb);
                    r = w.emit(Op::Div, num, in.b);
                } else if (da != kZero) {
                    r = w.emit(Op::Div, da, in.b);
                }
                break;
            case Op::Recip:  // −(q·a′)/a with q = 1/a
                if (da != kZero) {
                    r = w.emit(Op::Neg, w.emit(Op::Div, w.emit(Op::Mul, in.out, da), in.a));
                }
                break;
            case Op::Sqrt:  // (0.5/√a)·a′: unbounded where √a reaches 0
                if (da != kZero) {
                    r = w.emit(Op::Mul, w.emit(Op::Div, w.constant(0.5), in.out), da);
                }
                break;
            case Op::Exp:  // eᵃ·a′
                if (da != kZero) r = w.emit(Op::Mul, in.out, da);
                break;
            case Op::Log:  // a′/a
                if (da != kZero) r = w.emit(Op::Div, da, in.a);
                break;
            case Op::Sin:  // cos a · a′
                if (da != kZero) r = w.emit(Op::Mul, w.emit(Op::Cos, in.a), da);
                break;
            case Op::Cos:  // −sin a · a′
                if (da != kZero) r = w.emit(Op::Neg, w.emit(Op::Mul, w.emit(Op::Sin, in.a), da));
                break;
            case Op::Pow:  // n·aⁿ⁻¹·a′ (a⁰ = 1 has derivative 0, a¹ = a)
                if (da != kZero && in.b >= 1) {
                    if (in.b == 1) {
                        r = da;
                    } else {
                        const std::uint32_t p = w.emit(Op::Pow, in.a, in.b - 1);
                        const std::uint32_t np =
                            w.emit(Op::Mul, w.constant(static_cast<double>(in.b)), p);
                        r = w.emit(Op::Mul, np, da);
                    }
                }
                break;
            case Op::Min:  // g·a′ + (1 − g)·b′, g = 1 where a < b, 0 where b < a, [0, 1] at a tie
            case Op::Max:  // likewise with g = 1 where a > b
                if (da != kZero || db != kZero) {
                    const std::uint32_t g = gate(in.op == Op::Min ? w.emit(Op::Sub, in.b, in.a)
                                                                  : w.emit(Op::Sub, in.a, in.b),
                                                 0.0);
                    const std::uint32_t ga = da != kZero ? w.emit(Op::Mul, g, da) : kZero;
                    const std::uint32_t gb =
                        db != kZero ? w.emit(Op::Mul, w.emit(Op::Sub, constant(one, 1.0), g), db)
                                    : kZero;
                    r = ga == kZero ? gb : gb == kZero ? ga : w.emit(Op::Add, ga, gb);
                }
                break;
            case Op::Abs:  // sign(a)·a′, the sign [−1, 1] where a may be 0 (and 0 where a ≡ 0)
                if (da != kZero) r = w.emit(Op::Mul, gate(in.a, -1.0), da);
                break;
            default:  // jumps and the rest: no rule (has_rule)
                return std::nullopt;
        }
        d[in.out] = r;
    }
    t.value = list.back().out;
    t.derivative = d[t.value];
    if (t.derivative == kZero) t.derivative = w.constant(0.0);  // f constant: derivative 0
    t.list = std::move(w.out);
    t.slots = w.slots();
    return t;
}

std::size_t share_instructions(std::vector<Instr>& list,
                               std::span<const std::pair<std::uint32_t, std::uint32_t>> same,
                               std::span<const std::uint32_t> keep) {
    // Slot renaming: `same`, then each dropped repeat's slot to the earlier one's.
    std::unordered_map<std::uint32_t, std::uint32_t> renamed(same.begin(), same.end());
    const auto slot = [&](std::uint32_t s) {
        const auto it = renamed.find(s);
        return it == renamed.end() ? s : it->second;
    };
    // An instruction's key: op, operands as read (renamed), and the immediate's bits (Const) or
    // the exponent (Pow, in b). The Var ops read no slot.
    struct Key {
        Op op;
        std::uint32_t a, b;
        std::uint64_t imm;
        bool operator==(const Key&) const = default;
    };
    struct Hash {
        std::size_t operator()(const Key& k) const {
            std::size_t h = static_cast<std::size_t>(k.op);
            for (const std::uint64_t v : {std::uint64_t{k.a}, std::uint64_t{k.b}, k.imm})
                h = h * 0x9E3779B97F4A7C15ull + v;
            return h;
        }
    };
    std::unordered_map<Key, std::uint32_t, Hash> first;
    std::vector<Instr> out;
    out.reserve(list.size());
    for (Instr in : list) {
        const int n = arity(in.op);
        if (n >= 1) in.a = slot(in.a);
        if (n == 2) in.b = slot(in.b);
        const Key key{in.op, n >= 1 ? in.a : 0, n == 2 || in.op == Op::Pow ? in.b : 0,
                      in.op == Op::Const ? std::bit_cast<std::uint64_t>(in.imm) : 0};
        const auto [it, fresh] = first.try_emplace(key, in.out);
        if (!fresh && std::find(keep.begin(), keep.end(), in.out) == keep.end()) {
            renamed[in.out] = it->second;
            continue;
        }
        out.push_back(in);
    }
    // What the kept slots depend on, from the last instruction back.
    std::uint32_t slots = 0;
    for (const Instr& in : out) {
        const int n = arity(in.op);
        slots = std::max({slots, in.out + 1, n >= 1 ? in.a + 1 : 0, n == 2 ? in.b + 1 : 0});
    }
    for (const std::uint32_t k : keep) slots = std::max(slots, k + 1);
    std::vector<bool> live(slots, false);
    for (const std::uint32_t k : keep) live[k] = true;
    std::vector<Instr> kept;
    kept.reserve(out.size());
    for (std::size_t i = out.size(); i-- > 0;) {
        const Instr& in = out[i];
        if (!live[in.out]) continue;
        const int n = arity(in.op);
        if (n >= 1) live[in.a] = true;
        if (n == 2) live[in.b] = true;
        kept.push_back(in);
    }
    std::reverse(kept.begin(), kept.end());
    const std::size_t dropped = list.size() - kept.size();
    list = std::move(kept);
    return dropped;
}

}  // namespace certray::expr
