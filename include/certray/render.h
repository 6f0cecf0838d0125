// certray/render.h — certray::render: a 3D image of a Scene, one ray per pixel by any method.
//
// Contract: tracers/render.h (pixel rays, AOVs, statistics). The camera is auto-framed on the
// part of the bounds where the surface may be (interval subdivision) unless one is given; the
// bounds are the given box, else the scene's own (a CSG tree's aabb), else [-2, 2]³. The method
// gets the bounds as its `bounds` knob when it reads one. The image stays in memory: writing it
// (PNG, tracers/png_io.h) is the caller's choice.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "certray/query.h"
#include "certray/scene.h"
#include "tracers/camera.h"
#include "tracers/coherent.h"
#include "tracers/render.h"

namespace certray {

struct RenderSettings {
    unsigned width = 640;
    unsigned height = 480;
    std::string method = "certified";     ///< a name of certray::methods()
    KnobValues knobs;                     ///< the method's knobs (its bounds come from `bounds`)
    std::optional<tracers::Box3> bounds;  ///< per axis [lo, hi]
    /// The surface shown; unset: the scene's default_surface() (solid for .vm and CSG trees).
    std::optional<tracers::Surface> surface;
    /// An orthographic heightmap (one ray per pixel along −z over the bounds' x–y rectangle, from
    /// z = hi down to z = lo) instead of the pinhole camera; drawn by the coherent renderer.
    bool ortho = false;
    /// The certified method (zero or solid surface) is drawn by the coherent renderer
    /// (tracers/coherent.h: rays sharing interval work, each pixel keeping its certified
    /// meaning), and the Lipschitz tracers (MethodInfo::cone: sphere, enhanced, segment, bvh,
    /// octree) start their rays where a cone march of their tile proved them free
    /// (tracers/cone.h); false: one independent ray per pixel from the camera, for every method.
    bool coherent = true;
    /// Coherent certified images: a pixel's hit enclosure may stop narrowing once it is this many
    /// pixel footprints deep (tracers::CoherentOptions::depth_pixels; faster). 0: depths to 10⁻⁶
    /// relative, what a program reading the answers' t wants. The CLI uses 0.5 for an image
    /// written without --data.
    double depth_pixels = 0;
    std::optional<tracers::Camera> camera;               ///< unset: auto-framed
    double fov_degrees = tracers::Camera{}.fov_degrees;  ///< of the auto-framed camera
    tracers::Aov aov = tracers::Aov::Shade;
    tracers::Vec3 light{-0.4, -0.9, 1.2};
    unsigned threads = 0;                       ///< 0: one per hardware thread
    tracers::WorkProgress* progress = nullptr;  ///< advanced tile by tile when set
    /// Keep every pixel's answer in RenderResult::answers; false: the image and the totals alone,
    /// faster for the certified image of a local AOV (shade, normal, status), whose answers are
    /// then left empty (tracers::RenderOptions::answers).
    bool answers = true;
};

/// The bounds box render() uses for `settings` on `scene`.
tracers::Box3 render_bounds(const Scene& scene, const RenderSettings& settings);

/// A camera that sees the surface of `scene` inside `bounds` whole, from (1, -2, 0.8). The
/// subdivision that finds the surface runs on `threads` workers (0: one per hardware thread); the
/// camera is the same with any.
tracers::Camera auto_frame(const Scene& scene, const tracers::Box3& bounds, double fov_degrees,
                           double aspect, unsigned threads = 0);

/// True when the surface may reach a face of `bounds` (a cell of the interval subdivision that may
/// hold it lies on the face): the picture may show it clipped. `threads` as auto_frame's.
bool surface_reaches_bounds(const Scene& scene, const tracers::Box3& bounds, unsigned threads = 0);

/// Renders `scene` (see the file contract). Throws std::invalid_argument for a 2D scene, an empty
/// size, an unknown method or knob, or a method that does not apply to the scene.
tracers::RenderResult render(const Scene& scene, const RenderSettings& settings);

}  // namespace certray
