#pragma once
// The serial back ends behind LinearSystem: the matrix's upper triangle on the free dofs in
// the Assembler's pattern (CSC), factorized by a SparseSolver (CHOLMOD or CG).
#include <memory>
#include <vector>

#include "linalg/linear_system.hpp"

namespace hencky {

class SerialSystem final : public LinearSystem {
 public:
  /// `node_order`: a fill-reducing order of the nodes for the factorization (every node;
  /// empty: the solver's own), e.g. FactorEstimate::node_order.
  SerialSystem(const Assembler& assembler, const DofMap& dofs, std::unique_ptr<SparseSolver> solver,
               std::vector<std::int64_t> node_order = {})
      : assembler_(assembler),
        dofs_(dofs),
        solver_(std::move(solver)),
        node_order_(std::move(node_order)) {}

  void assemble_cells(const CellMatrix& cell_matrix) override;
  void keep_cells() override { kept_ = values_; }
  bool restore_cells() override;
  void add_block(int a, int b, const Mat3& block) override;
  void factorize() override;
  void solve(std::span<const double> rhs, std::span<double> x) override { solver_->solve(rhs, x); }
  void set_relative_tolerance(double rtol) override { solver_->set_relative_tolerance(rtol); }
  std::vector<std::string> unused_options() const override { return {}; }
  const std::vector<char>* own_cells() const override { return nullptr; }
  const LinearSolverStats& stats() const override { return solver_->stats(); }

 private:
  const Assembler& assembler_;
  const DofMap& dofs_;
  std::unique_ptr<SparseSolver> solver_;
  std::vector<std::int64_t> node_order_;
  bool analyzed_ = false;
  std::vector<double> values_, kept_;
};

/// The serial system of a model's assembler and dofs with the given back end.
std::unique_ptr<LinearSystem> make_serial_system(const Assembler& assembler, const DofMap& dofs,
                                                 LinearSolverKind kind, double tolerance = 1e-10,
                                                 std::vector<std::int64_t> node_order = {});

}  // namespace hencky
