// tracers/render.cpp — the 3D tile loop and the AOV colourings (see render.h).
#include "tracers/render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <new>
#include <optional>
#include <thread>

#ifdef __linux__
#include <sys/mman.h>
#endif

#include "expr/derived.h"
#include "tracers/cone.h"
#include "tracers/parallel.h"
#include "tracers/region_tapes.h"

namespace certray::tracers {

void* allocate_pixels(std::size_t bytes) {
    constexpr std::size_t kHuge = std::size_t{2} << 20;
    if (bytes >= kHuge) {
        const std::size_t size = (bytes + kHuge - 1) / kHuge * kHuge;
        void* p = std::aligned_alloc(kHuge, size);
        if (p == nullptr) throw std::bad_alloc();
#ifdef __linux__
        madvise(p, size, MADV_HUGEPAGE);  // a hint: where huge pages are off, nothing changes
#endif
        return p;
    }
    void* p = std::malloc(std::max<std::size_t>(bytes, 1));
    if (p == nullptr) throw std::bad_alloc();
    return p;
}

void free_pixels(void* p) { std::free(p); }

namespace {

constexpr unsigned kTile = 16;

std::uint8_t to_byte(double v) {
    if (!(v > 0)) return 0;
    if (v >= 1) return 255;
    return static_cast<std::uint8_t>(v * 255.0 + 0.5);  // rounded half up, without a libm call
}

void put(RgbImage& img, unsigned i, unsigned j, double r, double g, double b) {
    img.set(i, j, to_byte(r), to_byte(g), to_byte(b));
}

/// A perceptual-ish ramp (dark blue → teal → yellow → red) for t in [0, 1].
void ramp(double t, double& r, double& g, double& b) {
    static constexpr double kStops[5][3] = {{0.05, 0.03, 0.30},
                                            {0.10, 0.45, 0.60},
                                            {0.35, 0.75, 0.35},
                                            {0.98, 0.85, 0.20},
                                            {0.85, 0.10, 0.10}};
    t = std::clamp(t, 0.0, 1.0) * 4;
    const int k = std::min(3, static_cast<int>(t));
    const double f = t - k;
    r = kStops[k][0] + f * (kStops[k + 1][0] - kStops[k][0]);
    g = kStops[k][1] + f * (kStops[k + 1][1] - kStops[k][1]);
    b = kStops[k][2] + f * (kStops[k + 1][2] - kStops[k][2]);
}

void background(unsigned j, unsigned height, double& r, double& g, double& b) {
    const double s = height > 1 ? static_cast<double>(j) / (height - 1) : 0.0;
    r = 0.62 - 0.35 * s;
    g = 0.70 - 0.35 * s;
    b = 0.82 - 0.30 * s;
}

}  // namespace

bool parse_aov(std::string_view name, Aov& aov) {
    static constexpr std::pair<std::string_view, Aov> kNames[] = {{"shade", Aov::Shade},
                                                                  {"depth", Aov::Depth},
                                                                  {"steps", Aov::Steps},
                                                                  {"normal", Aov::Normal},
                                                                  {"status", Aov::Status}};
    for (const auto& [n, a] : kNames) {
        if (n == name) {
            aov = a;
            return true;
        }
    }
    return false;
}

namespace {

/// The colour bar of a depth or steps image, bottom right: its left end is the least value (depth:
/// the nearest hit, bright; steps: 0 evaluations) and its right end the greatest, in the image's
/// own ramp, inside a dark frame. Images smaller than 32×24 get none.
void draw_legend(RgbImage& img, Aov aov) {
    if (img.width < 32 || img.height < 24) return;
    const unsigned w = std::max(16u, img.width / 4), h = std::max(4u, img.height / 24);
    const unsigned i0 = img.width - w - 4, j0 = img.height - h - 4;
    for (unsigned j = j0 - 1; j <= j0 + h; ++j) {
        for (unsigned i = i0 - 1; i <= i0 + w; ++i) {
            double r = 0.1, g = 0.1, b = 0.1;  // the frame
            if (j >= j0 && j < j0 + h && i >= i0 && i < i0 + w) {
                const double f = (i - i0) / static_cast<double>(w - 1);
                if (aov == Aov::Depth) {
                    r = g = b = 1.0 - 0.85 * f;
                } else {
                    ramp(f, r, g, b);
                }
            }
            put(img, i, j, r, g, b);
        }
    }
}

}  // namespace

bool aov_is_local(Aov aov) { return aov != Aov::Depth && aov != Aov::Steps; }

AovScale aov_scale(const PixelAnswers& ans, Aov aov, const Vec3& light) {
    AovScale sc;
    sc.light = normalize(light);
    for (std::size_t k = 0; k < ans.status.size() && !aov_is_local(aov); ++k) {
        if (ans.status[k] == Status::Hit) {  // the ranges the depth and steps ramps need
            sc.tmin = std::min(sc.tmin, ans.t[k]);
            sc.tmax = std::max(sc.tmax, ans.t[k]);
        }
        sc.emax = std::max(sc.emax, ans.evals[k]);
    }
    sc.log_emax = std::log1p(static_cast<double>(sc.emax));
    return sc;
}

void colorize_span(const PixelAnswers& ans, Aov aov, const AovScale& sc, unsigned j, unsigned i0,
                   unsigned i1, RgbImage& img, unsigned x0, unsigned y0) {
    const Vec3& l = sc.light;
    if (aov == Aov::Shade) {  // the common case: a miss's colour is its row's, in bytes once
        double r, g, b;
        background(y0 + j, img.height, r, g, b);
        const std::uint8_t sky[3] = {to_byte(r), to_byte(g), to_byte(b)};
        for (unsigned i = i0; i < i1; ++i) {
            const std::size_t k = std::size_t{j} * ans.width + i;
            const Status s = ans.status[k];
            if (s == Status::Miss) {
                img.set(x0 + i, y0 + j, sky[0], sky[1], sky[2]);
            } else if (s == Status::Hit) {
                const auto& n = ans.normal[k];
                const double lambert = std::max(0.0, n[0] * l[0] + n[1] * l[1] + n[2] * l[2]);
                const double c = 0.18 + 0.82 * lambert;
                put(img, x0 + i, y0 + j, 0.92 * c, 0.86 * c, 0.74 * c);
            } else {
                img.set(x0 + i, y0 + j, 255, 0, 255);
            }
        }
        return;
    }
    for (unsigned i = i0; i < i1; ++i) {
        const std::size_t k = std::size_t{j} * ans.width + i;
        const Status s = ans.status[k];
        const auto& n = ans.normal[k];
        double r = 0, g = 0, b = 0;
        switch (aov) {
            case Aov::Shade:  // above
                break;
            case Aov::Depth:
                if (s == Status::Hit) {
                    const double d =
                        sc.tmax > sc.tmin ? (ans.t[k] - sc.tmin) / (sc.tmax - sc.tmin) : 0.0;
                    r = g = b = 1.0 - 0.85 * d;
                } else if (s == Status::Unknown) {
                    r = 1, g = 0, b = 1;
                }
                break;
            case Aov::Steps:
                ramp(sc.log_emax > 0 ? std::log1p(static_cast<double>(ans.evals[k])) / sc.log_emax
                                     : 0.0,
                     r, g, b);
                break;
            case Aov::Normal:
                if (s == Status::Hit) {
                    r = 0.5 * (n[0] + 1), g = 0.5 * (n[1] + 1), b = 0.5 * (n[2] + 1);
                } else if (s == Status::Unknown) {
                    r = 1, g = 0, b = 1;
                }
                break;
            case Aov::Status:
                if (s == Status::Hit) {
                    r = g = b = 1;
                } else if (s == Status::Miss) {
                    r = 0.05, g = 0.08, b = 0.35;
                } else {
                    r = 1, g = 0, b = 1;
                }
                break;
        }
        put(img, x0 + i, y0 + j, r, g, b);
    }
}

RgbImage colorize(const PixelAnswers& ans, Aov aov, const Vec3& light, unsigned threads) {
    RgbImage img(ans.width, ans.height, boost::container::default_init);  // every pixel written
    const AovScale sc = aov_scale(ans, aov, light);
    // A block of rows to each worker: each pixel's colour is its own (a 512² image: 3.4 ms on one
    // thread, after a render whose walk is threaded), and each worker writes its own pages.
    const unsigned workers = std::min(worker_count(threads), std::max(1u, ans.height / 32));
    run_workers(workers, [&](unsigned w) {
        const unsigned j0 = static_cast<unsigned>(std::uint64_t{ans.height} * w / workers);
        const unsigned j1 = static_cast<unsigned>(std::uint64_t{ans.height} * (w + 1) / workers);
        for (unsigned j = j0; j < j1; ++j) colorize_span(ans, aov, sc, j, 0, ans.width, img);
    });
    if (!aov_is_local(aov)) draw_legend(img, aov);
    return img;
}

AovRange aov_range(const PixelAnswers& ans, Aov aov) {
    AovRange r;
    for (std::size_t k = 0; k < ans.status.size(); ++k) {
        const double v = aov == Aov::Depth ? (ans.status[k] == Status::Hit ? ans.t[k] : NAN)
                                           : static_cast<double>(ans.evals[k]);
        if (std::isnan(v)) continue;
        r.lo = std::min(r.lo, v);
        r.hi = std::max(r.hi, v);
    }
    return r;
}

RenderResult render_3d(const expr::Tape& tape, const RayFunction& method,
                       const RenderOptions& options) {
    const CameraFrame frame(options.camera, options.width, options.height);
    const auto start = std::chrono::steady_clock::now();
    RenderResult result;
    PixelAnswers& ans = result.answers;
    ans.width = options.width;
    ans.height = options.height;
    const std::size_t pixels = std::size_t{ans.width} * ans.height;
    ans.status.assign(pixels, Status::Miss);
    ans.t.assign(pixels, std::numeric_limits<double>::quiet_NaN());
    ans.evals.assign(pixels, 0);
    ans.normal.assign(pixels, {0.f, 0.f, 0.f});

    const unsigned tiles_x = (ans.width + kTile - 1) / kTile;
    const unsigned tiles_y = (ans.height + kTile - 1) / kTile;
    const std::size_t tiles = std::size_t{tiles_x} * tiles_y;
    const unsigned workers = static_cast<unsigned>(
        std::clamp<std::size_t>(worker_count(options.threads), 1, std::max<std::size_t>(tiles, 1)));
    std::vector<EvalCounts> sums(workers);
    if (options.progress) options.progress->total.store(tiles, std::memory_order_relaxed);
    // The normals on region-pruned tapes (the same function at each point; a tenth of the time
    // of the full tape of Fidget's or the particles' models): the march's, or built on demand.
    std::optional<RegionTapes> own;
    const RegionTapes* regions = options.cone ? &options.cone->regions() : nullptr;
    if (!regions) {
        RegionOptions ro;
        ro.eager_depth = 0;
        own.emplace(tape,
                    std::array<Interval, 3>{Interval(options.bounds[0][0], options.bounds[0][1]),
                                            Interval(options.bounds[1][0], options.bounds[1][1]),
                                            Interval(options.bounds[2][0], options.bounds[2][1])},
                    ro);
        regions = &*own;
    }
    ParallelOptions po;
    po.threads = workers;
    po.chunk = 1;
    parallel_for(tiles, po, [&](std::size_t t, std::size_t, unsigned worker) {
        EvalCounts& sum = sums[worker];
        const unsigned i0 = static_cast<unsigned>(t % tiles_x) * kTile;
        const unsigned j0 = static_cast<unsigned>(t / tiles_x) * kTile;
        const unsigned i1 = std::min(ans.width, i0 + kTile);
        const unsigned j1 = std::min(ans.height, j0 + kTile);
        thread_local ConeTile tile;
        tile.width = i1 - i0;
        tile.height = j1 - j0;
        tile.rays.resize(std::size_t{tile.width} * tile.height);
        tile.state.resize(tile.rays.size());
        tile.share.assign(tile.rays.size(), 0.0);
        for (unsigned j = j0; j < j1; ++j) {
            for (unsigned i = i0; i < i1; ++i) {
                const std::size_t q = std::size_t{j - j0} * tile.width + (i - i0);
                tile.rays[q] = frame.ray(i + 0.5, j + 0.5);
                tile.state[q] =
                    clip_ray(tile.rays[q], options.bounds) ? ConeTile::Active : ConeTile::Outside;
            }
        }
        if (options.cone) sum += options.cone->march(tile);
        for (unsigned j = j0; j < j1; ++j) {
            for (unsigned i = i0; i < i1; ++i) {
                const std::size_t k = std::size_t{j} * ans.width + i;
                const std::size_t q = std::size_t{j - j0} * tile.width + (i - i0);
                const auto shared = static_cast<std::uint64_t>(std::llround(tile.share[q]));
                if (tile.state[q] != ConeTile::Active) {  // a Miss: outside, or proven free
                    ans.evals[k] = shared;
                    continue;
                }
                const Ray& ray = tile.rays[q];
                const RayResult r = method(ray);
                sum += r.evals;
                ans.status[k] = r.status;
                ans.evals[k] = r.evals.total() + shared;
                if (r.status == Status::Miss) continue;
                ans.t[k] = r.t;
                if (r.status != Status::Hit) continue;
                const Vec3 p{ray.o[0] + r.t * ray.d[0], ray.o[1] + r.t * ray.d[1],
                             ray.o[2] + r.t * ray.d[2]};
                const Dual<double, 3> g = expr::gradient(regions->at(p), p);
                Vec3 n = normalize({g.v[0], g.v[1], g.v[2]});
                if (dot(n, ray.d) > 0) n = {-n[0], -n[1], -n[2]};
                ans.normal[k] = {static_cast<float>(n[0]), static_cast<float>(n[1]),
                                 static_cast<float>(n[2])};
            }
        }
        if (options.progress) options.progress->done.fetch_add(1, std::memory_order_relaxed);
    });

    RenderStats& st = result.stats;
    for (const EvalCounts& s : sums) st.evals += s;
    for (std::size_t k = 0; k < pixels; ++k) st.count_pixel(ans.status[k], ans.evals[k]);
    result.image = colorize(ans, options.aov, options.light, options.threads);
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace certray::tracers
