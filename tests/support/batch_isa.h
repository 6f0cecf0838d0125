// tests/support/batch_isa.h — the batch walks' instruction-set copies, for tests that run each.
#pragma once

#include <vector>

#include "expr/eval_batch.h"

namespace certray::testing {

/// The copies of the batch walks (expr/eval_batch.h) this CPU runs.
inline std::vector<expr::BatchIsa> batch_isas() {
    std::vector<expr::BatchIsa> v;
    for (expr::BatchIsa isa :
         {expr::BatchIsa::Baseline, expr::BatchIsa::Avx2, expr::BatchIsa::Avx512}) {
        if (expr::batch_isa_supported(isa)) v.push_back(isa);
    }
    return v;
}

/// Restores the copy in use when it was made, when it ends (a test that forces copies).
class BatchIsaGuard {
  public:
    BatchIsaGuard() : saved_(expr::batch_isa()) {}
    ~BatchIsaGuard() { expr::set_batch_isa(saved_); }
    BatchIsaGuard(const BatchIsaGuard&) = delete;
    BatchIsaGuard& operator=(const BatchIsaGuard&) = delete;

  private:
    expr::BatchIsa saved_;
};

}  // namespace certray::testing
