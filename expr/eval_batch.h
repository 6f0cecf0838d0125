// expr/eval_batch.h — which instruction set Evaluator<Batch> runs on: query it, force it.
//
// Contract: Evaluator<Batch> (expr/eval.h, expr/eval_batch.cpp) walks a tape with one copy of its
// loop per instruction set. Every copy gives the same bits (each lane bit for bit the scalar
// double evaluator); only the speed differs. At the first evaluation the widest set the CPU and OS
// support is chosen, unless the environment variable CERTRAY_BATCH_ISA names one ("baseline",
// "avx2", "avx512"). Tests and benchmarks force a set with set_batch_isa to cover every copy.
#pragma once

#include <cstdint>

namespace certray::expr {

/// The copies of the batch walk. Baseline: SSE2 on x86-64 (every x86-64 CPU), plain scalar code
/// elsewhere; Avx2: 4 doubles per instruction (AVX and AVX2, never FMA); Avx512: 8 doubles per
/// instruction (AVX-512F, never FMA).
enum class BatchIsa : std::uint8_t { Baseline = 0, Avx2 = 1, Avx512 = 2 };

/// The copy Evaluator<Batch> uses now (choosing it if no evaluation has run yet).
BatchIsa batch_isa() noexcept;

/// True when this binary has the copy and this CPU (and OS) can run it. Baseline always is.
bool batch_isa_supported(BatchIsa isa) noexcept;

/// Makes every Evaluator<Batch> of the process use `isa` from now on; returns false (and changes
/// nothing) if it is not supported. Not meant to race with evaluations (tests, benchmarks).
bool set_batch_isa(BatchIsa isa) noexcept;

/// "baseline", "avx2" or "avx512".
const char* batch_isa_name(BatchIsa isa) noexcept;

}  // namespace certray::expr
