// expr/eval_dual_batch.h — a list's value and gradient at several points in one walk: the
// normals of a tile's hits.
//
// Contract: run_dual_batch runs an SSA list (each instruction writes a register that no earlier
// instruction wrote, and reads only registers written before it) at n ≤ kDualLanes points, and
// lane i of every register it writes is bit for bit what detail::run<Dual<double, 3>> (expr/
// eval.h) computes at point i with the variables x, y, z as partials e₀, e₁, e₂: the value and
// the three partials, signed zeros included, and NaN where it gives NaN (a NaN's sign and
// payload follow the operand order the compiler picks, in either walk). How: + − × ÷ neg square √
// exp log sin cos, 1/x, min, max and abs apply Dual's formulas (interval/dual.h) lane by lane, the
// same IEEE operations in the same order (libm's functions at each lane's value, as Dual's are);
// every other op is Dual's own operation, lane by lane. The arithmetic runs on vectors of 4 lanes,
// up to the one holding lane n − 1 (lanes from n on hold meaningless values); one copy for SSE2 and
// one for AVX2, chosen as expr/eval_batch.h's batch_isa() chooses.
#pragma once

#include <array>

#include "expr/tape.h"

namespace certray::expr {

/// The capacity of DualLanes: how many points one walk evaluates.
inline constexpr int kDualLanes = 16;

/// kDualLanes values and their partials ∂/∂x, ∂/∂y, ∂/∂z, structure of arrays.
struct alignas(64) DualLanes {
    double v[kDualLanes];
    double g[3][kDualLanes];
};

/// Runs the SSA list [begin, end) at points p[0, n), 1 ≤ n ≤ kDualLanes, into r (indexed by
/// register; see the file contract). Not thread-safe on a shared r. Allocates nothing.
void run_dual_batch(const Instr* begin, const Instr* end, const std::array<double, 3>* p, int n,
                    DualLanes* r);

}  // namespace certray::expr
