// tracers/coherent.cpp — coherent certified images: the pixels' rays, the root tiles shared out
// to the Walkers of tracers/coherent_walker.h, and camera-like ray bundles (see coherent.h;
// docs/theory/coherent.md).
#include "tracers/coherent.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <boost/container/vector.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <optional>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include "interval/interval.h"
#include "tracers/coherent_walker.h"
#include "tracers/parallel.h"

namespace certray::tracers {

using detail::coherent::kInf;
using detail::coherent::Rect;
using detail::coherent::Walker;

PixelRays::PixelRays(const CoherentOptions& options)
    : projection_(options.projection), bounds_(options.render.bounds) {
    const RenderOptions& r = options.render;
    if (r.width == 0 || r.height == 0) throw std::invalid_argument("render: empty image size");
    NearestScope env;
    if (projection_ == Projection::List) {
        throw std::invalid_argument("render: a ray list needs its rays (bundle_rays)");
    }
    if (projection_ == Projection::Pinhole) {
        angular_ = true;
        frame_.emplace(r.camera, r.width, r.height);
        pitch_ = std::tan(r.camera.fov_degrees * (M_PI / 360.0)) / (0.5 * r.height);
        return;
    }
    for (int c = 0; c < 3; ++c) {
        if (!(std::isfinite(bounds_[c][0]) && std::isfinite(bounds_[c][1]) &&
              bounds_[c][0] < bounds_[c][1])) {
            throw std::invalid_argument("ortho camera: the bounds must be finite with lo < hi");
        }
    }
    dx_ = (bounds_[0][1] - bounds_[0][0]) / r.width;
    dy_ = (bounds_[1][1] - bounds_[1][0]) / r.height;
    // One ulp up covers the rounding of the difference: o + tmax·d reaches z0.
    tmax_ = std::nextafter(bounds_[2][1] - bounds_[2][0], kInf);
    pitch_ = std::max(dx_, dy_);
}

PixelRays::PixelRays(std::span<const Ray> rays, unsigned width, unsigned height,
                     std::vector<std::uint32_t> cells, double pitch, bool angular)
    : projection_(Projection::List),
      angular_(angular),
      list_(rays),
      cells_(std::move(cells)),
      width_(width),
      pitch_(pitch) {
    if (width == 0 || height == 0 || cells_.size() != std::size_t{width} * height) {
        throw std::invalid_argument("ray bundle: the grid does not match its size");
    }
}

bool PixelRays::ray(unsigned i, unsigned j, Ray& ray) const {
    if (projection_ == Projection::List) return ray_in_scope(i, j, ray);
    NearestScope env;
    return ray_in_scope(i, j, ray);
}

bool PixelRays::ray_in_scope(unsigned i, unsigned j, Ray& ray) const {
    if (projection_ == Projection::List) {
        const std::uint32_t k = cells_[std::size_t{j} * width_ + i];
        if (k == kNoRay) return false;
        ray = list_[k];
        return true;
    }
    if (projection_ == Projection::Pinhole) {
        ray = frame_->ray(i + 0.5, j + 0.5);
        return clip_ray(ray, bounds_);
    }
    ray.o = {bounds_[0][0] + (i + 0.5) * dx_, bounds_[1][1] - (j + 0.5) * dy_, bounds_[2][1]};
    ray.d = {0, 0, -1};
    ray.tmin = 0;
    ray.tmax = tmax_;
    return true;
}

void PixelRays::row_in_scope(unsigned i0, unsigned j, unsigned n, Ray* rays, bool* in) const {
    if (projection_ == Projection::Pinhole) {
        frame_->clipped_row(i0, j, n, bounds_, rays, in);
        return;
    }
    for (unsigned k = 0; k < n; ++k) in[k] = ray_in_scope(i0 + k, j, rays[k]);
}

RenderResult render_3d_coherent(const expr::Tape& tape, const CoherentOptions& options,
                                CoherentStats* stats, std::vector<RayResult>* results) {
    return render_3d_coherent(tape, options, PixelRays(options), stats, results);
}

RenderResult render_3d_coherent(const expr::Tape& tape, const CoherentOptions& options,
                                const PixelRays& rays, CoherentStats* stats,
                                std::vector<RayResult>* results) {
    if (options.render.width == 0 || options.render.height == 0) {
        throw std::invalid_argument("render: empty image size");
    }
    if (options.root_tile == 0) throw std::invalid_argument("render: root tile side must be >= 1");
    const auto start = std::chrono::steady_clock::now();
    RenderResult result;
    PixelAnswers& ans = result.answers;
    ans.width = options.render.width;
    ans.height = options.render.height;
    const std::size_t pixels = std::size_t{ans.width} * ans.height;
    const Aov aov = options.render.aov;
    const bool colour_tiles = aov_is_local(aov);
    // Unwritten here: each root tile's worker writes its pixels' defaults (Walker::tile), so the
    // pages are first touched in the workers (a 512² image's 7.6 MB: 2.5 ms on one thread). Not
    // at all where the caller wants the image alone and each tile is coloured from its own.
    const bool keep = options.render.answers || !colour_tiles;
    if (keep) {
        ans.status.resize(pixels, boost::container::default_init);
        ans.t.resize(pixels, boost::container::default_init);
        ans.evals.resize(pixels, boost::container::default_init);
        ans.normal.resize(pixels, boost::container::default_init);
    }
    if (results != nullptr) {
        RayResult miss;
        miss.status = Status::Miss;
        results->assign(pixels, miss);
    }

    const unsigned side = options.root_tile;
    const unsigned tiles_x = (ans.width + side - 1) / side;
    const unsigned tiles_y = (ans.height + side - 1) / side;
    const std::size_t tiles = std::size_t{tiles_x} * tiles_y;
    const unsigned workers = static_cast<unsigned>(std::clamp<std::size_t>(
        options.render.threads > 0 ? options.render.threads : std::thread::hardware_concurrency(),
        1, std::max<std::size_t>(tiles, 1)));
    std::atomic<std::size_t> next{0};
    std::vector<CoherentStats> walk_stats(workers);
    std::vector<EvalCounts> sums(workers);
    std::vector<RenderStats> counts(workers);
    // A pixel's colour in a local AOV is its own answer's: each worker colours its tiles as it
    // answers them (while they are in its cache) instead of a pass over the image afterwards.
    // (For a local AOV the scale is the light alone: the answers, not written yet, are not read.)
    const AovScale scale = colour_tiles ? aov_scale(ans, aov, options.render.light) : AovScale{};
    if (colour_tiles)
        result.image = RgbImage(ans.width, ans.height, boost::container::default_init);
    // The tile's pixels counted (by the walker: `counted`) and coloured once the walk has
    // answered them, from the image's answers or the tile's own (`mine`). A tile answered without
    // its rays (every pixel a Miss with no evaluation, so each row's colour is its first pixel's):
    // its rows filled with that colour.
    const auto finish = [&](const Rect& r, RenderStats& c, bool empty, const RenderStats& counted,
                            const PixelAnswers& mine) {
        c.count_pixels(counted);
        if (!colour_tiles) return;
        const auto span = [&](unsigned j, unsigned i0, unsigned i1) {
            if (keep) {
                colorize_span(ans, aov, scale, j, i0, i1, result.image);
            } else {
                colorize_span(mine, aov, scale, j - r.j0, i0 - r.i0, i1 - r.i0, result.image, r.i0,
                              r.j0);
            }
        };
        if (empty) {
            for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
                span(j, r.i0, r.i0 + 1);
                const std::uint8_t* first = result.image.at(r.i0, j);
                for (unsigned i = r.i0 + 1; i < r.i0 + r.w; ++i) {
                    result.image.set(i, j, first[0], first[1], first[2]);
                }
            }
            return;
        }
        for (unsigned j = r.j0; j < r.j0 + r.h; ++j) span(j, r.i0, r.i0 + r.w);
    };
    WorkProgress* progress = options.render.progress;
    if (progress) progress->total.store(tiles, std::memory_order_relaxed);

    // One worker per thread (the library's one way of threads, tracers/parallel.h), each with its
    // walker; root tiles are taken in order.
    run_workers(workers, [&](unsigned w) {
        try {
            Walker walker(tape, options, rays, ans, results);
            for (;;) {
                const std::size_t t = next.fetch_add(1, std::memory_order_relaxed);
                if (t >= tiles) break;
                const unsigned i0 = static_cast<unsigned>(t % tiles_x) * side;
                const unsigned j0 = static_cast<unsigned>(t / tiles_x) * side;
                const Rect r{i0, j0, std::min(side, ans.width - i0),
                             std::min(side, ans.height - j0)};
                const bool empty = walker.tile(r);
                finish(r, counts[w], empty, walker.tile_counts, walker.tile_answers());
                if (progress) progress->done.fetch_add(1, std::memory_order_relaxed);
            }
            walk_stats[w] = walker.stats;
            sums[w] = walker.evals;
        } catch (...) {
            next.store(tiles);  // the others stop at their next tile
            throw;
        }
    });

    RenderStats& st = result.stats;
    CoherentStats total;
    total.tape_length = tape.size();
    for (unsigned w = 0; w < workers; ++w) {
        st.evals += sums[w];
        st.count_pixels(counts[w]);
        const CoherentStats& s = walk_stats[w];
        total.box_evals += s.box_evals;
        total.box_instructions += s.box_instructions;
        total.boxes_excluded += s.boxes_excluded;
        total.boxes_inside += s.boxes_inside;
        total.leaf_solves += s.leaf_solves;
        total.scans += s.scans;
        total.together += s.together;
        total.fallbacks += s.fallbacks;
        total.splits += s.splits;
        total.prunes += s.prunes;
        total.lane_forms += s.lane_forms;
        total.tile_pieces += s.tile_pieces;
        total.tile_decided += s.tile_decided;
        total.quarter_pieces += s.quarter_pieces;
        total.wide_forms += s.wide_forms;
        total.segment_forms += s.segment_forms;
        total.coarse_deferred += s.coarse_deferred;
        total.monotone_segments += s.monotone_segments;
        total.newton_brackets += s.newton_brackets;
        total.merged_scans += s.merged_scans;
        total.second_order += s.second_order;
        total.folds += s.folds;
        total.folded_instructions += s.folded_instructions;
        total.folded_scans += s.folded_scans;
        total.clipped += s.clipped;
        total.empty_tiles += s.empty_tiles;
    }
    if (stats != nullptr) *stats = total;
    if (!colour_tiles) {
        result.image = colorize(ans, aov, options.render.light, options.render.threads);
    }
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

std::optional<PixelRays> bundle_rays(std::span<const Ray> rays, std::size_t min_rays) {
    const std::size_t n = rays.size();
    if (n == 0 || n < min_rays || n >= PixelRays::kNoRay) return std::nullopt;
    NearestScope env;
    auto same = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
        return std::bit_cast<std::array<std::uint64_t, 3>>(a) ==
               std::bit_cast<std::array<std::uint64_t, 3>>(b);
    };
    bool one_origin = true, one_direction = true;
    for (const Ray& r : rays) {
        one_origin = one_origin && same(r.o, rays[0].o);
        one_direction = one_direction && same(r.d, rays[0].d);
        if (r.d[0] == 0 && r.d[1] == 0 && r.d[2] == 0) return std::nullopt;
    }
    if (!one_origin && !one_direction) return std::nullopt;
    // The bundle's axis e0 (the mean unit direction, or the one direction) and two axes across.
    Vec3 e0{0, 0, 0};
    for (const Ray& r : rays) {
        const Vec3 w = normalize({r.d[0], r.d[1], r.d[2]});
        for (int c = 0; c < 3; ++c) e0[c] += w[c];
        if (one_direction) break;
    }
    e0 = normalize(e0);
    if (!(std::isfinite(e0[0]) && std::isfinite(e0[1]) && std::isfinite(e0[2]))) {
        return std::nullopt;
    }
    const Vec3 helper = std::fabs(e0[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const Vec3 e1 = normalize(cross(e0, helper));
    const Vec3 e2 = cross(e0, e1);
    // Each ray's place across the bundle: its direction's projection onto the plane at unit
    // distance along e0 (one origin, within a cone around e0), or its origin's (one direction).
    std::vector<std::array<double, 2>> uv(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Ray& r = rays[k];
        if (one_origin) {
            const Vec3 w = normalize({r.d[0], r.d[1], r.d[2]});
            const double along = dot(w, e0);
            if (!(along > 0.2)) return std::nullopt;  // wider than a camera: one by one
            uv[k] = {dot(w, e1) / along, dot(w, e2) / along};
        } else {
            const Vec3 o{r.o[0], r.o[1], r.o[2]};
            uv[k] = {dot(o, e1), dot(o, e2)};
        }
    }
    const auto width = static_cast<unsigned>(std::ceil(std::sqrt(static_cast<double>(n))));
    const auto height = static_cast<unsigned>((n + width - 1) / width);
    std::vector<std::uint32_t> order(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = static_cast<std::uint32_t>(k);
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return uv[a][1] < uv[b][1]; });
    std::vector<std::uint32_t> cells(std::size_t{width} * height, PixelRays::kNoRay);
    for (std::size_t row = 0; row * width < n; ++row) {
        const auto first = order.begin() + static_cast<std::ptrdiff_t>(row * width);
        const auto last =
            order.begin() + static_cast<std::ptrdiff_t>(std::min(n, (row + 1) * width));
        std::sort(first, last,
                  [&](std::uint32_t a, std::uint32_t b) { return uv[a][0] < uv[b][0]; });
        std::copy(first, last, cells.begin() + static_cast<std::ptrdiff_t>(row * width));
    }
    double u0 = kInf, u1 = -kInf, v0 = kInf, v1 = -kInf;
    for (const auto& p : uv) {
        u0 = std::min(u0, p[0]);
        u1 = std::max(u1, p[0]);
        v0 = std::min(v0, p[1]);
        v1 = std::max(v1, p[1]);
    }
    const double pitch = std::max((u1 - u0) / width, (v1 - v0) / height);
    return PixelRays(rays, width, height, std::move(cells), pitch, one_origin);
}

std::optional<std::vector<RayResult>> query_coherent(const expr::Tape& tape,
                                                     std::span<const Ray> rays,
                                                     const CoherentOptions& options,
                                                     CoherentStats* stats) {
    std::optional<PixelRays> grid = bundle_rays(rays);
    if (!grid) return std::nullopt;
    CoherentOptions o = options;
    o.render.width = grid->grid_width();
    o.render.height = grid->grid_height();
    std::vector<RayResult> cells;
    render_3d_coherent(tape, o, *grid, stats, &cells);
    std::vector<RayResult> out(rays.size());
    for (unsigned j = 0; j < o.render.height; ++j) {
        for (unsigned i = 0; i < o.render.width; ++i) {
            const std::uint32_t k = grid->index(i, j);
            if (k != PixelRays::kNoRay) out[k] = cells[std::size_t{j} * o.render.width + i];
        }
    }
    return out;
}

}  // namespace certray::tracers
