// tracers/coherent_scan.cpp — the coherent walk's scans: a leaf segment in pieces half a pixel
// deep, and the rays of a node (or of several) scanned together in lanes, with tile pieces, forms
// and quarters (tracers/coherent_walker.h; docs/theory/coherent.md, "Options for images").
#include <algorithm>
#include <cassert>
#include <cmath>

#include "expr/eval.h"
#include "tracers/coherent_walker.h"

namespace certray::tracers::detail::coherent {
namespace {

/// How many pieces w wide a scan cuts segment s into.
int pieces_of(const Ray& s, double w) { return static_cast<int>(std::ceil((s.tmax - s.tmin) / w)); }

/// Piece k of the n pieces of segment s, w wide, front to back (the last one ends at s.tmax); it
/// may be empty (lo ≥ hi) where rounding left nothing for it.
std::pair<double, double> piece(const Ray& s, double w, int k, int n) {
    const double lo = k == 0 ? s.tmin : std::min(s.tmax, s.tmin + k * w);
    const double hi = k + 1 == n ? s.tmax : std::min(s.tmax, s.tmin + (k + 1) * w);
    return {lo, hi};
}

}  // namespace

RayResult Walker::scan(const Ssa& list, const Ray& s, double width, int finer) {
    if (scan_.size() < list.size()) scan_.resize(list.size());
    const double w = width > 0 ? width : piece_width(s);
    const int n = pieces_of(s, w);
    RayResult res;
    res.status = Status::Miss;
    const auto g = [&](double p, double q) {  // in the walk's upward mode
        ++res.evals.interval;
        expr::detail::run<UpInterval>(list, ray_box(s, p, q), scan_.data());
        return scan_[list.back().out];
    };
    const auto proven_neg = [](const UpInterval& v) { return v.defined && v.upper() < 0; };
    const auto proven_pos = [](const UpInterval& v) { return v.defined && v.lower() > 0; };
    for (int k = 0; k < n; ++k) {
        const auto [p, q] = piece(s, w, k, n);
        if (!(p < q)) continue;
        const UpInterval v = g(p, q);
        if (proof(v) == Proof::Excluded) continue;
        res.status = Status::Unknown;
        res.t_lo = p;
        res.t_hi = s.tmax;
        if (solid_) {
            if (proven_neg(v)) {
                res.status = Status::Hit;
                res.t_hi = p;
            } else if (proven_neg(g(q, q))) {
                res.status = Status::Hit;
                res.t_hi = q;
            }
        } else if (v.defined) {
            const UpInterval gp = g(p, p);
            const UpInterval gq = g(q, q);
            if ((proven_neg(gp) && proven_pos(gq)) || (proven_pos(gp) && proven_neg(gq))) {
                res.status = Status::Hit;
                res.t_hi = q;
            }
        }
        if (res.status == Status::Hit) {
            res.t = 0.5 * res.t_lo + 0.5 * res.t_hi;
            return res;
        }
        return after_points(list, s, p, q, res, finer);
    }
    return res;
}

RayResult Walker::after_points(const Ssa& list, const Ray& s, double p, double q, RayResult res,
                               int finer, const Proof* form) {
    Proof again = form != nullptr ? *form : piece_mean_value(list, s, p, q, res);
    if (again == Proof::None && finer > 0) {
        // Scanned again in quarters: a Hit or an Unknown there is the answer (the segment is
        // free before p); a Miss proves [p, q] free.
        Ray piece = s;
        piece.tmin = p;
        piece.tmax = q;
        RayResult fine = scan(list, piece, 0.25 * (q - p), finer - 1);
        fine.evals += res.evals;
        if (fine.status != Status::Miss) {
            if (fine.status == Status::Unknown) fine.t_hi = s.tmax;
            return fine;
        }
        res.evals = fine.evals;
        again = Proof::Excluded;
    }
    if (again == Proof::Excluded) {  // [tmin, q] is free: the rest is scanned afresh
        RayResult rest;
        rest.status = Status::Miss;
        if (q < s.tmax) {
            Ray r = s;
            r.tmin = q;
            rest = scan(list, r);
        }
        rest.evals += res.evals;
        return rest;
    }
    if (again == Proof::Inside) {
        res.status = Status::Hit;
        res.t_hi = p;
        res.t = p;
    }
    return res;
}

Walker::Proof Walker::piece_mean_value(const Ssa& list, const Ray& s, double p, double q,
                                       RayResult& res) {
    // mean_value() counts a node's evaluations; these are the pixel's (added to the walk's
    // when the pixel is spent or answered) and not box evaluations.
    const EvalCounts before = evals;
    const std::uint64_t boxes = stats.box_evals, instructions = stats.box_instructions;
    const UpInterval m = mean_value(list, p, q, s.o.data(), s.o.data(), s.d.data(), s.d.data());
    res.evals.interval += evals.interval - before.interval;
    res.evals.gradient += evals.gradient - before.gradient;
    evals = before;
    stats.box_evals = boxes;
    stats.box_instructions = instructions;
    return m.is_empty() ? Proof::None : proof(m);
}

bool Walker::scan_together(const Rect& r, double a, double b, const Ssa& list,
                           const expr::Tape* tape, Level& level, unsigned depth, const Hull& hull,
                           bool folded_only) {
    const ScanGroup one{r, a, b, &hull};
    return scan_groups(&one, 1, list, tape, level, depth, folded_only) != 0;
}

unsigned Walker::scan_groups(const ScanGroup* groups, int count, const Ssa& list,
                             const expr::Tape* tape, Level& level, unsigned depth,
                             bool folded_only) {
    // The hits of this scan wait for their normals until it returns (a nested scan's own hits
    // until that one returns).
    const DeferNormals defer(*this, list);
    // The rays' segments; none of a group scanned if one of its segments is too long.
    segments_.clear();
    double w_tile = kInf;  // the narrowest piece width (tile pieces: one group)
    unsigned taken = 0;
    // Coarse scans: longer segments, those the forms leave undecided to the node's halves.
    const bool coarse = !folded_only && coarse_scans(list, depth);
    const double most_pieces = coarse ? options_.coarse_pieces : kMaxPieces;
    assert(count <= 4);
    std::size_t group_end[4] = {0, 0, 0, 0};  // each group's segments end there
    for (int g = 0; g < count; ++g) {
        const Rect& r = groups[g].r;
        const double a = groups[g].a, b = groups[g].b;
        const bool halvable = coarse && splittable(a, b);  // its long segments may be deferred
        const std::size_t mark = segments_.size();
        double w_group = kInf;
        bool short_enough = true;
        for (unsigned j = r.j0; j < r.j0 + r.h && short_enough; ++j) {
            for (unsigned i = r.i0; i < r.i0 + r.w; ++i) {
                const Px& p = px(i, j);
                if (!p.open || p.ray.tmax < a || p.ray.tmin > b) continue;
                Ray s = p.ray;
                s.tmin = std::max(a, p.ray.tmin);
                s.tmax = std::min(b, p.ray.tmax);
                const double w = piece_width(s);
                if (!(w > 0 && s.tmax - s.tmin <= most_pieces * w)) {
                    short_enough = false;
                    break;
                }
                w_group = std::min(w_group, w);
                segments_.push_back(
                    {i, j, s.tmin, s.tmax, halvable && s.tmax - s.tmin > kMaxPieces * w});
            }
        }
        if (!short_enough) {
            segments_.resize(mark);
            group_end[g] = mark;
            continue;
        }
        group_end[g] = segments_.size();
        w_tile = std::min(w_tile, w_group);
        taken |= 1u << g;
    }
    if (taken == 0) return 0;
    // Scanned: the list its lanes walk, folded to the node's box where that pays (one group).
    if (count == 1) {
        const Hull& hull = *groups[0].hull;
        fold(list, segment_box(hull.olo, hull.ohi, hull.dlo, hull.dhi, groups[0].a, groups[0].b),
             level);
    } else {
        level.folded.list.clear();
        level.folded.fixed.clear();
        level.folded_tangent.forget();
    }
    if (folded_only && level.folded.list.empty()) return 0;
    // Tile pieces: [a, b] cut in pieces of the narrowest width, each one box over all the rays
    // (the hull's), in one batched evaluation. A piece proven free is free on every ray; a ray's
    // first piece not proven free decides it when the piece after it is proven inside (solid:
    // the ray enters {f < 0} in its piece, Hit [p, q]; or at p if the piece itself is inside) or
    // when the pieces either side have strict opposite signs (zero set, f defined and continuous
    // on the piece: Hit [p, q]). Otherwise the ray is scanned alone from that piece on.
    // One node's only (several share no hull; they are scanned together only while the tile
    // pieces do not pay, split_screen()).
    int tiles = 0;
    if (count == 1 && groups[0].hull->count >= 2 && tile_pieces_for(list, depth, &level) &&
        tile_trial_.attempt()) {
        const Hull& hull = *groups[0].hull;
        const Ray span{{}, {}, groups[0].a, groups[0].b};
        tiles = pieces_of(span, w_tile);
        if (tiles > 2 * kMaxPieces) tiles = 0;
        tile_boxes_.clear();
        for (int k = 0; k < tiles; ++k) {
            const auto [lo, hi] = piece(span, w_tile, k, tiles);
            const auto box = segment_box(hull.olo, hull.ohi, hull.dlo, hull.dhi, lo, hi);
            LaneBox lb;
            for (int c = 0; c < 3; ++c) {
                lb.lo[c] = box[c].lower();
                lb.hi[c] = box[c].upper();
            }
            tile_boxes_.push_back(lb);
            tile_t_[k] = lo;
            tile_t_[k + 1] = hi;
        }
        if (tiles > 0) {
            eval_lanes(list, tile_boxes_.data(), tiles, tile_values_, &level);
            stats.tile_pieces += tiles;
            evals.interval += tiles;
        }
    }

    // Each ray's segment after the tile pieces.
    pieces_.clear();
    level.scanned.clear();
    std::size_t decided = 0;  // rays the tile pieces answered
    std::size_t cleared = 0;  // rays the tile pieces answered or proved free on [a, b]
    int saved = 0;            // pieces of the rays' own that the tile pieces made unnecessary
    for (const Segment& g : segments_) {
        Level::Scanned& z = level.scanned.emplace_back(g.i, g.j, px(g.i, g.j).ray, g.tmin, g.tmax);
        z.long_segment = g.long_segment;
        coarse_long_ += g.long_segment;
        Ray& s = z.s;
        RayResult& res = z.res;
        if (tiles > 0) {
            const int before = pieces_of(s, piece_width(s));
            int k = 0;
            while (k < tiles && tile_t_[k + 1] <= s.tmin) ++k;  // the piece holding s.tmin
            for (; k < tiles && tile_t_[k] < s.tmax; ++k) {
                ++res.evals.interval;
                const Proof pr = proof(tile_values_[k]);
                if (pr == Proof::Excluded) continue;
                const double p = tile_t_[k], q = tile_t_[k + 1];
                const bool next = k + 1 < tiles && s.tmax >= q;  // the ray reaches piece k + 1
                // Its own lambda: calling the `hit` of the decisions below instead, hoisted here,
                // made the colonnade's heightmap 10% slower (measured; code generation).
                const auto hit = [&](double lo, double hi) {
                    res.status = Status::Hit;
                    res.t_lo = lo;
                    res.t_hi = hi;
                    res.t = 0.5 * lo + 0.5 * hi;
                    ++decided;
                };
                if (solid_ && pr == Proof::Inside) {
                    hit(std::max(p, s.tmin), std::max(p, s.tmin));
                } else if (solid_ && next && proof(tile_values_[k + 1]) == Proof::Inside) {
                    hit(std::max(p, s.tmin), q);
                } else if (!solid_ && next && k > 0 && s.tmin <= p && tile_values_[k].defined &&
                           strict_sign(tile_values_[k - 1]) * strict_sign(tile_values_[k + 1]) ==
                               -1) {
                    hit(p, q);  // g(p) and g(q) of strict opposite signs, g continuous between
                }
                s.tmin = std::max(s.tmin, p);  // free before its first piece not proven free
                break;
            }
            if (k == tiles || !(tile_t_[k] < s.tmax)) {
                s.tmin = s.tmax;  // every piece it meets proven free: Miss on [a, b]
            }
            const bool clear = res.status != Status::Miss || !(s.tmin < s.tmax);
            cleared += clear;
            saved += before - (clear ? 0 : pieces_of(s, piece_width(s)));
        }
    }
    stats.tile_decided += decided;
    // A win: the tile pieces answered a ray, left none of the node's rays to scan (the pieces'
    // walks and their points and forms spared), or spared four vectors' worth of pieces. A few
    // pieces spared do not pay: a walk costs about the same for a few lanes fewer
    // (docs/benchmarks.md, session 22).
    tile_trial_.wins +=
        tiles > 0 && (decided > 0 || cleared == segments_.size() || saved >= 4 * kWalkLanes);
    take_segment_forms(list, depth, level);
    // The pieces of every ray not decided yet, as scan() cuts them; in a coarse scan, a long
    // segment that the forms left undecided is left to the node's halves instead.
    for (Level::Scanned& z : level.scanned) {
        z.begin = pieces_.size();
        if (z.res.status == Status::Miss && z.s.tmin < z.s.tmax) {
            if (z.long_segment) {
                ++coarse_left_;
                z.deferred = true;
                z.end = z.begin;
                // Free before z.s.tmin (the forms' line or brackets cut that part off): the
                // halves start the ray there.
                Px& p = px(z.i, z.j);
                if (z.s.tmin > p.ray.tmin) {
                    p.ray.tmin = z.s.tmin;
                    block_of(z.i, z.j).stale = true;
                }
                continue;
            }
            const double w = piece_width(z.s);
            const int n = pieces_of(z.s, w);
            for (int k = 0; k < n; ++k) {
                const auto [lo, hi] = piece(z.s, w, k, n);
                if (lo < hi) pieces_.push_back({z.i, z.j, lo, hi});
            }
        }
        z.end = pieces_.size();
    }
    // Every piece's enclosure, in one batched evaluation.
    const std::size_t n = pieces_.size();
    if (lanes_.size() < n) lanes_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Piece& c = pieces_[k];
        lanes_[k] = lane_box(px(c.i, c.j).ray, c.p, c.q);
    }
    eval_lanes(list, lanes_.data(), n, piece_values_, &level);
    piece_proof_.resize(n);
    for (std::size_t k = 0; k < n; ++k) piece_proof_[k] = proof(piece_values_[k]);

    // A ray's decision at its first piece k not proven free, as scan() makes it: proven inside
    // (solid): Hit [p, p]; else the points' test — solid: g(q) < 0, zero: g defined and
    // continuous on the piece with g(p), g(q) of strict opposite signs: Hit [p, q]; else
    // undecided (the mean value form and the quarters come next). `point`: the lane of the
    // piece's first point value (q for the solid; p, then q, for the zero set), or none.
    const auto proven_neg = [](const UpInterval& v) { return v.defined && v.upper() < 0; };
    const auto proven_pos = [](const UpInterval& v) { return v.defined && v.lower() > 0; };
    const auto points_for = [&](const UpInterval& e) -> int {  // e: the piece's enclosure
        if (proof(e) == Proof::Inside) return 0;
        return solid_ ? 1 : e.defined ? 2 : 0;
    };
    const auto points_of = [&](std::size_t k) { return points_for(piece_values_[k]); };
    // The decision on a piece [p, q] of enclosure e (not proven free), up to `tmax`.
    const auto decide_piece = [&](RayResult& res, const UpInterval& e, double p, double q,
                                  double tmax, const UpInterval* point) {
        res.status = Status::Unknown;
        res.t_lo = p;
        res.t_hi = tmax;
        if (proof(e) == Proof::Inside) return hit_of(res, p, p);
        const int m = points_for(e);
        res.evals.interval += static_cast<unsigned>(m);
        if (m == 1 && proven_neg(point[0])) return hit_of(res, p, q);
        if (m == 2 && ((proven_neg(point[0]) && proven_pos(point[1])) ||
                       (proven_pos(point[0]) && proven_neg(point[1])))) {
            return hit_of(res, p, q);
        }
    };
    const auto decide = [&](Level::Scanned& z, std::size_t k, const UpInterval* point) {
        const Piece& c = pieces_[k];
        decide_piece(z.res, piece_values_[k], c.p, c.q, z.s.tmax, point);
    };
    const auto add_points_of = [&](std::vector<LaneBox>& boxes, const Ray& ray, const UpInterval& e,
                                   double p, double q) {
        const int m = points_for(e);
        if (m == 2) boxes.push_back(lane_box(ray, p, p));
        if (m >= 1) boxes.push_back(lane_box(ray, q, q));
    };
    const auto add_points = [&](std::vector<LaneBox>& boxes, std::size_t k) {
        const Piece& c = pieces_[k];
        add_points_of(boxes, px(c.i, c.j).ray, piece_values_[k], c.p, c.q);
    };

    // Each ray's first piece not proven free by its enclosure, decided by its points (a second
    // batched evaluation).
    std::vector<std::size_t>& first = first_piece_;  // per ray: the piece it stands at, or n
    std::vector<std::size_t>& at = point_lane_;      // per ray: its first point lane
    const std::size_t rays = level.scanned.size();
    first.assign(rays, n);
    at.assign(rays, 0);
    points_.clear();
    for (std::size_t ray = 0; ray < rays; ++ray) {
        Level::Scanned& z = level.scanned[ray];
        for (std::size_t k = z.begin; k < z.end; ++k) {
            ++z.res.evals.interval;
            if (piece_proof_[k] != Proof::Excluded) {
                first[ray] = k;
                break;
            }
        }
        if (first[ray] == n) continue;  // every piece proven free: Miss
        at[ray] = points_.size();
        add_points(points_, first[ray]);
    }
    if (!points_.empty()) eval_lanes(list, points_.data(), points_.size(), lane_values_, &level);
    std::size_t open = 0;  // rays still undecided
    for (std::size_t ray = 0; ray < rays; ++ray) {
        if (first[ray] == n) continue;
        decide(level.scanned[ray], first[ray], lane_values_.data() + at[ray]);
        open += level.scanned[ray].res.status == Status::Unknown;
    }

    // The undecided rays, where the list has a tangent list (expr/tangent.h): the mean value form
    // g(c) + G′·(P − c) on their piece P = [p, q] and on every later piece that its enclosure
    // does not prove free — G′ ⊇ g′ over the piece and g at its middle c = o + tc·d — with the
    // later pieces' points, all lanes of one walk of the tangent list (its values are the list's,
    // bit for bit). Then each ray goes on from its piece as scan() does: a piece the form proves
    // free is passed, the next one decided by its points or its form. It is what decides a
    // polynomial's pieces near its surface; without it, after_points() tries the form one ray and
    // one piece at a time.
    // A list with kinks: its forms are looser at the kinks' ties, so they are tried while they
    // pay in the root tile (otherwise each ray's form is one Dual walk, piece_mean_value()).
    const expr::TangentKind kind = open > 0 && options_.lane_mean_value
                                       ? lane_tangent_kind(list, depth, level)
                                       : expr::TangentKind::None;
    const bool kinked = kind == expr::TangentKind::Kinked;
    const expr::TangentList* tl =
        kind == expr::TangentKind::Smooth || (kinked && kink_forms_.attempt())
            ? lane_tangent(list, depth, level)
            : nullptr;
    std::size_t forms_tried = 0, forms_proven = 0;
    if (tl != nullptr) {
        form_boxes_.clear();
        dirs_.clear();
        form_of_.assign(n, n);
        // Per piece: its lane (the piece; its centre next; then its points), none if not asked.
        for (std::size_t ray = 0; ray < rays; ++ray) {
            const Level::Scanned& z = level.scanned[ray];
            if (z.res.status != Status::Unknown) continue;
            const Ray& full = px(z.i, z.j).ray;
            for (std::size_t k = first[ray]; k < z.end; ++k) {
                if (piece_proof_[k] != Proof::None) continue;
                const Piece& c = pieces_[k];
                form_of_[k] = form_boxes_.size();
                form_boxes_.push_back(lanes_[k]);
                const double tc = middle(c.p, c.q);
                form_boxes_.push_back(lane_box(full, tc, tc));  // holds the point o + tc·d
                if (k != first[ray]) add_points(form_boxes_, k);
            }
            dirs_.resize(form_boxes_.size(), full.d);
        }
        eval_tangent_lanes(*tl, form_boxes_.data(), dirs_.data(), form_boxes_.size(), lane_values_,
                           lane_slopes_, &level);
    }
    // The mean value form on a piece [p, q] of enclosure e from its lanes: G′ (the derivative
    // over the piece) and the value at its middle.
    const auto lane_form = [&](const UpInterval& e, const UpInterval& g1, const UpInterval& m,
                               double p, double q, RayResult& res) {
        const Proof pr = segment_form(e, g1, m, p, q, res);
        if (pr == Proof::Unusable) return Proof::None;
        stats.lane_forms += pr != Proof::None;
        ++forms_tried;
        forms_proven += pr != Proof::None;
        return pr;
    };
    const auto form = [&](std::size_t k, RayResult& res) {
        const std::size_t l = form_of_[k];
        return lane_form(piece_values_[k], lane_slopes_[l], lane_values_[l + 1], pieces_[k].p,
                         pieces_[k].q, res);
    };
    // Each undecided ray from its piece on, as scan() and after_points() go on: the piece's mean
    // value form (from the lanes, or one Dual walk without a tangent list) decides it, or the
    // piece is scanned again in quarters, where a Hit or an Unknown is the answer. A piece proven
    // free passes the ray to its next piece that the lanes' enclosures do not prove free, decided
    // by its points (the lanes', or two point walks), else as this one (a scan afresh from there
    // would evaluate the later pieces again).
    UpInterval points[2];
    if (tl == nullptr && scan_.size() < list.size()) scan_.resize(list.size());
    const auto point = [&](const Ray& ray, double t) {
        expr::detail::run<UpInterval>(list, ray_box(ray, t, t), scan_.data());
        return scan_[list.back().out];
    };
    // Ray z's piece k is free: its next piece not proven free, decided by its points; false when
    // that decides the ray (a Miss past its last piece, or a Hit).
    const auto next = [&](Level::Scanned& z, std::size_t& k) {
        do {
            ++k;
            if (k < z.end) ++z.res.evals.interval;
        } while (k < z.end && piece_proof_[k] == Proof::Excluded);
        if (k == z.end) {
            z.res.status = Status::Miss;
            return false;
        }
        if (tl != nullptr) {
            decide(z, k, lane_values_.data() + form_of_[k] + 2);
        } else {
            const Piece& e = pieces_[k];
            const Ray& full = px(e.i, e.j).ray;
            const int m = points_of(k);
            if (m == 2) points[0] = point(full, e.p);
            if (m >= 1) points[m - 1] = point(full, e.q);
            decide(z, k, points);
        }
        return z.res.status == Status::Unknown;
    };
    // Ray z undecided at its piece k: its forms there and on; true when it waits for the
    // quarters of piece k (its form does not decide it), false when it is decided.
    const auto go_on = [&](Level::Scanned& z, std::size_t& k) {
        for (;;) {
            const Piece& c = pieces_[k];
            const Proof pr =
                tl != nullptr ? form(k, z.res) : piece_mean_value(list, z.s, c.p, c.q, z.res);
            if (pr == Proof::Inside) {
                hit_of(z.res, c.p, c.p);
                return false;
            }
            if (pr == Proof::None) return true;
            if (!next(z, k)) return false;
        }
    };
    waiting_.clear();
    for (std::size_t ray = 0; ray < rays; ++ray) {
        Level::Scanned& z = level.scanned[ray];
        if (z.res.status == Status::Unknown && go_on(z, first[ray])) waiting_.push_back({ray});
    }
    // The quarters of the waiting rays' pieces, in rounds: each quarter one lane of a batched
    // evaluation, then the points of each ray's first quarter not proven free another; each
    // ray's quarters decided as scan() decides them (the same enclosures, bit for bit), with
    // after_points() on a quarter that they leave undecided.
    while (!waiting_.empty()) {
        stats.quarter_pieces += waiting_.size();
        quarter_boxes_.clear();
        quarter_t_.clear();
        for (Waiting& v : waiting_) {
            const Level::Scanned& z = level.scanned[v.ray];
            const Piece& c = pieces_[first[v.ray]];
            const Ray& full = px(z.i, z.j).ray;
            v.seg = z.s;
            v.seg.tmin = c.p;
            v.seg.tmax = c.q;
            const double w = 0.25 * (c.q - c.p);
            const int m = pieces_of(v.seg, w);
            v.box = quarter_boxes_.size();
            for (int j = 0; j < m; ++j) {
                const auto [lo, hi] = piece(v.seg, w, j, m);
                if (!(lo < hi)) continue;
                quarter_boxes_.push_back(lane_box(full, lo, hi));
                quarter_t_.push_back({lo, hi});
            }
            v.count = quarter_boxes_.size() - v.box;
        }
        eval_lanes(list, quarter_boxes_.data(), quarter_boxes_.size(), quarter_values_, &level);
        points_.clear();
        quarter_dirs_.clear();
        for (Waiting& v : waiting_) {
            const Level::Scanned& z = level.scanned[v.ray];
            const Ray& full = px(z.i, z.j).ray;
            v.res = RayResult{};
            v.res.status = Status::Miss;
            v.first = v.count;
            for (std::size_t j = 0; j < v.count; ++j) {
                ++v.res.evals.interval;
                if (proof(quarter_values_[v.box + j]) != Proof::Excluded) {
                    v.first = j;
                    break;
                }
            }
            if (v.first == v.count) continue;
            const UpInterval& e = quarter_values_[v.box + v.first];
            const auto [lo, hi] = quarter_t_[v.box + v.first];
            v.points = points_.size();
            v.m = points_for(e);
            add_points_of(points_, full, e, lo, hi);
            if (tl != nullptr && v.m >= 1) {  // the quarter's form: its box, then its centre
                points_.push_back(quarter_boxes_[v.box + v.first]);
                const double tc = middle(lo, hi);
                points_.push_back(lane_box(full, tc, tc));
            }
            quarter_dirs_.resize(points_.size(), full.d);
        }
        if (!points_.empty() && tl != nullptr) {
            eval_tangent_lanes(*tl, points_.data(), quarter_dirs_.data(), points_.size(),
                               quarter_points_, quarter_slopes_, &level);
        } else if (!points_.empty()) {
            eval_lanes(list, points_.data(), points_.size(), quarter_points_, &level);
        }
        still_.clear();
        for (Waiting& v : waiting_) {
            Level::Scanned& z = level.scanned[v.ray];
            std::size_t& k = first[v.ray];
            if (v.count == 0) continue;  // no quarter to look at: Unknown from the piece on
            if (v.first < v.count) {
                const UpInterval& e = quarter_values_[v.box + v.first];
                const auto [lo, hi] = quarter_t_[v.box + v.first];
                RayResult& res = v.res;
                decide_piece(res, e, lo, hi, v.seg.tmax, quarter_points_.data() + v.points);
                if (res.status == Status::Unknown && tl != nullptr && v.m >= 1) {
                    // The quarter's form lanes follow its points (taken where it has points).
                    const std::size_t l = v.points + static_cast<std::size_t>(v.m);
                    const Proof pr =
                        lane_form(e, quarter_slopes_[l], quarter_points_[l + 1], lo, hi, res);
                    res = after_points(list, v.seg, lo, hi, res, 1, &pr);
                } else if (res.status == Status::Unknown) {
                    res = after_points(list, v.seg, lo, hi, res, 1);
                }
                res.evals += z.res.evals;
                if (res.status != Status::Miss) {
                    if (res.status == Status::Unknown) res.t_hi = z.s.tmax;
                    z.res = res;
                    continue;
                }
                z.res.evals = res.evals;
            } else {
                z.res.evals += v.res.evals;
            }
            // Piece k proven free in quarters: on to the next one.
            if (next(z, k) && go_on(z, k)) still_.push_back(v);
        }
        waiting_.swap(still_);
    }
    if (kinked && tl != nullptr) kink_forms_.wins += 2 * forms_proven >= forms_tried;
    // Settled in pixel order; a split recurses into deeper levels, which do not touch this one.
    bool deferred = false;
    for (std::size_t ray = 0; ray < level.scanned.size(); ++ray) {
        const Level::Scanned& z = level.scanned[ray];  // settle() recurses into deeper levels only
        if (z.deferred) {
            deferred = true;
            ++stats.coarse_deferred;
            spend(z.i, z.j, z.res.evals);
            continue;
        }
        stats.together += z.res.status != Status::Unknown;
        settle(z.i, z.j, z.s, z.res, true, list, tape, level, depth);
    }
    if (!deferred) return taken;
    // The deferred rays, group by group, in the node's halves (deeper levels: this one's
    // scanned rays are read before they start).
    std::size_t begin = 0;
    for (int g = 0; g < count; ++g) {
        const std::size_t end = group_end[g];
        if (end > begin) {
            descend_deferred(groups[g].r, groups[g].a, groups[g].b, list, tape, level, begin, end,
                             depth);
        }
        begin = end;
    }
    return taken;
}

void Walker::descend_deferred(const Rect& r, double a, double b, const Ssa& list,
                              const expr::Tape* tape, Level& level, std::size_t begin,
                              std::size_t end, unsigned depth) {
    // The group's rays that are not deferred are closed while the halves run: those still open
    // are proven free on [a, b] (their answers past b come later). The halves run at depth + 1
    // and leave this level's scanned rays as they are.
    const std::size_t mark = hidden_.size();
    bool any = false;
    for (std::size_t ray = begin; ray < end; ++ray) {
        const Level::Scanned& z = level.scanned[ray];
        if (z.deferred) {
            any = true;
        } else if (px(z.i, z.j).open) {
            set_open(z.i, z.j, false);
            hidden_.emplace_back(z.i, z.j);
        }
    }
    if (any) {
        const double m = 0.5 * a + 0.5 * b;
        deferred_half(r, a, m, list, tape, depth + 1);
        deferred_half(r, m, b, list, tape, depth + 1);
    }
    for (std::size_t k = mark; k < hidden_.size(); ++k)
        set_open(hidden_[k].first, hidden_[k].second, true);
    hidden_.resize(mark);
}

void Walker::deferred_half(const Rect& r, double a, double b, const Ssa& list,
                           const expr::Tape* tape, unsigned depth) {
    // A half holds a few rays (three on average on Barth's sextic), each of which the scan takes
    // its segment form on: a node's interval box and mean value form over them all, a scalar
    // walk and one of the tangent list, prove nothing the forms do not. Without them, Barth's
    // 512² zero set takes 1.2% fewer instructions (docs/benchmarks.md, session 31). A list that
    // prunes (the tape has min/max) or folds reads the node's box enclosures (level.values) in
    // the descent below: node() makes them.
    if (choices_ || may_fold(list)) {
        node(r, a, b, list, tape, depth);
        return;
    }
    const Hull hull = hull_of(r, a, b);
    if (hull.count == 0) return;
    a = std::max(a, hull.tlo);
    b = std::min(b, hull.thi);
    if (scans_together(hull.count, list, depth) &&
        scan_together(r, a, b, list, tape, levels_[depth], depth, hull)) {
        return;
    }
    node(r, a, b, list, tape, depth, &hull);
}

}  // namespace certray::tracers::detail::coherent
