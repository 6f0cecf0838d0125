// tracers/coherent_segments.cpp — the coherent walk's forms over a ray's whole scanned segment:
// first-order (free where the ray runs beside the surface), monotone segments bracketed by
// interval Newton steps, and second-order forms (tracers/coherent_walker.h;
// docs/theory/coherent.md, "Segment forms", "Monotone segments", "Newton brackets", "Second-order
// segment forms").
#include <algorithm>
#include <cmath>

#include "tracers/coherent_walker.h"

namespace certray::tracers::detail::coherent {

void Walker::take_segment_forms(const Ssa& list, unsigned depth, Level& level) {
    // Each open ray's whole segment S gets the mean value form in t, g(c) + G′·(S − c): G′ ⊇ g′
    // along the ray over S (a lane of one walk of the tangent list, which also gives g's plain
    // enclosure over S) and g at its middle c (a lane of one walk of the list). A segment it
    // proves free needs no pieces: rays that run beside the surface (grazing it, or between close
    // sheets) are proven so, where their pieces' plain enclosures are as wide as the box a piece
    // spans. Short lists keep their pieces: there a walk's cost is mostly its own, not its lanes'.
    // At a kink G′ encloses Clarke's derivative: the form holds (Lebourg's mean value theorem),
    // and a G′ of one strict sign still makes g strictly monotone. Lists with kinks get the forms
    // only where folded: the bear's folded lists pay (−9%), the molecule's unfolded ones of
    // thousands of instructions (+11%) and the colonnade's short ones (+4%) do not.
    if (!options_.segment_forms || list.size() < kSegmentFormList) return;
    const expr::TangentKind kind = lane_tangent_kind(list, depth, level);
    if (kind == expr::TangentKind::None ||
        (kind == expr::TangentKind::Kinked && level.folded.list.empty())) {
        return;
    }
    const expr::TangentList& tl = *lane_tangent(list, depth, level);
    form_boxes_.clear();
    points_.clear();
    dirs_.clear();
    form_of_.clear();
    monotone_.clear();
    second_rays_.clear();
    for (std::size_t ray = 0; ray < level.scanned.size(); ++ray) {
        const Level::Scanned& z = level.scanned[ray];
        // A form costs two lanes (one of the tangent list, one of the list) in walks that run
        // anyway; a segment of one piece keeps its piece.
        if (z.res.status != Status::Miss || !(z.s.tmin < z.s.tmax) ||
            fewer_pieces(z.s, piece_width(z.s), kSegmentFormPieces)) {
            continue;
        }
        const Ray& full = px(z.i, z.j).ray;
        const double tc = middle(z.s.tmin, z.s.tmax);
        form_of_.push_back(ray);
        form_boxes_.push_back(lane_box(full, z.s.tmin, z.s.tmax));
        points_.push_back(lane_box(full, tc, tc));
        dirs_.push_back(full.d);
    }
    // On a folded list, where the segments' plain enclosures prove enough of them free (3 in 10
    // in the root tile so far, from the forms' own value lanes until then), those enclosures
    // come first, one walk of the list, and only the segments they leave walk the tangent list
    // (whose value lanes are the same enclosures, bit for bit) and the list at their middles:
    // the same decisions, fewer lanes. A walk of the tangent list and one of the list cost about
    // three of the list. The bear's heightmap: 54% of its segments so, the form itself 0.5%.
    // Short unfolded lists (the particles' 80 instructions) took up to 19% longer: a walk's
    // own cost is then most of it.
    const std::size_t tried = form_of_.size();
    const bool plain_first = options_.segment_enclosures_first && !level.folded.list.empty() &&
                             plain_tried_ > 0 && 10 * plain_free_ >= 3 * plain_tried_;
    plain_tried_ += tried;
    if (tried > 0 && plain_first) {
        eval_lanes(list, form_boxes_.data(), tried, lane_values_, &level);
        std::size_t rest = 0;
        for (std::size_t l = 0; l < tried; ++l) {
            Level::Scanned& z = level.scanned[form_of_[l]];
            ++z.res.evals.interval;
            if (proof(lane_values_[l]) == Proof::Excluded) {
                ++plain_free_;
                prove_free(z);
                continue;
            }
            form_of_[rest] = form_of_[l];
            form_boxes_[rest] = form_boxes_[l];
            points_[rest] = points_[l];
            dirs_[rest] = dirs_[l];
            ++rest;
        }
        form_of_.resize(rest);
        form_boxes_.resize(rest);
        points_.resize(rest);
        dirs_.resize(rest);
    }
    if (!form_of_.empty()) {
        // The middles' values: lanes of the tangent list's walk where they fit in its vector
        // (its value lanes are the list's, bit for bit: a walk of the list spared), else a walk
        // of the list.
        const std::size_t n = form_of_.size();
        if (options_.middles_in_forms && 2 * n <= kWalkLanes) {
            form_boxes_.insert(form_boxes_.end(), points_.begin(), points_.end());
            dirs_.resize(2 * n);
            std::copy_n(dirs_.begin(), n, dirs_.begin() + static_cast<std::ptrdiff_t>(n));
            eval_tangent_lanes(tl, form_boxes_.data(), dirs_.data(), 2 * n, lane_values_,
                               lane_slopes_, &level);
            if (quarter_points_.size() < n) quarter_points_.resize(n);
            std::copy_n(lane_values_.begin() + static_cast<std::ptrdiff_t>(n), n,
                        quarter_points_.begin());
        } else {
            eval_tangent_lanes(tl, form_boxes_.data(), dirs_.data(), n, lane_values_, lane_slopes_,
                               &level);
            eval_lanes(list, points_.data(), points_.size(), quarter_points_, &level);
        }
        for (std::size_t l = 0; l < form_of_.size(); ++l) {
            Level::Scanned& z = level.scanned[form_of_[l]];
            const UpInterval& e = lane_values_[l];
            const UpInterval& g1 = lane_slopes_[l];
            ++z.res.evals.interval;
            const bool plain = proof(e) == Proof::Excluded;  // only without plain_first
            plain_free_ += plain;
            if (plain || segment_form(e, g1, quarter_points_[l], z.s.tmin, z.s.tmax, z.res) ==
                             Proof::Excluded) {
                prove_free(z);
            } else if (options_.monotone_segments && e.defined && finite(g1) &&
                       (g1.lower() > 0 || g1.upper() < 0)) {
                // g′ (Clarke's at kinks) keeps one strict sign: g is strictly monotone (on a
                // folded list h(·, s) is, for each value s of the fixed inputs, which is what
                // decide_monotone() needs: docs/theory/coherent.md).
                monotone_.push_back({form_of_[l], z.s.tmin, z.s.tmax, 0, g1.upper() < 0,
                                     middle(z.s.tmin, z.s.tmax), quarter_points_[l], false, g1});
            } else if (options_.clip_forms && e.defined && finite(g1) &&
                       !quarter_points_[l].is_empty() && quarter_points_[l].defined) {
                // The form as a line in t narrows the segment its pieces cover.
                const LinearForm lin{quarter_points_[l], g1, middle(z.s.tmin, z.s.tmax), true};
                double lo = z.s.tmin, hi = z.s.tmax;
                clip_to_line(lin, lo, hi);
                stats.clipped += lo != z.s.tmin || hi != z.s.tmax;
                if (!(lo <= hi)) {
                    prove_free(z);
                } else {
                    z.s.tmin = lo;
                    z.s.tmax = hi;
                    // The second-order form can prove the segment free only where g at its
                    // middle is proven away from 0 on the free side.
                    const UpInterval& gc = quarter_points_[l];
                    if (solid_ ? gc.lower() > 0 : strict_sign(gc) != 0) {
                        second_rays_.push_back(form_of_[l]);
                    }
                }
            }
        }
        try_second_order(list, level);
        decide_monotone(list, level);
    }
}

void Walker::try_second_order(const Ssa& list, Level& level) {
    // Segments whose form neither proved them free nor found g monotone (G′ holds 0: the ray
    // runs beside the surface, or through it) get the second-order form of g(t) = f(o + t·d)
    // about the middle c of S = [a, b]: g(t) ∈ g(c) + g′(c)·(t − c) + ½·G″·(t − c)² (Taylor's
    // theorem with Lagrange's remainder; g is C² where the smooth list is defined, G″ ⊇ g″ over
    // S finite). Its error is quadratic in the width and g′(c) is a point's, so where G′ over S
    // is wide (the dependency of a polynomial's interval evaluation) but g stays away from 0 — a
    // ray that passes near the surface without meeting it — it proves S free where the
    // first-order form needed pieces. Where G″ keeps one strict sign, the model's extreme over
    // all t and every curvature k in G″ is g(c) − g′(c)²/(2·k) at the bound of G″ nearest 0, on
    // the side G″ points away from: the form is that tight wherever the ray's closest approach
    // lies in S. One walk of the second-order list, two lanes a segment (its box: G″; its
    // middle: g(c) and g′(c)).
    if (second_rays_.empty() || !tape_second_ || &list != &tape_.ssa() ||
        !level.folded.list.empty() || !second_trial_.attempt()) {
        return;
    }
    const std::size_t n = second_rays_.size();
    second_boxes_.clear();
    second_dirs_.clear();
    for (const std::size_t ray : second_rays_) {
        const Level::Scanned& z = level.scanned[ray];
        const Ray& full = px(z.i, z.j).ray;
        const double tc = middle(z.s.tmin, z.s.tmax);
        second_boxes_.push_back(lane_box(full, z.s.tmin, z.s.tmax));
        second_boxes_.push_back(lane_box(full, tc, tc));
        second_dirs_.push_back(full.d);
        second_dirs_.push_back(full.d);
    }
    eval_tangent_lanes(*tape_tangent_, second_boxes_.data(), second_dirs_.data(), 2 * n, second_g_,
                       second_g1_, nullptr, &*tape_second_, &second_g2_);
    std::size_t proven = 0;
    for (std::size_t k = 0; k < n; ++k) {
        Level::Scanned& z = level.scanned[second_rays_[k]];
        z.res.evals.gradient += 1;
        const UpInterval &e = second_g_[2 * k], &g1 = second_g1_[2 * k], &g2 = second_g2_[2 * k];
        if (!e.defined || !g1.defined || !g2.defined || !finite(g1) || !finite(g2)) continue;
        const UpInterval &v = second_g_[2 * k + 1], &d = second_g1_[2 * k + 1];
        if (!v.defined || !finite(v) || !finite(d)) continue;
        const double c = middle(z.s.tmin, z.s.tmax);
        const UpInterval s = UpInterval(z.s.tmin, z.s.tmax) - UpInterval(c);
        const UpInterval form = v + d * s + UpInterval(0.5) * g2 * square(s);
        double lo = form.lower(), hi = form.upper();
        if (g2.lower() > 0) {
            lo = std::max(lo, (v - square(d) / (UpInterval(2.0) * UpInterval(g2.lower()))).lower());
        } else if (g2.upper() < 0) {
            hi = std::min(hi, (v - square(d) / (UpInterval(2.0) * UpInterval(g2.upper()))).upper());
        }
        if (!(lo <= hi)) continue;
        if (proof(UpInterval(lo, hi)) == Proof::Excluded) {
            ++proven;
            ++stats.second_order;
            prove_free(z);
        }
    }
    second_trial_.wins += proven == n;
}

void Walker::decide_monotone(const Ssa& list, Level& level) {
    // g at the middle tc (the form's lane) and, where that does not decide, at one end (one
    // batched walk; below). Points of one strict sign (the solid: both ≥ 0) prove the part
    // between them free; points of strict opposite signs (the zero set) hold a zero (exactly one
    // unless the list is folded), bracketed by halving [lo, hi] at points (a walk per round)
    // until it is as deep as a piece: Hit [lo, hi], with none before lo. The solid's g
    // decreasing from g(lo) ≥ 0 to g(hi) < 0 enters once, bracketed alike. A midpoint whose side
    // is not proven ends the halving: the ray is scanned in pieces from lo.
    // With newton_brackets, g's value at a point c also gives the interval Newton step
    // c − g(c)/G′, which holds every zero of g on the segment (G′ ⊇ g′ there, of one strict
    // sign; docs/theory/coherent.md): the bracket is narrowed to it, and where the step from tc
    // ends inside the segment, g has crossed 0 by its far end, so it brackets the zero without
    // the end's point. Near a simple zero the step is a few ulps wide where g(c) is small.
    if (monotone_.empty()) return;
    // The side of a value: the solid's ≥ 0 (1) or < 0 (−1), the zero set's strict sign; 0: not
    // proven.
    const auto side = [&](const UpInterval& v) {
        if (!solid_) return strict_sign(v);
        return !v.defined ? 0 : v.lower() >= 0 ? 1 : v.upper() < 0 ? -1 : 0;
    };
    const bool newton = options_.newton_brackets;
    // The Newton step from c, empty where g(c) is not proven defined and bounded.
    const auto step = [&](const Monotone& mo, double c, const UpInterval& gc) {
        if (!newton || !gc.defined || !finite(gc)) return UpInterval::empty();
        return UpInterval(c) - gc / mo.slope;
    };
    // [lo, hi] narrowed to the step n: every zero lies in n. The solid's g ≤ 0 at n's upper end
    // (past every zero), so g < 0 just after it (g strictly decreasing): hi is the next double.
    const auto narrow = [&](Monotone& mo, const UpInterval& n) {
        if (n.is_empty()) return;
        mo.lo = std::max(mo.lo, n.lower());
        const double up = solid_ ? std::nextafter(n.upper(), kInf) : n.upper();
        mo.hi = std::min(mo.hi, up);
    };
    // g at the middle tc is known. Where its side is proven, g moves away from g(tc) towards one
    // end (the zero set: decreasing from > 0 or increasing from < 0 moves towards 0 after tc; the
    // solid decreasing from ≥ 0 likewise), so the other half has g(tc)'s side, and the end on
    // the zero's side either has that side too (free) or the other one (a bracket half as deep).
    // The solid increasing: g(a) is its least value. Where g(tc)'s side is not proven (none of
    // the gallery's segments), the zero lies near tc: the ray is scanned in pieces.
    // The step from tc narrows that half to where a zero may be; a step that misses it proves
    // the half free of zeros (free where g(tc)'s side is: the solid's g < 0 there is left to
    // its pieces). A step whose far end lies inside the segment brackets the zero by itself:
    // g there has crossed 0 (the mean value theorem with G′'s bound nearest 0), no end point.
    std::size_t open = 0;
    ready_.clear();
    points_.clear();
    for (Monotone& mo : monotone_) {
        const int sc = side(mo.centre);
        if (sc == 0) continue;
        Level::Scanned& z = level.scanned[mo.ray];
        mo.sign = sc;
        mo.high = mo.decreasing ? sc == 1 : !solid_ && sc == -1;
        mo.bracket = !solid_ || mo.decreasing;
        mo.step_lo = mo.high ? mo.tc : mo.lo;
        mo.step_hi = mo.high ? mo.hi : mo.tc;
        if (mo.bracket) {
            const UpInterval n = step(mo, mo.tc, mo.centre);
            Monotone half = mo;
            half.lo = mo.step_lo;
            half.hi = mo.step_hi;
            narrow(half, n);
            if (!(half.lo <= half.hi)) {
                if (!solid_ || sc == 1) prove_free(z);
                continue;  // the solid's g < 0 on [a, tc]: its pieces
            }
            mo.step_lo = half.lo;
            mo.step_hi = half.hi;
            if (!n.is_empty() && (mo.high ? n.upper() < mo.hi : n.lower() > mo.lo)) {
                half.sign = mo.high ? sc : -sc;
                ready_.push_back(half);
                continue;
            }
        }
        const double end = mo.high ? mo.hi : mo.lo;
        points_.push_back(lane_box(px(z.i, z.j).ray, end, end));
        monotone_[open++] = mo;
    }
    monotone_.resize(open);
    if (open > 0) eval_lanes(list, points_.data(), points_.size(), quarter_points_, &level);
    open = 0;
    for (std::size_t k = 0; k < monotone_.size(); ++k) {
        Monotone& mo = monotone_[k];
        Level::Scanned& z = level.scanned[mo.ray];
        const int sc = mo.sign, s_end = side(quarter_points_[k]);
        ++z.res.evals.interval;
        bool free = false, bracket = false;
        if (!mo.bracket) {
            free = s_end == 1;  // the solid increasing: g(a) ≥ 0, its least value
        } else if (s_end == sc) {
            free = !solid_ || sc == 1;  // the solid's g < 0 at both: it entered at a
        } else if (s_end == -sc) {
            bracket = true;
            // The half after the middle (g(tc) keeps its side on [a, tc]), else the one before
            // it, as far as the step leaves it.
            mo.lo = mo.step_lo;
            mo.hi = mo.step_hi;
            if (!mo.high) mo.sign = s_end;
        } else if (mo.high) {
            z.s.tmin = mo.step_lo;  // free before the step's part: its pieces from there
        }
        if (free) {
            prove_free(z);
            continue;
        }
        if (!bracket) continue;
        monotone_[open++] = mo;
    }
    monotone_.resize(open);
    monotone_.insert(monotone_.end(), ready_.begin(), ready_.end());
    stats.monotone_segments += monotone_.size();
    stats.newton_brackets += ready_.size();
    while (!monotone_.empty()) {
        // Halving: the brackets deeper than a piece get their midpoints.
        points_.clear();
        open = 0;
        for (const Monotone& mo : monotone_) {
            Level::Scanned& z = level.scanned[mo.ray];
            const double mid = 0.5 * mo.lo + 0.5 * mo.hi;
            if (mo.hi - mo.lo <= piece_width(z.s) || !(mo.lo < mid && mid < mo.hi)) {
                hit_of(z.res, mo.lo, mo.hi);  // one zero in [lo, hi], none before
                continue;
            }
            points_.push_back(lane_box(px(z.i, z.j).ray, mid, mid));
            monotone_[open++] = mo;
        }
        monotone_.resize(open);
        if (open == 0) break;
        eval_lanes(list, points_.data(), points_.size(), quarter_points_, &level);
        open = 0;
        for (std::size_t k = 0; k < monotone_.size(); ++k) {
            Monotone& mo = monotone_[k];
            Level::Scanned& z = level.scanned[mo.ray];
            const double mid = 0.5 * mo.lo + 0.5 * mo.hi;
            ++z.res.evals.interval;
            // The solid keeps g(lo) ≥ 0 (so g ≥ 0 on [a, lo]) and g < 0 at hi.
            const int sm = side(quarter_points_[k]);
            if (sm == mo.sign) {
                mo.lo = mid;
            } else if (sm == -mo.sign) {
                mo.hi = mid;
            }
            const double width = mo.hi - mo.lo, lo = mo.lo;
            narrow(mo, step(mo, mid, quarter_points_[k]));
            // A side not proven and a step that leaves more than half: its pieces from lo
            // (free before it). (A step that misses the bracket cannot be, as the bracket holds a
            // zero; were it to, the pieces from lo would answer.)
            if (!(mo.lo <= mo.hi)) {
                z.s.tmin = lo;
                continue;
            }
            if (sm == 0 && !(mo.hi - mo.lo <= 0.5 * width)) {
                z.s.tmin = mo.lo;
                continue;
            }
            monotone_[open++] = mo;
        }
        monotone_.resize(open);
    }
}

}  // namespace certray::tracers::detail::coherent
