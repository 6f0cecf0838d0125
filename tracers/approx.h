// tracers/approx.h — "approximation in space" made certified: per-cell Taylor models (polynomial
// of degree 1–3 in x, y, z plus a proven remainder) on the ambiguous leaves of an octree, solved
// along the ray as univariate polynomials.
//
// Contract:
//   - certified(): solvers/ray.h certification semantics for the whole ray. On each ambiguous
//     leaf's segment (when it provably lies in the leaf's inflated box) the model f̃ + [r] composed
//     with the ray, p(t) + [r], encloses g(t) = f(o + t·d) wherever f is defined
//     (interval/taylor.h): sub-segments where p + [r] excludes 0 are excluded without touching the
//     tape; the remaining candidates (narrowed by bisection of the model, no tape evaluations) are
//     finished by solvers::certified_first_root on the leaf's pruned tape, in order along the ray.
//     Segments not provably inside their cell and the parts of [tmin, tmax] outside the bounds use
//     the certified solver with the full tape (as Octree::certified). A candidate where p ± r has
//     certain opposite signs at its ends and the model is defined holds a zero proven by the
//     model ("proven"); others are "fallback".
//   - plain(): approximate. The remainder is ignored: p(t) = 0 is solved in closed form
//     (solvers/closed_form.h) on the coefficients' midpoints and the first root in a leaf's
//     segment is reported as a Hit; outside the bounds the scene is taken as empty. It may miss
//     or invent roots; that is what it measures.
// Models are built lazily (once per leaf, thread-safe) by one evaluation of the pruned tape over
// TaylorModel<3> on the inflated cell; the degree kept is the lowest whose remainder (the higher
// terms bounded over the cell and moved into it) is at most `tolerance` × cell size × |∇f̃(c)|.
// A model composition counts as one interval evaluation in RayResult.evals.
// Reference: docs/theory/taylor.md.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "expr/tape.h"
#include "interval/interval.h"
#include "solvers/certified.h"
#include "solvers/ray.h"
#include "tracers/octree.h"

namespace certray::tracers {

/// The knobs of Approx.
struct ApproxOptions {
    /// The octree whose ambiguous leaves carry the models.
    OctreeOptions octree;
    /// The degree kept per cell is the lowest d in [1, 3] with width(R_d) ≤ tolerance · h · |∇f̃(c)|
    /// (h the cell's largest side); 3 otherwise.
    double tolerance = 1.0 / 1024;
    /// Bisection depth of a segment with the model before a candidate goes to the solver.
    int max_split_depth = 10;
};

/// One cell's model: f(p) ∈ Σ a_m (p − c)^m + r on the inflated cell where f is defined.
struct CellModel {
    std::array<double, 20> a{};  ///< graded order of interval/taylor.h; 0 above `degree`
    Interval r;                  ///< remainder; decoration: f defined and continuous on the cell
    std::array<double, 3> c{};   ///< centre
    std::uint8_t degree = 0;     ///< 1–3
    std::uint8_t level = 0;      ///< octree depth of the leaf
    double size = 0;             ///< the cell's largest side
};

/// Counters of what happened (summed over all rays so far; relaxed atomics).
struct ApproxStats {
    std::uint64_t segments = 0;                ///< leaf segments met by certified()
    std::uint64_t excluded = 0;                ///< segments excluded by the model alone
    std::uint64_t proven = 0;                  ///< candidates with a zero proven by the model
    std::uint64_t fallback = 0;                ///< candidates the model could not decide
    std::uint64_t full_tape = 0;               ///< segments not inside their cell, and outer parts
    std::uint64_t model_ranges = 0;            ///< interval ranges of p(t) + r computed (bisection)
    std::uint64_t models_built = 0;            ///< cells whose model has been built
    std::array<std::uint64_t, 4> by_degree{};  ///< built models by kept degree
    std::size_t model_bytes = 0;               ///< memory of the model slots
};

/// The octree of a scene with a lazily built Taylor model per ambiguous leaf, and the two ray
/// queries over them (see the file contract). Thread-safe after construction.
class Approx {
  public:
    /// Builds the octree of `tape` (which must outlive this object) over `bounds`; models lazily.
    Approx(const expr::Tape& tape, const std::array<Interval, 3>& bounds,
           const ApproxOptions& options = {});
    Approx(const Approx&) = delete;
    Approx& operator=(const Approx&) = delete;

    /// The first root along the ray, certified (see the file contract).
    RayResult certified(const Ray& ray, const solvers::CertifiedOptions& options) const;
    /// The first root of the models without remainder (approximate; see the file contract).
    RayResult plain(const Ray& ray) const;

    /// The model of an ambiguous leaf (built on first use; thread-safe).
    const CellModel& model(std::uint32_t node) const;
    /// Builds every ambiguous leaf's model now.
    void build_all() const;
    /// The models built so far (leaf node, model), for statistics.
    std::vector<std::pair<std::uint32_t, const CellModel*>> built_models() const;

    /// A snapshot of the counters and the memory of the models.
    ApproxStats stats() const;
    /// The underlying octree.
    const Octree& octree() const noexcept { return tree_; }

  private:
    struct Slot {
        std::once_flag once;
        CellModel model;
    };
    void build(std::uint32_t node, CellModel& out) const;

    Octree tree_;
    ApproxOptions options_;
    std::vector<std::uint32_t> slot_of_;  ///< node → slot (ambiguous leaves), else UINT32_MAX
    std::unique_ptr<Slot[]> slots_;
    std::size_t slot_count_ = 0;
    mutable std::unique_ptr<std::atomic<bool>[]> built_;
    mutable std::atomic<std::uint64_t> segments_{0}, excluded_{0}, proven_{0}, fallback_{0},
        full_tape_{0}, model_ranges_{0}, models_built_{0};
    mutable std::array<std::atomic<std::uint64_t>, 4> by_degree_{};
};

}  // namespace certray::tracers
