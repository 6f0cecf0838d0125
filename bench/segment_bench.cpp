// bench/segment_bench.cpp — segment tracing on the Segment Tracing particle scene: evaluations
// and µs per ray, every answer checked against the certified first root, and the authors' loop on
// the same rays for reference.
//
// Two ray sets on scenes/particles.txt (Galin et al. 2020, 1,000 blobs):
//   peers   — the camera of `certray bench` peers: eye (0, −80, 0) at the origin, fov 35°,
//             100×100 rays from the eye, tmax 200, epsilon 1e-6 (MethodOptions' default);
//   authors — the authors' camera (their main.cpp: horizontal and vertical angle of view
//             2·atan(1.995·25.4/2/35) ≈ 71.8°, 500×500, every `stride`-th pixel), each ray clipped
//             to their bounding box (the union of the blobs' boxes c ± 2.25); a ray missing it
//             costs 0, as in their count; epsilon 1e-3 (their Epsilon()).
// For each set and variant (tracers::segment_presets()): hits / misses / unknowns; evaluations
// per ray as the authors count them (field values g(t): one per step) and all of them (every pass
// over the tape, by kind), overall and for hit and miss rays; µs per ray (thread CPU time, one
// thread, best of `reps`); and the check against solvers::certified_first_root: hits past the
// certified first root, hits with a proven bracket on a certified miss, misses of a certified
// hit (each makes the exit status non-zero), and the largest distance of a hit before the root.
// The authors' loop (their Algorithm with their per-blob bound, rewritten here from the paper and
// the falloff) runs on the same rays for their count. Usage:
//   segment_bench [particles.txt] [stride=5] [reps=3] [variant|all|authors] [check=1]
// and, to sweep knobs, SEG_GROWTH, SEG_GP, SEG_SHRINK, SEG_FLOOR, SEG_NEXT, SEG_TAIL, SEG_SWEEP
// override the SegmentOptions fields growth, growth_partial, shrink, switch_floor, next_factor,
// tail, sweep_pruned_above.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <string>
#include <vector>

#include "apps/bench.h"
#include "expr/load.h"
#include "expr/tape.h"
#include "solvers/certified.h"
#include "tracers/camera.h"
#include "tracers/segment_trace.h"

namespace certray {
namespace {

using Clock = std::chrono::steady_clock;

std::vector<std::array<double, 3>> g_centres;  // the particles (read by authors_rays)
constexpr double kR = 2.25;
tracers::Box3 g_box;  // the authors' box (set by authors_rays)

struct RaySet {
    std::string name;
    std::vector<Ray> rays;  // tmin > tmax marks a ray that misses the box (cost 0)
    double epsilon;
    std::vector<RayResult> certified = {};  // filled on first use
};

RaySet peers_rays() {
    const unsigned side = apps::kSegmentPeerSide;  // the view `certray bench` compares on
    const tracers::CameraFrame frame(apps::segment_peer_camera(), side, side);
    RaySet s{"peers 100x100 fov35 eps1e-6", {}, 1e-6};
    for (unsigned j = 0; j < side; ++j)
        for (unsigned i = 0; i < side; ++i) {
            Ray r = frame.ray(i + 0.5, j + 0.5);
            r.tmax = 200;
            s.rays.push_back(r);
        }
    return s;
}

RaySet authors_rays(const std::string& path, unsigned stride) {
    // Their box: the union of c ± 2.25 over the particles.
    std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    if (FILE* f = std::fopen(path.c_str(), "r")) {
        double c[3];
        g_centres.clear();
        while (std::fscanf(f, "%lf %lf %lf", &c[0], &c[1], &c[2]) == 3) {
            g_centres.push_back({c[0], c[1], c[2]});
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], c[k] - 2.25);
                hi[k] = std::max(hi[k], c[k] + 2.25);
            }
        }
        std::fclose(f);
    }
    const tracers::Box3 box{{{lo[0], hi[0]}, {lo[1], hi[1]}, {lo[2], hi[2]}}};
    g_box = box;
    const int w = 500, h = 500;
    const double avh = 2.0 * std::atan(1.995 * 25.4 * 0.5 / 35.0);
    const double len = std::tan(avh / 2.0);  // vertical = horizontal (square image)
    RaySet s{"authors 500x500/" + std::to_string(stride) + " fov71.8 eps1e-3", {}, 1e-3};
    for (int py = 0; py < h; py += static_cast<int>(stride))
        for (int px = 0; px < w; px += static_cast<int>(stride)) {
            const double x = (px - w / 2.0) / (w / 2.0), y = (h / 2.0 - py) / (h / 2.0);
            Ray r;
            r.o = {0, -80, 0};
            r.d = tracers::normalize({len * x, 1.0, len * y});
            r.tmin = 0;
            r.tmax = std::numeric_limits<double>::infinity();
            if (!tracers::clip_ray(r, box)) r.tmin = 1, r.tmax = 0;
            s.rays.push_back(r);
        }
    return s;
}

// ---- the authors' algorithm, for reference counts only ---------------------------------------
// Their loop (Galin et al. 2020, Algorithm 1 as in their main.cpp): start with the whole box chord
// as the segment, step min(|f|/K(segment), segment) but at least 1e-3, grow the segment by 1.5,
// stop when f < 0 (inside). K(segment) is their hand-derived per-blob bound, written here from the
// falloff: the largest |d/dr (1 − r²/R²)³| over the blob's distance range to the segment, times
// the largest |cos| between the segment and the direction to the centre at its two ends.

double blob_field(const std::array<double, 3>& p) {  // our sign: 0.5 − Σ, < 0 inside
    double s = 0;
    for (const auto& c : g_centres) {
        const double d2 = (p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                          (p[2] - c[2]) * (p[2] - c[2]);
        if (d2 < kR * kR) s += std::pow(1 - d2 / (kR * kR), 3);
    }
    return 0.5 - s;
}

double falloff_slope(double r) {  // |d/dr (1 − r²/R²)³| = 6r/R² (1 − r²/R²)²
    if (r >= kR) return 0;
    const double k = 1 - r * r / (kR * kR);
    return 6 * r / (kR * kR) * k * k;
}

double blob_k(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    std::array<double, 3> ax{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double len = std::sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
    for (double& v : ax) v /= len;
    double k = 0;
    for (const auto& c : g_centres) {
        // Segment box against the blob box.
        bool out = false;
        for (int i = 0; i < 3; ++i)
            out |= std::min(a[i], b[i]) > c[i] + kR || std::max(a[i], b[i]) < c[i] - kR;
        if (out) continue;
        std::array<double, 3> ca{c[0] - a[0], c[1] - a[1], c[2] - a[2]},
            cb{c[0] - b[0], c[1] - b[1], c[2] - b[2]};
        const double na = std::sqrt(ca[0] * ca[0] + ca[1] * ca[1] + ca[2] * ca[2]);
        const double nb = std::sqrt(cb[0] * cb[0] + cb[1] * cb[1] + cb[2] * cb[2]);
        const double l = ca[0] * ax[0] + ca[1] * ax[1] + ca[2] * ax[2];
        double rmin = std::min(na, nb), rmax = std::max(na, nb);
        if (l >= 0 && l <= len) rmin = std::sqrt(std::max(0.0, na * na - l * l));
        double slope = std::max(falloff_slope(rmin), falloff_slope(rmax));
        const double peak = kR / std::sqrt(5.0);
        if (rmin <= peak && peak <= rmax) slope = falloff_slope(peak);
        const double cosa = na > 0 ? std::fabs(l) / na : 1;
        const double lb = cb[0] * ax[0] + cb[1] * ax[1] + cb[2] * ax[2];
        const double cosb = nb > 0 ? std::fabs(lb) / nb : 1;
        k += slope * std::max(cosa, cosb);
    }
    return k;
}

/// The authors' loop on the clipped ray; returns the number of field evaluations.
int authors_trace(const Ray& r, bool& hit, double& t) {
    auto at = [&](double u) {
        return std::array<double, 3>{r.o[0] + u * r.d[0], r.o[1] + u * r.d[1], r.o[2] + u * r.d[2]};
    };
    t = r.tmin;
    double ts = r.tmax - r.tmin;
    int s = 0;
    hit = false;
    while (t < r.tmax) {
        ++s;
        const double f = blob_field(at(t));
        if (f < 0) {
            hit = true;
            return s;
        }
        const double k = blob_k(at(t), at(t + ts));
        const double tk = std::min(std::fabs(f) / k, ts);
        t += std::max(tk, 1e-3);
        ts = tk * 1.5;
    }
    return s;
}

void run_authors(const RaySet& set) {
    double evals = 0;
    std::size_t hits = 0, box = 0;
    double eh = 0, em = 0;
    const auto t0 = Clock::now();
    for (const Ray& r : set.rays) {
        if (r.tmin > r.tmax) continue;
        ++box;
        bool hit;
        double t;
        const int e = authors_trace(r, hit, t);
        evals += e;
        hits += hit;
        (hit ? eh : em) += e;
    }
    const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
    const double n = static_cast<double>(set.rays.size());
    std::printf(
        "%-34s %-9s | hit %5zu of %zu rays (%zu in the box) | field values %5.2f per ray; %.2f "
        "per hit ray, %.2f per miss ray in the box | %7.1f us/ray (their loop in plain C++ over "
        "all blobs, no BVH)\n",
        set.name.c_str(), "authors", hits, set.rays.size(), box, evals / n,
        eh / std::max<double>(1, static_cast<double>(hits)),
        em / std::max<double>(1, static_cast<double>(box - hits)), secs * 1e6 / n);
}

bool g_check = true;  // compare with certified_first_root (slow: the certified solver per ray)

int run(const expr::Tape& tape, RaySet& set, const tracers::SegmentOptions& so, int reps) {
    tracers::TraceOptions o;
    o.epsilon = set.epsilon;
    std::vector<RayResult> res(set.rays.size());
    double best = 1e300;
    for (int rep = 0; rep < reps; ++rep) {
        timespec c0, c1;
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c0);
        for (std::size_t i = 0; i < set.rays.size(); ++i) {
            const Ray& r = set.rays[i];
            if (r.tmin > r.tmax) {  // outside the box: a miss at no cost, as the authors count
                res[i] = RayResult{};
                res[i].status = Status::Miss;
                continue;
            }
            res[i] = tracers::segment_trace(tape, r, o, so);
        }
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c1);
        best = std::min(best, static_cast<double>(c1.tv_sec - c0.tv_sec) +
                                  1e-9 * static_cast<double>(c1.tv_nsec - c0.tv_nsec));
    }
    EvalCounts sum;
    std::size_t hit = 0, miss = 0, unk = 0, bracketed = 0;
    double on_hits = 0, on_misses = 0;
    for (const RayResult& r : res) {
        sum += r.evals;
        hit += r.status == Status::Hit;
        miss += r.status == Status::Miss;
        unk += r.status == Status::Unknown;
        bracketed += r.status == Status::Hit && r.t_hi > r.t_lo;
        (r.status == Status::Hit ? on_hits : on_misses) += static_cast<double>(r.evals.total());
    }
    // Against the certified solver.
    int past = 0, bracket_on_miss = 0, wrong_miss = 0, checked = 0;
    double worst = 0;
    if (g_check && set.certified.empty()) {
        for (const Ray& r : set.rays) {
            set.certified.push_back(r.tmin > r.tmax ? RayResult{}
                                                    : solvers::certified_first_root(tape, r));
        }
    }
    for (std::size_t i = 0; i < res.size() && g_check; ++i) {
        const Ray& r = set.rays[i];
        if (r.tmin > r.tmax) continue;
        ++checked;
        const RayResult& c = set.certified[i];
        const RayResult& x = res[i];
        if (x.status == Status::Hit) {
            if (c.status != Status::Miss && x.t > c.t_hi) ++past;
            if (c.status == Status::Miss && x.t_hi > x.t_lo) ++bracket_on_miss;
            if (c.status == Status::Hit) worst = std::max(worst, c.t_lo - x.t);
        } else if (x.status == Status::Miss && c.status == Status::Hit) {
            ++wrong_miss;
        }
    }
    const double n = static_cast<double>(set.rays.size());
    // Every evaluation of segment_trace computes g at its t (the point part of the jet): the
    // authors' count (field values) is the number of evaluations with a point part, here all.
    std::printf(
        "%-34s %-9s | hit %5zu miss %5zu unknown %zu | field values %5.2f, all evaluations %5.2f "
        "(interval %.2f, gradient %.2f) per ray; %.2f per hit ray, %.2f per miss ray | %7.1f "
        "us/ray\n",
        set.name.c_str(), so.name, hit, miss, unk, static_cast<double>(sum.gradient) / n,
        static_cast<double>(sum.total()) / n, static_cast<double>(sum.interval) / n,
        static_cast<double>(sum.gradient) / n, on_hits / std::max<double>(1, hit),
        on_misses / std::max<double>(1, miss), best * 1e6 / n);
    if (g_check) {
        std::printf(
            "    %zu of the hits with a proven bracket; vs certified on %d rays: past the first "
            "root %d, bracket on a miss %d, missed hits %d; largest t* - t %.2e\n",
            bracketed, checked, past, bracket_on_miss, wrong_miss, worst);
    }
    return past + bracket_on_miss + wrong_miss;
}

}  // namespace
}  // namespace certray

int main(int argc, char** argv) {
    using namespace certray;
    const std::string path = argc > 1 ? argv[1] : CERTRAY_SCENES_DIR "/particles.txt";
    const unsigned stride = argc > 2 ? static_cast<unsigned>(std::atoi(argv[2])) : 5;
    const int reps = argc > 3 ? std::atoi(argv[3]) : 3;
    const std::string which = argc > 4 ? argv[4] : "all";
    g_check = argc > 5 ? std::atoi(argv[5]) != 0 : true;
    const expr::Tape tape(expr::load_graph_file(path));
    RaySet sets[2] = {peers_rays(), authors_rays(path, stride)};
    int bad = 0;
    if (which == "all" || which == "authors") {
        run_authors(sets[1]);
        // The authors' loop on the peers camera's rays, clipped to their box.
        RaySet clipped = sets[0];
        clipped.name = "peers rays clipped to the box";
        for (Ray& r : clipped.rays)
            if (!tracers::clip_ray(r, g_box)) r.tmin = 1, r.tmax = 0;
        run_authors(clipped);
    }
    for (tracers::SegmentOptions so : tracers::segment_presets()) {
        if (which != "all" && which != so.name) continue;
        if (const char* e = std::getenv("SEG_GROWTH")) so.growth = std::atof(e);
        if (const char* e = std::getenv("SEG_GP")) so.growth_partial = std::atof(e);
        if (const char* e = std::getenv("SEG_SHRINK")) so.shrink = std::atof(e);
        if (const char* e = std::getenv("SEG_FLOOR")) so.switch_floor = std::atof(e);
        if (const char* e = std::getenv("SEG_NEXT")) so.next_factor = std::atof(e);
        if (const char* e = std::getenv("SEG_TAIL")) so.tail = std::atof(e);
        if (const char* e = std::getenv("SEG_SWEEP")) so.sweep_pruned_above = std::atol(e);
        for (RaySet& s : sets) bad += run(tape, s, so, reps);
    }
    return bad ? 1 : 0;
}
