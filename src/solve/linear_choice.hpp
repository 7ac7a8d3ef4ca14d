#pragma once
// `solver.linear: auto` (the default): which back end solves a run's linear systems, and why.
// On one process the choice is between CHOLMOD (2 threads) and PETSc CG + GAMG with the
// rigid-body near null space (one process, one core). What decides is the factorization's
// cost against the unknowns n: a factorization costs its flops (at ~45 Gflop/s on this
// machine's 2 cores), which grow much faster for a compact body than for a slender one (at
// ~390k unknowns the cylinder's factor costs 2.9× the cantilever's flops); CG + GAMG costs
// about 8 s × (n / 100k)^1.4 on the bench problems (elastic tet10, one core: 80 µs per unknown
// at 100k, 210 µs at 1M). So CG + GAMG is faster from 3.6 Mflop per unknown × (n / 100k)^0.4
// on. The rule, from the crossovers measured on both problems (docs/performance.md,
// "solver.linear: auto"):
//
//  - more than one MPI rank: CG + GAMG (MUMPS was slower on 2 ranks on every benchmark);
//  - a factor predicted not to fit in the memory available: CG + GAMG;
//  - from `analyze_from` unknowns, the factor is predicted by a symbolic analysis of the node
//    graph (linalg/sparse_solver.hpp, Model::node_factor): CG + GAMG when it costs at least
//    crossover_flops × (n / 100k)^crossover_growth per unknown;
//  - otherwise CHOLMOD.
#include <cstdint>
#include <string>

#include "spec/case.hpp"

namespace hencky {

struct LinearChoiceInputs {
  std::int64_t unknowns = 0;  ///< free dofs of the system
  int per_node = 3;           ///< dofs per node: 3 displacement, 1 temperature
  bool nonlinear = false;     ///< plasticity or contact: a factorization per iteration or so
  int ranks = 1;
  double available_bytes = 0;  ///< memory the run may use; 0: unknown (not checked)
  /// The factor predicted by a symbolic analysis (0: not analysed, below analyze_from).
  double factor_flops = 0;
  double factor_entries = 0;
};

struct LinearChoiceRule {
  /// From this many unknowns on (of a displacement system; a temperature system counts its
  /// nodes × 3) the factor is predicted by a symbolic analysis; below, the factorization is
  /// cheaper than CG + GAMG on every model measured (at most 1.3 Mflop per unknown at ~100k).
  std::int64_t analyze_from = 150'000;
  /// Factorization flops per unknown from which CG + GAMG is faster, at 100k unknowns, and
  /// the exponent of its growth with n / 100k (GAMG's time grows as n^1.4 here).
  double crossover_flops = 3.6e6;
  double crossover_growth = 0.4;
  /// crossover_flops at n unknowns.
  double crossover_at(double n) const;
  /// The factorization's peak may take this fraction of the memory available.
  double memory_fraction = 0.7;
  /// Peak of a direct solve per factor entry (measured 12.3 bytes, docs/performance.md).
  double bytes_per_factor_entry = 12.5;
  /// Without an analysis, the factor's entries predicted as factor_coefficient ×
  /// nodes^(4/3) × per_node² (nested dissection of a 3D mesh), the coefficient at the top of
  /// the measured range (5-9 for tet10 up to 1M unknowns).
  double factor_coefficient = 10.0;

  /// The defaults, with HENCKY_AUTO_ANALYZE_FROM (unknowns) and HENCKY_AUTO_CROSSOVER (flops
  /// per unknown at 100k unknowns) from the environment when set: for tests and experiments
  /// (docs/development.md).
  static LinearChoiceRule from_environment();
};

struct LinearChoice {
  SolverSpec::Linear linear = SolverSpec::Linear::direct;  ///< direct or petsc
  double predicted_direct_bytes = 0;
  std::string reason;  ///< one sentence for the log
};

LinearChoice choose_linear(const LinearChoiceInputs& in, const LinearChoiceRule& rule);

/// Whether choose_linear wants the factor predicted (the model is at least analyze_from).
bool wants_factor_estimate(const LinearChoiceInputs& in, const LinearChoiceRule& rule);

/// MemAvailable of /proc/meminfo in bytes, or HENCKY_AUTO_MEMORY when set (tests); 0 when
/// neither can be read.
double available_memory_bytes();

}  // namespace hencky
