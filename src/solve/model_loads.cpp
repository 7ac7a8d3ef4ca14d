// Boundary conditions bound to the mesh: prescribed displacements, loaded faces, the heat
// conditions' faces, and the loads they give at a time.
#include "solve/model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>

#include "fem/geometry.hpp"
#include "fem/reference_element.hpp"
#include "parallel/mpi.hpp"

namespace hencky {

void Model::bind_boundary() {
  const auto& bcs = case_->boundary;
  std::vector<bool> prescribed(3 * static_cast<std::size_t>(mesh_.n_nodes()), false);
  std::vector<int> nc_ptr, nc_idx;
  node_cell_incidence(mesh_.cells, mesh_.n_nodes(), nc_ptr, nc_idx);

  for (std::size_t b = 0; b < bcs.size(); ++b) {
    const BoundarySpec& bc = bcs[b];
    if (bc.kind == BoundaryKind::displacement) {
      const Region& r = find_region(bc.region, bc.where, 0, 3, "region");
      for (int n : r.nodes)
        for (int d = 0; d < 3; ++d)
          if (bc.components[d]) {
            prescribed[3 * n + d] = true;
            loads_.prescribed.push_back({3 * n + d, &*bc.components[d]});
          }
      continue;
    }
    if (bc.kind == BoundaryKind::nodal_force) {
      // On a part, each node's owner applies it (the ranks' forces are summed over the copies).
      const Region& r = find_region(bc.region, bc.where, 0, 3, "region");
      if (r.nodes.empty() && !dist_.part)
        throw InputError(bc.where, fmt::format("region '{}' has no nodes to load", r.name));
      const int owned = dist_.part ? dist_.part->owned_nodes : mesh_.n_nodes();
      for (int n : r.nodes)
        if (n < owned) loads_.nodal.emplace_back(n, static_cast<int>(b));
      continue;
    }
    const Region& r = find_region(bc.region, bc.where, 2, 2, "physical surface");
    if (r.cells.empty() && !dist_.part)
      throw InputError(bc.where, fmt::format("region '{}' has no faces to load", r.name));
    double area = 0;
    for (int f : r.cells) {
      const auto nodes = mesh_.faces.nodes(f);
      const CellType ft = mesh_.faces.type[f];
      std::vector<Vec3> x(nodes.size());
      for (std::size_t a = 0; a < nodes.size(); ++a) x[a] = mesh_.x[nodes[a]];
      const auto& t = reference_table(ft);
      Vec3 normal = Vec3::Zero();
      for (int q = 0; q < t.n_points; ++q) {
        const Vec3 nq = face_normal(t, q, x);
        normal += nq * t.weights[q];
        area += nq.norm() * t.weights[q];
      }
      const int owner = outer_face_owner(f, nc_ptr, nc_idx, bc.where, r.name,
                                         fmt::format("a {} must be applied", to_string(bc.kind)));
      Vec3 cell_centre = Vec3::Zero(), face_centre = Vec3::Zero();
      const auto cn = mesh_.cells.nodes(owner);
      for (int n : cn) cell_centre += mesh_.x[n] / static_cast<double>(cn.size());
      for (int n : nodes) face_centre += mesh_.x[n] / static_cast<double>(nodes.size());
      const double sign = normal.dot(face_centre - cell_centre) >= 0 ? 1.0 : -1.0;
      loads_.faces.push_back({f, static_cast<int>(b), sign, 1.0});
    }
    if (bc.kind == BoundaryKind::force && dist_.part) {
      loads_.part_areas.emplace_back(static_cast<int>(b), area);  // join() divides by the whole's
    } else if (bc.kind == BoundaryKind::force) {
      if (!(area > 0))
        throw InputError(bc.where, fmt::format("region '{}' has zero area", r.name));
      for (auto it = loads_.faces.end() - r.cells.size(); it != loads_.faces.end(); ++it)
        it->scale = 1.0 / area;
    }
  }
  dofs_ = DofMap::from_constraints(mesh_.n_nodes(), prescribed);
  if (dist_.part) return;  // a part may hold no support and no free dof: the whole model has both
  bool any = false;
  for (bool p : prescribed) any = any || p;
  // With contact the rigid surfaces may hold the body (check_held decides).
  if (!any && case_->contact.empty() && !case_->heat.only)
    throw InputError(SourceLocation{case_->file.string(), 0, 0, "boundary"},
                     "no displacement condition: the body is free to move as a rigid body; "
                     "prescribe displacements on some region");
}

int Model::face_owner(int f, const std::vector<int>& nc_ptr, const std::vector<int>& nc_idx) const {
  const auto nodes = mesh_.faces.nodes(f);
  const int n_corners = cell_n_corners(mesh_.faces.type[f]);
  int owner = -1, n_owners = 0;
  for (int k = nc_ptr[nodes[0]]; k < nc_ptr[nodes[0] + 1]; ++k) {
    const int c = nc_idx[k];
    const auto cn = mesh_.cells.nodes(c);
    bool all = true;
    for (int a = 1; a < n_corners && all; ++a)
      all = std::find(cn.begin(), cn.end(), nodes[a]) != cn.end();
    if (all) {
      owner = c;
      ++n_owners;
    }
  }
  return n_owners > 1 ? -2 : owner;
}

int Model::outer_face_owner(int f, const std::vector<int>& nc_ptr, const std::vector<int>& nc_idx,
                            const SourceLocation& where, const std::string& region,
                            const std::string& what) const {
  const int owner = face_owner(f, nc_ptr, nc_idx);
  if (owner < 0)
    throw InputError(where, fmt::format("face {} of region '{}' is {}; {} on the outer surface "
                                        "of the body",
                                        mesh_.faces.tag[f], region,
                                        owner == -1 ? "not a face of any volume element"
                                                    : "inside the body (between two elements)",
                                        what));
  return owner;
}

void Model::bind_heat() {
  const HeatSpec& heat = case_->heat;
  if (!heat.given) return;
  const int n_nodes = mesh_.n_nodes();
  heat_.fixed.assign(n_nodes, -1);
  std::vector<int> nc_ptr, nc_idx;
  node_cell_incidence(mesh_.cells, n_nodes, nc_ptr, nc_idx);
  std::vector<std::vector<HeatFace>> by_cell(mesh_.cells.size());
  for (std::size_t b = 0; b < heat.boundary.size(); ++b) {
    const HeatBoundarySpec& bc = heat.boundary[b];
    if (bc.kind == HeatBoundarySpec::Kind::temperature) {
      const Region& r = find_region(bc.region, bc.where, 0, 3, "region");
      if (r.nodes.empty() && !dist_.part)
        throw InputError(bc.where, fmt::format("region '{}' has no nodes", r.name));
      for (int n : r.nodes) heat_.fixed[n] = static_cast<int>(b);
      continue;
    }
    if (bc.kind == HeatBoundarySpec::Kind::nodal_flux) {  // each node's owner applies it
      const Region& r = find_region(bc.region, bc.where, 0, 3, "region");
      if (r.nodes.empty() && !dist_.part)
        throw InputError(bc.where, fmt::format("region '{}' has no nodes", r.name));
      const int owned = dist_.part ? dist_.part->owned_nodes : n_nodes;
      for (int n : r.nodes)
        if (n < owned) heat_.nodal.emplace_back(n, static_cast<int>(b));
      continue;
    }
    const Region& r = find_region(bc.region, bc.where, 2, 2, "physical surface");
    if (r.cells.empty() && !dist_.part)
      throw InputError(bc.where, fmt::format("region '{}' has no faces for the {} condition",
                                             r.name, to_string(bc.kind)));
    for (int f : r.cells) {
      const int owner = outer_face_owner(f, nc_ptr, nc_idx, bc.where, r.name,
                                         fmt::format("a {} condition acts", to_string(bc.kind)));
      HeatFace hf{f, static_cast<int>(b), owner, {}};
      const auto fn = mesh_.faces.nodes(f);
      const auto cn = mesh_.cells.nodes(owner);
      for (std::size_t a = 0; a < fn.size(); ++a) {
        const auto it = std::find(cn.begin(), cn.end(), fn[a]);
        if (it == cn.end())  // a mid-edge node the cell lacks: meshes of mixed order
          throw InputError(bc.where,
                           fmt::format("face {} of region '{}' has a node that its "
                                       "volume element {} lacks (mixed orders?)",
                                       mesh_.faces.tag[f], r.name, mesh_.cells.tag[owner]));
        hf.local[a] = static_cast<std::int8_t>(it - cn.begin());
      }
      by_cell[owner].push_back(hf);
    }
  }
  heat_.face_start.assign(mesh_.cells.size() + 1, 0);
  for (int c = 0; c < mesh_.cells.size(); ++c) {
    heat_.face_start[c + 1] = heat_.face_start[c] + static_cast<int>(by_cell[c].size());
    heat_.faces.insert(heat_.faces.end(), by_cell[c].begin(), by_cell[c].end());
  }
  std::vector<bool> prescribed(n_nodes);
  for (int n = 0; n < n_nodes; ++n) prescribed[n] = heat_.fixed[n] >= 0;
  heat_.dofs = DofMap::from_constraints(n_nodes, prescribed, 1);
  heat_.assembler = std::make_unique<Assembler>(mesh_.cells, n_nodes, heat_.dofs);
}

void Model::prescribed_displacement(double t, std::vector<double>& u) const {
  for (const auto& p : loads_.prescribed) {
    const Vec3& x = mesh_.x[p.dof / 3];
    u[p.dof] = p.value->eval_checked(x.x(), x.y(), x.z(), t, "displacement");
  }
}

namespace {
/// A load whose values are finite but whose nodal force is not (a traction of 1e308 times an
/// area, a total force over a small region, the sum of several such loads at a node).
[[noreturn]] void load_overflow(const Expression& value, const char* what, long node, double t) {
  throw InputError(value.where(),
                   fmt::format("{}: \"{}\" gives at t = {:g} a force at node {} beyond the range "
                               "of floating point; check the load's magnitude and units",
                               what, value.text(), t, node));
}
}  // namespace

void Model::external_forces(double t, std::vector<double>& f,
                            const std::vector<Vec3>* config) const {
  if (dist_.layout.kind() != NodalLayout::Kind::distributed)
    return own_external_forces(t, f, config);
  // A part's loads, then the sums over the copies of its shared nodes. A load that overflows
  // on one rank stops every rank: the one that found it says where.
  std::exception_ptr error;
  try {
    own_external_forces(t, f, config);
  } catch (const InputError&) {
    error = std::current_exception();
  }
  par::rethrow_anywhere(error, SourceLocation{case_->file.string(), 0, 0, "boundary"},
                        "a load met an input error on another MPI rank");
  dist_.layout.sum(f, 3);
}

void Model::own_external_forces(double t, std::vector<double>& f,
                                const std::vector<Vec3>* config) const {
  f.assign(3 * static_cast<std::size_t>(mesh_.n_nodes()), 0.0);
  std::vector<Vec3> x(max_cell_nodes), xc(max_cell_nodes);
  for (const FaceLoad& load : loads_.faces) {
    const BoundarySpec& bc = case_->boundary[load.boundary];
    const auto nodes = mesh_.faces.nodes(load.face);
    const auto& tab = reference_table(mesh_.faces.type[load.face]);
    for (std::size_t a = 0; a < nodes.size(); ++a) {
      x[a] = mesh_.x[nodes[a]];
      xc[a] = config ? (*config)[nodes[a]] : x[a];
    }
    const std::span<const Vec3> xs(x.data(), nodes.size()), xcs(xc.data(), nodes.size());
    for (int q = 0; q < tab.n_points; ++q) {
      // Outward n dA on the configuration loaded: a pressure follows the faces, a traction
      // acts on their current area; a total force keeps its distribution over the undeformed
      // region (it stays that force). The expressions take the undeformed coordinates.
      const Vec3 n_da = face_normal(tab, q, xcs) * (load.sign * tab.weights[q]);
      const Vec3 p = point_position(tab, q, xs);
      Vec3 traction;
      if (bc.kind == BoundaryKind::pressure) {
        traction = -bc.pressure->eval_checked(p.x(), p.y(), p.z(), t, "pressure") * n_da;
      } else {
        for (int d = 0; d < 3; ++d)
          traction[d] = bc.components[d]->eval_checked(p.x(), p.y(), p.z(), t, to_string(bc.kind));
        const double da = bc.kind == BoundaryKind::force && config
                              ? face_normal(tab, q, xs).norm() * tab.weights[q]
                              : n_da.norm();
        traction *= load.scale * da;
      }
      const double* N = &tab.N[static_cast<std::size_t>(q) * tab.n_nodes];
      for (std::size_t a = 0; a < nodes.size(); ++a)
        for (int d = 0; d < 3; ++d) {
          double& fi = f[3 * nodes[a] + d];
          fi += N[a] * traction[d];
          if (!std::isfinite(fi))
            load_overflow(bc.kind == BoundaryKind::pressure ? *bc.pressure : *bc.components[d],
                          to_string(bc.kind), mesh_.node_tag[nodes[a]], t);
        }
    }
  }
  for (const auto& [n, boundary] : loads_.nodal) {
    // The vector at the node, whatever the configuration (a force stays that force); the
    // expressions take the undeformed coordinates.
    const BoundarySpec& bc = case_->boundary[boundary];
    const Vec3& p = mesh_.x[n];
    for (int d = 0; d < 3; ++d) {
      double& fi = f[3 * static_cast<std::size_t>(n) + d];
      fi += bc.components[d]->eval_checked(p.x(), p.y(), p.z(), t, "nodal_force");
      if (!std::isfinite(fi)) load_overflow(*bc.components[d], "nodal_force", mesh_.node_tag[n], t);
    }
  }
  if (case_->body_force) {
    const auto& b = *case_->body_force;
    double dNdx[3 * max_cell_nodes];
    for (int e = 0; e < mesh_.cells.size(); ++e) {
      const auto nodes = mesh_.cells.nodes(e);
      const auto& tab = reference_table(mesh_.cells.type[e]);
      for (std::size_t a = 0; a < nodes.size(); ++a) x[a] = mesh_.x[nodes[a]];
      const std::span<const Vec3> xs(x.data(), nodes.size());
      for (int q = 0; q < tab.n_points; ++q) {
        const double dv = physical_gradients(tab, q, xs, dNdx) * tab.weights[q];
        const Vec3 p = point_position(tab, q, xs);
        Vec3 bq;
        for (int d = 0; d < 3; ++d) bq[d] = b[d].eval_checked(p.x(), p.y(), p.z(), t, "body_force");
        const double* N = &tab.N[static_cast<std::size_t>(q) * tab.n_nodes];
        for (std::size_t a = 0; a < nodes.size(); ++a)
          for (int d = 0; d < 3; ++d) {
            double& fi = f[3 * nodes[a] + d];
            fi += N[a] * bq[d] * dv;
            if (!std::isfinite(fi)) load_overflow(b[d], "body_force", mesh_.node_tag[nodes[a]], t);
          }
      }
    }
  }
}

}  // namespace hencky
