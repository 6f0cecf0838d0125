// tests/support/face_cases.h — boxes whose faces lie on octree cell faces, and rays that meet
// them there: the roots of the octree methods' cell boundaries, with the answer mathematics gives.
//
// The scenes have their faces at x, y, z = ±0.75: on cell faces of the default bounds [−2, 2]³ at
// every depth ≥ 4 (cells 4/2^depth wide). Every ray starts outside at |x| = 3 (or |y|, |z|), aims
// at a point of the face with the other two coordinates in [−0.45, 0.45], and enters through it:
// its first root is the t* where that coordinate is ∓0.75, and nowhere before (the ray is outside
// the box until then). t* is rarely a double, so it lies strictly inside a cell's t-segment end
// and the next one's start, a few ulps apart.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "interval/mpfr_interval.h"
#include "solvers/ray.h"

namespace certray::testing {

/// The face scenes: a box, a rounded box (core 0.5, radius 0.25) and a CSG difference (the box
/// minus a sphere of radius 0.9 centred at the origin: the faces' centres are cut away, so only
/// rays through their outer parts are used with it).
inline const std::array<const char*, 3> kFaceScenes{
    "max(max(abs(x), abs(y)), abs(z)) - 0.75",
    "sqrt(max(abs(x) - 0.5, 0)^2 + max(abs(y) - 0.5, 0)^2 + max(abs(z) - 0.5, 0)^2) - 0.25",
    "b = max(max(abs(x), abs(y)), abs(z)) - 0.75\n"
    "s = sqrt(x^2 + y^2 + z^2) - 0.9\n"
    "max(b, -s)"};

struct FaceRay {
    Ray ray;
    int axis = 0;         ///< the coordinate that reaches the face first
    double face = -0.75;  ///< its value there
};

/// `count` rays: head-on (parallel to an axis) and oblique, into the six faces, with scaled
/// directions so that t* is not a double; a fixed sequence (the same rays every run). With
/// `outer`, the aimed points have one of the two other coordinates in ±[0.6, 0.7], outside the
/// CSG scene's sphere (0.75² + 0.6² > 0.9²).
inline std::vector<FaceRay> face_rays(int count, bool outer) {
    std::vector<FaceRay> out;
    std::uint64_t s = 0x9e3779b97f4a7c15ull;
    auto uniform = [&](double lo, double hi) {  // a 53-bit LCG step mapped to [lo, hi]
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        return lo + (hi - lo) * static_cast<double>(s >> 11) * 0x1p-53;
    };
    for (int k = 0; k < count; ++k) {
        FaceRay f;
        f.axis = k % 3;
        const double sign = (k / 3) % 2 ? 1.0 : -1.0;
        f.face = 0.75 * sign;
        const int u = (f.axis + 1) % 3, v = (f.axis + 2) % 3;
        std::array<double, 3> target{};
        target[f.axis] = f.face;
        if (outer) {
            target[u] = uniform(0.6, 0.7) * (uniform(0, 1) < 0.5 ? -1 : 1);
            target[v] = uniform(-0.45, 0.45);
        } else {
            target[u] = uniform(-0.45, 0.45);
            target[v] = uniform(-0.45, 0.45);
        }
        std::array<double, 3> o{};
        o[f.axis] = 3 * sign;  // outside, on the face's side
        const bool head_on = k % 4 == 0;
        o[u] = head_on ? target[u] : uniform(-1.5, 1.5);
        o[v] = head_on ? target[v] : uniform(-1.5, 1.5);
        const double scale = uniform(0.3, 1.9);
        for (int i = 0; i < 3; ++i) f.ray.d[i] = (target[i] - o[i]) * scale;
        if (head_on) f.ray.d[u] = f.ray.d[v] = 0;
        f.ray.o = o;
        f.ray.tmin = 0;
        f.ray.tmax = 20;
        out.push_back(f);
    }
    return out;
}

/// Checks a certified answer on a face ray: a hit (proven, not unknown) whose enclosure holds
/// t* — o[axis] + t_lo·d[axis] is on the outer side of the face or on it, o[axis] + t_hi·d[axis]
/// on the inner side or on it, computed exactly in MPFR (53 × 53 bits and a sum fit in 256) and
/// compared through the outward roundings to doubles (exact, the face being a double) — and is
/// a few ulps wide.
inline void check_face_hit(const FaceRay& f, const RayResult& r, const std::string& what) {
    SCOPED_TRACE(what + ": got " + std::string(name(r.status)) + " [" + std::to_string(r.t_lo) +
                 ", " + std::to_string(r.t_hi) + "]");
    ASSERT_EQ(r.status, Status::Hit);
    auto coord = [&](double t) {
        return MpfrInterval(f.ray.o[f.axis]) + MpfrInterval(t) * MpfrInterval(f.ray.d[f.axis]);
    };
    const MpfrInterval lo = coord(r.t_lo), hi = coord(r.t_hi);
    if (f.face < 0) {
        EXPECT_LE(lo.upper_up(), f.face);
        EXPECT_GE(hi.lower_down(), f.face);
    } else {
        EXPECT_GE(lo.lower_down(), f.face);
        EXPECT_LE(hi.upper_up(), f.face);
    }
    const double ulp = std::nextafter(std::fabs(r.t_hi), INFINITY) - std::fabs(r.t_hi);
    EXPECT_LE(r.t_hi - r.t_lo, 8 * ulp);
}

}  // namespace certray::testing
