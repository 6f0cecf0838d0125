// tests/support/image2d_reference.h — the reference the 2D quadtree's tests compare against.
//
// brute_force_2d classifies every pixel by a plain double evaluation of the full tape at its
// centre (tracers/image2d.h's sample points), with no interval, no pruning and no tiling: what
// render_2d must reproduce pixel for pixel. without_z turns a random 3D DAG into a 2D scene.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "expr/eval.h"
#include "expr/graph.h"
#include "expr/tape.h"
#include "tracers/image2d.h"

namespace certray::testing {

/// The repository's scenes/ folder.
inline const std::filesystem::path kScenesDir =
    std::filesystem::path(CERTRAY_TEST_DATA) / "../../scenes";

/// Every pixel of the image `o` describes, classified from the double value of `tape` at its
/// centre, with the counts of inside and undefined pixels.
struct Reference2d {
    std::vector<tracers::Pixel2d> pixels;
    std::uint64_t inside = 0, undefined = 0;
};
inline Reference2d brute_force_2d(const expr::Tape& tape, const tracers::Image2dOptions& o) {
    expr::Evaluator<double> e;
    Reference2d b;
    for (unsigned j = 0; j < o.height; ++j) {
        for (unsigned i = 0; i < o.width; ++i) {
            const tracers::Pixel2d p = tracers::classify(
                e(tape, {tracers::pixel_center_x(o, i), tracers::pixel_center_y(o, j), 0.0}));
            b.pixels.push_back(p);
            b.inside += p == tracers::Pixel2d::Inside;
            b.undefined += p == tracers::Pixel2d::Undefined;
        }
    }
    return b;
}

/// The graph with z replaced by the constant c (random DAGs read all three variables).
inline expr::Graph without_z(const expr::Graph& g, double c) {
    expr::Graph out;
    out.set_output(out.copy(g, g.output(), {out.var(0), out.var(1), out.constant(c)}));
    return out;
}

}  // namespace certray::testing
