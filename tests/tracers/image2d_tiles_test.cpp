// tests/tracers/image2d_tiles_test.cpp — the 2D quadtree's tiling and threads (tracers/image2d.cpp,
// tracers/tile_walker.cpp): every root tile side, thread count and image shape gives the image of
// the brute-force double evaluation, pixel for pixel.
//
// The reference is a plain double evaluation per pixel. The quadtree equals it on random DAGs for
// one thread and one tiling in image2d_test.cpp; here the tiles above the threads' tiles (each
// thread settles its own path from the top, in Z order), several threads writing one image, and
// tile shapes clipped by odd image sizes. Renders reuse pooled walker buffers, so running many
// renders in one process also checks that nothing stale leaks from one render into the next.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "expr/eval.h"
#include "expr/graph.h"
#include "expr/load.h"
#include "expr/tape.h"
#include "tests/support/image2d_reference.h"
#include "tests/support/random_dag.h"
#include "tracers/image2d.h"

namespace certray::tracers {
namespace {

using testing::brute_force_2d;
using testing::kScenesDir;
using testing::without_z;

TEST(Image2dTiles, ProsperoEveryTilingAndThreadCountGivesTheBruteForceImage) {
    const expr::Tape tape(expr::load_graph_file((kScenesDir / "prospero.vm").string()));
    Image2dOptions o;
    o.width = 121;  // odd: clipped tiles on the right and bottom edges
    o.height = 87;
    o.threads = 2;
    const testing::Reference2d reference = brute_force_2d(tape, o);
    for (unsigned root : {8u, 16u, 64u, 256u, 512u}) {
        for (unsigned threads : {1u, 2u, 3u}) {
            o.root_tile = root;
            o.threads = threads;
            const Image2d img = render_2d(tape, o);
            EXPECT_EQ(img.pixels, reference.pixels) << "root " << root << ", threads " << threads;
            EXPECT_EQ(img.inside, reference.inside);
        }
    }
}

TEST(Image2dTiles, ProsperoFullSizeCountOnThreeThreads) {
    // Fidget's reference count at 1024² (also checked on the default options in image2d_test).
    const expr::Tape tape(expr::load_graph_file((kScenesDir / "prospero.vm").string()));
    Image2dOptions o;
    o.threads = 3;
    o.root_tile = 32;
    EXPECT_EQ(render_2d(tape, o).inside, 132816u);
}

TEST(Image2dTiles, OneRowAndOneColumnImages) {
    // Tiles one pixel wide or high: degenerate boxes, so enclosures of x or y are points.
    const expr::Tape tape(expr::load_graph_file((kScenesDir / "prospero.vm").string()));
    for (auto [w, h] : {std::pair{1u, 300u}, std::pair{300u, 1u}, std::pair{1u, 1u}}) {
        Image2dOptions o;
        o.width = w;
        o.height = h;
        o.root_tile = 8;
        o.threads = 2;
        EXPECT_EQ(render_2d(tape, o).pixels, brute_force_2d(tape, o).pixels) << w << "x" << h;
    }
}

RC_GTEST_PROP(Image2dTiles, RandomDagAnyTilingEqualsBruteForce, ()) {
    const expr::Tape tape(without_z(*testing::gen_dag(16), 0.25));
    Image2dOptions o;
    o.width = *rc::gen::inRange(1u, 70u);
    o.height = *rc::gen::inRange(1u, 50u);
    o.root_tile = *rc::gen::element(8u, 16u, 32u);
    o.threads = *rc::gen::element(1u, 2u);
    const double lo = *rc::gen::element(-1.0, -2.0, -0.3, 0.0, -1e6);
    const double hi = *rc::gen::element(1.0, 3.0, 0.7, 1e-3, 1e6);
    o.x = {lo, hi};
    o.y = {lo - 0.5, hi + 0.25};
    const Image2d img = render_2d(tape, o);
    const testing::Reference2d ref = brute_force_2d(tape, o);
    RC_ASSERT(img.pixels == ref.pixels);
    RC_ASSERT(img.inside == ref.inside);
    RC_ASSERT(img.undefined == ref.undefined);
}

}  // namespace
}  // namespace certray::tracers
