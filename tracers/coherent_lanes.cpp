// tracers/coherent_lanes.cpp — the coherent walk's walks in lanes (boxes, their folded lists,
// tangent lists) and the nodes' mean value forms with their lines (tracers/coherent_walker.h;
// docs/theory/coherent.md, "Mean value forms in lanes", "Lists folded to their boxes").
#include <algorithm>
#include <cassert>
#include <cfenv>
#include <cmath>

#include "expr/batch_simd.h"
#include "expr/eval.h"
#include "expr/eval_batch.h"
#include "expr/eval_interval_batch.h"
#include "tracers/coherent_walker.h"

#if CERTRAY_BATCH_X86
#include <immintrin.h>
#endif

namespace certray::tracers::detail::coherent {
namespace {

#if CERTRAY_BATCH_X86
/// Lanes k0 … k0 + 7 of the binary32 inputs `to` from boxes k0 … k0 + 7 (48 doubles: each box's
/// lo[3], hi[3]), as load_lanes' loop sets them, bit for bit, in the walks' upward mode: the six
/// bounds of the eight boxes transposed (three two-source permutes and two blends a bound), each
/// rounded outward by one conversion of eight (a lower bound as −RU(−lo)), and an axis that is
/// not lo ≤ hi given empty()'s NaN bounds. Sets bit k of ok[c] where box k's axis c is lo ≤ hi.
[[gnu::target("avx512f")]] void load8_avx512(const LaneBox* boxes, expr::IntervalLanesF* const* to,
                                             int k0, std::uint64_t* ok) {
    // Bound e (lo[0..2], hi[0..2]) of box j is double 6j + e of the block: from the first pair
    // of registers where 6j + e < 16, the second where < 32, else the third.
    struct Transpose {
        alignas(64) long long index[3][6][8];
        unsigned char in_first[6], in_second[6];
    };
    static constexpr Transpose t = [] {
        Transpose r{};
        for (int e = 0; e < 6; ++e) {
            for (int j = 0; j < 8; ++j) {
                const int x = 6 * j + e;
                for (int q = 0; q < 3; ++q) r.index[q][e][j] = (x - 16 * q) & 15;
                if (x < 16) {
                    r.in_first[e] |= static_cast<unsigned char>(1u << j);
                } else if (x < 32) {
                    r.in_second[e] |= static_cast<unsigned char>(1u << j);
                }
            }
        }
        return r;
    }();
    static_assert(sizeof(LaneBox) == 6 * sizeof(double), "a box is its six bounds");
    const double* p = boxes[k0].lo;
    const __m512d z0 = _mm512_loadu_pd(p), z1 = _mm512_loadu_pd(p + 8),
                  z2 = _mm512_loadu_pd(p + 16), z3 = _mm512_loadu_pd(p + 24),
                  z4 = _mm512_loadu_pd(p + 32), z5 = _mm512_loadu_pd(p + 40);
    __m512d bound[6];
    for (int e = 0; e < 6; ++e) {
        const __m512d a = _mm512_permutex2var_pd(z0, _mm512_load_si512(t.index[0][e]), z1);
        const __m512d b = _mm512_permutex2var_pd(z2, _mm512_load_si512(t.index[1][e]), z3);
        const __m512d c = _mm512_permutex2var_pd(z4, _mm512_load_si512(t.index[2][e]), z5);
        bound[e] =
            _mm512_mask_blend_pd(t.in_first[e], _mm512_mask_blend_pd(t.in_second[e], c, b), a);
    }
    // An axis that is not lo ≤ hi gets empty()'s bounds (NaN), converted as load_lanes' loop
    // converts them (AVX-512F alone: the integer xor, the blend of doubles).
    const __m512i sign = _mm512_set1_epi64(static_cast<long long>(0x8000000000000000ULL));
    const __m256 sign_f = _mm256_castsi256_ps(_mm256_set1_epi32(static_cast<int>(0x80000000u)));
    const UpInterval empty = UpInterval::empty();
    const __m512d empty_lo = _mm512_set1_pd(empty.lower()),
                  empty_hi = _mm512_set1_pd(empty.upper());
    for (int c = 0; c < 3; ++c) {
        const __mmask8 valid = _mm512_cmp_pd_mask(bound[c], bound[c + 3], _CMP_LE_OQ);
        const __m512d lo = _mm512_mask_blend_pd(valid, empty_lo, bound[c]);
        const __m512d hi = _mm512_mask_blend_pd(valid, empty_hi, bound[c + 3]);
        const __m512d neg_lo = _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(lo), sign));
        _mm256_storeu_ps(to[c]->lo + k0, _mm256_xor_ps(_mm512_cvtpd_ps(neg_lo), sign_f));
        _mm256_storeu_ps(to[c]->hi + k0, _mm512_cvtpd_ps(hi));
        ok[c] |= std::uint64_t{valid} << k0;
    }
}
#endif

}  // namespace

UpInterval Walker::mean_value(const Ssa& list, double a, double b, const double* olo,
                              const double* ohi, const double* dlo, const double* dhi,
                              const expr::TangentList* tl, LinearForm* lin) {
    const UpInterval none = UpInterval::empty();
    using D = Dual<UpInterval, 3>;
    if (duals_.size() < list.size()) duals_.resize(list.size());
    if (centre_.size() < list.size()) centre_.resize(list.size());
    count_form(list.size());
    const UpInterval t(a, b);
    const std::array<UpInterval, 3> x = segment_box(olo, ohi, dlo, dhi, a, b);
    const bool one_ray = std::equal(olo, olo + 3, ohi) && std::equal(dlo, dlo + 3, dhi);
    if (one_ray) {
        // One ray: the mean value form of g(t) = f(o + t·d) in t, g(tc) + G′(T)·(T − tc), with
        // G′ ⊇ ∇F(X)·d from one walk of Dual<UpInterval, 1> seeded with d (tighter than the form
        // over the box X, which ignores that the points lie on one line, and half the work).
        using D1 = Dual<UpInterval, 1>;
        if (duals1_.size() < list.size()) duals1_.resize(list.size());
        std::array<D1, 3> q;
        std::array<UpInterval, 3> c;
        const double tc = midpoint(t);
        for (int k = 0; k < 3; ++k) {
            const UpInterval o(olo[k]), d(dlo[k]);
            q[k] = D1(x[k], {d});
            c[k] = o + UpInterval(tc) * d;  // holds the real point o + tc·d
        }
        expr::detail::run<D1>(list, q, duals1_.data());
        const D1& g = duals1_[list.back().out];
        if (g.a.is_empty() || !g.a.defined || g.v[0].is_empty() || !std::isfinite(g.v[0].lower()) ||
            !std::isfinite(g.v[0].upper())) {
            return none;
        }
        expr::detail::run<UpInterval>(list, c, centre_.data());
        UpInterval m = centre_[list.back().out];
        if (m.is_empty() || !m.defined) return none;
        if (lin != nullptr) *lin = {m, g.v[0], tc, true};
        return m + g.v[0] * (t - UpInterval(tc));
    }
    // The form in the rays' own coordinates: for the point x = o + t·d of a ray of the node and
    // the centre x_c = oc + tc·dc (a point of the node's set: oc, dc, tc lie in the hulls),
    // x − x_c = (o − oc) + t·(d − dc) + (t − tc)·dc. Along the rays the gradient is dotted with dc
    // before it is widened by the segment's length, which the form over the box (Σ G_k·(X_k −
    // c_k)) cannot do: Barth's sextic, 512² pinhole, 7.2 → 6.7 evaluations per pixel.
    RayForm form;
    prepare_form(form, a, b, olo, ohi, dlo, dhi);
    const std::array<UpInterval, 3>& c = form.c;
    const double tc = form.tc;
    const double* oc = form.oc;
    const double* dc = form.dc;
    if (tl != nullptr) {
        // The same form from the tangent list: five lanes of one walk (ray_form_lanes), the box X
        // with the seeds e_x, e_y, e_z (the gradient's components, as the Dual walk has them) and
        // dc (∇f·dc directly: tighter than Σ G_k·dc_k), and the centre. (A scalar walk of the list
        // for the centre had paid on a first-generation Zen, 3–4%; on AVX2 and the baseline of
        // the Zen 4 of session 22 the lane is 0.96–1.02 of the time.) Interval seeds O − oc and
        // D − dc would lose the cancellations inside each component (twice as wide on Barth's
        // sextic), so those sums are taken over the components.
        ray_form_lanes(*tl, &form, 1);
        return ray_form(form, a, b, olo, ohi, dlo, dhi, lin);
    }
    std::array<D, 3> p;
    for (int k = 0; k < 3; ++k) {
        p[k] = D(x[k]);
        p[k].v[k] = UpInterval(1.0);
    }
    expr::detail::run<D>(list, p, duals_.data());
    const D& g = duals_[list.back().out];
    // Lebourg's mean value theorem (Clarke gradients cover the kinks of abs, min, max) needs f
    // defined and continuous on the whole box and a bounded gradient enclosure.
    if (g.a.is_empty() || !g.a.defined) return none;
    for (int k = 0; k < 3; ++k) {
        if (g.v[k].is_empty() || !std::isfinite(g.v[k].lower()) || !std::isfinite(g.v[k].upper())) {
            return none;
        }
    }
    expr::detail::run<UpInterval>(list, c, centre_.data());
    UpInterval m = centre_[list.back().out];
    if (m.is_empty() || !m.defined) return none;
    UpInterval along(0.0), across(0.0);
    for (int k = 0; k < 3; ++k) {
        m = m + g.v[k] * (UpInterval(olo[k], ohi[k]) - UpInterval(oc[k]));
        across = across + g.v[k] * (UpInterval(dlo[k], dhi[k]) - UpInterval(dc[k]));
        along = along + g.v[k] * UpInterval(dc[k]);
    }
    if (lin != nullptr) *lin = {m + UpInterval(tc) * across, across + along, tc, true};
    return m + t * across + along * (t - UpInterval(tc));
}

void Walker::prepare_form(RayForm& f, double a, double b, const double* olo, const double* ohi,
                          const double* dlo, const double* dhi) {
    f.x = segment_box(olo, ohi, dlo, dhi, a, b);
    f.tc = middle(a, b);
    for (int k = 0; k < 3; ++k) {
        f.oc[k] = std::clamp(0.5 * olo[k] + 0.5 * ohi[k], olo[k], ohi[k]);
        f.dc[k] = std::clamp(0.5 * dlo[k] + 0.5 * dhi[k], dlo[k], dhi[k]);
        f.c[k] = UpInterval(f.oc[k]) + UpInterval(f.tc) * UpInterval(f.dc[k]);  // oc + tc·dc
    }
}

UpInterval Walker::ray_form(const RayForm& f, double a, double b, const double* olo,
                            const double* ohi, const double* dlo, const double* dhi,
                            LinearForm* lin) {
    UpInterval m = f.m;
    if (!f.ok || m.is_empty() || !m.defined) return UpInterval::empty();
    const UpInterval t(a, b);
    UpInterval across(0.0);
    // A coordinate that does not vary (a pinhole's origin, a heightmap's direction) adds
    // G_k·[0, 0]: nothing, the term is passed.
    for (int k = 0; k < 3; ++k) {
        if (olo[k] != ohi[k]) m = m + f.g[k] * (UpInterval(olo[k], ohi[k]) - UpInterval(f.oc[k]));
        if (dlo[k] != dhi[k]) {
            across = across + f.g[k] * (UpInterval(dlo[k], dhi[k]) - UpInterval(f.dc[k]));
        }
    }
    if (lin != nullptr) {
        // At a point t, t·G·(d − dc) lies in tc·across + (t − tc)·across: the line's terms.
        *lin = {m + UpInterval(f.tc) * across, across + f.g[3], f.tc, true};
    }
    return m + t * across + f.g[3] * (t - UpInterval(f.tc));
}

void Walker::clip_to_line(const LinearForm& lin, double& a, double& b) const {
    // u = t − tc runs over [u0, u1] ⊇ [a − tc, b − tc]; over a sub-range U of it the line's
    // values are p + U·q, exactly the interval product's (each of p, q, u occurs once), which
    // proves a part free as a box's enclosure does. Where the line may vanish is found in plain
    // doubles (a guess); each cut is kept only where p + U·q over the part cut off proves it.
    const UpInterval& p = lin.p;
    const UpInterval& q = lin.q;
    if (p.is_empty() || q.is_empty() || !std::isfinite(p.lower()) || !std::isfinite(p.upper()) ||
        !std::isfinite(q.lower()) || !std::isfinite(q.upper())) {
        return;
    }
    const double u0 = -(lin.tc - a), u1 = b - lin.tc;  // rounded down, and up (upward mode)
    if (!(u0 < u1)) return;
    const auto may = [&](double u) {  // the line may vanish (the solid: be negative) at u
        const double lo = p.lower() + std::min(u * q.lower(), u * q.upper());
        const double hi = p.upper() + std::max(u * q.lower(), u * q.upper());
        return solid_ ? lo < 0 : lo <= 0 && 0 <= hi;
    };
    // Its ends lie among the roots of the bounds' lines (on u ≥ 0 and on u ≤ 0 each bound is one):
    // up to five inside (u0, u1), sorted between u0 and u1 by a network of minima and maxima
    // (the padding u1 sorts last), without the branches an insertion took at random.
    double inner[5] = {u1, u1, u1, u1, u1};
    int m = 0;
    const auto add = [&](double u) {
        if (u > u0 && u < u1) inner[m++] = u;
    };
    if (u0 < 0 && u1 > 0) add(0);
    for (const double c : {q.lower(), q.upper()}) {
        if (c == 0) continue;
        add(-p.lower() / c);
        if (!solid_) add(-p.upper() / c);
    }
    const auto order = [&](int i, int j) {
        const double x = inner[i], y = inner[j];
        inner[i] = std::min(x, y);
        inner[j] = std::max(x, y);
    };
    // Five inputs, nine comparators (Knuth, TAOCP 5.3.4).
    order(0, 1), order(3, 4), order(2, 4), order(2, 3), order(0, 3);
    order(0, 2), order(1, 4), order(1, 3), order(1, 2);
    double cut[7] = {u0};
    for (int k = 0; k < m; ++k) cut[k + 1] = inner[k];
    cut[m + 1] = u1;
    const int n = m + 2;
    int first = -1, last = -1;  // the first and last cuts where it may vanish, or just after
    for (int k = 0; k < n; ++k) {
        const bool here = may(cut[k]) || (k + 1 < n && may(0.5 * cut[k] + 0.5 * cut[k + 1]));
        const bool before = may(cut[k]) || (k > 0 && may(0.5 * cut[k - 1] + 0.5 * cut[k]));
        if (here && first < 0) first = k;
        if (before) last = k;
    }
    const double margin = 1e-6 * (u1 - u0);
    const auto free = [&](double lo, double hi) {
        return lo <= hi && proof(p + UpInterval(lo, hi) * q) == Proof::Excluded;
    };
    if (first < 0 || last < 0) {
        if (free(u0, u1)) a = kInf, b = -kInf;  // (a guess proven: no point of it may vanish)
        return;
    }
    const double front = cut[first] - margin, back = cut[last] + margin;
    if (cut[first] > u0 && front > u0 && free(u0, front)) {
        a = std::max(a, -(-lin.tc - front));  // tc + front rounded down
    }
    if (cut[last] < u1 && back < u1 && free(back, u1)) {
        b = std::min(b, lin.tc + back);  // rounded up
    }
}

void Walker::ray_form_lanes(const expr::TangentList& tl, RayForm* forms, int n) {
    if (float_lanes_) {
        ray_form_lanes_in(f32_, tl, forms, n);
    } else {
        ray_form_lanes_in(d64_, tl, forms, n);
    }
}

template <class L>
void Walker::ray_form_lanes_in(LaneFile<L>& file, const expr::TangentList& tl, RayForm* forms,
                               int n) {
    // Form k's lanes 5k … 5k + 3 walk its box x with the seeds e_x, e_y, e_z (the gradient's
    // components) and dc (∇f·dc directly, tighter than Σ G_k·dc_k); lane 5k + 4 its centre c
    // with the seed 0 (the tangent list's value lanes are the list's, bit for bit). In binary32
    // lanes the boxes and dc are rounded outward: every lane encloses what the double walk's
    // does, and three forms fill one vector.
    constexpr int kLanes = 5;
    LaneBox boxes[kMaxForms * kLanes];
    const int lanes = n * kLanes;
    for (int f = 0; f < n; ++f) {
        for (int k = 0; k < 3; ++k) {
            for (int l = 0; l < 4; ++l) {
                boxes[f * kLanes + l].lo[k] = forms[f].x[k].lower();
                boxes[f * kLanes + l].hi[k] = forms[f].x[k].upper();
            }
            boxes[f * kLanes + 4].lo[k] = forms[f].c[k].lower();
            boxes[f * kLanes + 4].hi[k] = forms[f].c[k].upper();
        }
    }
    const LaneWalk<L> w = lane_walk(file, tl.list);
    LaneFile<L>& lf = w.file;
    load_lanes(lf, boxes, lanes, w.ll);
    if (lf.regs.size() < tl.slots) lf.regs.resize(tl.slots);
    for (int k = 0; k < 3; ++k) {
        L& seed = lf.regs[tl.seed[k]];
        for (int f = 0; f < n; ++f) {
            for (int l = 0; l < 3; ++l) {
                expr::set_lane(seed, f * kLanes + l, UpInterval(l == k ? 1.0 : 0.0));
            }
            expr::set_lane(seed, f * kLanes + 3, UpInterval(forms[f].dc[k]));
            expr::set_lane(seed, f * kLanes + 4, UpInterval(0.0));
        }
    }
    expr::run_interval_batch(w.walked.data(), w.walked.data() + w.walked.size(), lf.in.data(),
                             lf.regs.data(), lanes);
    for (int f = 0; f < n; ++f) {
        RayForm& form = forms[f];
        form.m = expr::lane(lf.regs[tl.value], f * kLanes + 4);
        const UpInterval v = expr::lane(lf.regs[tl.value], f * kLanes);
        form.ok = !v.is_empty() && v.defined;
        for (int l = 0; l < 4 && form.ok; ++l) {
            form.g[l] = expr::lane(lf.regs[tl.derivative], f * kLanes + l);
            form.ok = finite(form.g[l]);
        }
    }
}

template <class L>
void Walker::load_lanes(LaneFile<L>& file, const LaneBox* boxes, int m, const LaneList<L>* ll) {
    static_assert(expr::kIntervalLanes <= 64, "one word of decorations per register");
    // The walks hold the upward mode, in which set_bounds_upward rounds binary32 bounds outward
    // without set_bounds' branches (MXCSR's field on x86-64: the x87 word, which fegetround
    // reads there, stays nearest).
#ifdef CERTRAY_X86_64_ROUNDING
    assert((certray::detail::X86RoundingControl::current().mxcsr >> 13 & 3u) == 2u);
#else
    assert(std::fegetround() == FE_UPWARD);
#endif
    // Box by box (they lie in memory so), without a branch: a lane that is not lo ≤ hi gets
    // empty()'s bounds (NaN, which both conversions keep) and no decoration, as set_lane would.
    // Axis c goes to file.in[c], or to the slot of the LaneList's variable c.
    L* to[3];
    for (int c = 0; c < 3; ++c) {
        to[c] = ll != nullptr && ll->var[c] != LaneList<L>::kNoVar ? &file.regs[ll->var[c]]
                                                                   : &file.in[c];
    }
    const UpInterval empty = UpInterval::empty();
    std::uint64_t def[3] = {0, 0, 0};
    int k0 = 0;  // the boxes before it are loaded eight at a time
#if CERTRAY_BATCH_X86
    if constexpr (std::is_same_v<L, expr::IntervalLanesF>) {
        if (m >= 8 && expr::batch_isa() == expr::BatchIsa::Avx512) {
            for (; k0 + 8 <= m; k0 += 8) load8_avx512(boxes, to, k0, def);
        }
    }
#endif
    for (int k = k0; k < m; ++k) {
        for (int c = 0; c < 3; ++c) {
            const double lo = boxes[k].lo[c], hi = boxes[k].hi[c];
            const bool ok = lo <= hi;
            expr::set_bounds_upward(*to[c], k, ok ? lo : empty.lower(), ok ? hi : empty.upper());
            def[c] |= std::uint64_t{ok} << k;
        }
    }
    for (int c = 0; c < 3; ++c) to[c]->defined[0] = def[c];
}

void Walker::eval_lanes(const Ssa& list, const LaneBox* boxes, std::size_t n,
                        std::vector<UpInterval>& out, const Level* fold) {
    if (float_lanes_) {
        eval_lanes_in(f32_, list, boxes, n, out, fold);
    } else {
        eval_lanes_in(d64_, list, boxes, n, out, fold);
    }
}

template <class L>
const LaneFile<L>& Walker::eval_lanes_in(LaneFile<L>& file, const Ssa& list, const LaneBox* boxes,
                                         std::size_t n, std::vector<UpInterval>& out,
                                         const Level* fold) {
    if (fold != nullptr && fold->folded.list.empty()) fold = nullptr;
    const Ssa& listed = fold != nullptr ? fold->folded.list : list;
    const LaneWalk<L> w = lane_walk(file, listed);
    LaneFile<L>& lf = w.file;
    // The folded list's slots (and its fixed ones) are the list's: fewer than its length.
    if (lf.regs.size() < list.size()) lf.regs.resize(list.size());
    if (out.size() < n) out.resize(n);
    const std::uint32_t f = listed.back().out;
    for (std::size_t k0 = 0; k0 < n; k0 += expr::kIntervalLanes) {
        const int m = static_cast<int>(std::min<std::size_t>(expr::kIntervalLanes, n - k0));
        load_lanes(lf, boxes + k0, m, w.ll);
        if (fold != nullptr) load_fixed(lf, *fold, m);
        expr::run_interval_batch(w.walked.data(), w.walked.data() + w.walked.size(), lf.in.data(),
                                 lf.regs.data(), m);
        for (int k = 0; k < m; ++k) out[k0 + k] = expr::lane(lf.regs[f], k);
    }
    return lf;
}

template <class L>
void Walker::load_fixed(LaneFile<L>& file, const Level& level, int m) {
    for (const auto& [slot, v] : level.folded.fixed) {
        L& x = file.regs[slot];
        expr::set_bounds(x, 0, v.lower(), v.upper());  // binary32: rounded outward
        std::fill(x.lo + 1, x.lo + m, x.lo[0]);
        std::fill(x.hi + 1, x.hi + m, x.hi[0]);
        x.defined[0] = ~std::uint64_t{0};  // fold_ssa fixes defined enclosures only
    }
}

void Walker::fold(const Ssa& sub, const std::array<UpInterval, 3>& box, Level& level) {
    expr::FoldedList& folded = level.folded;
    folded.list.clear();
    folded.fixed.clear();
    level.folded_tangent.forget();
    if (!may_fold(sub) || !fold_trial_.attempt()) return;
    // The enclosures of sub's slots over the box: level.values (the node's list's), through
    // prune_ssa's renaming where sub is that list pruned (a slot that took over a dropped
    // min/max's has the same values on the box; prune_ws_.bind has a slot per slot of the
    // node's list).
    const std::size_t n = sub.size();
    const UpInterval* values = level.values.data();
    if (&sub == &level.list) {
        fold_values_.assign(n, UpInterval::empty());
        for (std::size_t i = 0; i < prune_ws_.bind.size(); ++i) {
            const std::uint32_t s = prune_ws_.bind[i];
            if (s < n) fold_values_[s] = level.values[i];
        }
        values = fold_values_.data();
    }
    const UpInterval f = values[sub.back().out];
    const double w = f.upper() - f.lower();
    if (!(w > 0) || !std::isfinite(w)) return;
    std::array<UpInterval, 3> centre;
    for (int c = 0; c < 3; ++c) centre[c] = UpInterval(midpoint(box[c]));
    if (fold_regs_.size() < n) fold_regs_.resize(n);
    double width = kFoldWidth * w;
    for (int tries = 0; tries < 3; ++tries, width /= 32) {
        // An eighth of the list or more, or none (a narrower width drops less).
        if (8 * expr::fold_ssa(sub, values, width, folded) < n) break;
        for (const auto& [slot, v] : folded.fixed) fold_regs_[slot] = v;
        expr::detail::run<UpInterval>(folded.list, centre, fold_regs_.data());
        const UpInterval at = fold_regs_[folded.list.back().out];
        if (at.upper() - at.lower() <= kFoldCentre * w) {
            ++stats.folds;
            stats.folded_instructions += n - folded.list.size();
            ++fold_trial_.wins;
            return;
        }
    }
    folded.list.clear();
    folded.fixed.clear();
}

expr::TangentKind Walker::lane_tangent_kind(const Ssa& list, unsigned depth, Level& level) {
    if (level.folded.list.empty()) return tangent_kind(list, depth);
    return level.folded_tangent.kind_of(level.folded.list);
}

const expr::TangentList* Walker::lane_tangent(const Ssa& list, unsigned depth, Level& level) {
    if (level.folded.list.empty()) return tangent(list, depth);
    return level.folded_tangent.of(level.folded.list);
}

const expr::TangentList* Walker::tangent(const Ssa& list, unsigned depth) {
    // The tape's own list, or a level's pruned list (rewritten only where that level prunes,
    // which marks its tangent list unknown); any other list gets none.
    if (&list == &tape_.ssa()) return tape_tangent_ ? &*tape_tangent_ : nullptr;
    Level* owner = owner_of(list, depth);
    if (owner == nullptr) return nullptr;
    return owner->tangent.of(list);
}

Level* Walker::owner_of(const Ssa& list, unsigned depth) {
    for (unsigned k = std::min<unsigned>(depth + 1, kMaxDepth); k-- > 0;) {
        if (&levels_[k].list == &list) return &levels_[k];
    }
    return nullptr;
}

expr::TangentKind Walker::tangent_kind(const Ssa& list, unsigned depth) {
    using K = expr::TangentKind;
    if (&list == &tape_.ssa()) {
        return !tape_tangent_ ? K::None : tape_tangent_->smooth ? K::Smooth : K::Kinked;
    }
    Level* owner = owner_of(list, depth);
    if (owner == nullptr) return K::None;
    return owner->tangent.kind_of(list);
}

void Walker::eval_tangent_lanes(const expr::TangentList& tl, const LaneBox* boxes,
                                const std::array<double, 3>* dirs, std::size_t n,
                                std::vector<UpInterval>& values, std::vector<UpInterval>& slopes,
                                const Level* fold, const expr::TangentList* second,
                                std::vector<UpInterval>* curvatures) {
    if (float_lanes_) {
        eval_tangent_lanes_in(f32_, tl, boxes, dirs, n, values, slopes, fold, second, curvatures);
    } else {
        eval_tangent_lanes_in(d64_, tl, boxes, dirs, n, values, slopes, fold, second, curvatures);
    }
}

template <class L>
void Walker::eval_tangent_lanes_in(LaneFile<L>& file, const expr::TangentList& tl,
                                   const LaneBox* boxes, const std::array<double, 3>* dirs,
                                   std::size_t n, std::vector<UpInterval>& values,
                                   std::vector<UpInterval>& slopes, const Level* fold,
                                   const expr::TangentList* second,
                                   std::vector<UpInterval>* curvatures) {
    // With `second` (second_order_list(tl)), its list is walked: it keeps tl's slots (g and g′)
    // and adds g″ in its derivative slot, into `curvatures`.
    const std::vector<expr::Instr>& listed = second != nullptr ? second->list : tl.list;
    const std::uint32_t slots = second != nullptr ? second->slots : tl.slots;
    // (With a folded list at the level, tl is its tangent list: the shared registers.)
    const LaneWalk<L> w = lane_walk(file, listed);
    LaneFile<L>& lf = w.file;
    if (lf.regs.size() < slots) lf.regs.resize(slots);
    if (values.size() < n) values.resize(n);
    if (slopes.size() < n) slopes.resize(n);
    if (curvatures != nullptr && curvatures->size() < n) curvatures->resize(n);
    for (std::size_t k0 = 0; k0 < n; k0 += expr::kIntervalLanes) {
        const int m = static_cast<int>(std::min<std::size_t>(expr::kIntervalLanes, n - k0));
        load_lanes(lf, boxes + k0, m, w.ll);
        if (fold != nullptr) load_fixed(lf, *fold, m);  // none where the level has no folded list
        // The seeds (both lists' with `second`): each lane's direction, a point (defined),
        // rounded outward.
        const std::uint64_t lanes = m == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << m) - 1;
        for (const expr::TangentList* list : {&tl, second}) {
            if (list == nullptr) continue;
            for (int c = 0; c < 3; ++c) {
                L& seed = lf.regs[list->seed[c]];
                for (int k = 0; k < m; ++k) {
                    const double d = dirs[k0 + k][c];
                    expr::set_bounds_upward(seed, k, d, d);
                }
                seed.defined[0] |= lanes;
            }
        }
        expr::run_interval_batch(w.walked.data(), w.walked.data() + w.walked.size(), lf.in.data(),
                                 lf.regs.data(), m);
        for (int k = 0; k < m; ++k) {
            values[k0 + k] = expr::lane(lf.regs[tl.value], k);
            slopes[k0 + k] = expr::lane(lf.regs[tl.derivative], k);
            if (curvatures != nullptr) {
                (*curvatures)[k0 + k] = expr::lane(lf.regs[second->derivative], k);
            }
        }
    }
}

// split_screen() (tracers/coherent_walk.cpp) walks the quarters' boxes in double lanes.
template const LaneFile<expr::IntervalLanes>& Walker::eval_lanes_in(
    LaneFile<expr::IntervalLanes>& file, const Ssa& list, const LaneBox* boxes, std::size_t n,
    std::vector<UpInterval>& out, const Level* fold);

}  // namespace certray::tracers::detail::coherent
