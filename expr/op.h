// expr/op.h — the operations of the expression DAG, with frozen numeric codes.
//
// The codes are written into files and tapes: NEVER renumber or reorder them; a new op gets the
// next free code. Every switch over Op has no `default`, so that the build (-Werror=switch) fails
// where a new op is not handled.
#pragma once

#include <cstdint>
#include <string_view>

namespace certray::expr {

/// One operation of the DAG. Codes are frozen: never renumber, only append.
enum class Op : std::uint8_t {
    Const = 0,   ///< a finite double constant (never NaN, never infinite)
    VarX = 1,    ///< the variable x
    VarY = 2,    ///< the variable y
    VarZ = 3,    ///< the variable z
    Neg = 4,     ///< -a
    Abs = 5,     ///< |a|
    Square = 6,  ///< a²
    Sqrt = 7,    ///< √a, defined for a ≥ 0
    Exp = 8,     ///< eᵃ
    Log = 9,     ///< ln a, defined for a > 0
    Sin = 10,    ///< sin a
    Cos = 11,    ///< cos a
    Add = 12,    ///< a + b
    Sub = 13,    ///< a − b
    Mul = 14,    ///< a · b
    Div = 15,    ///< a / b, defined for b ≠ 0
    Min = 16,    ///< min(a, b)
    Max = 17,    ///< max(a, b)
    Pow = 18,    ///< aⁿ for the non-negative integer n stored in the node
    // Fidget's further opcodes (issue 14). Discontinuous ones carry the decoration: over a box
    // where they jump, an enclosure is not `defined`.
    Floor = 19,    ///< ⌊a⌋ (jumps at the integers)
    Ceil = 20,     ///< ⌈a⌉ (jumps at the integers)
    Round = 21,    ///< a rounded to the nearest integer, halves away from 0 (jumps at the halves)
    Tan = 22,      ///< tan a, defined for a ∉ π/2 + πℤ
    Asin = 23,     ///< asin a, defined for a ∈ [−1, 1]
    Acos = 24,     ///< acos a, defined for a ∈ [−1, 1]
    Atan = 25,     ///< atan a
    Recip = 26,    ///< 1/a, defined for a ≠ 0
    Not = 27,      ///< 1 if a = 0, else 0
    Atan2 = 28,    ///< atan2(a, b): the angle of the point (x = b, y = a) in (−π, π]; not at 0
    Compare = 29,  ///< −1 if a < b, 0 if a = b, 1 if a > b
    Mod = 30,  ///< a − |b|·⌊a/|b|⌋ ∈ [0, |b|) (Euclidean remainder), defined for b ≠ 0
    And = 31,  ///< a if a = 0, else b
    Or = 32,   ///< a if a ≠ 0, else b
};

/// The number of Op values (one past the largest code).
inline constexpr int kOpCount = 33;

/// Number of child nodes of `op`: 0 for leaves, 1 for unary ops (and Pow), 2 for binary ops.
constexpr int arity(Op op) noexcept {
    switch (op) {
        case Op::Const:
        case Op::VarX:
        case Op::VarY:
        case Op::VarZ:
            return 0;
        case Op::Neg:
        case Op::Abs:
        case Op::Square:
        case Op::Sqrt:
        case Op::Exp:
        case Op::Log:
        case Op::Sin:
        case Op::Cos:
        case Op::Pow:
        case Op::Floor:
        case Op::Ceil:
        case Op::Round:
        case Op::Tan:
        case Op::Asin:
        case Op::Acos:
        case Op::Atan:
        case Op::Recip:
        case Op::Not:
            return 1;
        case Op::Atan2:
        case Op::Compare:
        case Op::Mod:
        case Op::And:
        case Op::Or:
        case Op::Add:
        case Op::Sub:
        case Op::Mul:
        case Op::Div:
        case Op::Min:
        case Op::Max:
            return 2;
    }
    return -1;  // unreachable for valid codes
}

/// Lower-case name of `op` (the function name used by the .expr language where there is one).
constexpr std::string_view name(Op op) noexcept {
    switch (op) {
        case Op::Const:
            return "const";
        case Op::VarX:
            return "x";
        case Op::VarY:
            return "y";
        case Op::VarZ:
            return "z";
        case Op::Neg:
            return "neg";
        case Op::Abs:
            return "abs";
        case Op::Square:
            return "square";
        case Op::Sqrt:
            return "sqrt";
        case Op::Exp:
            return "exp";
        case Op::Log:
            return "log";
        case Op::Sin:
            return "sin";
        case Op::Cos:
            return "cos";
        case Op::Add:
            return "add";
        case Op::Sub:
            return "sub";
        case Op::Mul:
            return "mul";
        case Op::Div:
            return "div";
        case Op::Min:
            return "min";
        case Op::Max:
            return "max";
        case Op::Pow:
            return "pow";
        case Op::Floor:
            return "floor";
        case Op::Ceil:
            return "ceil";
        case Op::Round:
            return "round";
        case Op::Tan:
            return "tan";
        case Op::Asin:
            return "asin";
        case Op::Acos:
            return "acos";
        case Op::Atan:
            return "atan";
        case Op::Recip:
            return "recip";
        case Op::Not:
            return "not";
        case Op::Atan2:
            return "atan2";
        case Op::Compare:
            return "compare";
        case Op::Mod:
            return "mod";
        case Op::And:
            return "and";
        case Op::Or:
            return "or";
    }
    return "?";  // unreachable for valid codes
}

/// True for the ops whose operands may be swapped: Add, Mul, Min, Max (not And, Or: they select
/// by their first operand).
constexpr bool is_commutative(Op op) noexcept {
    return op == Op::Add || op == Op::Mul || op == Op::Min || op == Op::Max;
}

}  // namespace certray::expr
