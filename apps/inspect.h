// apps/inspect.h — `certray inspect`: what a scene is made of and how much of it each region needs.
#pragma once

#include <array>
#include <ostream>
#include <string>

namespace certray::apps {

struct InspectOptions {
    std::array<double, 2> bounds{-2.0, 2.0};  ///< the cube [lo, hi]³ (square for 2D scenes)
    int levels = 5;                           ///< subdivision levels for the pruning table
};

/// Prints the report for one scene file to `out`. Throws certray::InputError on bad input.
void inspect_scene(const std::string& path, const InspectOptions& options, std::ostream& out);

}  // namespace certray::apps
