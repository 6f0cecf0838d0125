// tracers/coherent_walk.cpp — the coherent walk's descent: a root tile's rays, the hulls of their
// rectangles, nodes and their boxes, splits in t and across the screen, leaves, and the answers
// with their normals (tracers/coherent_walker.h; docs/theory/coherent.md, "The method").
#include <algorithm>
#include <cmath>
#include <limits>

#include "expr/batch_simd.h"
#include "expr/derived.h"
#include "expr/eval.h"
#include "expr/eval_batch.h"
#include "expr/eval_dual_batch.h"
#include "tracers/coherent_walker.h"

namespace certray::tracers::detail::coherent {
namespace {

/// The arithmetic of set_normal on kDualLanes gradients g at once (the lanes past the hits' are
/// computed and not read): each lane's |g| = √(gx·gx + gy·gy + gz·gz), u = g / |g| and u·d, the
/// same IEEE operations in the same order as camera.h's normalize and dot (no contraction: the
/// build's -ffp-contract=off), so every lane is bit for bit the scalar's. V: a vector type of
/// expr/batch_simd.h.
struct NormalLanes {
    alignas(64) double d[3][expr::kDualLanes];    ///< the rays' directions
    alignas(64) double u[3][expr::kDualLanes];    ///< g / |g|
    alignas(64) double len[expr::kDualLanes];     ///< |g|
    alignas(64) double facing[expr::kDualLanes];  ///< u·d
};

template <class V>
[[gnu::always_inline]] inline void normal_lanes_in(const expr::DualLanes& f, NormalLanes& n) {
    static_assert(expr::kDualLanes % V::kWidth == 0);
    for (int k = 0; k < expr::kDualLanes; k += V::kWidth) {
        const typename V::R x = V::load(f.g[0] + k), y = V::load(f.g[1] + k),
                            z = V::load(f.g[2] + k);
        const typename V::R len = V::sqrt(V::add(V::add(V::mul(x, x), V::mul(y, y)), V::mul(z, z)));
        const typename V::R ux = V::div(x, len), uy = V::div(y, len), uz = V::div(z, len);
        V::store(n.len + k, len);
        V::store(n.u[0] + k, ux);
        V::store(n.u[1] + k, uy);
        V::store(n.u[2] + k, uz);
        V::store(n.facing + k,
                 V::add(V::add(V::mul(ux, V::load(n.d[0] + k)), V::mul(uy, V::load(n.d[1] + k))),
                        V::mul(uz, V::load(n.d[2] + k))));
    }
}

#if CERTRAY_BATCH_X86
[[gnu::flatten]] void normal_lanes_baseline(const expr::DualLanes& f, NormalLanes& n) {
    normal_lanes_in<expr::detail::Sse2>(f, n);
}
[[gnu::target("avx2"), gnu::flatten]] void normal_lanes_avx2(const expr::DualLanes& f,
                                                             NormalLanes& n) {
    normal_lanes_in<expr::detail::Avx2>(f, n);
}
[[gnu::target("avx512f"), gnu::flatten]] void normal_lanes_avx512(const expr::DualLanes& f,
                                                                  NormalLanes& n) {
    normal_lanes_in<expr::detail::Avx512>(f, n);
}
#endif

/// normal_lanes_in on the instruction set of the batch walks (expr::batch_isa()).
void normal_lanes(const expr::DualLanes& f, NormalLanes& n) {
#if CERTRAY_BATCH_X86
    switch (expr::batch_isa()) {
        case expr::BatchIsa::Avx512:
            return normal_lanes_avx512(f, n);
        case expr::BatchIsa::Avx2:
            return normal_lanes_avx2(f, n);
        case expr::BatchIsa::Baseline:
            break;
    }
    normal_lanes_baseline(f, n);
#else
    normal_lanes_in<expr::detail::Scalar>(f, n);
#endif
}

/// A register tape from a list written by prune_ssa (slots in any order): renumbered so that slot
/// i is instruction i, as Tape::from_ssa wants.
expr::Tape tape_of(const Ssa& list) {
    Ssa ssa = list;
    std::vector<std::uint32_t> index(ssa.size());
    for (std::size_t i = 0; i < ssa.size(); ++i) {
        expr::Instr& in = ssa[i];
        const int k = expr::arity(in.op);
        if (k >= 1) in.a = index[in.a];
        if (k == 2) in.b = index[in.b];
        index[in.out] = static_cast<std::uint32_t>(i);
        in.out = static_cast<std::uint32_t>(i);
    }
    return expr::Tape::from_ssa(std::move(ssa));
}

}  // namespace

bool Walker::tile(const Rect& r) {
    root_ = r;
    mean_values_.reset();  // each tile decides afresh (the same in any thread)
    wide_forms_.reset();
    tile_trial_.reset();
    kink_forms_.reset();
    second_trial_.reset();
    plain_tried_ = plain_free_ = 0;
    coarse_long_ = coarse_left_ = 0;
    fold_trial_.reset();
    root_box_.reset();
    // The tile's answers, a miss until answered: kept here while the walk writes them (a few
    // KiB, in cache) and written into the image's arrays row by row at the end, one pass instead
    // of the defaults and then the answers.
    const std::size_t n = std::size_t{r.w} * r.h;
    mine_.width = r.w;
    mine_.height = r.h;
    mine_.status.assign(n, Status::Miss);
    mine_.t.assign(n, std::numeric_limits<double>::quiet_NaN());
    mine_.evals.assign(n, 0);
    mine_.normal.assign(n, {0.f, 0.f, 0.f});
    const bool empty = (rays_.projection() == Projection::Ortho && ortho_tile_free(r)) ||
                       rays_.misses(r.i0, r.j0, r.w, r.h);  // no ray to build: every pixel a Miss
    if (empty) {
        ++stats.empty_tiles;
    } else {
        walk_tile(r);
    }
    // Counted here, in the tile's own arrays (a few KiB, in cache), in loops the compiler turns
    // into vectors: the pass over the image's arrays after the copy had taken 7% of Barth's 512²
    // heightmap.
    // (An empty tile's: n Misses of no evaluation.)
    tile_counts = RenderStats{};
    if (!empty) {
        for (std::size_t k = 0; k < n; ++k) {
            tile_counts.hit += mine_.status[k] == Status::Hit;
            tile_counts.unknown += mine_.status[k] == Status::Unknown;
        }
        for (std::size_t k = 0; k < n; ++k) {
            tile_counts.max_pixel_evals = std::max(tile_counts.max_pixel_evals, mine_.evals[k]);
        }
    }
    tile_counts.miss = n - tile_counts.hit - tile_counts.unknown;
    if (ans_.status.empty()) return empty;  // the image's answers not kept (RenderOptions::answers)
    for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
        const std::size_t from = std::size_t{j - r.j0} * r.w,
                          to = std::size_t{j} * ans_.width + r.i0;
        std::copy_n(mine_.status.data() + from, r.w, ans_.status.data() + to);
        std::copy_n(mine_.t.data() + from, r.w, ans_.t.data() + to);
        std::copy_n(mine_.evals.data() + from, r.w, ans_.evals.data() + to);
        std::copy_n(mine_.normal.data() + from, r.w, ans_.normal.data() + to);
    }
    return empty;
}

void Walker::walk_tile(const Rect& r) {
    px_.assign(std::size_t{r.w} * r.h, Px{});
    blocks_w_ = (r.w + kBlock - 1) / kBlock;
    blocks_.assign(std::size_t{blocks_w_} * ((r.h + kBlock - 1) / kBlock), Block{});
    double a = kInf, b = -kInf;
    {
        NearestScope env;  // one switch for the tile's rays
        row_rays_.resize(r.w);
        row_in_.resize(r.w);
        for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
            rays_.row_in_scope(r.i0, j, r.w, row_rays_.data(), row_in_.data());
            for (unsigned i = r.i0; i < r.i0 + r.w; ++i) {
                Px& p = px(i, j);
                p.ray = row_rays_[i - r.i0];
                // A ray that misses the bounds: Miss, no evaluation.
                p.open = row_in_[i - r.i0];
                if (!p.open) continue;
                ++block_of(i, j).open;
                a = std::min(a, p.ray.tmin);
                b = std::max(b, p.ray.tmax);
            }
        }
    }
    if (a <= b) {
        // One RoundingScope for the whole walk (a mode switch costs more than a box evaluation of
        // a short tape): node() and the mean value form compute UpIntervals in it; their plain
        // double arithmetic only picks split points, whose rounding does not matter; the solver
        // and the normals open a NearestScope of their own.
        RoundingScope up;
        node(r, a, b, tape_.ssa(), &tape_, 0);
        flush_normals();  // (none waits: each scan's wait ends with it)
    }
    // Open rays left are proven free of zeros on their whole segment: Misses (the default).
}

bool Walker::ortho_tile_free(const Rect& r) {
    // A heightmap's rays are a grid, each in scope over the same [0, tmax] straight down: the
    // hull of the tile's rays is that of its corner rays (the coordinates PixelRays computes are
    // monotone in i and j), and the box over the whole depth is the root node's. Where f is
    // proven free of the surface on it, the tile is answered without building its rays.
    Ray c0, c1;
    {
        NearestScope env;  // as tile() builds the rays
        if (!rays_.ray_in_scope(r.i0, r.j0, c0) ||
            !rays_.ray_in_scope(r.i0 + r.w - 1, r.j0 + r.h - 1, c1)) {
            return false;
        }
    }
    double olo[3], ohi[3];
    for (int c = 0; c < 3; ++c) {
        olo[c] = std::min(c0.o[c], c1.o[c]);
        ohi[c] = std::max(c0.o[c], c1.o[c]);
    }
    const double a = std::min(c0.tmin, c1.tmin), b = std::max(c0.tmax, c1.tmax);
    const Ssa& list = tape_.ssa();
    Level& level = levels_[0];
    if (level.values.size() < list.size()) level.values.resize(list.size());
    RoundingScope up;
    root_box_ = segment_box(olo, ohi, c0.d.data(), c0.d.data(), a, b);
    expr::detail::run<UpInterval>(list, *root_box_, level.values.data());
    ++stats.box_evals;
    stats.box_instructions += list.size();
    ++evals.interval;
    if (proof(level.values[list.back().out]) != Proof::Excluded) return false;  // node() goes on
    root_box_.reset();
    ++stats.boxes_excluded;
    return true;
}

Walker::Hull Walker::hull_of(const Rect& r, double a, double b) {
    Hull hull;
    hull.answered = answered_;
    // Whole blocks: r starts on a block's corner and ends on one, or at the root tile's end.
    const bool blocks = options_.block_hulls && (r.i0 - root_.i0) % kBlock == 0 &&
                        (r.j0 - root_.j0) % kBlock == 0 &&
                        (r.w % kBlock == 0 || r.i0 + r.w == root_.i0 + root_.w) &&
                        (r.h % kBlock == 0 || r.j0 + r.h == root_.j0 + root_.h);
    // The origin or direction that does not vary is the first open ray's.
    varying([&](auto vary_o, auto vary_d) {
        const Px* first = nullptr;
        const auto pixels = [&](unsigned i0, unsigned j0, unsigned w, unsigned h) {
            for (unsigned j = j0; j < j0 + h; ++j) {
                for (unsigned i = i0; i < i0 + w; ++i) {
                    const Px& p = px(i, j);
                    if (!p.open || p.ray.tmax < a || p.ray.tmin > b) continue;
                    if (first == nullptr) first = &p;
                    hull.add<vary_o, vary_d>(p.ray);
                }
            }
        };
        if (!blocks) {
            pixels(r.i0, r.j0, r.w, r.h);
        } else {
            for (unsigned bj = r.j0; bj < r.j0 + r.h; bj += kBlock) {
                for (unsigned bi = r.i0; bi < r.i0 + r.w; bi += kBlock) {
                    Block& k = block_of(bi, bj);
                    if (k.open == 0) continue;
                    if (k.stale) take_block(k, bi, bj);
                    if (k.max_tmin <= b && k.min_tmax >= a) {  // every open ray meets [a, b]
                        if (first == nullptr) first = k.first;
                        hull.add<vary_o, vary_d>(k.hull);
                    } else {
                        pixels(bi, bj, std::min(kBlock, r.i0 + r.w - bi),
                               std::min(kBlock, r.j0 + r.h - bj));
                    }
                }
            }
        }
        if (first == nullptr) return;
        for (int c = 0; c < 3; ++c) {
            if constexpr (!vary_o) hull.olo[c] = hull.ohi[c] = first->ray.o[c];
            if constexpr (!vary_d) hull.dlo[c] = hull.dhi[c] = first->ray.d[c];
        }
    });
    return hull;
}

void Walker::take_block(Block& k, unsigned i0, unsigned j0) {
    const unsigned open = k.open;
    k = Block{};
    k.open = open;
    k.stale = false;
    Hull& h = k.hull;
    const unsigned i1 = std::min(i0 + kBlock, root_.i0 + root_.w);
    const unsigned j1 = std::min(j0 + kBlock, root_.j0 + root_.h);
    // As hull_of: the origins where they vary (not a pinhole's), the directions where they do
    // (not a heightmap's); hull_of takes the other one from the first open ray.
    varying([&](auto vary_o, auto vary_d) {
        for (unsigned j = j0; j < j1; ++j) {
            for (unsigned i = i0; i < i1; ++i) {
                const Px& p = px(i, j);
                if (!p.open) continue;
                if (k.first == nullptr) k.first = &p;
                h.add<vary_o, vary_d>(p.ray);
                k.max_tmin = std::max(k.max_tmin, p.ray.tmin);
                k.min_tmax = std::min(k.min_tmax, p.ray.tmax);
            }
        }
    });
}

void Walker::node(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
                  unsigned depth, const Hull* given) {
    // The open rays of r that meet [a, b], and the hull of their origins and directions. A
    // parent's hull over the same rectangle serves while no ray has been answered since it was
    // taken: its rays are a superset, so its box still holds them all.
    const Hull hull = given != nullptr && given->answered == answered_ ? *given : hull_of(r, a, b);
    const unsigned count = hull.count;
    if (count == 0) return;
    // Rays start no earlier than tlo and end by thi: nothing of them lies outside [tlo, thi].
    a = std::max(a, hull.tlo);
    b = std::min(b, hull.thi);

    // The box [o] + [a, b]·[d] holds o + t·d for every such ray and t in [a, b] (rounded outward).
    Level& level = levels_[depth];
    const Box box = segment_box(hull.olo, hull.ohi, hull.dlo, hull.dhi, a, b);
    const auto same = [](const Box& x, const Box& y) {
        for (int c = 0; c < 3; ++c) {
            if (x[c].lower() != y[c].lower() || x[c].upper() != y[c].upper()) return false;
        }
        return true;
    };
    if (depth == 0 && list.data() == tape_.ssa().data() && root_box_ && same(*root_box_, box)) {
        // ortho_tile_free() evaluated the full tape over this box into level.values.
    } else {
        if (level.values.size() < list.size()) level.values.resize(list.size());
        expr::detail::run<UpInterval>(list, box, level.values.data());
        ++stats.box_evals;
        stats.box_instructions += list.size();
        ++evals.interval;
    }
    root_box_.reset();
    // Zero: 0 ∉ F (or f undefined on the whole box), no ray meets f = 0 here. Solid: F ≥ 0, no
    // ray enters {f < 0} here; or F < 0, every ray enters at its first point in the box.
    Proof proven = proof(level.values[list.back().out]);
    if (proven == Proof::None && try_mean_value(count, list, depth)) {
        const expr::TangentList* tl =
            tangent_kind(list, depth) == expr::TangentKind::Smooth ? tangent(list, depth) : nullptr;
        LinearForm lin;
        const UpInterval m =
            mean_value(list, a, b, hull.olo, hull.ohi, hull.dlo, hull.dhi, tl, &lin);
        mean_value_tried(count, take_form(m, lin, proven, a, b));
    }
    descend(r, a, b, list, tape, depth, hull, proven);
}

void Walker::descend(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
                     unsigned depth, const Hull& hull, Proof proven) {
    if (proven == Proof::Excluded) {
        ++stats.boxes_excluded;
        return;
    }
    if (proven == Proof::Inside) {
        ++stats.boxes_inside;
        inside(r, a, b, list);
        return;
    }
    Level& level = levels_[depth];
    const unsigned count = hull.count;
    const Ssa* sub = &list;
    const expr::Tape* sub_tape = tape;
    if (choices_) level.tangent.forget();  // level.list may be rewritten
    if (choices_ && expr::prune_ssa(list, level.values.data(), prune_ws_, level.list)) {
        sub = &level.list;
        sub_tape = nullptr;
        ++stats.prunes;
    }

    // Smooth lists (a tangent list without kinks) get their scans' forms in lanes and tight:
    // wider scans pay there (kinked ones keep 8: their forms at ties are looser).
    // Long lists too: a walk's cost per instruction is then spread over more lanes.
    const bool together = scans_together(count, *sub, depth);
    if (together && scan_together(r, a, b, *sub, sub_tape, level, depth, hull)) {
        return;
    }
    // More rays still, where the list folds to the node's box: the folded list's walks are
    // shorter, and one box, prune and fold serve them all.
    if (!together && count <= options_.folded_together_rays && may_fold(*sub) &&
        scan_together(r, a, b, *sub, sub_tape, level, depth, hull, true)) {
        ++stats.folded_scans;
        return;
    }
    if (count > 1 && depth + 1 < kMaxDepth) {
        // How far apart the rays are at the far end, plus a pixel: the box's lateral extent.
        double spread_o = 0, spread_d = 0;
        for (int c = 0; c < 3; ++c) {
            spread_o = std::max(spread_o, hull.ohi[c] - hull.olo[c]);
            spread_d = std::max(spread_d, hull.dhi[c] - hull.dlo[c]);
        }
        const double lateral = spread_o + std::fabs(b) * spread_d +
                               rays_.pixel_pitch() * (rays_.angular() ? std::fabs(b) : 1);
        // Nodes that a coarse scan may take (not those left to a folded scan of their own).
        const bool coarse =
            count <= kCoarseRays && (together || !may_fold(*sub)) && coarse_scans(*sub, depth);
        const double aspect = coarse ? options_.scan_aspect : options_.aspect;
        if (t_splits_ && b - a > aspect * lateral && splittable(a, b)) {
            // Near segment first: the far one only sees the rays the near one left open.
            const double m = 0.5 * a + 0.5 * b;
            node(r, a, m, *sub, sub_tape, depth + 1, &hull);
            node(r, m, b, *sub, sub_tape, depth + 1, &hull);
            return;
        }
        if (r.w > 1 || r.h > 1) {
            split_screen(r, a, b, *sub, sub_tape, depth + 1);
            return;
        }
    }
    leaf(r, a, b, *sub, sub_tape, level, depth);
}

void Walker::split_screen(const Rect& r, double a, double b, const Ssa& list,
                          const expr::Tape* tape, unsigned depth) {
    const unsigned w1 = (r.w + 1) / 2, h1 = (r.h + 1) / 2;
    Rect quarter[4];
    int n = 0;
    quarter[n++] = {r.i0, r.j0, w1, h1};
    if (r.w > w1) quarter[n++] = {r.i0 + w1, r.j0, r.w - w1, h1};
    if (r.h > h1) quarter[n++] = {r.i0, r.j0 + h1, w1, r.h - h1};
    if (r.w > w1 && r.h > h1) quarter[n++] = {r.i0 + w1, r.j0 + h1, r.w - w1, r.h - h1};
    // A long list's registers of 64 lanes (a KiB each) outgrow the caches where a walk per quarter
    // stays in them: the molecule's lists of thousands of instructions took 1.1× the time (a limit
    // of 256: the same as a walk per quarter, within the noise).
    if (!options_.children_in_lanes || list.size() > kLanesList) {
        for (int k = 0; k < n; ++k) node(quarter[k], a, b, list, tape, depth);
        return;
    }
    // Each quarter's slot enclosures are level.values at `depth`, which the descent below reads
    // to prune (choices_) and to fold (may_fold): there they are kept from the lanes.
    Level& level = levels_[depth];
    const bool keep_values = choices_ || may_fold(list);
    // The quarters' rays are disjoint: a quarter's hull, taken before the others are walked,
    // is the one node() would take when it comes to it.
    struct Quarter {
        Hull hull;
        double a, b;
        Proof proven;
        int form;  // its lanes in forms, or −1
    };
    Quarter q[4];
    LaneBox boxes[4];
    int live[4];
    int m = 0;
    for (int k = 0; k < n; ++k) {
        q[k].hull = hull_of(quarter[k], a, b);
        if (q[k].hull.count == 0) continue;
        q[k].a = std::max(a, q[k].hull.tlo);
        q[k].b = std::min(b, q[k].hull.thi);
        const Box box =
            segment_box(q[k].hull.olo, q[k].hull.ohi, q[k].hull.dlo, q[k].hull.dhi, q[k].a, q[k].b);
        for (int c = 0; c < 3; ++c) {
            boxes[m].lo[c] = box[c].lower();
            boxes[m].hi[c] = box[c].upper();
        }
        live[m++] = k;
    }
    if (m == 0) return;
    // The boxes' enclosures in double lanes: lane l is bit for bit run<UpInterval>'s over box l.
    const LaneFile<expr::IntervalLanes>& lanes =
        eval_lanes_in(d64_, list, boxes, static_cast<std::size_t>(m), split_values_, nullptr);
    if (keep_values) {
        // Lane l of every slot is what node() would leave in level.values for quarter l; kept
        // apart, as the forms' walks and the deeper levels reuse the lane file.
        for (int l = 0; l < m; ++l) {
            std::vector<UpInterval>& v = level.quarters[l];
            if (v.size() < list.size()) v.resize(list.size());
            for (const expr::Instr& in : list) v[in.out] = expr::lane(lanes.regs[in.out], l);
        }
    }
    stats.box_evals += m;
    stats.box_instructions += m * list.size();
    evals.interval += m;
    const expr::TangentList* tl = nullptr;
    bool smooth_known = false;
    int forms = 0;
    for (int l = 0; l < m; ++l) {
        Quarter& z = q[live[l]];
        z.proven = proof(split_values_[l]);
        z.form = -1;
        if (z.proven != Proof::None || !try_mean_value(z.hull.count, list, depth)) continue;
        if (!smooth_known) {
            smooth_known = true;
            if (tangent_kind(list, depth) == expr::TangentKind::Smooth) tl = tangent(list, depth);
        }
        const Hull& h = z.hull;
        const bool one_ray =
            std::equal(h.olo, h.olo + 3, h.ohi) && std::equal(h.dlo, h.dlo + 3, h.dhi);
        if (tl != nullptr && !one_ray) {
            prepare_form(forms_[forms], z.a, z.b, h.olo, h.ohi, h.dlo, h.dhi);
            z.form = forms++;
            continue;
        }
        LinearForm lin;
        const UpInterval f = mean_value(list, z.a, z.b, h.olo, h.ohi, h.dlo, h.dhi, tl, &lin);
        mean_value_tried(h.count, take_form(f, lin, z.proven, z.a, z.b));
    }
    if (forms > 0) {
        ray_form_lanes(*tl, forms_, forms);
        for (int l = 0; l < m; ++l) {
            Quarter& z = q[live[l]];
            if (z.form < 0) continue;
            const Hull& h = z.hull;
            count_form(list.size());
            LinearForm lin;
            const UpInterval f =
                ray_form(forms_[z.form], z.a, z.b, h.olo, h.ohi, h.dlo, h.dhi, &lin);
            mean_value_tried(h.count, take_form(f, lin, z.proven, z.a, z.b));
        }
    }
    // The quarters that descend() would scan at once, scanned together (merged_scans): their
    // rays are disjoint, and one list without a prune or fold serves them all, so each phase of
    // the scan is one walk for all of them where it was one per quarter.
    unsigned merged = 0;
    if (options_.merged_scans && !keep_values && m >= 2 &&
        !(tile_pieces_for(list, depth, nullptr) && tile_trial_.paying())) {
        ScanGroup groups[4];
        int of[4];
        int g = 0;
        for (int l = 0; l < m; ++l) {
            const Quarter& z = q[live[l]];
            if (z.proven != Proof::None || !scans_together(z.hull.count, list, depth)) continue;
            groups[g] = {quarter[live[l]], z.a, z.b, &z.hull};
            of[g++] = l;
        }
        if (g >= 2) {
            const unsigned taken = scan_groups(groups, g, list, tape, level, depth, false);
            stats.merged_scans += std::popcount(taken) >= 2;
            for (int k = 0; k < g; ++k) merged |= (taken >> k & 1u) << of[k];
        }
    }
    for (int l = 0; l < m; ++l) {
        if (merged >> l & 1u) continue;
        Quarter& z = q[live[l]];
        z.hull.answered = answered_;  // the rays answered since are the other quarters'
        if (keep_values) level.values.swap(level.quarters[l]);
        descend(quarter[live[l]], z.a, z.b, list, tape, depth, z.hull, z.proven);
    }
}

void Walker::leaf(const Rect& r, double a, double b, const Ssa& list, const expr::Tape* tape,
                  Level& level, unsigned depth) {
    for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
        for (unsigned i = r.i0; i < r.i0 + r.w; ++i) {
            Px& p = px(i, j);
            if (!p.open || p.ray.tmax < a || p.ray.tmin > b) continue;
            // [tmin, a) is proven free of zeros, and `list` equals f on the ray for t in [a, b].
            Ray s = p.ray;
            s.tmin = std::max(a, p.ray.tmin);
            s.tmax = std::min(b, p.ray.tmax);
            const double w = piece_width(s);
            // A segment a few depths long is scanned in pieces, the solver only where that does
            // not decide.
            const bool scanned = w > 0 && s.tmax - s.tmin <= kMaxPieces * w;
            settle(i, j, s, scanned ? scan(list, s) : RayResult{}, scanned, list, tape, level,
                   depth);
        }
    }
}

void Walker::settle(unsigned i, unsigned j, const Ray& s, RayResult res, bool scanned,
                    const Ssa& list, const expr::Tape*& tape, Level& level, unsigned depth) {
    // The register tape only when a solver runs (a scan walks the list itself).
    const auto solver_tape = [&]() -> const expr::Tape& {
        if (tape == nullptr) {
            level.tape = tape_of(list);
            tape = &level.tape;
        }
        return *tape;
    };
    Px& p = px(i, j);
    ++stats.leaf_solves;
    // Where the list has choices, an undecided segment is split with a tape pruned to each half
    // (below) before the solver is tried on it: the scan has taken its pieces, points, forms and
    // quarters, and the solver on the same list seldom decides more (Fidget's colonnade: 585 such
    // rays, 185 evaluations each, none decided; the halves' prunes decide them).
    const bool split_first =
        choices_ && p.splits < kMaxSplits && depth + 1 < kMaxDepth && splittable(s.tmin, s.tmax);
    if (!scanned) {
        res = solve(solver_tape(), s);
    } else if (res.status != Status::Unknown || split_first) {
        ++stats.scans;
    } else {
        const EvalCounts spent = res.evals;
        Ray rest = s;
        rest.tmin = res.t_lo;
        res = solve(solver_tape(), rest);
        res.evals += spent;
    }
    if (res.status == Status::Miss) {  // free of zeros up to b: the walk goes on
        spend(i, j, res.evals);
        return;
    }
    if (res.status == Status::Unknown && split_first) {
        // Undecided on the segment with this tape: each half gets its own box evaluation and a
        // tape pruned to it, where the choices that blurred the sign may resolve
        // (max(x, −min(x, y)) at the edge of a plane where f touches 0, say).
        ++p.splits;
        ++stats.splits;
        spend(i, j, res.evals);
        const double m = 0.5 * s.tmin + 0.5 * s.tmax;
        const Rect one{i, j, 1, 1};  // this ray alone
        node(one, s.tmin, m, list, tape, depth + 1);
        if (p.open) node(one, m, s.tmax, list, tape, depth + 1);
        return;  // answered by the halves, or proven free of zeros up to s.tmax
    }
    if (res.status == Status::Unknown && s.tmax < p.ray.tmax) {
        // Undecided in this segment: the per-ray solver on the rest of the ray (full tape) may
        // still prove a zero further along, as it would on the whole ray.
        ++stats.fallbacks;
        Ray rest = p.ray;
        rest.tmin = s.tmin;
        const EvalCounts spent = res.evals;
        res = solve(tape_, rest);
        res.evals += spent;
    }
    answer(i, j, p, res, list, s.tmin, s.tmax);
}

void Walker::inside(const Rect& r, double a, double b, const Ssa& list) {
    const DeferNormals defer(*this, list);  // the box's hits, a walk of lanes per 16
    for (unsigned j = r.j0; j < r.j0 + r.h; ++j) {
        for (unsigned i = r.i0; i < r.i0 + r.w; ++i) {
            Px& p = px(i, j);
            if (!p.open || p.ray.tmax < a || p.ray.tmin > b) continue;
            // The point at t lies in the box, where f < 0 is proven; g ≥ 0 on [tmin, t) by the
            // walk's invariant.
            const double t = std::max(a, p.ray.tmin);
            RayResult res;
            res.status = Status::Hit;
            res.t_lo = res.t_hi = res.t = t;
            answer(i, j, p, res, list, a, b);
        }
    }
}

void Walker::spend(unsigned i, unsigned j, const EvalCounts& e) {
    evals += e;
    mine_.evals[slot(i, j)] += e.total();
    if (results_ != nullptr) (*results_)[std::size_t{j} * ans_.width + i].evals += e;
}

void Walker::answer(unsigned i, unsigned j, Px& p, const RayResult& res, const Ssa& list, double a,
                    double b) {
    assert(p.open);  // answered once
    set_open(i, j, false);
    evals += res.evals;
    const Ray& ray = p.ray;
    const std::size_t k = slot(i, j);
    mine_.status[k] = res.status;
    mine_.evals[k] += res.evals.total();
    mine_.t[k] = res.t;
    if (results_ != nullptr) {
        RayResult& out = (*results_)[std::size_t{j} * ans_.width + i];
        const EvalCounts before = out.evals;  // of the segments this ray was proven free on
        out = res;
        out.evals += before;
    }
    if (res.status != Status::Hit) return;
    const bool on_list = a <= res.t && res.t <= b;
    if (on_list && &list == defer_list_) {
        if (pending_ > 0 && pending_list_ != &list) flush_normals();
        pending_list_ = &list;
        pending_px_[pending_] = k;
        pending_t_[pending_] = res.t;
        pending_ray_[pending_] = &ray;  // the root tile's pixel
        if (++pending_ == expr::kDualLanes) flush_normals();
        return;
    }
    NearestInUpward env;  // as render_3d computes the normal (the walk holds its upward scope)
    const Vec3 q = point_at(ray, res.t);
    Dual<double, 3> g;
    if (on_list && list.size() < tape_.size()) {
        // The pruned list, much shorter than the tape (a tenth on Fidget's colonnade).
        g = list_gradient(list, q);
    } else {
        g = expr::gradient(tape_, q);
    }
    set_normal(k, {g.v[0], g.v[1], g.v[2]}, ray.d);
}

Dual<double, 3> Walker::list_gradient(const Ssa& list, const Vec3& q) {
    using D = Dual<double, 3>;
    if (grad_.size() < list.size()) grad_.resize(list.size());
    expr::detail::run<D>(list, {D::variable(q[0], 0), D::variable(q[1], 1), D::variable(q[2], 2)},
                         grad_.data());
    return grad_[list.back().out];
}

void Walker::set_normal(std::size_t k, const Vec3& g, const Vec3& d) {  // in round-to-nearest
    const Vec3 n = normalize(g);
    store_normal(k, n, dot(n, d));
}

void Walker::store_normal(std::size_t k, Vec3 n, double facing) {
    if (facing > 0) n = {-n[0], -n[1], -n[2]};
    mine_.normal[k] = {static_cast<float>(n[0]), static_cast<float>(n[1]),
                       static_cast<float>(n[2])};
}

void Walker::flush_normals() {
    if (pending_ == 0) return;
    const Ssa& list = *pending_list_;
    NearestInUpward env;  // as answer() computes a normal, its normalisation included
    for (int k = 0; k < pending_; ++k) {
        pending_q_[k] = point_at(*pending_ray_[k], pending_t_[k]);
    }
    if (pending_ < kFewNormals) {
        for (int k = 0; k < pending_; ++k) {
            const Dual<double, 3> g = list_gradient(list, pending_q_[k]);
            set_normal(pending_px_[k], {g.v[0], g.v[1], g.v[2]}, pending_ray_[k]->d);
        }
    } else {
        if (dual_regs_.size() < list.size()) dual_regs_.resize(list.size());
        expr::run_dual_batch(list.data(), list.data() + list.size(), pending_q_, pending_,
                             dual_regs_.data());
        const expr::DualLanes& f = dual_regs_[list.back().out];
        // set_normal's arithmetic in vectors (its square roots and divisions were 5% of Barth's
        // heightmap), then its tests lane by lane.
        NormalLanes n;
        for (int k = 0; k < expr::kDualLanes; ++k) {
            const Vec3& d = pending_ray_[k < pending_ ? k : 0]->d;
            for (int c = 0; c < 3; ++c) n.d[c][k] = d[c];
        }
        normal_lanes(f, n);
        for (int k = 0; k < pending_; ++k) {
            // normalize's test: where |g| is 0, NaN or infinite the normal is 0 (facing nothing).
            if (n.len[k] > 0 && std::isfinite(n.len[k])) {
                store_normal(pending_px_[k], {n.u[0][k], n.u[1][k], n.u[2][k]}, n.facing[k]);
            } else {
                store_normal(pending_px_[k], {0, 0, 0}, 0);
            }
        }
    }
    pending_ = 0;
}

}  // namespace certray::tracers::detail::coherent
