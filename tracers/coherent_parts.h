// tracers/coherent_parts.h — internal to the coherent walk (tracers/coherent_*.cpp): the pieces
// its Walker is made of (boxes of lanes, trials that run while they pay, a root tile's pixels, the
// buffers of one depth of the descent) and the small functions on segments and lists they share.
//
// Contract: what tracers/coherent.h promises rests on tracers/coherent_walker.h's Walker; these are
// its parts, with no meaning of their own outside it. Reference: docs/theory/coherent.md.
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "expr/eval_interval_batch.h"
#include "expr/prune.h"
#include "expr/tangent.h"
#include "expr/tape.h"
#include "interval/interval.h"
#include "solvers/ray.h"
#include "tracers/segment_box.h"

namespace certray::tracers::detail::coherent {

using Ssa = std::vector<expr::Instr>;
using Box = std::array<UpInterval, 3>;

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Deepest node: past it a node is a leaf whatever its size (the solver bisects further).
constexpr unsigned kMaxDepth = 80;

/// A box of a batched evaluation (Walker::eval_lanes): [lo[c], hi[c]] per axis, from ray_bounds.
struct LaneBox {
    double lo[3], hi[3];
};

/// The box of ray_box(ray, p, q), as a LaneBox.
[[gnu::always_inline]] inline LaneBox lane_box(const Ray& ray, double p, double q) {
    LaneBox b;
    ray_bounds(ray, p, q, b.lo, b.hi);
    return b;
}

/// Something tried while it pays in a root tile (the mean value form of a box, tile pieces): the
/// first `First` tries, then while at least one try in `Share` wins, and one in `Every` otherwise,
/// to notice when it pays again. Each root tile starts afresh (the same answers in any thread).
template <unsigned First, unsigned Every, unsigned Share = 4>
struct PayingTrial {
    unsigned tries = 0, wins = 0, passed = 0;
    bool attempt() {
        if (tries < First || Share * wins >= tries || ++passed % Every == 0) {
            ++tries;
            return true;
        }
        return false;
    }
    void reset() { tries = wins = passed = 0; }
    /// Whether it is tried every time now (the first tries, or while it wins).
    bool paying() const { return tries < First || Share * wins >= tries; }
};

/// The tangent list of a smooth tangent list `tl` (expr/tangent.h applied twice): run over a
/// segment's box with its seeds holding the ray's direction d, its slots tl.value and
/// tl.derivative hold g and g′ and its `derivative` slot g″, for g(t) = f(o + t·d). tl's list
/// gets two negations that copy its derivative into its last slot (the second list differentiates
/// the last one). Both lists' seeds hold d, so the second's are tl's (its seed slots), and the
/// instructions that repeat others are dropped (expr::share_instructions): the derivatives of
/// the values along the second seeds are the first list's again, and a product's a′·b′ comes
/// twice. Barth's sextic: 116 instructions → 88. None where tl is absent or has kinks.
inline std::optional<expr::TangentList> second_order_list(
    const std::optional<expr::TangentList>& tl) {
    if (!tl || !tl->smooth) return std::nullopt;
    std::vector<expr::Instr> list = tl->list;
    const std::uint32_t neg = tl->slots, copy = tl->slots + 1;
    expr::Instr n{};
    n.op = expr::Op::Neg;
    n.a = tl->derivative;
    n.out = neg;
    list.push_back(n);
    n.a = neg;
    n.out = copy;
    list.push_back(n);
    auto second = expr::tangent_list(list);
    if (!second || !second->smooth) return std::nullopt;
    const std::pair<std::uint32_t, std::uint32_t> same[3] = {{second->seed[0], tl->seed[0]},
                                                             {second->seed[1], tl->seed[1]},
                                                             {second->seed[2], tl->seed[2]}};
    const std::uint32_t keep[4] = {tl->value, tl->derivative, second->value, second->derivative};
    expr::share_instructions(second->list, same, keep);
    for (int c = 0; c < 3; ++c) second->seed[c] = tl->seed[c];
    return second;
}

/// The pixels [i0, i0 + w) × [j0, j0 + h) of the image.
struct Rect {
    unsigned i0, j0, w, h;
};

/// A pixel of the current root tile: its ray and whether it is still open (meets the bounds and
/// has no answer yet).
struct Px {
    Ray ray;
    bool open = false;
    std::uint8_t splits = 0;  ///< undecided leaf segments split again for this ray so far
};

/// How often one ray's undecided leaf segment is split again (with a tape pruned to each half)
/// before the per-ray solver takes the rest of the ray.
constexpr std::uint8_t kMaxSplits = 24;

/// The buffers of one depth of the descent: the slot enclosures of the node's box evaluation,
/// the list pruned to that box, and the register tape a leaf builds from it.
/// A list's tangent list (expr/tangent.h; none when the list has an op without a rule) and its
/// kind (expr::tangent_kind), each made once asked for; forgotten when the list is rewritten.
struct TangentCache {
    std::optional<expr::TangentList> tangent;
    bool known = false;
    std::optional<expr::TangentKind> kind;
    const expr::TangentList* of(const Ssa& list) {
        if (!known) {
            tangent = expr::tangent_list(list);
            known = true;
        }
        return tangent ? &*tangent : nullptr;
    }
    expr::TangentKind kind_of(const Ssa& list) {
        if (!kind) kind = expr::tangent_kind(list);
        return *kind;
    }
    void forget() {
        known = false;
        kind.reset();
    }
};

struct Level {
    std::vector<UpInterval> values;
    /// Walker::split_screen: the slot enclosures of the quarters walked in lanes, each swapped
    /// into `values` when its descent comes.
    std::array<std::vector<UpInterval>, 4> quarters;
    Ssa list;
    expr::Tape tape;
    /// A ray scanned with others (Walker::scan_together), waiting to be settled.
    struct Scanned {
        unsigned i, j;
        Ray s;
        RayResult res;
        std::size_t begin = 0, end = 0;  ///< its pieces: Walker::pieces_[begin, end)
        /// In a coarse scan, s was longer than Walker::kMaxPieces pieces when the scan took it
        /// (and its node's [a, b] can be halved): left to the halves if the forms do not decide it.
        bool long_segment = false;
        /// Left to the node's halves in t (a coarse scan: CoherentOptions::coarse_scans).
        bool deferred = false;
        // Built in place (emplace_back) and filled there: a local copy written field by field
        // and then copied 16 bytes at a time stalled store forwarding (a fifth of
        // scan_together's samples on Barth's sextic). `ray` over [tmin, tmax], not answered.
        Scanned(unsigned pi, unsigned pj, const Ray& ray, double tmin, double tmax)
            : i(pi), j(pj), s(ray) {
            s.tmin = tmin;
            s.tmax = tmax;
            res.status = Status::Miss;
        }
    };
    std::vector<Scanned> scanned;
    TangentCache tangent;  ///< of `list`
    /// The list that this level's scan in lanes walks (Walker::fold): folded to the node's box
    /// (expr::fold_ssa), or empty (the list itself).
    expr::FoldedList folded;
    TangentCache folded_tangent;  ///< of folded.list
};

/// The inputs (x, y, z) and registers of the walks in lanes: IntervalLanes (double bounds) or
/// IntervalLanesF (binary32 bounds, CoherentOptions::float_lanes).
template <class L>
struct LaneFile {
    std::array<L, 3> in;
    std::vector<L> regs;
};

/// A list that the walks take again and again (the tape's own, its tangent and second-order
/// lists) with registers of its own: its constants are written into them once, in every lane,
/// and each walk loads its boxes straight into its variables' slots, so that a walk runs only
/// the rest (`core`), with the same bits in every slot. The Const and Var steps cost a walk about
/// as much as its arithmetic ones (7 of Barth's sextic's 25 instructions).
template <class L>
struct LaneList {
    static constexpr std::uint32_t kNoVar = ~std::uint32_t{0};
    Ssa core;  ///< the list without its Const and Var instructions
    std::uint32_t var[3] = {kNoVar, kNoVar, kNoVar};  ///< the slots VarX, VarY, VarZ write
    LaneFile<L> file;                                 ///< its registers (file.in is not read)
};

/// The LaneList of `list` (SSA, its slots below `slots`): each constant as the walks' Const step
/// writes it (UpInterval(imm), rounded outward in binary32 lanes), in all kIntervalLanes lanes.
/// None where a variable is written twice (no tape's list does: its Graph writes each once).
template <class L>
std::optional<LaneList<L>> make_lane_list(const Ssa& list, std::uint32_t slots) {
    std::optional<LaneList<L>> made(std::in_place);  // value-initialized, built in place
    LaneList<L>& ll = *made;
    ll.file.regs.resize(slots);
    for (const expr::Instr& in : list) {
        switch (in.op) {
            case expr::Op::Const:
                for (int k = 0; k < expr::kIntervalLanes; ++k)
                    expr::set_lane(ll.file.regs[in.out], k, UpInterval(in.imm));
                break;
            case expr::Op::VarX:
            case expr::Op::VarY:
            case expr::Op::VarZ: {
                std::uint32_t& v =
                    ll.var[static_cast<int>(in.op) - static_cast<int>(expr::Op::VarX)];
                if (v != LaneList<L>::kNoVar) return std::nullopt;
                v = in.out;
                break;
            }
            default:
                ll.core.push_back(in);
        }
    }
    return made;
}

/// Whether the ops that the binary32 walk takes in double (expr::binary32_kernel: tan, floor
/// and the other ops without a vector kernel) are at most a sixth of the instructions of
/// `list`: where they are many, that costs more than eight lanes save (the gyroid's quarter of sin
/// and cos, before they had binary32 kernels: 7% more time; docs/benchmarks.md, session 19).
inline bool mostly_arithmetic(const Ssa& list) {
    const auto n = std::count_if(list.begin(), list.end(), [](const expr::Instr& in) {
        return !expr::binary32_kernel(in.op);
    });
    return 6 * static_cast<std::size_t>(n) <= list.size();
}

inline bool has_choices(const Ssa& list) {
    return std::any_of(list.begin(), list.end(), [](const expr::Instr& in) {
        return in.op == expr::Op::Min || in.op == expr::Op::Max;
    });
}

/// Whether pieces_of(s, w) < m for a nonempty s (s.tmin < s.tmax), w > 0 and m − 1 a power of
/// two, without the division: in any rounding mode the quotient rounds to at most m − 1 exactly
/// when the length is at most (m − 1)·w (exact: m − 1 is a power of two).
inline bool fewer_pieces(const Ray& s, double w, int m) { return s.tmax - s.tmin <= (m - 1) * w; }

/// midpoint(UpInterval(a, b)) for finite a ≤ b, bit for bit in any rounding mode, without making
/// the interval (its checks and the cases of unbounded ends): 0.5·a + 0.5·b kept inside [a, b].
inline double middle(double a, double b) {
    assert(a <= b && std::isfinite(a) && std::isfinite(b));
    const double m = 0.5 * a + 0.5 * b;
    return m < a ? a : (m > b ? b : m);
}

/// Whether [a, b] can be halved: its middle, as the walk takes it, lies strictly inside.
inline bool splittable(double a, double b) {
    const double m = 0.5 * a + 0.5 * b;
    return a < m && m < b;
}

/// Hits waiting for their normals (Walker::flush_normals): fewer take a Dual walk each (a walk of
/// lanes costs more for one or two points: measured on the gyroid).
constexpr int kFewNormals = 3;

}  // namespace certray::tracers::detail::coherent
