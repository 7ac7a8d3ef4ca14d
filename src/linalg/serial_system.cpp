#include "linalg/serial_system.hpp"

namespace hencky {

void SerialSystem::assemble_cells(const CellMatrix& cell_matrix) {
  values_.resize(assembler_.pattern().nnz());
  assembler_.matrix(cell_matrix, values_);
}

bool SerialSystem::restore_cells() {
  if (kept_.empty()) return false;
  values_ = kept_;
  return true;
}

void SerialSystem::add_block(int a, int b, const Mat3& block) {
  const auto& eq = dofs_.eq;
  const auto& pattern = assembler_.pattern();
  // One triangle of the symmetric matrix: each global pair once, from the ordering in which
  // its row is the smaller.
  for (int dj = 0; dj < 3; ++dj)
    for (int dk = 0; dk < 3; ++dk) {
      const int gj = eq[3 * a + dj], gk = eq[3 * b + dk];
      if (gj < 0 || gk < 0 || gj > gk) continue;
      values_[pattern.find(gj, gk)] += block(dj, dk);
    }
}

void SerialSystem::factorize() {
  if (!analyzed_) {
    // The nodes' order, as the dofs' (each node's free dofs in their order).
    std::vector<std::int64_t> perm;
    const int k = dofs_.per_node;
    for (std::int64_t v : node_order_)
      for (int d = 0; d < k; ++d)
        if (const int j = dofs_.eq[k * v + d]; j >= 0) perm.push_back(j);
    solver_->analyze(assembler_.pattern(), perm);
    node_order_ = {};
    analyzed_ = true;
  }
  solver_->factorize(values_);
}

std::unique_ptr<LinearSystem> make_serial_system(const Assembler& assembler, const DofMap& dofs,
                                                 LinearSolverKind kind, double tolerance,
                                                 std::vector<std::int64_t> node_order) {
  return std::make_unique<SerialSystem>(assembler, dofs, make_sparse_solver(kind, tolerance),
                                        std::move(node_order));
}

}  // namespace hencky
