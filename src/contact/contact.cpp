#include "contact/contact.hpp"

#include <fmt/format.h>

#include <cmath>
#include <unordered_map>

#include "fem/geometry.hpp"
#include "fem/reference_element.hpp"
#include "mesh/mesh.hpp"

namespace hencky {

const char* branch_name(ContactBranch b) {
  switch (b) {
    case ContactBranch::stays_inside: return "stays inside";
    case ContactBranch::released: return "released";
    case ContactBranch::held_outside: return "held outside";
    case ContactBranch::back_in: return "back in";
    case ContactBranch::stays_separated: return "stays separated";
    case ContactBranch::closes: return "closes";
    case ContactBranch::stays_free: return "stays free";
  }
  return "?";
}

Vec3 contact_force(const ContactNode& s, const Vec3& r) {
  if (!s.contact) return Vec3::Zero();
  return (s.force.dot(s.normal) + s.kappa * (s.point - r).dot(s.normal)) * s.normal;
}

Mat3 contact_matrix(const ContactNode& s) {
  if (!s.contact) return Mat3::Zero();
  return s.kappa * s.normal * s.normal.transpose();
}

void release_contact_node(ContactNode& s, const ContactNode& committed) {
  s.contact = false;
  s.separation = committed.contact;
  s.force = Vec3::Zero();
}

ContactBranch update_contact_node(ContactNode& s, const ContactNode& committed, const Vec3& r_t,
                                  const Vec3& r_k, const SurfaceMotion& where) {
  const RigidSurface& surface = *where.surface;
  // The node in the surface's own frame at t + Δt and at t (see the header on moving surfaces).
  const Vec3 p_k = r_k - where.m1, p_t = r_t - where.m0;
  s.gap = surface.signed_distance(p_k);
  const int side = s.gap < 0 ? -1 : 1;
  const auto hold_at = [&](const SurfacePoint& q) {
    s.contact = true;
    s.separation = false;
    s.point = q.x + where.m1;
    s.normal = q.n;
  };
  if (s.contact) {
    // (3.4): the augmented update of the reaction with the penetration left by the solve.
    s.force = (s.force.dot(s.normal) + s.kappa * (s.point - r_k).dot(s.normal)) * s.normal;
    if (side == -1) {
      hold_at(surface.nearest(p_k));
      return ContactBranch::stays_inside;
    }
    if (s.force.dot(s.normal) < 0) {
      release_contact_node(s, committed);
      return ContactBranch::released;
    }
    hold_at(surface.nearest(p_k));
    return ContactBranch::held_outside;
  }
  s.force = Vec3::Zero();  // (3.5)
  if (committed.contact) {
    if (side == -1) {
      hold_at(surface.nearest(p_t));
      return ContactBranch::back_in;
    }
    s.separation = true;
    return ContactBranch::stays_separated;
  }
  if (auto q = surface.intersection(p_t, p_k)) {
    hold_at(*q);
    return ContactBranch::closes;
  }
  s.separation = false;
  return ContactBranch::stays_free;
}

Vec3 ContactBody::motion(double t) const {
  Vec3 m = Vec3::Zero();
  for (int k = 0; k < 3; ++k)
    if (spec->motion[k]) m[k] = spec->motion[k]->eval_checked(0, 0, 0, t, "contact motion");
  return m;
}

double ContactBody::initial_kappa(int i) const {
  return spec->stiffness ? *spec->stiffness : auto_kappa_factor * points[i].stiffness;
}

ContactTotals contact_totals(const ContactBody& body, const std::vector<ContactNode>& states,
                             const std::vector<double>& u, const std::vector<int>* node_owner,
                             int rank) {
  ContactTotals t;
  for (std::size_t i = 0; i < body.points.size(); ++i) {
    const ContactPoint& p = body.points[i];
    if (node_owner && (*node_owner)[p.node] != rank) continue;
    const ContactNode& s = states[i];
    t.max_penetration = std::max(t.max_penetration, -s.gap);
    t.max_penetration_relative = std::max(t.max_penetration_relative, -s.gap / p.size);
    if (!s.contact) continue;
    const Vec3 f = contact_force(s, contact_position(p, u));
    ++t.nodes;
    t.force += f.dot(s.normal);
    t.max_pressure = std::max(t.max_pressure, f.dot(s.normal) / p.area);
    t.resultant += f;  // Σ T̃ᵀF̃ over the mesh nodes is Σ F̃: each row of T̃ sums to 1
  }
  return t;
}

// ---------------------------------------------------------------------------------------------
// Contact points of a region

namespace {

/// Mid-edge nodes of a quadratic face and the corners of their edges (Gmsh ordering:
/// fem/reference_element.hpp). Empty for linear faces.
struct FaceEdge {
  int mid, a, b;
};
std::span<const FaceEdge> quadratic_edges(CellType t) {
  static const FaceEdge tri6[] = {{3, 0, 1}, {4, 1, 2}, {5, 2, 0}};
  static const FaceEdge quad8[] = {{4, 0, 1}, {5, 1, 2}, {6, 2, 3}, {7, 3, 0}};
  if (t == CellType::tri6) return tri6;
  if (t == CellType::quad8) return quad8;
  return {};
}

}  // namespace

ContactFaceSums contact_face_sums(const Mesh& mesh, const Region& region,
                                  std::span<const int> nodes, const SourceLocation& where) {
  constexpr double alpha = quadratic_face_alpha;
  std::unordered_map<int, int> index;  // mesh node -> contact point
  ContactFaceSums sums;
  std::vector<ContactPoint>& pts = sums.points;
  pts.resize(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    index.emplace(nodes[i], static_cast<int>(i));
    pts[i].node = nodes[i];
    pts[i].term_node[0] = nodes[i];
  }
  sums.size2.assign(pts.size(), 0.0);
  sums.faces.assign(pts.size(), 0.0);
  for (int f : region.cells) {
    const auto face = mesh.faces.nodes(f);
    const CellType type = mesh.faces.type[f];
    const auto edges = quadratic_edges(type);
    for (const FaceEdge& e : edges)
      set_mid_edge_terms(pts[index.at(face[e.mid])], face[e.a], face[e.b]);
    // ∫Ñ_i dA, Ñ_corner = N_corner + α Σ N_m over the face's edges at the corner,
    // Ñ_m = (1 − 2α) N_m.
    const ReferenceTable& tab = reference_table(type);
    Vec3 x[max_cell_nodes];
    for (std::size_t a = 0; a < face.size(); ++a) x[a] = mesh.x[face[a]];
    double w[max_cell_nodes] = {};
    double area = 0;
    for (int q = 0; q < tab.n_points; ++q) {
      const double da =
          tab.weights[q] * face_normal(tab, q, std::span<const Vec3>(x, face.size())).norm();
      const double* N = &tab.N[static_cast<std::size_t>(q) * tab.n_nodes];
      double Nt[max_cell_nodes];
      for (std::size_t a = 0; a < face.size(); ++a) Nt[a] = N[a];
      for (const FaceEdge& e : edges) {
        Nt[e.mid] = (1 - 2 * alpha) * N[e.mid];
        Nt[e.a] += alpha * N[e.mid];
        Nt[e.b] += alpha * N[e.mid];
      }
      for (std::size_t a = 0; a < face.size(); ++a) w[a] += Nt[a] * da;
      area += da;
    }
    if (!(area > 0))
      throw InputError(where, fmt::format("face {} of region '{}' has zero area",
                                          mesh.faces.tag[f], region.name));
    for (std::size_t a = 0; a < face.size(); ++a) {
      const int i = index.at(face[a]);
      pts[i].area += w[a];
      sums.size2[i] += area;
      sums.faces[i] += 1;
    }
  }
  return sums;
}

std::vector<ContactPoint> finish_contact_points(const Mesh& mesh, ContactFaceSums sums) {
  for (std::size_t i = 0; i < sums.points.size(); ++i) {
    ContactPoint& p = sums.points[i];
    p.size = sums.faces[i] > 0 ? std::sqrt(sums.size2[i] / sums.faces[i]) : 0.0;
    p.x = Vec3::Zero();
    for (int k = 0; k < p.terms; ++k) p.x += p.term_coef[k] * mesh.x[p.term_node[k]];
  }
  return std::move(sums.points);
}

std::vector<ContactPoint> contact_points(const Mesh& mesh, const Region& region,
                                         const SourceLocation& where) {
  return finish_contact_points(mesh, contact_face_sums(mesh, region, region.nodes, where));
}

}  // namespace hencky
