#include "solve/step_matrix.hpp"

#include <fmt/format.h>

#include "core/timer.hpp"
#include "parallel/mpi.hpp"
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
  // Under `updated` the step's start matrix that spread_prescribed factorized is the one the
  // first solve takes (StepStart::at_start: it does not depend on the iterate), unless the
  // points' matrices it was made of changed since.
  if (iteration == 0 && start_factorized_) {
    if (iterate_.points().tangents() == assembled_tangents_) return false;
  }
  return !factorized_ || (iteration == 0 && (changes_with_temperature_ || updated_)) ||
         (updated_ && policy == MatrixPolicy::per_iteration) ||
         (tangent_changed &&
          (policy == MatrixPolicy::per_iteration ||
           (policy == MatrixPolicy::per_step && iteration <= first_iteration + 1)));
}

namespace {
/// Where the system's unknown `equation` is (a factorization's failed pivot): " at the y
/// displacement of node 12 (0.1, 0, 0)", or "" when not known (an iterative solver's failure).
std::string equation_place(const Model& m, long equation) {
  const DofMap& dofs = m.dofs();
  for (int i = 0; equation >= 0 && i < dofs.n_dofs(); ++i) {
    if (dofs.eq[i] != equation) continue;
    const int node = i / dofs.per_node;
    const Vec3& x = m.mesh().x[node];
    return fmt::format(" at the {} displacement of node {} ({:.4g}, {:.4g}, {:.4g})",
                       "xyz"[i % dofs.per_node], m.mesh().node_tag[node], x.x(), x.y(), x.z());
  }
  return "";
}

/// The failure of the tangent of a converged state under `updated` (a step's start). At t = 0
/// the body is undeformed and free of stress: its matrix is the small strain's, and a failure
/// is a body not held (the step control says so).
LinearSystemError limit_point(const LinearSystemError& e, double t) {
  if (t == 0) return e;
  return LinearSystemError(
      e.kind(), fmt::format("the tangent is not positive definite at the step's start ({}): a "
                            "buckling or limit point near t = {:g} (geometry: updated), or a "
                            "body its supports do not hold; past a bifurcation `linear: petsc` with an LU factorization "
                            "(petsc_options: \"-pc_type lu\") can follow the path it is on, but "
                            "a load control cannot pass a limit point and an arc-length control "
                            "is not available",
                            e.what(), t),
      e.equation());
}
}  // namespace

void StepMatrix::assemble_and_factorize(const State& c, const State& trial, bool new_elements,
                                        int iteration, bool at_start) {
  at_start_ = at_start;
  assemble(c, trial, new_elements, UpdatedMatrix::exact);
  if (!updated_) return factorize();
  // Under `updated` the exact tangent can stop being positive definite at an iterate far from
  // the answer: the first iterates of a slender strip under a follower pressure strain its tip
  // by tens of per cent, where the initial-stress part of Hencky's S in compression (E ln λ/λ²
  // in uniaxial compression, against the Green strain's E(λ² − 1)/2) makes the matrix
  // indefinite (examples/cantilever-hook on 25 elements: each of its 45 steps was cut back
  // once, and the scheme's matrix on the Green strain with the initial-stress part was
  // indefinite too).
  // Such an iterate goes on with the scheme's matrix on the Green strain and no initial-stress
  // part, positive definite wherever the scheme's matrix is and the body is held: the matrix
  // changes the path of the iteration, not its answer. At the step's start the state is a
  // converged one (or newton's extrapolation of it): a tangent that is not positive definite
  // there is the structure's own, a buckling or limit point.
  try {
    factorize();
  } catch (const LinearSystemError& e) {
    if (iteration == 0) throw limit_point(e, c.time);
    if (!fall_back(c, trial, iteration, e)) throw;
  }
}

bool StepMatrix::fall_back(const State& c, const State& trial, int iteration,
                           const LinearSystemError& e) {
  // An iterative solver (CG) finds an indefinite matrix in the solve, not in a factorization.
  if (!updated_ || iteration == 0 || last_matrix_ != UpdatedMatrix::exact) return false;
  log_.detail("  the tangent is not positive definite at iteration {} ({}): assembled again "
              "with the scheme's matrix on the step's Green strain, without the initial-stress "
              "part",
              iteration, e.what());
  assemble(c, trial, true, UpdatedMatrix::law_without_stress);
  factorize();
  return true;
}

void StepMatrix::assemble(const State& c, const State& trial, bool new_elements,
                          UpdatedMatrix matrix) {
  ScopedTimer timer(timings_.assembly);
  last_matrix_ = matrix;
  start_factorized_ = false;
  const StepStart step_start{c, iterate_.points().start_volume_ratio(), matrix, at_start_};
  const StepStart* start = updated_ ? &step_start : nullptr;
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

double StepMatrix::spread_prescribed(const State& c, State& trial) {
  const auto& dofs = m_.dofs();
  std::vector<double> du(dofs.n_dofs(), 0.0);
  bool moved = false;
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (dofs.eq[i] < 0 && trial.u[i] != c.u[i]) du[i] = trial.u[i] - c.u[i], moved = true;
  if (!par::any(moved)) return 0.0;
  // K_fp Δu_p of the step's start, cell by cell: ke of the start times the cell's prescribed
  // increments.
  std::vector<double> f;
  {
    ScopedTimer timer(timings_.assembly);
    const StepStart start{c, iterate_.points().start_volume_ratio(), UpdatedMatrix::exact, true};
    const auto& mesh = m_.mesh();
    const auto& tangents = iterate_.points().tangents();
    f.assign(dofs.n_dofs(), 0.0);
    m_.assembler().vector(
        [&](int e, CellBuffers& b) {
          const auto nodes = mesh.cells.nodes(e);
          const int nd = 3 * static_cast<int>(nodes.size());
          bool any = false;  // most cells have no prescribed node that moves
          for (int n : nodes) any = any || du[3 * n] != 0 || du[3 * n + 1] != 0 || du[3 * n + 2] != 0;
          if (!any) return;
          std::fill(b.ke, b.ke + nd * nd, 0.0);
          element_matrix(m_, trial, tangents, iterate_.x(), &start, e, b);
          for (int r = 0; r < nd; ++r)
            for (std::size_t a = 0; a < nodes.size(); ++a)
              for (int d = 0; d < 3; ++d)
                b.fe[r] += b.ke[r * nd + 3 * static_cast<int>(a) + d] * du[3 * nodes[a] + d];
        },
        f, iterate_.points().cells());
    m_.layout().sum(f, 3);
  }
  std::vector<double> rhs(dofs.n_free, 0.0);
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) rhs[k] = -f[i];
  at_start_ = true;
  assemble(c, trial, true, UpdatedMatrix::exact);
  try {
    factorize();
  } catch (const LinearSystemError& e) {
    throw limit_point(e, c.time);  // the converged state's own tangent
  }
  start_factorized_ = true;  // the step's first solve may take it (needs_elements)
  system_.set_relative_tolerance(1e-6);
  {
    ScopedTimer timer(timings_.solve);
    system_.solve(rhs, delta_);
  }
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) trial.u[i] += delta_[k];
  return iterate_.norm(f);
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
    // The failed pivot's place in the mesh, after the solver's words for it; every message
    // built on this error (a body not held, a limit point) quotes it.
    if (cell_index < 0)
      throw LinearSystemError(e.kind(), e.what() + equation_place(m_, e.equation()),
                              e.equation());
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
