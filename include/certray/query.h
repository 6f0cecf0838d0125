// certray/query.h — certray::query: the first surface crossing along many rays, on threads.
//
// Contract (certray/certray.h): results in input order, one per ray, by the named method with
// the knobs given (each validated against the method registry: tracers/methods.h). Threads,
// cancellation and progress as tracers::parallel_for (tracers/parallel.h). Camera-like rays
// for `certified` — at least 256, all from one origin or all along one direction — are answered
// together by the coherent walk (tracers/coherent.h: query_coherent), with the same meaning;
// each ray's evaluations then count its own solves (the shared box evaluations are not split
// among the rays). QueryOptions::coherent = false answers them one by one.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "certray/scene.h"
#include "solvers/ray.h"
#include "tracers/methods.h"

namespace certray {

using tracers::KnobValues;
using tracers::MethodInfo;
using tracers::Surface;

/// How query() answers.
struct QueryOptions {
    std::string method = "certified";  ///< a name of certray::methods()
    /// Knob values by name; a knob the method does not read is an error.
    KnobValues knobs;
    /// The surface answered: Zero (the first f = 0) or Solid (the first entry into f < 0).
    tracers::Surface surface = tracers::Surface::Zero;
    unsigned threads = 0;  ///< worker threads; 0: one per hardware thread
    /// Called with (rays done, rays in all) from the calling thread while the query runs.
    std::function<void(std::size_t, std::size_t)> progress;
    /// When set (by another thread), the query stops early and throws certray::Cancelled.
    const std::atomic<bool>* cancel = nullptr;
    /// Camera-like rays for `certified` answered together by the coherent walk (see above).
    bool coherent = true;
};

/// Thrown by query() when QueryOptions::cancel was set before it finished.
struct Cancelled : std::runtime_error {
    Cancelled() : std::runtime_error("certray: query cancelled") {}
};

/// The registry: every method with whether it is certified, its knobs and its sweep.
const std::vector<MethodInfo>& methods();
/// The registry entry of `name`; throws std::invalid_argument naming the available methods.
const MethodInfo& method_info(std::string_view name);

/// Checks one ray: finite components, tmin ≤ tmax, tmin not NaN (tmax may be +inf). Throws
/// std::invalid_argument naming `index` and the component when it is not.
void check_ray(const Ray& ray, std::size_t index = 0);

/// Answers every ray (see the file contract). Throws std::invalid_argument for a bad ray,
/// method or knob (before any work), and Cancelled when cancelled.
std::vector<RayResult> query(const Scene& scene, std::span<const Ray> rays,
                             const QueryOptions& options = {});

/// Answers one ray (on the calling thread).
RayResult query_one(const Scene& scene, const Ray& ray, const QueryOptions& options = {});

}  // namespace certray
