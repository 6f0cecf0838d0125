// expr/csg_shapes.h — the primitives and blend operators of Lipschitz-Pruning CSG trees, built as
// Graph expressions of a point already in the primitive's own frame.
//
// Contract: each function returns the real function that the authors' shader evaluates
// (wbrbr/LipschitzPruning shaders/common.glsl eval_prim, sdRoundBox, sdExtrude, sdCone; the blend
// of shaders/eval.glsl sdf), written without branches: where their code chooses a formula by the
// sign of a coordinate, the expression is a max over the candidates, which equals their choice
// under each function's stated preconditions (docs/guide/formats.md derives each one). The
// preconditions are checked by the caller (expr/csg_json.cpp), which names the offending node.
// Reference: Barbier, Sanchez, Paris, Michel, Lambert, Boubekeur, Paulin, Thonat, "Lipschitz
// Pruning: Hierarchical Simplification of Primitive-Based SDFs", CGF (Eurographics) 2025.
#pragma once

#include <array>

#include "expr/builder.h"

namespace certray::expr::csg {

/// A point in a primitive's frame: three expressions of the world point.
struct Local {
    Expr x, y, z;
};

/// ‖q‖ − radius. Precondition: radius > 0.
Expr sphere(const Local& q, double radius);

/// A box with full side lengths `sides` (x, y, z), its vertical edges (parallel to y) rounded with
/// radii bevel[i]/2 — bevel[0] at the corner x > 0, z > 0; [1] x > 0, z ≤ 0; [2] x ≤ 0, z > 0;
/// [3] x ≤ 0, z ≤ 0 — and the cross-section extruded along y with its edges rounded with radius
/// round_top for y > 0 and round_bottom for y ≤ 0 (their round_x and round_y).
struct BoxShape {
    std::array<double, 3> sides{1, 1, 1};
    std::array<double, 4> bevel{0, 0, 0, 0};
    double round_top = 0;
    double round_bottom = 0;
};

/// The box's field: the 2D rounded rectangle d(x, z) = min(max(qx, qz), 0) + ‖max(q, 0)‖ − r with
/// q = (|x|, |z|) − (sx, sz)/2 + r, r the radius of the point's corner, then the extrusion
/// min(max(d + e, |y| − sy/2 + e), 0) + ‖max((d + e, |y| − sy/2 + e), 0)‖ − e with e the rounding
/// of the point's half. Preconditions: sides > 0, 0 ≤ bevel[i] ≤ min(sx, sz), 0 ≤ round_top,
/// round_bottom ≤ sy/2 (then each candidate is at most the chosen one, so the max is exact).
Expr box(const Local& q, const BoxShape& shape);

/// A cylinder along y: d = (‖(x, z)‖ − radius, |y| − height/2),
/// min(max(d.x, d.y), 0) + ‖max(d, 0)‖. Preconditions: height > 0, radius > 0.
Expr cylinder(const Local& q, double height, double radius);

/// A cone along y: base disc of `radius` at y = −height/2, apex at (0, height/2, 0); the exact
/// signed distance of their sdCone (outside: distance to the cone; inside: minus the distance to
/// the slanted side or to the base plane, whichever is nearer). Preconditions: height > 0,
/// radius > 0.
Expr cone(const Local& q, double height, double radius);

/// The blend modes of a binaryOperator node.
enum class Blend { Union, Inter, Sub };

/// With b′ = −b for Sub and b otherwise, and K(x) = max(k − x, 0)²/(4k) (K = 0 when k = 0):
/// Union min(a, b′) − K(|a − b′|); Inter and Sub max(a, b′) + K(|a − b′|) (the quadratic
/// polynomial smooth minimum). Precondition: k ≥ 0.
Expr blend(Blend mode, double k, const Expr& a, const Expr& b);

}  // namespace certray::expr::csg
