#pragma once
#include <array>
#include <span>

#include "core/types.hpp"
#include "fem/reference_element.hpp"

namespace hencky {

/// Shape-function gradients in physical coordinates at integration point q of a volume cell:
/// dNdx[3*a + i] = dN_a/dx_i. Returns det J (negative or zero for an inverted or degenerate cell).
double physical_gradients(const ReferenceTable& table, int q, std::span<const Vec3> x, double* dNdx);

/// Position of integration point q.
Vec3 point_position(const ReferenceTable& table, int q, std::span<const Vec3> x);

/// Area element and (unnormalized) normal dx/dξ × dx/dη at point q of a face; |n| is the area
/// element.
Vec3 face_normal(const ReferenceTable& table, int q, std::span<const Vec3> x);

/// Natural coordinates of physical point p in a volume cell (Newton on the geometric map).
/// Returns false when the iteration fails or the point is outside the cell by more than `tol`
/// in natural coordinates.
bool locate_in_cell(CellType type, std::span<const Vec3> x, const Vec3& p, double tol, double xi[3]);

/// Strain-displacement product B_a^T: builds eps (Voigt, engineering shears) from nodal
/// displacement u and gradients dNdx, eps = sum_a B_a u_a, (1.5), (1.10).
inline Voigt strain_from_gradients(int n, const double* dNdx, const double* u) {
  Voigt e = Voigt::Zero();
  for (int a = 0; a < n; ++a) {
    const double gx = dNdx[3 * a], gy = dNdx[3 * a + 1], gz = dNdx[3 * a + 2];
    const double ux = u[3 * a], uy = u[3 * a + 1], uz = u[3 * a + 2];
    e[0] += gx * ux;
    e[1] += gy * uy;
    e[2] += gz * uz;
    e[3] += gz * uy + gy * uz;
    e[4] += gz * ux + gx * uz;
    e[5] += gy * ux + gx * uy;
  }
  return e;
}

/// f_a += w * B_a^T s for a Voigt stress-like vector s.
inline void add_bt_sigma(int n, const double* dNdx, const Voigt& s, double w, double* f) {
  for (int a = 0; a < n; ++a) {
    const double gx = dNdx[3 * a], gy = dNdx[3 * a + 1], gz = dNdx[3 * a + 2];
    f[3 * a] += w * (gx * s[0] + gz * s[4] + gy * s[5]);
    f[3 * a + 1] += w * (gy * s[1] + gz * s[3] + gx * s[5]);
    f[3 * a + 2] += w * (gz * s[2] + gy * s[3] + gx * s[4]);
  }
}

/// Cell types whose strain is the B-bar strain (Hughes, "Generalization of selective
/// integration procedures to anisotropic and nonlinear media", IJNME 15, 1980): the volumetric
/// part of the strain at each integration point is replaced by its mean over the cell. Fully
/// integrated linear hexahedra and wedges lock under (nearly) isochoric deformation, which
/// plastic flow is; with B-bar they do not, and they still pass the patch test. 4-node
/// tetrahedra have one constant strain and gain nothing from it.
inline bool uses_bbar(CellType t) { return t == CellType::hex8 || t == CellType::wedge6; }

/// The strain-displacement operator of one cell at all its integration points: the gradients
/// g_a(q) = ∇N_a, the volume weights dv(q) = det J · w, and for B-bar cells the corrections
/// d_a(q) = b̄_a − g_a(q) with b̄_a = (1/V)∫ ∇N_a dV. Then
///   ε̄ = ε + (1/3) m Σ_a d_a·u_a,   B̄_a = B_a + (1/3) m d_aᵀ,   m = (1, 1, 1, 0, 0, 0).
struct CellKinematics {
  int n = 0;         ///< nodes
  int points = 0;    ///< integration points
  bool bbar = false;
  double volume = 0;
  std::array<double, max_cell_points> dv{};
  std::array<double, 3 * max_cell_nodes * max_cell_points> g{}, d{};

  /// Fills everything for a cell with nodes x. Returns the smallest det J (≤ 0: the cell is
  /// inverted or degenerate and nothing else is meaningful).
  double compute(const ReferenceTable& table, std::span<const Vec3> x);
  const double* grad(int q) const { return &g[static_cast<std::size_t>(q) * 3 * n]; }
  const double* corr(int q) const { return &d[static_cast<std::size_t>(q) * 3 * n]; }
  /// ε̄(q) of nodal displacements u.
  Voigt strain(int q, const double* u) const;
  /// f_a += w·B̄_aᵀ s.
  void add_bt_sigma(int q, const Voigt& s, double w, double* f) const;
  /// The displacement gradient L_ij = ∂u_i/∂x_j of nodal displacements u at point q (without
  /// the B-bar correction, which changes the volumetric part only).
  Mat3 gradient(int q, const double* u) const;
};

/// The deformation of one step on a cell (solver.geometry: updated), in the updated
/// Lagrangian form of Bathe (Finite Element Procedures, 1996, sec. 6.2.3): `kin` holds the
/// cell's kinematics on the configuration x at the step's start, Δu the step's nodal
/// displacements, F = I + ∂Δu/∂x at each point. The step's kinematics are given by the
/// Green–Lagrange strain E = (FᵀF − I)/2 relative to x, zero for a rigid motion of any size
/// (HenckyStep, fem/hencky_strain.hpp, makes the point laws' logarithmic strain of C = I + 2E
/// and S of their Kirchhoff stress); S is the second Piola–Kirchhoff stress relative to x,
/// the Cauchy stress is J⁻¹ F S Fᵀ, and the internal forces are ∫ F S ∇N_a dx, the exact ones at t + Δt pulled
/// back to x. For B-bar cells the trace of E takes the cell's mean, as the small strain's does
/// (CellKinematics), so that its variation is B̄_L, with the corrections
/// c_a = F⁻¹ d̄_a − ∇N_a, d̄_a the cell's mean of F ∇N_a:  δĒ = B(∇N_a + c_a/3 in the trace)·Fᵀδu_a.
struct CellDeformation {
  int n = 0, points = 0;
  bool bbar = false;
  std::array<Mat3, max_cell_points> F, F_inv;
  std::array<double, max_cell_points> J{};
  std::array<Voigt, max_cell_points> E;  ///< (B-bar) Green strain, engineering shears
  std::array<double, 3 * max_cell_nodes * max_cell_points> c{};  ///< B-bar corrections c_a

  /// Everything for the nodal displacements du of the step; returns the smallest det F (≤ 0:
  /// the cell turned inside out, or a B-bar point whose C̄ = I + 2Ē is not positive definite).
  double compute(const CellKinematics& kin, const double* du);
  const double* corr(int q) const { return &c[static_cast<std::size_t>(q) * 3 * n]; }
  /// f_a += w·F(S∇N_a + tr(S)/3·c_a): the internal force of S at point q.
  void add_force(const CellKinematics& kin, int q, const Voigt& S, double w, double* f) const;
  /// The rotation R of the polar decomposition F = R U.
  Mat3 rotation(int q) const;
};

/// The symmetric tensor of a stress-like Voigt vector s (tensor shears), and back.
Mat3 stress_tensor(const Voigt& s);
Voigt stress_voigt(const Mat3& t);
/// The symmetric tensor of a strain-like Voigt vector e (engineering shears), and back.
Mat3 strain_tensor(const Voigt& e);
Voigt strain_voigt(const Mat3& t);
/// R e Rᵀ for a strain-like Voigt vector e (engineering shears).
Voigt rotate_strain(const Mat3& R, const Voigt& e);
/// R s Rᵀ for a stress-like Voigt vector s (tensor shears).
Voigt rotate_stress(const Mat3& R, const Voigt& s);

}  // namespace hencky
