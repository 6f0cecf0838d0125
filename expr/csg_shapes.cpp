// expr/csg_shapes.cpp — the Lipschitz-Pruning primitives and blends as Graph expressions.
//
// Every constant derived from the file's numbers (half sides, radii r − h, R² + h²) is built as a
// Graph operation on the numbers themselves, so it is folded only when the double result is exact
// and the real function is the one of the numbers as read.
#include "expr/csg_shapes.h"

namespace certray::expr::csg {

namespace {

Expr half(Graph& g, double v) { return constant(g, v) * 0.5; }

/// ‖max((a, b), 0)‖ + min(max(a, b), 0): the distance to the quadrant {a ≤ 0, b ≤ 0}, exact
/// inside and outside.
Expr quadrant(const Expr& a, const Expr& b) {
    return min(max(a, b), 0.0) + sqrt(square(max(a, 0.0)) + square(max(b, 0.0)));
}

/// Their sdRoundBox for the corner u > 0, v > 0: half sides (hx, hz), corner radius r;
/// q = (u, v) − (hx, hz) + r, then quadrant(q) − r.
Expr rounded_rect(const Expr& u, const Expr& v, const Expr& hx, const Expr& hz, const Expr& r) {
    return quadrant(u + (r - hx), v + (r - hz)) - r;
}

/// Their sdExtrude: the 2D distance d extruded to |w| ≤ hy with edge radius e; w is |y| or ±y.
Expr extrude(const Expr& d, const Expr& w, const Expr& hy, const Expr& e) {
    return quadrant(d + e, w + (e - hy)) - e;
}

}  // namespace

Expr sphere(const Local& q, double radius) {
    return sqrt(square(q.x) + square(q.y) + square(q.z)) - radius;
}

Expr box(const Local& q, const BoxShape& s) {
    Graph& g = *q.x.graph;
    const Expr hx = half(g, s.sides[0]), hy = half(g, s.sides[1]), hz = half(g, s.sides[2]);
    // Cross-section in (x, z). Their code picks the corner radius by the signs of x and z. With
    // every r ≤ min(hx, hz), the formula of another corner evaluated with that corner's signs
    // (e.g. (−x, z) for x > 0) is at most max(|x| − hx, |z| − hz), which is at most the chosen
    // one: the max over the four corners is their value, and continuous.
    const std::array<double, 4>& b = s.bevel;
    Expr d;
    if (b[0] == b[1] && b[0] == b[2] && b[0] == b[3]) {
        d = rounded_rect(abs(q.x), abs(q.z), hx, hz, half(g, b[0]));
    } else {
        const Expr mx = -q.x, mz = -q.z;
        d = max(max(rounded_rect(q.x, q.z, hx, hz, half(g, b[0])),
                    rounded_rect(q.x, mz, hx, hz, half(g, b[1]))),
                max(rounded_rect(mx, q.z, hx, hz, half(g, b[2])),
                    rounded_rect(mx, mz, hx, hz, half(g, b[3]))));
    }
    // Extrusion along y, rounded with round_top above y = 0 and round_bottom below; the same
    // argument (each rounding ≤ hy) makes the max of the two candidates their choice.
    if (s.round_top == s.round_bottom) {
        return extrude(d, abs(q.y), hy, constant(g, s.round_top));
    }
    return max(extrude(d, q.y, hy, constant(g, s.round_top)),
               extrude(d, -q.y, hy, constant(g, s.round_bottom)));
}

Expr cylinder(const Local& q, double height, double radius) {
    Graph& g = *q.x.graph;
    return quadrant(sqrt(square(q.x) + square(q.z)) - radius, abs(q.y) - half(g, height));
}

Expr cone(const Local& q, double height, double radius) {
    // In the half plane (ρ, y), ρ = ‖(x, z)‖, the cone is the triangle with base from (0, −H) to
    // (R, −H) and slanted side S from the rim (R, −H) to the apex (0, H), H = height/2. With p
    // the point relative to the rim and e = (−R, 2H) the rim-to-apex vector, their sdCone is
    // max(Φ, Ψ) (docs/guide/formats.md):
    //   Φ = min(L, 0) + sqrt(max(L, 0)² + o²): L the signed distance to the line of S (outward
    //       normal (2H, R)/‖e‖), o how far the projection falls outside S along e;
    //   Ψ = min(−p.y, 0) + sqrt(max(−p.y, 0)² + max(p.x, 0)²): the same for the base.
    // Here L′ = ‖e‖·L, s′ = e·p, o′ = ‖e‖·o, and Φ = (min(L′, 0) + ‖(max(L′, 0), o′)‖)/‖e‖.
    Graph& g = *q.x.graph;
    const Expr rho = sqrt(square(q.x) + square(q.z));
    const Expr px = rho - radius;
    const Expr py = q.y + half(g, height);
    const Expr l = height * px + radius * py;
    const Expr s = height * py - radius * px;
    const Expr e2 = constant(g, radius) * radius + constant(g, height) * height;  // ‖e‖²
    const Expr o = max(max(-s, s - e2), 0.0);
    const Expr phi = (min(l, 0.0) + sqrt(square(max(l, 0.0)) + square(o))) / sqrt(e2);
    const Expr mpy = -py;
    const Expr psi = min(mpy, 0.0) + sqrt(square(max(mpy, 0.0)) + square(max(px, 0.0)));
    return max(phi, psi);
}

Expr blend(Blend mode, double k, const Expr& a, const Expr& b) {
    const Expr bb = mode == Blend::Sub ? -b : b;
    const bool uni = mode == Blend::Union;
    const Expr hard = uni ? min(a, bb) : max(a, bb);
    if (k == 0) return hard;
    const Expr kernel = square(max(k - abs(a - bb), 0.0)) / (4 * k);
    return uni ? hard - kernel : hard + kernel;
}

}  // namespace certray::expr::csg
