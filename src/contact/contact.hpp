#pragma once
// Frictionless contact of the body's nodes with rigid surfaces: the penalty / augmented
// algorithm of report section 3, node by node (docs/contact.md).
//
// Per node: the flags Contact and Separation, the support's reaction F, the contact point r*
// with the surface's outward normal n there, and the penalty κ. Each iteration of a step adds
// G = κ n nᵀ to the node's 3x3 diagonal block and, in the residual form of the step loop
// (solve/schemes.hpp), the force (F + κ(r* − r)·n) n of the support at the current position r:
// with u = r − r(t) and u* = r* − r(t) this is the report's b of (3.2) plus the −F(t) that the
// residual's correction term (3.6) carries. After the solve, (3.4)/(3.5) update F and the
// state machine (update_contact_node) the flags and r*.
//
// Moving surfaces. The report's support is fixed. A surface that translates by m(t) is handled
// in its own frame: the node moves there from r(t) − m(t) to r − m(t+Δt), so a node that the
// surface runs into crosses the surface like a node that runs into a fixed one, and a contact
// point is a point of the rigid body that moves with it (r*_0 = r*(t) + m(t+Δt) − m(t)).
//
// Quadratic faces. Under a uniform pressure the consistent nodal loads of a 6-node triangle
// are 0 at the corners and those of an 8-node quadrilateral negative there, so node-wise
// contact would release the corners (F·n < 0) of a face that is pressed uniformly. The
// contact therefore acts on transformed nodal values: ũ_corner = u_corner and, for the
// mid-edge node m of the edge (a, b), ũ_m = (u_m − α(u_a + u_b)) / (1 − 2α), α = 1/5. This is
// the basis Ñ_a = N_a + α Σ N_m (over the edges at a), Ñ_m = (1 − 2α) N_m, which spans the
// same displacement field and whose integrals ∫Ñ_i dA are positive on both face types (the
// transformation of Wohlmuth, Popp, Gee and Wall for quadratic mortar contact, Comput. Mech.
// 49, 2012): the support's forces F̃_i on the transformed nodes are then positive under a
// uniform pressure, equal to p·∫Ñ_i dA, and the nodal forces on the mesh are f = T̃ᵀF̃. Linear
// faces have ũ = u.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "contact/rigid_surface.hpp"
#include "core/types.hpp"
#include "spec/case.hpp"

namespace hencky {

/// One node's contact state (report section 3) at a converged time or at an iteration.
struct ContactNode {
  bool contact = false;     ///< Contact: the node is held by the surface
  bool separation = false;  ///< Separation: the node leaves the surface in this step
  Vec3 force = Vec3::Zero();   ///< F: the support's reaction on the node
  Vec3 point = Vec3::Zero();   ///< r*: the contact point, at the time of the state
  Vec3 normal = Vec3::UnitZ(); ///< n: the surface's outward normal at r*
  double kappa = 0;            ///< κ
  double gap = 0;  ///< signed distance of the node from the surface (< 0: penetration)
};

/// The branches of the report's state update (step 4), for tests and diagnostics.
enum class ContactBranch {
  stays_inside,      ///< Contact, side(r) = −1: stays, r* = nearestPoint(r)
  released,          ///< Contact, side(r) = +1, F·n < 0: Contact off, Separation = ⁽ᵗ⁾Contact
  held_outside,      ///< Contact, side(r) = +1, F·n ≥ 0: stays, r* = nearestPoint(r)
  back_in,           ///< not Contact, ⁽ᵗ⁾Contact, side(r) = −1: Contact, r* = nearestPoint(⁽ᵗ⁾r)
  stays_separated,   ///< not Contact, ⁽ᵗ⁾Contact, side(r) = +1: Separation
  closes,            ///< not Contact, not ⁽ᵗ⁾Contact, the path crosses the surface: Contact
  stays_free,        ///< not Contact, not ⁽ᵗ⁾Contact, no crossing
};
const char* branch_name(ContactBranch b);

/// The force of the support on the node at position r in state s: (F + κ(r* − r)·n) n in
/// contact, zero otherwise. Its derivative with respect to r is −G, G = κ n nᵀ.
Vec3 contact_force(const ContactNode& s, const Vec3& r);
/// G = κ n nᵀ in contact, zero otherwise: the node's 3x3 block of the matrix.
Mat3 contact_matrix(const ContactNode& s);

/// The node leaves contact: Separation if it was in contact at t (`committed`), and no
/// reaction ((3.5); the report leaves F of a node released in the step it closed in unstated:
/// zero as well).
void release_contact_node(ContactNode& s, const ContactNode& committed);

/// Where the surface is during a step: translated by m0 at t, by m1 at t + Δt.
struct SurfaceMotion {
  const RigidSurface* surface;
  Vec3 m0 = Vec3::Zero(), m1 = Vec3::Zero();
};

/// Report steps 3 and 4 for one node: from state k (`s`, updated in place to state k+1), the
/// committed state at t (`committed`: ⁽ᵗ⁾Contact), the node's position at t (`r_t`) and the
/// position r_k the solve gave, the force update (3.4)/(3.5) and the new flags, contact point
/// and normal. κ is left as it is (the strategy is the caller's). Returns the branch taken.
ContactBranch update_contact_node(ContactNode& s, const ContactNode& committed, const Vec3& r_t,
                                  const Vec3& r_k, const SurfaceMotion& where);

/// A node of the contact region as the contact sees it: its value ũ = Σ coef·u over up to
/// three mesh nodes (see the header comment), and what the κ strategy and the output need.
struct ContactPoint {
  int node = 0;    ///< the mesh node it stands for (output fields are written there)
  int terms = 1;   ///< 1 (corner or linear face) or 3 (mid-edge node of a quadratic face)
  int term_node[3] = {0, 0, 0};
  double term_coef[3] = {1, 0, 0};
  Vec3 x = Vec3::Zero();  ///< its position in the undeformed mesh, Σ coef·X
  double area = 0;        ///< tributary area ∫Ñ dA over the region's faces (> 0)
  double size = 0;        ///< local element size h: root mean square of the faces' √area
  double stiffness = 0;   ///< stiffness scale of the mesh at the node: tr(K_aa)/3, elastic at T_ref
  double gap0 = 0;        ///< signed distance from the surface at t = 0 (set with the surface)
};

/// The point's position for nodal displacements u (3 per mesh node): x + Σ coef·u.
inline Vec3 contact_position(const ContactPoint& p, const std::vector<double>& u) {
  Vec3 r = p.x;
  for (int k = 0; k < p.terms; ++k) {
    const double* v = &u[3 * static_cast<std::size_t>(p.term_node[k])];
    r += p.term_coef[k] * Vec3(v[0], v[1], v[2]);
  }
  return r;
}

/// One entry of the case's `contact`, bound to the mesh.
struct ContactBody {
  const ContactSpec* spec = nullptr;
  std::unique_ptr<RigidSurface> surface;
  std::vector<ContactPoint> points;
  /// On a rank's part of a distributed mesh: each point's index in the whole model's list of
  /// the surface's points, and that list's length (empty and 0 on a whole mesh).
  std::vector<int> whole_index;
  int whole_points = 0;
  /// The translation m(t) of the surface.
  Vec3 motion(double t) const;
  /// κ_0 of point i: the user's value, or auto_kappa_factor times the mesh's stiffness there.
  double initial_kappa(int i) const;
  /// Allowed |gap| of a node in contact: `penetration` times the local element size.
  double allowed_gap(int i) const { return spec->penetration * points[i].size; }
  /// Point i touches the surface at t = 0 (to round-off of its element size, or inside it:
  /// the Model rejects starts deeper than allowed_gap); it then starts in Contact.
  bool touches_at_start(int i) const { return points[i].gap0 <= 1e-9 * points[i].size; }
};

/// What one contact reports for a state: Σ of the nodes' normal forces, the nodes in contact,
/// the resultant force of the support on the body, the largest penetration (also relative to
/// the element size) and the largest nodal contact pressure.
struct ContactTotals {
  double force = 0;
  int nodes = 0;
  Vec3 resultant = Vec3::Zero();
  double max_penetration = 0;
  double max_penetration_relative = 0;
  double max_pressure = 0;
};
/// The totals of `body` for its points' states and the nodal displacements u. With
/// `node_owner`: of the points whose node `rank` owns only (a rank's share, to be summed).
ContactTotals contact_totals(const ContactBody& body, const std::vector<ContactNode>& states,
                             const std::vector<double>& u,
                             const std::vector<int>* node_owner = nullptr, int rank = 0);

/// κ = auto starts at this multiple of the stiffness tr(K_aa)/3 of the node's elements: large
/// enough that the augmented update (3.4) removes about 90 % of the penetration per iteration,
/// small enough not to spoil the matrix's conditioning (docs/contact.md measures the choice).
inline constexpr double auto_kappa_factor = 10.0;

struct Mesh;
struct Region;

/// The contact points of a surface region: one per node, with the quadratic-face
/// transformation, tributary areas and element sizes (stiffness is left at 0 for the caller).
/// Throws InputError (at `where`) for a region with a face whose area is zero.
std::vector<ContactPoint> contact_points(const Mesh& mesh, const Region& region,
                                         const SourceLocation& where);

/// What a region's faces give the points at `nodes` (every node of the faces, and maybe more:
/// a part of a distributed mesh has points whose faces are on other ranks): each point's
/// tributary area and mid-edge terms, and the sums that make its element size, the faces'
/// Σ area (size2) and their number (faces). Sums of several parts' faces add up.
struct ContactFaceSums {
  std::vector<ContactPoint> points;
  std::vector<double> size2, faces;
};
ContactFaceSums contact_face_sums(const Mesh& mesh, const Region& region,
                                  std::span<const int> nodes, const SourceLocation& where);
/// The points of (summed) face sums: their element sizes and undeformed positions.
std::vector<ContactPoint> finish_contact_points(const Mesh& mesh, ContactFaceSums sums);

/// α of the quadratic-face transformation (see the header comment).
inline constexpr double quadratic_face_alpha = 0.2;

/// Makes `p` a mid-edge point of the edge with corner nodes a and b:
/// ũ_m = (u_m − α(u_a + u_b)) / (1 − 2α).
inline void set_mid_edge_terms(ContactPoint& p, int a, int b) {
  constexpr double alpha = quadratic_face_alpha;
  p.terms = 3;
  p.term_node[1] = a;
  p.term_node[2] = b;
  p.term_coef[0] = 1 / (1 - 2 * alpha);
  p.term_coef[1] = p.term_coef[2] = -alpha / (1 - 2 * alpha);
}

}  // namespace hencky
