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
/// inside and outside. Written max(a, b, min(‖max((a, b), 0)‖, a + b)), the same function (both
/// ≤ 0: a + b ≤ 0 and max(a, b) wins; one > 0: the norm is that one, a + b is below it; both > 0:
/// the norm is below a + b and above a and b), so that inside the norm of (0, 0), whose derivative
/// does not exist, is never the branch taken: the gradient (shading normals) stays finite.
Expr quadrant(const Expr& a, const Expr& b) {
    const Expr norm = sqrt(square(max(a, 0.0)) + square(max(b, 0.0)));
    return max(max(a, b), min(norm, a + b));
}

/// min(a, 0) + ‖(max(a, 0), o)‖ for o ≥ 0, written min(a + o, ‖(max(a, 0), o)‖): the same
/// function (a < 0: the norm is o ≥ a + o; a ≥ 0: the norm is at most a + o), with a finite
/// gradient where a < 0 and o = 0.
Expr half_quadrant(const Expr& a, const Expr& o) {
    return min(a + o, sqrt(square(max(a, 0.0)) + square(o)));
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
    //   Φ = min(L, 0) + ‖(max(L, 0), o)‖: L the signed distance to the line of S (outward normal
    //       (2H, R)/‖e‖), o ≥ 0 how far the projection of p falls outside S along e;
    //   Ψ = quadrant(−p.y, p.x): the distance to {p.y ≥ 0, p.x ≤ 0} (above the base, within the
    //       rim's radius). Inside the triangle p.x ≤ L (the side is nearer horizontally than the
    //       rim), so max(Φ, Ψ) = max(L, −p.y) there, as in their code.
    // Here L′ = ‖e‖·L, s′ = e·p, o′ = ‖e‖·o, and Φ = half_quadrant(L′, o′)/‖e‖.
    Graph& g = *q.x.graph;
    const Expr rho = sqrt(square(q.x) + square(q.z));
    const Expr px = rho - radius;
    const Expr py = q.y + half(g, height);
    const Expr l = height * px + radius * py;
    const Expr s = height * py - radius * px;
    const Expr e2 = constant(g, radius) * radius + constant(g, height) * height;  // ‖e‖²
    const Expr o = max(max(-s, s - e2), 0.0);
    const Expr phi = half_quadrant(l, o) / sqrt(e2);
    const Expr psi = quadrant(-py, px);
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
