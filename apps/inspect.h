// apps/inspect.h — `certray inspect`: what a scene is made of and how much of it each region needs.
#pragma once

#include <array>
#include <optional>
#include <ostream>
#include <string>

namespace certray::apps {

struct InspectOptions {
    /// {lo, hi}: the cube [lo, hi]³ (the square [lo, hi]² for 2D scenes); unset: [−2, 2]³ for a 3D
    /// scene, [−1, 1]² for a 2D one (as `certray render`).
    std::optional<std::array<double, 2>> bounds;
    int levels = 5;  ///< subdivision levels for the pruning table
};

/// Prints the report for one scene file to `out`. Throws certray::InputError on bad input.
void inspect_scene(const std::string& path, const InspectOptions& options, std::ostream& out);

}  // namespace certray::apps
