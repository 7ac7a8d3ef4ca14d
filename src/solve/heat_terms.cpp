#include "solve/heat_terms.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace hencky {

// ---------------------------------------------------------------------------------------------
// HeatCapacity

HeatCapacity::HeatCapacity(const PropertyTable& density, const PropertyTable& specific_heat,
                           double T_ref)
    : rho_(&density), c_(&specific_heat) {
  T_ = density.temperature;
  T_.insert(T_.end(), specific_heat.temperature.begin(), specific_heat.temperature.end());
  T_.push_back(T_ref);
  std::sort(T_.begin(), T_.end());
  T_.erase(std::unique(T_.begin(), T_.end()), T_.end());
  H_.assign(T_.size(), 0.0);
  const std::size_t i0 = std::lower_bound(T_.begin(), T_.end(), T_ref) - T_.begin();
  for (std::size_t i = i0 + 1; i < T_.size(); ++i) H_[i] = H_[i - 1] + integral(T_[i - 1], T_[i]);
  for (std::size_t i = i0; i-- > 0;) H_[i] = H_[i + 1] - integral(T_[i], T_[i + 1]);
}

double HeatCapacity::integral(double a, double b) const {
  const double m = 0.5 * (a + b), h = 0.5 * (b - a), g = h / std::sqrt(3.0);
  return h * (rho_c(m - g) + rho_c(m + g));
}

double HeatCapacity::enthalpy(double T) const {
  // The piece that holds T; beyond the ends ρc is constant and the end piece extends.
  const auto it = std::upper_bound(T_.begin(), T_.end(), T);
  const std::size_t i = it == T_.begin() ? 0 : static_cast<std::size_t>(it - T_.begin()) - 1;
  return H_[i] + integral(T_[i], T);
}

// ---------------------------------------------------------------------------------------------
// Boundary terms

namespace heat_terms {

FaceFlux face_flux(const HeatBoundarySpec& bc, const Expression& value, const Expression& ambient,
                   const HeatSpec& spec, const Vec3& p, double t, double T) {
  FaceFlux f;
  const char* what = to_string(bc.kind);
  const double v = value.eval_checked(p.x(), p.y(), p.z(), t, what);
  switch (bc.kind) {
    case HeatBoundarySpec::Kind::flux:
      f.q = v;
      f.scale = std::abs(v);
      break;
    case HeatBoundarySpec::Kind::convection: {
      if (v < 0)
        throw InputError(bc.value_where,
                         fmt::format("\"{}\" gives the film coefficient h = {:g} at ({:g}, {:g}, "
                                     "{:g}), t = {:g}; h must be >= 0",
                                     value.text(), v, p.x(), p.y(), p.z(), t));
      const double Ta = ambient.eval_checked(p.x(), p.y(), p.z(), t, "ambient");
      f.q = v * (Ta - T);
      f.dq_dT = -v;
      f.scale = v * (std::abs(Ta) + std::abs(T));
      break;
    }
    case HeatBoundarySpec::Kind::radiation: {
      if (v < 0 || v > 1)
        throw InputError(bc.value_where,
                         fmt::format("\"{}\" gives the emissivity {:g} at ({:g}, {:g}, {:g}), "
                                     "t = {:g}; it must be in 0 .. 1",
                                     value.text(), v, p.x(), p.y(), p.z(), t));
      const double Ta = ambient.eval_checked(p.x(), p.y(), p.z(), t, "ambient");
      const double z = *spec.absolute_zero, es = v * spec.stefan_boltzmann;
      const double a = Ta - z, b = std::max(T - z, 0.0);
      f.q = es * (a * a * a * a - b * b * b * b);
      f.dq_dT = -4 * es * b * b * b;
      f.scale = es * (a * a * a * a + b * b * b * b);
      break;
    }
    case HeatBoundarySpec::Kind::temperature:
    case HeatBoundarySpec::Kind::nodal_flux:  // not a face's (HeatSolver::nodal_flows)
      break;
  }
  return f;
}

}  // namespace heat_terms

// ---------------------------------------------------------------------------------------------
// The recovered heat flux

std::vector<double> nodal_heat_flux(const Model& model, const std::vector<double>& T) {
  const Mesh& mesh = model.mesh();
  // Per node the count of cells at it, then the sum of their fluxes there: each rank goes over
  // the cells whose points it holds, and the layout completes values and counts alike (as the
  // recovery of the stresses does).
  std::vector<double> sums(4 * static_cast<std::size_t>(mesh.n_nodes()), 0.0);
  double dN[3 * max_cell_nodes];
  for (int e = 0; e < mesh.cells.size(); ++e) {
    if (!model.holds_points(e)) continue;
    const auto nodes = mesh.cells.nodes(e);
    const int n = static_cast<int>(nodes.size());
    const CellType type = mesh.cells.type[e];
    const double* xi = node_coordinates(type);
    const MaterialSpec& mat = *model.material_of(e).spec;
    for (int a = 0; a < n; ++a) {
      shape_gradients(type, xi + 3 * a, dN);
      Mat3 J = Mat3::Zero();  // J(i, k) = dx_i / dξ_k
      for (int b = 0; b < n; ++b)
        for (int k = 0; k < 3; ++k) J.col(k) += mesh.x[nodes[b]] * dN[3 * b + k];
      if (!(J.determinant() > 0)) continue;
      const Mat3 Jinv_t = J.inverse().transpose();
      Vec3 g = Vec3::Zero();
      for (int b = 0; b < n; ++b)
        g += Jinv_t * Vec3(dN[3 * b], dN[3 * b + 1], dN[3 * b + 2]) * T[nodes[b]];
      const Vec3 qa = -mat.conductivity(T[nodes[a]]) * g;
      double* v = &sums[4 * static_cast<std::size_t>(nodes[a])];
      v[0] += 1;
      for (int d = 0; d < 3; ++d) v[1 + d] += qa[d];
    }
  }
  model.layout().sum(sums, 4);
  std::vector<double> q(3 * static_cast<std::size_t>(mesh.n_nodes()), 0.0);
  for (int m = 0; m < mesh.n_nodes(); ++m) {
    const double* v = &sums[4 * static_cast<std::size_t>(m)];
    if (v[0] > 0)
      for (int d = 0; d < 3; ++d) q[3 * m + d] = v[1 + d] / v[0];
  }
  return q;
}

}  // namespace hencky
