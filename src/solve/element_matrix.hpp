#pragma once
// The element matrix of the step loop: B̄ᵀCB̄ over a cell's points, C the point's matrix
// (elastic D, or the scheme's tangent at a plastic point).
#include <vector>

#include "fem/geometry.hpp"
#include "linalg/assembler.hpp"
#include "material/plastic_point.hpp"
#include "solve/model.hpp"
#include "solve/state.hpp"

namespace hencky {

/// Per-thread scratch for a cell's kinematics (about 26 kB: not on every stack frame).
inline CellKinematics& thread_kinematics() {
  thread_local CellKinematics kin;
  return kin;
}
/// The same for a cell's deformation in an updated-geometry step (about 25 kB).
inline CellDeformation& thread_deformation() {
  thread_local CellDeformation def;
  return def;
}

/// Under `geometry: updated`, the matrix of an iterate: the exact tangent of Hencky's strain,
/// or for an iterate far from the answer whose exact tangent is not positive definite
/// (StepMatrix::assemble_and_factorize) the scheme's matrix dτ/dΔε itself for dS/dE (the
/// material part of the step's Green strain) without the initial-stress part.
enum class UpdatedMatrix { exact, law_without_stress };

/// Under `geometry: updated`, the step's start: the state at t and the points' volume ratios
/// J(t) = dv/dV there (PointPass::start_volume_ratio).
struct StepStart {
  const State& state;
  const std::vector<double>& volume_ratio;
  UpdatedMatrix matrix = UpdatedMatrix::exact;
  /// The matrix of the step's start (F = I, S = σ(t)) whatever the iterate: the fixed matrix
  /// of the schemes that keep one through the step.
  bool at_start = false;
};

/// The matrix of cell e for the iterate's tangents into b.ke (zeroed by the caller): B̄ᵀCB̄
/// over the cell's points, C = tangents[p] at the points of plastic materials (the scheme's
/// matrix), the elastic D at the others.
/// x: the coordinates the step is written on (PointPass::update); start: under
/// `geometry: updated`, the state at the step's start, whose displacements the step's
/// deformation is measured from (the matrix is then that of the updated Lagrangian step,
/// with its initial-stress part), else nullptr.
void element_matrix(const Model& m, const State& trial, const std::vector<Tangent>& tangents,
                    const std::vector<Vec3>& x, const StepStart* start, int e,
                    CellBuffers& b);

}  // namespace hencky
