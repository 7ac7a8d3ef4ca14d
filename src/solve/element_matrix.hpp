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
/// A second one, for the midpoint configuration of an updated-geometry step.
inline CellKinematics& thread_kinematics_midpoint() {
  thread_local CellKinematics kin;
  return kin;
}

/// The matrix of cell e for the iterate's tangents into b.ke (zeroed by the caller): B̄ᵀCB̄
/// over the cell's points, C = tangents[p] at the points of plastic materials (the scheme's
/// matrix), the elastic D at the others.
/// x: the coordinates the step is written on (PointPass::update); initial_stress: σ(t) per
/// point for the initial-stress (geometric) part ∫(∇N_a·σ(t)∇N_b) I of an updated-geometry
/// step, or nullptr.
void element_matrix(const Model& m, const State& trial, const std::vector<Tangent>& tangents,
                    const std::vector<Vec3>& x, const std::vector<Voigt>* initial_stress, int e,
                    CellBuffers& b);

}  // namespace hencky
