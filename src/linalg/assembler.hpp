#pragma once
// Lock-free parallel assembly. Element kernels fill a local matrix and vector and know nothing
// of the global system; the assembler scatters them into the upper-triangle CSC values and a
// full-length nodal vector. Cells of one colour share no node, so threads never write the same
// entry, and nothing is allocated per cell.
#include <omp.h>

#include <span>
#include <vector>

#include "linalg/sparse.hpp"

namespace hencky {

inline constexpr int max_cell_dofs = 3 * max_cell_nodes;

struct CellBuffers {
  double ke[max_cell_dofs * max_cell_dofs];  ///< row-major n_dofs x n_dofs
  double fe[max_cell_dofs];
};

class Assembler {
 public:
  Assembler(const CellSet& cells, int n_nodes, const DofMap& dofs)
      : cells_(&cells), dofs_(&dofs), n_nodes_(n_nodes), colors_(color_cells(cells, n_nodes)) {}

  /// The upper-triangle pattern of the serial back ends, built on first use (the PETSc back
  /// end never asks for it). Call it outside parallel regions.
  const SymmetricPattern& pattern() const {
    if (!pattern_built_) {
      pattern_ = build_pattern(*cells_, n_nodes_, *dofs_);
      pattern_built_ = true;
    }
    return pattern_;
  }
  int n_colors() const { return static_cast<int>(colors_.size()); }

  /// Dofs per node (3: displacement, 1: temperature); a cell's buffers hold per_node() entries
  /// per node, in the order of its nodes.
  int per_node() const { return dofs_->per_node; }

  /// kernel(cell, CellBuffers&) fills ke (zeroed before the call); the matrix goes into
  /// `values` (free x free).
  template <class Kernel>
  void matrix(Kernel&& kernel, std::span<double> values) const {
    std::fill(values.begin(), values.end(), 0.0);
    const SymmetricPattern& pattern = this->pattern();
    for_each_cell([&](int c, CellBuffers& b, int nd) {
      std::fill(b.ke, b.ke + nd * nd, 0.0);
      kernel(c, b);
      scatter_matrix(pattern, c, b.ke, nd, values);
    });
  }

  /// kernel(cell, CellBuffers&) fills fe (zeroed before the call), added into `f_full`. Only
  /// the cells with only[c] != 0 when `only` is given (a rank's own cells).
  template <class Kernel>
  void vector(Kernel&& kernel, std::span<double> f_full,
              const std::vector<char>* only = nullptr) const {
    for_each_cell(
        [&](int c, CellBuffers& b, int nd) {
          std::fill(b.fe, b.fe + nd, 0.0);
          kernel(c, b);
          scatter_vector(c, b.fe, f_full);
        },
        only);
  }

  /// kernel(cell, CellBuffers&) fills ke (zeroed before the call); sink(cell, ke) takes it.
  /// Cells of one colour run in parallel: the sink serializes what it must. Only the cells
  /// with only[c] != 0 when `only` is given.
  template <class Kernel, class Sink>
  void matrices(Kernel&& kernel, Sink&& sink, const std::vector<char>* only = nullptr) const {
    for_each_cell(
        [&](int c, CellBuffers& b, int nd) {
          std::fill(b.ke, b.ke + nd * nd, 0.0);
          kernel(c, b);
          sink(c, static_cast<const double*>(b.ke));
        },
        only);
  }

 private:
  template <class F>
  void for_each_cell(F&& f, const std::vector<char>* only = nullptr) const {
    // Small meshes run on one thread: a barrier per colour costs more than their cells.
#pragma omp parallel if (cells_->size() > 4000)
    {
      CellBuffers buffers;  // one per thread, reused for every cell
      for (const auto& color : colors_) {
#pragma omp for schedule(dynamic, 32)
        for (std::size_t k = 0; k < color.size(); ++k) {
          const int c = color[k];
          if (only && !(*only)[c]) continue;
          f(c, buffers, dofs_->per_node * static_cast<int>(cells_->nodes(c).size()));
        }
        // the implicit barrier of `omp for` separates colours
      }
    }
  }
  void scatter_matrix(const SymmetricPattern& pattern, int c, const double* ke, int nd,
                      std::span<double> values) const {
    const auto nodes = cells_->nodes(c);
    const int k = dofs_->per_node;
    int eq[max_cell_dofs];
    for (std::size_t a = 0; a < nodes.size(); ++a)
      for (int d = 0; d < k; ++d) eq[k * a + d] = dofs_->eq[k * nodes[a] + d];
    for (int j = 0; j < nd; ++j) {
      const int gj = eq[j];
      if (gj < 0) continue;
      for (int i = 0; i < nd; ++i) {
        const int gi = eq[i];
        if (gi < 0 || gi > gj) continue;
        values[pattern.find(gi, gj)] += ke[i * nd + j];
      }
    }
  }
  void scatter_vector(int c, const double* fe, std::span<double> f_full) const {
    const auto nodes = cells_->nodes(c);
    const int k = dofs_->per_node;
    for (std::size_t a = 0; a < nodes.size(); ++a)
      for (int d = 0; d < k; ++d) f_full[k * nodes[a] + d] += fe[k * a + d];
  }

  const CellSet* cells_;
  const DofMap* dofs_;
  int n_nodes_;
  mutable SymmetricPattern pattern_;
  mutable bool pattern_built_ = false;
  std::vector<std::vector<int>> colors_;
};

}  // namespace hencky
