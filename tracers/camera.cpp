// tracers/camera.cpp — pinhole camera, ray clipping and auto-framing (see camera.h).
#include "tracers/camera.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include "expr/batch_simd.h"
#include "expr/eval.h"
#include "expr/eval_batch.h"
#include "expr/prune.h"
#include "interval/interval.h"
#include "tracers/parallel.h"

namespace certray::tracers {

Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

CameraFrame::CameraFrame(const Camera& camera, unsigned width, unsigned height) {
    if (width == 0 || height == 0) throw std::invalid_argument("camera: empty image size");
    if (!(camera.fov_degrees > 0 && camera.fov_degrees < 180)) {
        throw std::invalid_argument("camera: fov must be in (0, 180) degrees");
    }
    eye_ = camera.eye;
    forward_ = normalize(
        {camera.target[0] - eye_[0], camera.target[1] - eye_[1], camera.target[2] - eye_[2]});
    if (dot(forward_, forward_) == 0) throw std::invalid_argument("camera: eye equals target");
    right_ = normalize(cross(forward_, camera.up));
    if (dot(right_, right_) == 0) {
        throw std::invalid_argument("camera: up is parallel to the view direction");
    }
    up_ = cross(right_, forward_);
    scale_ = std::tan(camera.fov_degrees * (M_PI / 360.0)) / (0.5 * height);
    half_w_ = 0.5 * width;
    half_h_ = 0.5 * height;
}

Ray CameraFrame::ray(double px, double py) const {
    const double u = (px - half_w_) * scale_;
    const double v = (half_h_ - py) * scale_;
    Ray r;
    r.o = eye_;
    r.d = normalize({forward_[0] + u * right_[0] + v * up_[0],
                     forward_[1] + u * right_[1] + v * up_[1],
                     forward_[2] + u * right_[2] + v * up_[2]});
    r.tmin = 0;
    r.tmax = std::numeric_limits<double>::infinity();
    return r;
}

namespace {

constexpr int kRow = 8;  ///< rays per call of the vector code (an AVX-512 vector)

/// The inputs of eight rays of a row (CameraFrame::clipped_row), and what they come to.
struct Row8 {
    double u[kRow];   ///< (px − half_w)·scale of each
    double v;         ///< (half_h − py)·scale
    double frame[9];  ///< forward, right, up
    double eye[3];
    double box[6];  ///< x0, x1, y0, y1, z0, z1
    double d[3][kRow], t0[kRow], t1[kRow];
    std::int64_t odd[kRow];  ///< nonzero: a lane the vectors do not take (redone one by one)
};

/// GCC's generic vectors of W doubles, and of their bits as integers. W is the width of the
/// copy's registers: wider vectors, and comparisons on AVX-512F without AVX512DQ, GCC 12 takes
/// apart lane by lane (row8_avx512). (Spelled out per width: GCC drops vector_size on a type that
/// depends on a template parameter.)
template <int W>
struct Lanes;
template <>
struct Lanes<2> {
    using D = double __attribute__((vector_size(16)));
    using I = std::int64_t __attribute__((vector_size(16)));
    using U = std::uint64_t __attribute__((vector_size(16)));
};
template <>
struct Lanes<4> {
    using D = double __attribute__((vector_size(32)));
    using I = std::int64_t __attribute__((vector_size(32)));
    using U = std::uint64_t __attribute__((vector_size(32)));
};
template <>
struct Lanes<8> {
    using D = double __attribute__((vector_size(64)));
    using I = std::int64_t __attribute__((vector_size(64)));
    using U = std::uint64_t __attribute__((vector_size(64)));
};
static_assert(sizeof(Lanes<4>::D) == 32 && sizeof(Lanes<8>::I) == 64);

/// √ of the W lanes of x: the vector instruction of V (correctly rounded, as std::sqrt), or one by
/// one where there are no vectors.
template <class V, int W>
[[gnu::always_inline]] inline typename Lanes<W>::D sqrt_lanes(const typename Lanes<W>::D& x) {
    alignas(64) double a[W], s[W];
    std::memcpy(a, &x, sizeof a);
#if CERTRAY_BATCH_X86
    static_assert(V::kWidth == W);
    V::store(s, V::sqrt(V::load(a)));
#else
    for (int k = 0; k < W; ++k) s[k] = std::sqrt(a[k]);
#endif
    typename Lanes<W>::D r;
    std::memcpy(&r, s, sizeof r);
    return r;
}

/// CameraFrame::ray's direction and clip_ray's slabs for eight rays, W at a time, with the scalar
/// code's operations in its order (IEEE arithmetic: the same bits). A lane where a branch of the
/// scalar code is not the common one (a zero length or direction component, a slab parameter
/// outside step_up's integer range) is marked odd. V: the vector type of the √ (expr/batch_simd.h).
template <class V, int W>
[[gnu::always_inline]] inline void row8_in(Row8& r) {
    using D = typename Lanes<W>::D;
    using I = typename Lanes<W>::I;
    using U = typename Lanes<W>::U;
    // |p| within [2⁻¹⁰⁰⁰, 2¹⁰⁰⁰] (step_up's integer range), compared as the bits of |p|, which
    // order the non-negative doubles as their values do and put NaN above +inf.
    const I magnitude = I{} + std::numeric_limits<std::int64_t>::max();
    const std::int64_t small = std::bit_cast<std::int64_t>(0x1p-1000),
                       big = std::bit_cast<std::int64_t>(0x1p1000);
    const auto out_of_range = [&](const D& p) {
        const I a = (I)p & magnitude;  // a cast of vectors keeps the bits
        return (a < small) | (a > big);
    };
    const D inf = D{} + std::numeric_limits<double>::infinity();
    const U four = U{} + 4;
    const double* f = r.frame;
    for (int k = 0; k < kRow; k += W) {
        D u, x[3];
        std::memcpy(&u, r.u + k, sizeof u);
        for (int c = 0; c < 3; ++c) x[c] = f[c] + u * f[3 + c] + r.v * f[6 + c];
        const D n = sqrt_lanes<V, W>(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        I odd = ~(n > 0) | ~(n < inf);  // masks: 0 or −1
        D t0 = D{}, t1 = inf;
        for (int c = 0; c < 3; ++c) {
            const D d = x[c] / n;
            std::memcpy(r.d[c] + k, &d, sizeof d);
            odd |= d == 0;
            D ta = (r.box[2 * c] - r.eye[c]) / d, tb = (r.box[2 * c + 1] - r.eye[c]) / d;
            const I swap = ta > tb;
            const D lo = swap ? tb : ta, hi = swap ? ta : tb;
            odd |= out_of_range(lo) | out_of_range(hi);
            // step_down(lo, 4) and step_up(hi, 4) in their integer range: 4 ulps away from 0
            // (up) or towards it, as the sign says.
            const U blo = (U)lo, bhi = (U)hi;
            const U slo = lo > 0 ? blo - four : blo + four;
            const U shi = hi > 0 ? bhi + four : bhi - four;
            ta = (D)slo;
            tb = (D)shi;
            t0 = t0 < ta ? ta : t0;  // std::max(t0, ta)
            t1 = tb < t1 ? tb : t1;  // std::min(t1, tb)
        }
        std::memcpy(r.t0 + k, &t0, sizeof t0);
        std::memcpy(r.t1 + k, &t1, sizeof t1);
        std::memcpy(r.odd + k, &odd, sizeof odd);
    }
}

#if CERTRAY_BATCH_X86
using expr::detail::Avx2;
using expr::detail::Sse2;
[[gnu::flatten]] void row8_baseline(Row8& r) { row8_in<Sse2, 2>(r); }
[[gnu::target("avx2"), gnu::flatten]] void row8_avx2(Row8& r) { row8_in<Avx2, 4>(r); }

/// row8_in in AVX-512F's own terms: its comparisons give mask registers, which GCC 12 cannot
/// turn into row8_in's vectors of masks without AVX512DQ (it took each lane apart: 5.8% of the
/// sphere's render at 1024², docs/benchmarks.md, session 26). The same operations on the same
/// operands in the same order: the same bits.
[[gnu::target("avx512f"), gnu::always_inline]] inline __mmask8 out_of_range512(__m512d p) {
    // row8_in's test, on the bits of |p|
    const __m512i a = _mm512_and_si512(_mm512_castpd_si512(p),
                                       _mm512_set1_epi64(std::numeric_limits<std::int64_t>::max()));
    return static_cast<__mmask8>(
        _mm512_cmp_epi64_mask(a, _mm512_set1_epi64(std::bit_cast<std::int64_t>(0x1p-1000)),
                              _MM_CMPINT_LT) |
        _mm512_cmp_epi64_mask(a, _mm512_set1_epi64(std::bit_cast<std::int64_t>(0x1p1000)),
                              _MM_CMPINT_NLE));
}
[[gnu::target("avx512f")]] void row8_avx512(Row8& r) {
    const __m512d zero = _mm512_setzero_pd(),
                  inf = _mm512_set1_pd(std::numeric_limits<double>::infinity());
    const __m512d u = _mm512_loadu_pd(r.u), v = _mm512_set1_pd(r.v);
    const double* f = r.frame;
    __m512d x[3];
    for (int c = 0; c < 3; ++c) {
        x[c] = _mm512_add_pd(
            _mm512_add_pd(_mm512_set1_pd(f[c]), _mm512_mul_pd(u, _mm512_set1_pd(f[3 + c]))),
            _mm512_mul_pd(v, _mm512_set1_pd(f[6 + c])));
    }
    const __m512d n = _mm512_sqrt_pd(
        _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(x[0], x[0]), _mm512_mul_pd(x[1], x[1])),
                      _mm512_mul_pd(x[2], x[2])));
    __mmask8 odd = static_cast<__mmask8>(
        ~(_mm512_cmp_pd_mask(n, zero, _CMP_GT_OQ) & _mm512_cmp_pd_mask(n, inf, _CMP_LT_OQ)));
    __m512d t0 = zero, t1 = inf;
    const __m512i four = _mm512_set1_epi64(4);
    for (int c = 0; c < 3; ++c) {
        const __m512d d = _mm512_div_pd(x[c], n);
        _mm512_storeu_pd(r.d[c], d);
        odd |= _mm512_cmp_pd_mask(d, zero, _CMP_EQ_OQ);
        const __m512d ta = _mm512_div_pd(_mm512_set1_pd(r.box[2 * c] - r.eye[c]), d);
        const __m512d tb = _mm512_div_pd(_mm512_set1_pd(r.box[2 * c + 1] - r.eye[c]), d);
        const __mmask8 swap = _mm512_cmp_pd_mask(ta, tb, _CMP_GT_OQ);
        const __m512d lo = _mm512_mask_blend_pd(swap, ta, tb),
                      hi = _mm512_mask_blend_pd(swap, tb, ta);
        odd |= out_of_range512(lo) | out_of_range512(hi);
        const __m512i blo = _mm512_castpd_si512(lo), bhi = _mm512_castpd_si512(hi);
        const __mmask8 plo = _mm512_cmp_pd_mask(lo, zero, _CMP_GT_OQ),
                       phi = _mm512_cmp_pd_mask(hi, zero, _CMP_GT_OQ);
        const __m512d sa = _mm512_castsi512_pd(
            _mm512_mask_blend_epi64(plo, _mm512_add_epi64(blo, four), _mm512_sub_epi64(blo, four)));
        const __m512d sb = _mm512_castsi512_pd(
            _mm512_mask_blend_epi64(phi, _mm512_sub_epi64(bhi, four), _mm512_add_epi64(bhi, four)));
        t0 = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(t0, sa, _CMP_LT_OQ), t0, sa);
        t1 = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(sb, t1, _CMP_LT_OQ), t1, sb);
    }
    _mm512_storeu_pd(r.t0, t0);
    _mm512_storeu_pd(r.t1, t1);
    for (int k = 0; k < kRow; ++k) r.odd[k] = (odd >> k) & 1 ? -1 : 0;
}
#endif

/// row8_in on the instruction set of the batch walks (expr::batch_isa(): the same bits on each).
void row8(Row8& r) {
#if CERTRAY_BATCH_X86
    switch (expr::batch_isa()) {
        case expr::BatchIsa::Avx512:
            return row8_avx512(r);
        case expr::BatchIsa::Avx2:
            return row8_avx2(r);
        case expr::BatchIsa::Baseline:
            break;
    }
    row8_baseline(r);
#else
    row8_in<void, kRow>(r);
#endif
}

}  // namespace

void CameraFrame::clipped_row(unsigned i0, unsigned j, unsigned n, const Box3& box, Ray* rays,
                              bool* in) const {
    Row8 r;
    r.v = (half_h_ - (j + 0.5)) * scale_;
    for (int c = 0; c < 3; ++c) {
        r.frame[c] = forward_[c];
        r.frame[3 + c] = right_[c];
        r.frame[6 + c] = up_[c];
        r.eye[c] = eye_[c];
        r.box[2 * c] = box[c][0];
        r.box[2 * c + 1] = box[c][1];
    }
    for (unsigned k0 = 0; k0 < n; k0 += kRow) {
        const unsigned m = std::min<unsigned>(kRow, n - k0);
        for (unsigned k = 0; k < kRow; ++k) {
            r.u[k] = ((i0 + k0 + std::min(k, m - 1)) + 0.5 - half_w_) * scale_;
        }
        row8(r);
        for (unsigned k = 0; k < m; ++k) {
            Ray& ray = rays[k0 + k];
            if (r.odd[k] != 0) {
                ray = this->ray(i0 + k0 + k + 0.5, j + 0.5);
                in[k0 + k] = clip_ray(ray, box);
                continue;
            }
            ray.o = eye_;
            ray.d = {r.d[0][k], r.d[1][k], r.d[2][k]};
            ray.tmin = r.t0[k];
            ray.tmax = r.t1[k];
            in[k0 + k] = r.t0[k] <= r.t1[k];
            if (!in[k0 + k]) {
                ray.tmin = 0;  // as clip_ray leaves a ray that misses the box
                ray.tmax = std::numeric_limits<double>::infinity();
            }
        }
    }
}

bool CameraFrame::misses(unsigned i0, unsigned j0, unsigned w, unsigned h, const Box3& box) const {
    if (w == 0 || h == 0) return true;
    RoundingScope up;
    // The pixel centres' image-plane coordinates (as ray() computes them), widened by a
    // billionth: ray() rounds them, and the normalised directions differ from these by ulps.
    const auto widen = [](const UpInterval& x) {
        const double m = 1e-9 * (std::fabs(x.lower()) + std::fabs(x.upper())) + 1e-300;
        return x + UpInterval(-m, m);
    };
    const UpInterval s(scale_);
    const UpInterval u = widen((UpInterval(i0 + 0.5, i0 + w - 0.5) - UpInterval(half_w_)) * s);
    const UpInterval v = widen((UpInterval(half_h_) - UpInterval(j0 + 0.5, j0 + h - 0.5)) * s);
    // Ray eye + t·x (t ≥ 0, x = forward + u·right + v·up) lies in slab c for t between
    // (lo − eye)/x and (hi − eye)/x: every ray enters the box no earlier than the greatest
    // lower bound of those entries, and leaves it no later than the least upper bound of the
    // exits. An axis whose x may vanish (or an operation that gives NaN) bounds nothing.
    double enter = 0, leave = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 3; ++c) {
        const UpInterval x =
            UpInterval(forward_[c]) + u * UpInterval(right_[c]) + v * UpInterval(up_[c]);
        if (!(x.lower() > 0 || x.upper() < 0)) continue;
        const double m =
            1e-9 * (std::fabs(box[c][0]) + std::fabs(box[c][1]) + std::fabs(eye_[c])) + 1e-300;
        const UpInterval e(eye_[c]);
        const UpInterval ta = (UpInterval(box[c][0]) - UpInterval(m) - e) / x;
        const UpInterval tb = (UpInterval(box[c][1]) + UpInterval(m) - e) / x;
        if (ta.is_empty() || tb.is_empty()) continue;
        const double in = std::min(ta.lower(), tb.lower()), out = std::max(ta.upper(), tb.upper());
        if (in > enter) enter = in;
        if (out < leave) leave = out;
    }
    return enter > leave;
}

bool clip_ray(Ray& ray, const Box3& box) {
    double t0 = ray.tmin, t1 = ray.tmax;
    for (int a = 0; a < 3; ++a) {
        const double o = ray.o[a], d = ray.d[a];
        if (d == 0) {
            if (o < box[a][0] || o > box[a][1]) return false;
            continue;
        }
        double ta = (box[a][0] - o) / d, tb = (box[a][1] - o) / d;
        if (ta > tb) std::swap(ta, tb);
        // Each slab parameter is one rounding of a subtraction and a division away from the
        // exact one: step a few ulps outward so the clipped segment keeps the whole box.
        ta = detail::step_down(ta, 4);
        tb = detail::step_up(tb, 4);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    if (!(t0 <= t1)) return false;
    ray.tmin = t0;
    ray.tmax = t1;
    return true;
}

namespace {

using Ssa = std::vector<expr::Instr>;
using Box = std::array<UpInterval, 3>;

/// One worker's state of the subdivision of surface_cells: each cell is evaluated with the list
/// pruned to its parent (equal to f there), so that a CSG tree of thousands of primitives is not
/// evaluated whole on every small cell; one list and one register file per level.
struct CellWalk {
    struct Level {
        std::vector<UpInterval> values;
        Ssa list;
    };
    std::vector<Level> level;
    expr::PruneWorkspace ws;

    explicit CellWalk(int levels) : level(static_cast<std::size_t>(levels) + 1) {
        ws.absolute_values = true;
    }
    /// Whether f may vanish on `box` (0 ∈ F, or F not proven defined), by `list` at `depth`
    /// (upward mode held); then *sub is the list for its children (pruned to it, or `list`).
    bool may_vanish(const Box& box, const Ssa& list, int depth, const Ssa*& sub) {
        Level& l = level[static_cast<std::size_t>(depth)];
        if (l.values.size() < list.size()) l.values.resize(list.size());
        expr::detail::run<UpInterval>(list, box, l.values.data());
        const UpInterval v = l.values[list.back().out];
        if (v.defined && !v.is_empty() && !possibly_zero(v)) return false;
        sub = &list;
        if (depth + 1 < static_cast<int>(level.size()) &&
            expr::prune_ssa(list, l.values.data(), ws, l.list)) {
            sub = &l.list;
        }
        return true;
    }
};

/// Octant k of `box` (bit a of k: the upper half along axis a).
Box octant(const Box& box, int k) {
    Box s;
    for (int a = 0; a < 3; ++a) {
        const double m = 0.5 * box[a].lower() + 0.5 * box[a].upper();  // a split point only
        s[a] = (k >> a) & 1 ? UpInterval(m, box[a].upper()) : UpInterval(box[a].lower(), m);
    }
    return s;
}

/// visit_surface_cells walks the levels above kSplit on the calling thread; the cells at kSplit
/// (at most kMaxTasks) are its tasks.
constexpr int kSplit = 2;
constexpr std::size_t kMaxTasks = 64;  // 8^kSplit

Box3 box3(const Box& box) {
    return Box3{{{box[0].lower(), box[0].upper()},
                 {box[1].lower(), box[1].upper()},
                 {box[2].lower(), box[2].upper()}}};
}

/// The subdivision of surface_cells, depth first: `leaf(cell, task)` for each cell of the last
/// level where f may vanish, only below cells for which `descend(box)` holds; stops at the first
/// leaf that returns true (and returns true then). The levels above kSplit are walked by the
/// calling thread; the cells at kSplit (at most kMaxTasks) are tasks spread over `threads` workers
/// (tracers/parallel.h), `task` their index in depth-first order, so that a caller that keeps
/// each task's leaves apart gets them in the order of one thread. `descend` is called from any
/// worker, `leaf` from the one that runs the task.
template <class Descend, class Leaf>
bool visit_surface_cells(const expr::Tape& tape, const Box3& bounds, int levels, unsigned threads,
                         Descend descend, Leaf leaf) {
    levels = std::clamp(levels, 0, 6);  // at most 8^6 cells
    const int split = std::min(levels, kSplit);
    struct Task {
        Box box;
        std::size_t list;  ///< index in `lists`: its parent's list
    };
    std::vector<Ssa> lists;
    std::vector<Task> tasks;
    const Box root{UpInterval(bounds[0][0], bounds[0][1]), UpInterval(bounds[1][0], bounds[1][1]),
                   UpInterval(bounds[2][0], bounds[2][1])};
    {
        RoundingScope up;  // UpInterval arithmetic below; midpoints are only split points
        CellWalk walk(levels);
        const auto top = [&](const auto& self, const Box& box, const Ssa& list, int depth) -> void {
            const Ssa* sub = nullptr;
            if (!descend(box) || !walk.may_vanish(box, list, depth, sub)) return;
            if (depth + 1 == split) {
                lists.push_back(*sub);  // its octants' tasks share it
                for (int k = 0; k < 8; ++k) tasks.push_back({octant(box, k), lists.size() - 1});
                return;
            }
            for (int k = 0; k < 8; ++k) self(self, octant(box, k), *sub, depth + 1);
        };
        if (split == 0) {
            lists.push_back(tape.ssa());
            tasks.push_back({root, 0});
        } else {
            top(top, root, tape.ssa(), 0);
        }
    }
    std::atomic<bool> found{false};
    const unsigned workers =
        std::min<unsigned>(worker_count(threads), std::max<std::size_t>(tasks.size(), 1));
    std::vector<CellWalk> walks(workers, CellWalk(levels));
    ParallelOptions po;
    po.threads = workers;
    po.chunk = 1;
    po.cancel = &found;
    parallel_for(tasks.size(), po, [&](std::size_t begin, std::size_t end, unsigned worker) {
        RoundingScope up;
        CellWalk& walk = walks[worker];
        for (std::size_t t = begin; t < end; ++t) {
            const auto visit = [&](const auto& self, const Box& box, const Ssa& list,
                                   int depth) -> bool {
                if (found.load(std::memory_order_relaxed)) return true;
                const Ssa* sub = nullptr;
                if (!descend(box) || !walk.may_vanish(box, list, depth, sub)) return false;
                if (depth == levels) {
                    if (!leaf(box3(box), t)) return false;
                    found.store(true, std::memory_order_relaxed);
                    return true;
                }
                for (int k = 0; k < 8; ++k) {
                    if (self(self, octant(box, k), *sub, depth + 1)) return true;
                }
                return false;
            };
            if (visit(visit, tasks[t].box, lists[tasks[t].list], split)) return;
        }
    });
    return found.load();
}

}  // namespace

std::vector<Box3> surface_cells(const expr::Tape& tape, const Box3& bounds, int levels,
                                unsigned threads) {
    std::vector<std::vector<Box3>> per_task(kMaxTasks);
    visit_surface_cells(
        tape, bounds, levels, threads, [](const auto&) { return true; },
        [&](const Box3& cell, std::size_t task) {
            per_task[task].push_back(cell);
            return false;
        });
    std::vector<Box3> out;
    for (const std::vector<Box3>& cells : per_task)
        out.insert(out.end(), cells.begin(), cells.end());
    return out;
}

bool surface_cells_touch_bounds(const expr::Tape& tape, const Box3& bounds, int levels,
                                unsigned threads) {
    const auto touches = [&](const auto& box) {
        for (int a = 0; a < 3; ++a) {
            if (box[a].lower() <= bounds[a][0] || box[a].upper() >= bounds[a][1]) return true;
        }
        return false;
    };
    return visit_surface_cells(tape, bounds, levels, threads, touches,
                               [](const Box3&, std::size_t) { return true; });
}

std::optional<Box3> hull(const std::vector<Box3>& boxes) {
    if (boxes.empty()) return std::nullopt;
    Box3 box = boxes.front();
    for (const Box3& c : boxes) {
        for (int a = 0; a < 3; ++a) {
            box[a][0] = std::min(box[a][0], c[a][0]);
            box[a][1] = std::max(box[a][1], c[a][1]);
        }
    }
    return box;
}

std::optional<Box3> surface_extent(const expr::Tape& tape, const Box3& bounds, int levels,
                                   unsigned threads) {
    return hull(surface_cells(tape, bounds, levels, threads));
}

Camera frame_box(const Box3& box, double fov_degrees, double aspect, Vec3 from) {
    return frame_boxes({box}, box, fov_degrees, aspect, from);
}

Camera frame_boxes(const std::vector<Box3>& boxes, const Box3& hull, double fov_degrees,
                   double aspect, Vec3 from) {
    Vec3 c;
    for (int a = 0; a < 3; ++a) c[a] = 0.5 * (hull[a][0] + hull[a][1]);
    const Vec3 dir = normalize(from);
    const Vec3 forward{-dir[0], -dir[1], -dir[2]};
    const Vec3 right = normalize(cross(forward, {0, 0, 1}));
    const Vec3 up = cross(right, forward);
    const double tan_v = std::tan(fov_degrees * (M_PI / 360.0));
    const double tan_h = tan_v * aspect;
    // The eye sits at c + D·dir. Corner p (relative to c) is at depth D + p·forward and projects
    // inside the image when |p·right| <= tan_h·depth and |p·up| <= tan_v·depth.
    double distance = 1e-6;
    for (const Box3& box : boxes) {
        for (int k = 0; k < 8; ++k) {
            Vec3 p;
            for (int a = 0; a < 3; ++a) p[a] = box[a][(k >> a) & 1] - c[a];
            const double depth_needed =
                std::max(std::abs(dot(p, right)) / tan_h, std::abs(dot(p, up)) / tan_v);
            distance = std::max(distance, depth_needed - dot(p, forward));
        }
    }
    distance *= 1.08;  // a margin around the silhouette
    Camera cam;
    cam.target = c;
    cam.eye = {c[0] + dir[0] * distance, c[1] + dir[1] * distance, c[2] + dir[2] * distance};
    cam.up = {0, 0, 1};
    cam.fov_degrees = fov_degrees;
    return cam;
}

}  // namespace certray::tracers
