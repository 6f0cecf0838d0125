// certray/certray.h — the public interface of certray: certified ray–implicit-surface queries.
//
//   #include <certray/certray.h>
//   const certray::Scene scene = certray::Scene::parse("sqrt(x^2 + y^2 + z^2) - 1");
//   const std::vector<certray::Ray> rays = {{{0, 0, -3}, {0, 0, 1}, 0, 10}};
//   const std::vector<certray::RayResult> hits = certray::query(scene, rays, {});
//   // hits[0]: Status::Hit with 2 ∈ [t_lo, t_hi], proven (certray::method_info("certified")).
//
// Contract: a certified method's Hit [t_lo, t_hi] holds a zero of g(t) = f(o + t·d) and none in
// [tmin, t_lo); its Miss means no zero in [tmin, tmax]; otherwise Unknown (docs/guide/
// semantics.md). Approximate methods use the same types; MethodInfo::certified says which is which.
// The answers are the same whatever the caller's floating-point environment (rounding direction,
// flush-to-zero, denormals-are-zero): the library sets what it needs and restores the caller's.
// Bad input (a malformed scene, a NaN or infinite ray, tmin > tmax, an unknown method or knob)
// throws certray::InputError or std::invalid_argument with a message naming what and where.
#pragma once

#if defined(__FAST_MATH__)
#error \
    "certray: this translation unit is compiled with -ffast-math (or -Ofast), which breaks the directed rounding every certified answer depends on; compile it without"
#endif

#include "certray/query.h"
#include "certray/render.h"
#include "certray/scene.h"
#include "certray/version.h"
