#pragma once
// What the heat analysis's sources share (solve/heat.hpp is its interface): heat.cpp takes
// the steps (Newton, cut-backs, snapshots), heat_assembly.cpp makes the passes over the cells
// (G, its matrix, dG/dT v), heat_terms.cpp the terms at a point (capacity, the boundary
// conditions' fluxes) and the recovered heat flux. Not for use outside these files.
#include <algorithm>
#include <span>
#include <vector>

#include "core/expression.hpp"
#include "fem/geometry.hpp"
#include "fem/quadrature.hpp"
#include "fem/reference_element.hpp"
#include "solve/heat.hpp"

namespace hencky {

/// The case's expressions, one copy per thread (Expression is not thread-safe).
struct HeatExpressions {
  Expression source;
  std::vector<Expression> value, ambient;  ///< per heat.boundary entry
};

/// What a pass over the cells gives, per node (whole on every rank): R(T, t1) and the
/// capacity term C = ∫ (H(T) − H(T0)) N dV, each with its scale (the sum of the magnitudes
/// of the terms it is made of, which bounds its round-off).
struct HeatSolver::Evaluation {
  std::vector<double> R, SR, C, SC;
  std::vector<double> G, S;  ///< the step's residual and its scale
};

namespace heat_terms {

/// The quadrature of the heat terms: at least the mechanical one, and exact for the capacity
/// (mass) matrix of an affine cell.
inline int heat_degree(CellType type) {
  const int order = cell_linear(type) == type ? 1 : 2;
  return std::max(default_degree(type), 2 * order);
}

/// The heat flux into the body of a natural condition at a face point, its derivative with
/// respect to T and the magnitude of its terms.
struct FaceFlux {
  double q = 0, dq_dT = 0, scale = 0;
};
/// `value` and `ambient` are the thread's copies of bc's expressions; p the point, t the time,
/// T the temperature there. Throws InputError for a negative h or an emissivity outside 0 .. 1.
FaceFlux face_flux(const HeatBoundarySpec& bc, const Expression& value, const Expression& ambient,
                   const HeatSpec& spec, const Vec3& p, double t, double T);

/// Calls f(N, nf, da, p) at each quadrature point of heat face hf: its shape functions, node
/// count, area element and position.
template <class F>
void for_face_points(const Mesh& mesh, const HeatFace& hf, F&& f) {
  const auto fnodes = mesh.faces.nodes(hf.face);
  const int nf = static_cast<int>(fnodes.size());
  const CellType ft = mesh.faces.type[hf.face];
  const ReferenceTable& ftab = reference_table(ft, heat_degree(ft));
  Vec3 xf[max_cell_nodes];
  for (int a = 0; a < nf; ++a) xf[a] = mesh.x[fnodes[a]];
  const std::span<const Vec3> xfs(xf, nf);
  for (int q = 0; q < ftab.n_points; ++q)
    f(&ftab.N[static_cast<std::size_t>(q) * nf], nf,
      face_normal(ftab, q, xfs).norm() * ftab.weights[q], point_position(ftab, q, xfs));
}

}  // namespace heat_terms
}  // namespace hencky
