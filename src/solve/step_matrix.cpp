#include "solve/step_matrix.hpp"

#include <fmt/format.h>

#include "core/timer.hpp"
#include "solve/element_matrix.hpp"

namespace hencky {

StepMatrix::StepMatrix(const Model& m, LinearSystem& system, IterateEvaluator& iterate, Log& log,
                       Timings& timings)
    : m_(m),
      system_(system),
      iterate_(iterate),
      log_(log),
      timings_(timings),
      updated_(m.spec().solver.updated_geometry),
      delta_(m.dofs().n_free) {
  if (m.has_temperature())
    for (const auto& mat : m.materials())
      changes_with_temperature_ =
          changes_with_temperature_ || !mat.spec->E.is_constant() || !mat.spec->nu.is_constant();
}

bool StepMatrix::needs_elements(int iteration, int first_iteration, bool tangent_changed,
                                MatrixPolicy policy) const {
  // Under `geometry: updated` the matrix is that of the step's configuration, rebuilt at each
  // step's start, and for the schemes whose matrix follows the iterate (newton,
  // variable-stiffness) at every iteration: the iterate's deformation and stress enter it
  // (updated_matrix, element_matrix.cpp), also for elastic points.
  return !factorized_ || (iteration == 0 && (changes_with_temperature_ || updated_)) ||
         (updated_ && policy == MatrixPolicy::per_iteration) ||
         (tangent_changed &&
          (policy == MatrixPolicy::per_iteration ||
           (policy == MatrixPolicy::per_step && iteration <= first_iteration + 1)));
}

void StepMatrix::assemble_and_factorize(const State& c, const State& trial, bool new_elements) {
  {
    ScopedTimer timer(timings_.assembly);
    const State* start = updated_ ? &c : nullptr;
    ContactStep& contact = iterate_.contact();
    if (new_elements || !contact.active() || !system_.restore_cells()) {
      const auto& tangents = iterate_.points().tangents();
      const auto& x = iterate_.x();
      assembled_tangents_ = tangents;
      system_.assemble_cells(
          [&](int e, CellBuffers& b) { element_matrix(m_, trial, tangents, x, start, e, b); });
      if (contact.active()) system_.keep_cells();
    }
    if (contact.active())
      contact.add_matrix(trial,
                         [&](int a, int b, const Mat3& block) { system_.add_block(a, b, block); });
  }
  factorize();
}

void StepMatrix::solve(double residual) {
  // An iterative solve need only reduce this iterate's residual to 0.1 % of the step's
  // tolerance, not to its own default (an inexact Newton method with a fixed forcing term,
  // after Eisenstat and Walker): the error it leaves is a thousandth of what convergence
  // allows, and the residual recomputed from the points still decides.
  if (residual > 0) system_.set_relative_tolerance(1e-3 * m_.spec().solver.tolerance / residual);
  ScopedTimer timer(timings_.solve);
  system_.solve(iterate_.rhs(), delta_);
  if (!options_checked_) {
    // PETSc ignores options it does not know: say so once it has read them (at set-up).
    options_checked_ = true;
    for (const auto& name : system_.unused_options())
      log_.warn(fmt::format(
          "PETSc option '{}' was not used (misspelt, or for a solver that is not in use)", name));
  }
}

void StepMatrix::factorize() {
  ScopedTimer timer(timings_.factorization);
  try {
    system_.factorize();
  } catch (const LinearSystemError& e) {
    const int cell_index = iterate_.negative_secant_cell();
    if (cell_index < 0) throw;
    const Model::CellFacts cell = m_.cell_facts(cell_index);
    // variable-stiffness with a negative slope: say why the matrix is indefinite (a plain
    // SolveError: the step failed, the supports are not to blame).
    throw SolveError(fmt::format(
        "{}: scheme 'variable-stiffness' has a negative slope of the curve of material "
        "'{}' at element {} (a softening curve makes its matrix indefinite); use newton or "
        "initial-stress",
        e.what(), m_.materials()[cell.material].spec->name, cell.tag));
  }
  if (m_.global_free() > 0) ++factorizations_;  // none where every dof is prescribed
  factorized_ = true;
}

}  // namespace hencky
