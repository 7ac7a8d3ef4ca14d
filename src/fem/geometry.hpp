#pragma once
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

}  // namespace hencky
