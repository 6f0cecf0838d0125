// expr/eval.h — the one evaluator: a tape run over any Number type.
//
// Contract: eval<T>(tape, p) computes the tape's function with T's arithmetic, at the point (or
// over the box, for enclosure types) p = (x, y, z). For an enclosure T, for every point q in the
// box p at which f is defined, f(q) lies in the result, and the result's decoration is true only if
// f is defined and continuous on the whole box. A new number type is a new instantiation, never a
// copy of this loop. For types whose operations switch the rounding mode (Interval, and anything
// built on it), `Fast<T>` names the variant that runs inside one hoisted RoundingScope.
#pragma once

#include <array>
#include <type_traits>
#include <vector>

#include "expr/tape.h"
#include "interval/interval.h"
#include "interval/number.h"
#include "interval/poly.h"

namespace certray {
struct Batch;  // interval/batch.h: kBatch doubles in lock-step
}  // namespace certray

namespace certray::expr {

/// The type a tape is evaluated in for inputs of type T, and the scope that makes it valid.
/// By default T itself with no scope; Interval runs as UpInterval inside a RoundingScope.
template <class T>
struct Fast {
    using type = T;
    struct Scope {};
    static const T& in(const T& x) { return x; }
    static const T& out(const T& x) { return x; }
};

template <>
struct Fast<Interval> {
    using type = UpInterval;
    using Scope = RoundingScope;
    static UpInterval in(const Interval& x) { return UpInterval(x); }
    static Interval out(const UpInterval& x) { return Interval(x); }
};

/// Polynomials over Interval run as polynomials over UpInterval inside one RoundingScope (7× faster
/// on the algebraic scenes). Declared here, beside the primary template, so that every user of
/// Evaluator<Poly<Interval>> sees it (one definition).
template <>
struct Fast<Poly<Interval>> {
    using type = Poly<UpInterval>;
    using Scope = RoundingScope;
    static type in(const Poly<Interval>& x) { return poly_cast<UpInterval>(x); }
    static Poly<Interval> out(const type& x) { return poly_cast<Interval>(x); }
};

namespace detail {

/// Does nothing after each instruction (the default observer of run()).
struct NoObserver {
    template <class T>
    void operator()(const Instr&, const T*) const noexcept {}
};

/// The loop itself, over registers of type T; callers hold whatever scope T needs. `obs(in, r)` is
/// called after each instruction (pruning records min/max choices there).
template <class T, class Observer = NoObserver>
void run(const std::vector<Instr>& instrs, const std::array<T, 3>& p, T* r, Observer obs = {}) {
    // The math functions of namespace certray (and std's, which it brings in) for doubles; other
    // types are found by ADL. Named here so that the builder's expr::min & co. cannot hide them.
    using certray::abs, certray::square, certray::pow, certray::sqrt, certray::exp, certray::log,
        certray::sin, certray::cos, certray::min, certray::max, certray::floor, certray::ceil,
        certray::round, certray::tan, certray::asin, certray::acos, certray::atan, certray::atan2,
        certray::compare, certray::mod, certray::logic_and, certray::logic_or, certray::logic_not;
    for (const Instr& in : instrs) {
        switch (in.op) {
            case Op::Const:
                r[in.out] = T(in.imm);
                break;
            case Op::VarX:
                r[in.out] = p[0];
                break;
            case Op::VarY:
                r[in.out] = p[1];
                break;
            case Op::VarZ:
                r[in.out] = p[2];
                break;
            case Op::Neg:
                r[in.out] = -r[in.a];
                break;
            case Op::Abs:
                r[in.out] = abs(r[in.a]);
                break;
            case Op::Square:
                r[in.out] = square(r[in.a]);
                break;
            case Op::Sqrt:
                r[in.out] = sqrt(r[in.a]);
                break;
            case Op::Exp:
                r[in.out] = exp(r[in.a]);
                break;
            case Op::Log:
                r[in.out] = log(r[in.a]);
                break;
            case Op::Sin:
                r[in.out] = sin(r[in.a]);
                break;
            case Op::Cos:
                r[in.out] = cos(r[in.a]);
                break;
            case Op::Pow:
                r[in.out] = pow(r[in.a], static_cast<unsigned>(in.b));
                break;
            case Op::Add:
                r[in.out] = r[in.a] + r[in.b];
                break;
            case Op::Sub:
                r[in.out] = r[in.a] - r[in.b];
                break;
            case Op::Mul:
                r[in.out] = r[in.a] * r[in.b];
                break;
            case Op::Div:
                r[in.out] = r[in.a] / r[in.b];
                break;
            case Op::Min:
                r[in.out] = min(r[in.a], r[in.b]);
                break;
            case Op::Max:
                r[in.out] = max(r[in.a], r[in.b]);
                break;
            case Op::Floor:
                r[in.out] = floor(r[in.a]);
                break;
            case Op::Ceil:
                r[in.out] = ceil(r[in.a]);
                break;
            case Op::Round:
                r[in.out] = round(r[in.a]);
                break;
            case Op::Tan:
                r[in.out] = tan(r[in.a]);
                break;
            case Op::Asin:
                r[in.out] = asin(r[in.a]);
                break;
            case Op::Acos:
                r[in.out] = acos(r[in.a]);
                break;
            case Op::Atan:
                r[in.out] = atan(r[in.a]);
                break;
            case Op::Not:
                r[in.out] = logic_not(r[in.a]);
                break;
            case Op::Recip:
                r[in.out] = T(1.0) / r[in.a];
                break;
            case Op::Atan2:
                r[in.out] = atan2(r[in.a], r[in.b]);
                break;
            case Op::Compare:
                r[in.out] = compare(r[in.a], r[in.b]);
                break;
            case Op::Mod:
                r[in.out] = mod(r[in.a], r[in.b]);
                break;
            case Op::And:
                r[in.out] = logic_and(r[in.a], r[in.b]);
                break;
            case Op::Or:
                r[in.out] = logic_or(r[in.a], r[in.b]);
                break;
        }
        obs(in, r);
    }
}

/// A tape's instructions as the batch walk runs them (expr/eval_batch.cpp): a constant read by
/// add, sub, mul, div, min or max is folded into that instruction (an immediate operand), and a
/// Const instruction whose every reader took it so is dropped. Same registers, same results bit
/// for bit. `serial` is the Tape::serial() it was made from (0: none yet).
struct BatchCode {
    std::uint64_t serial = 0;
    /// Op bytes are the walk's dispatch keys (eval_batch.cpp), not Op values: run them only
    /// through run_batch(const BatchCode&, …).
    std::vector<Instr> instrs;
};
/// Makes `code` the batch code of `tape` (reusing its storage).
void compile_batch(const Tape& tape, BatchCode& code);

/// The batch walk: runs [begin, end) — a tape's instructions or an SSA list (register = index) —
/// or a tape's batch code over kBatch lanes; lane i of the last instruction's register is bit for
/// bit what run<double> gives at lane i of p[0..2]. Vectorised for the running CPU. Other
/// registers may be left stale. `lanes`: how many leading lanes matter (−1: all); when that is
/// at most kBatch / 2, only the first kBatch / 2 lanes are computed (the others keep stale
/// values).
void run_batch(const Instr* begin, const Instr* end, const Batch* p, Batch* r, int lanes = -1);
void run_batch(const BatchCode& code, const Batch* p, Batch* r);

struct NoBatchCode {};

}  // namespace detail

/// Evaluates tapes over T, reusing its register file: no allocation once the largest tape has
/// been seen. Not thread-safe; use one Evaluator per thread.
template <class T>
requires Number<typename Fast<T>::type>
class Evaluator {
  public:
    using Inner = typename Fast<T>::type;

    /// f(p) computed in T (for enclosures: an enclosure of f over the box p).
    T operator()(const Tape& tape, const std::array<T, 3>& p) {
        if (regs_.size() < tape.registers()) regs_.resize(tape.registers());
        if constexpr (std::is_same_v<T, Batch>) {
            if (code_.serial != tape.serial() || tape.serial() == 0) {
                detail::compile_batch(tape, code_);
            }
            detail::run_batch(code_, p.data(), regs_.data());
            return regs_[tape.output()];
        } else {
            [[maybe_unused]] typename Fast<T>::Scope scope;
            const std::array<Inner, 3> q{Fast<T>::in(p[0]), Fast<T>::in(p[1]), Fast<T>::in(p[2])};
            detail::run<Inner>(tape.instrs(), q, regs_.data());
            return Fast<T>::out(regs_[tape.output()]);
        }
    }

  private:
    std::vector<Inner> regs_;
    [[no_unique_address]] std::conditional_t<std::is_same_v<T, Batch>, detail::BatchCode,
                                             detail::NoBatchCode>
        code_;
};

/// One-shot evaluation (allocates its registers; use an Evaluator in loops).
template <class T>
T eval(const Tape& tape, const std::array<T, 3>& p) {
    Evaluator<T> e;
    return e(tape, p);
}

}  // namespace certray::expr
