#include "solve/model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstring>
#include <exception>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#include "contact/stl_surface.hpp"
#include "core/suggest.hpp"
#include "fem/geometry.hpp"
#include "fem/reference_element.hpp"
#include "parallel/mpi.hpp"
#include "parallel/node_exchange.hpp"

namespace hencky {

ElasticConstants MaterialModel::at(double T, bool* outside) const {
  ElasticConstants c;
  bool out_e = false, out_nu = false, out_a = false;
  c.E = spec->E(T, &out_e);
  c.nu = spec->nu(T, &out_nu);
  c.alpha = spec->alpha(T, &out_a);
  if (outside) *outside = out_e || out_nu || out_a;
  return c;
}

void MaterialModel::warn_outside(double T_min, double T_max, Log& log) const {
  for (const PropertyTable* p : {&spec->E, &spec->nu, &spec->alpha}) {
    if (p->left_by(T_min, T_max))
      log.warn_once("table:" + p->where.key,
                    fmt::format("material '{}': temperatures {:g} .. {:g} at integration points "
                                "leave the table of '{}' ({:g} .. {:g}); the end values are used "
                                "outside it (warned once)",
                                spec->name, T_min, T_max, p->where.key, p->temperature.front(),
                                p->temperature.back()));
  }
}

/// Everything the case says, bound to the mesh (or the part) and checked.
void Model::bind(Log& log) {
  reference_temperature_ = case_->temperature.given ? case_->temperature.reference : 0.0;
  bind_materials(log);
  check_cells();
  bind_boundary();
  bind_temperature();
  check_temperature_range();
  bind_heat();
  bind_outputs();
  bind_contact();
}

Model::Model(const Case& c, Mesh mesh, Log& log) : case_(&c), mesh_(std::move(mesh)) {
  bind(log);
  set_partition(partition_from(mesh_, std::vector<int>(mesh_.cells.size(), 0), 1, 0));
  total_points_ = n_points();
  assembler_ = std::make_unique<Assembler>(mesh_.cells, mesh_.n_nodes(), dofs_);
  global_[0] = mesh_.n_nodes();
  global_[1] = mesh_.cells.size();
  global_[2] = dofs_.n_free;
  global_[3] = static_cast<long long>(mesh_.cells.conn.size());
}

Model::Model(const Case& c, MeshPart part, Log& log) : case_(&c), mesh_(std::move(part.mesh)) {
  part.mesh = Mesh();
  part_ = std::move(part);
  if (part_->node_owner.size() != static_cast<std::size_t>(mesh_.n_nodes()) ||
      part_->owned_nodes > mesh_.n_nodes())
    throw std::invalid_argument("Model: the part's owners do not match its nodes");
  bind(log);
  // Every cell of the part is this rank's, and so are its points.
  partition_.parts = par::size();
  partition_.rank = par::rank();
  partition_.cell_owner.assign(mesh_.cells.size(), partition_.rank);
  partition_.owned_cell.assign(mesh_.cells.size(), 1);
  partition_.node_owner = part_->node_owner;
  partition_.owned_cells = mesh_.cells.size();
  partition_.owned_nodes = part_->owned_nodes;
  hold_points(partition_.owned_cell);
  assembler_ = std::make_unique<Assembler>(mesh_.cells, mesh_.n_nodes(), dofs_);
}

void Model::join() {
  if (!part_) return;
  exchange_ = std::make_shared<const NodeExchange>(*part_);
  layout_ = NodalLayout::distributed(exchange_);
  // The whole model's counts: each node counted by its owner.
  total_points_ = static_cast<int>(par::sum(static_cast<long long>(n_points())));
  global_[0] = par::sum(static_cast<long long>(part_->owned_nodes));
  global_[1] = par::sum(static_cast<long long>(mesh_.cells.size()));
  global_[2] = par::sum(static_cast<long long>(layout_.owned_free(dofs_.eq, 3)));
  global_[3] = par::sum(static_cast<long long>(mesh_.cells.conn.size()));
  // Where each cell's points start in the whole mesh's order: the reading rank counted them
  // (MeshPart::global_point), with the points this model holds.
  whole_point_offset_ = part_->global_point;
  if (whole_point_offset_.size() != static_cast<std::size_t>(mesh_.cells.size()))
    throw std::logic_error("Model::join: the part has no point offsets for its cells");
  long long end = 0;
  for (int e = 0; e < mesh_.cells.size(); ++e)
    end = std::max(end, whole_point_offset_[e] + point_offset_[e + 1] - point_offset_[e]);
  if (par::max(end) != total_points_)
    throw std::logic_error("Model::join: the part's point offsets are not the model's points");
  check_outer_faces();
  check_whole();
  // A total force spreads over its region's whole area.
  std::vector<double> area(case_->boundary.size(), 0.0);
  for (const auto& [b, a] : part_areas_) area[b] += a;
  par::sum_in_place(std::span<double>(area));
  for (FaceLoad& load : face_loads_)
    if (case_->boundary[load.boundary].kind == BoundaryKind::force) {
      if (!(area[load.boundary] > 0))
        throw InputError(
            case_->boundary[load.boundary].where,
            fmt::format("region '{}' has zero area", case_->boundary[load.boundary].region));
      load.scale = 1.0 / area[load.boundary];
    }
  // A probe belongs to the lowest rank that found it in its cells (a point on a face between
  // two ranks' cells is in both).
  for (Probe& p : probes_) {
    const int owner = par::min(p.cell >= 0 ? partition_.rank : INT_MAX);
    if (owner == INT_MAX)
      throw InputError(
          p.spec->where,
          fmt::format("probe '{}' at ({:g}, {:g}, {:g}) is outside the mesh", p.spec->name,
                      p.spec->point.x(), p.spec->point.y(), p.spec->point.z()));
    if (owner != partition_.rank) p.cell = -1;
  }
  // A region carries a reaction where some rank prescribes a displacement in it.
  for (std::size_t k = 0; k < reactions_.size(); ++k) {
    ReactionRegion& r = reactions_[k];
    r.force = par::any(r.force);
    if (!r.force && !r.heat)
      throw InputError(case_->output.reaction_where[k],
                       fmt::format("region '{}' has no prescribed displacement{}, so it carries "
                                   "no reaction",
                                   r.name, has_heat() ? " or temperature" : ""));
  }
  bind_contact_of_part();
}

void Model::check_outer_faces() const {
  // A loaded face between two ranks' cells: each rank that holds it finds one cell at it
  // (face_owner), so the ranks count together the cells at every loaded face whose corners
  // all have copies on other ranks (only such a face can have a cell elsewhere).
  std::vector<double> copies(mesh_.n_nodes(), 1.0);
  exchange_->sum(copies, 1);
  std::string mine;  // per candidate: heat?, condition, face tag, corners' whole numbers
  const auto add = [&](int f, int b, bool heat) {
    const auto nodes = mesh_.faces.nodes(f);
    const int corners = cell_n_corners(mesh_.faces.type[f]);
    std::array<long long, 4> key{-1, -1, -1, -1};
    for (int a = 0; a < corners; ++a) {
      if (copies[nodes[a]] < 1.5) return;
      key[a] = part_->global_node[nodes[a]];
    }
    mine += fmt::format("{} {} {} {} {} {} {}\n", int(heat), b, mesh_.faces.tag[f], key[0], key[1],
                        key[2], key[3]);
  };
  for (const FaceLoad& load : face_loads_) add(load.face, load.boundary, false);
  for (const HeatFace& face : heat_faces_) add(face.face, face.boundary, true);
  std::string all;
  for (const std::string& text : par::gather_strings(mine)) all += text;
  par::broadcast(all);
  if (all.empty()) return;
  struct Candidate {
    int heat, condition;
    long tag;
    std::array<long long, 4> key;
  };
  std::vector<Candidate> candidates;
  std::istringstream in(all);
  for (Candidate c{};
       in >> c.heat >> c.condition >> c.tag >> c.key[0] >> c.key[1] >> c.key[2] >> c.key[3];)
    candidates.push_back(c);
  std::unordered_map<long long, int> local;
  for (int n = 0; n < mesh_.n_nodes(); ++n) local.emplace(part_->global_node[n], n);
  std::vector<int> nc_ptr, nc_idx;
  node_cell_incidence(mesh_.cells, mesh_.n_nodes(), nc_ptr, nc_idx);
  std::vector<double> cells(candidates.size(), 0.0);  // this rank's cells at each face
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    int corner[4], n = 0;
    for (long long g : candidates[i].key)
      if (g >= 0) {
        const auto it = local.find(g);
        if (it == local.end()) break;
        corner[n++] = it->second;
      }
    if (n != std::count_if(candidates[i].key.begin(), candidates[i].key.end(),
                           [](long long g) { return g >= 0; }))
      continue;
    for (int k = nc_ptr[corner[0]]; k < nc_ptr[corner[0] + 1]; ++k) {
      const auto cn = mesh_.cells.nodes(nc_idx[k]);
      cells[i] += std::all_of(corner + 1, corner + n, [&](int c) {
        return std::find(cn.begin(), cn.end(), c) != cn.end();
      });
    }
  }
  par::sum_in_place(std::span<double>(cells));
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (cells[i] < 2) continue;
    const Candidate& c = candidates[i];
    if (c.heat) {
      const HeatBoundarySpec& bc = case_->heat.boundary[c.condition];
      throw InputError(bc.where,
                       fmt::format("face {} of region '{}' is inside the body (between two "
                                   "elements); a {} condition acts on the outer surface of the "
                                   "body",
                                   c.tag, bc.region, to_string(bc.kind)));
    }
    const BoundarySpec& bc = case_->boundary[c.condition];
    throw InputError(bc.where,
                     fmt::format("face {} of region '{}' is inside the body (between two "
                                 "elements); a {} must be applied on the outer surface of the body",
                                 c.tag, bc.region, to_string(bc.kind)));
  }
}

void Model::check_whole() const {
  // In the order a whole mesh's binding makes them (bind_boundary, bind_heat), so that the
  // first error is the same.
  const auto& bcs = case_->boundary;
  for (const BoundarySpec& bc : bcs)
    if (bc.kind != BoundaryKind::displacement &&
        par::sum(static_cast<long long>(
            mesh_.find_region(bc.region, 2, 2, region_names_ignore_case())->cells.size())) == 0)
      throw InputError(bc.where, fmt::format("region '{}' has no faces to load", bc.region));
  if (!par::any(!prescribed_.empty()))
    throw InputError(SourceLocation{case_->file.string(), 0, 0, "boundary"},
                     "no displacement condition: the body is free to move as a rigid body; "
                     "prescribe displacements on some region");
  for (const HeatBoundarySpec& bc : case_->heat.boundary) {
    const bool nodes = bc.kind == HeatBoundarySpec::Kind::temperature;
    const Region& r =
        *mesh_.find_region(bc.region, nodes ? 0 : 2, nodes ? 3 : 2, region_names_ignore_case());
    if (nodes) {
      if (par::sum(static_cast<long long>(r.nodes.size())) == 0)
        throw InputError(bc.where, fmt::format("region '{}' has no nodes", r.name));
    } else if (par::sum(static_cast<long long>(r.cells.size())) == 0) {
      throw InputError(bc.where, fmt::format("region '{}' has no faces for the {} condition",
                                             r.name, to_string(bc.kind)));
    }
  }
}

void Model::set_partition(Partition partition) {
  partition_ = std::move(partition);
  layout_ = partition_.parts > 1 ? NodalLayout::replicated() : NodalLayout();
  hold_points(partition_.owned_cell);
}

void Model::hold_points(const std::vector<char>& held) {
  point_offset_.assign(mesh_.cells.size() + 1, 0);
  for (int e = 0; e < mesh_.cells.size(); ++e)
    point_offset_[e + 1] =
        point_offset_[e] + (held[e] ? reference_table(mesh_.cells.type[e]).n_points : 0);
}

const Region& Model::find_region(const std::string& name, const SourceLocation& where,
                                 int dim_min, int dim_max, const char* what) const {
  std::vector<std::string> names;
  const bool ignore_case = region_names_ignore_case();
  for (const auto& r : mesh_.regions)
    if (r.dim >= dim_min && r.dim <= dim_max) {
      if (Mesh::same_region_name(r.name, name, ignore_case)) return r;
      names.push_back(r.name);
    }
  std::string msg = fmt::format("region '{}' is not a {} of the mesh {}", name, what,
                                case_->mesh.file.filename().string());
  if (const Region* other = mesh_.find_region(name, 0, 3, ignore_case))
    msg += fmt::format(" (it is a {}D physical group)", other->dim);
  throw InputError(where, msg + "; " + suggestion(name, names, std::string(what) + "s"));
}

void Model::bind_materials(Log& log) {
  const auto& specs = case_->materials;
  cell_material_.assign(mesh_.cells.size(), -1);
  for (std::size_t m = 0; m < specs.size(); ++m) {
    materials_.push_back(MaterialModel{&specs[m], nullptr, true});
    if (const auto& pl = specs[m].plasticity) {
      materials_.back().hardening = std::make_shared<Hardening>(*pl, specs[m].E, specs[m].nu);
      materials_.back().elastic_unloading =
          pl->unloading == PlasticitySpec::Unloading::elastic;
    }
    if (specs[m].regions.empty()) {
      std::fill(cell_material_.begin(), cell_material_.end(), static_cast<int>(m));
      continue;
    }
    for (std::size_t k = 0; k < specs[m].regions.size(); ++k) {
      const Region& r = find_region(specs[m].regions[k], specs[m].region_where[k], 3, 3,
                                    "physical volume");
      for (int cell : r.cells) {
        if (cell_material_[cell] >= 0 && cell_material_[cell] != static_cast<int>(m))
          throw InputError(specs[m].region_where[k],
                           fmt::format("region '{}' already has material '{}'", r.name,
                                       specs[cell_material_[cell]].name));
        cell_material_[cell] = static_cast<int>(m);
      }
    }
  }
  const auto it = std::find(cell_material_.begin(), cell_material_.end(), -1);
  if (it != cell_material_.end()) {
    const int cell = static_cast<int>(it - cell_material_.begin());
    const int n = static_cast<int>(std::count(cell_material_.begin(), cell_material_.end(), -1));
    const int region = mesh_.cell_region[cell];
    throw InputError(specs.front().where,
                     fmt::format("{} elements have no material, e.g. element {} of region '{}'; "
                                 "list every physical volume under some material's 'regions'",
                                 n, mesh_.cells.tag[cell],
                                 region >= 0 ? mesh_.regions[region].name : "(none)"));
  }
  // Tables over temperature need a temperature.
  if (!case_->temperature.given)
    for (const auto& m : specs)
      for (const PropertyTable* p : {&m.E, &m.nu, &m.alpha})
        if (!p->is_constant())
          throw InputError(p->where, "a table over temperature needs a 'temperature' section "
                                     "(with its 'reference') in the case");
  // 4-node tetrahedra lock under the incompressible flow of plasticity: one constant strain per
  // element cannot be isochoric over a whole patch. Linear hexahedra and wedges use B-bar
  // (fem/geometry.hpp) and do not.
  int n_tet4 = 0;
  for (int e = 0; e < mesh_.cells.size(); ++e)
    n_tet4 += mesh_.cells.type[e] == CellType::tet4 && materials_[cell_material_[e]].plastic();
  if (n_tet4 > 0)
    log.warn(fmt::format("{} 4-node tetrahedra have a plastic material: they lock under "
                         "incompressible plastic flow and overestimate stiffness and limit loads; "
                         "use quadratic elements (mesh.order: 2)",
                         n_tet4));
}

const FactorEstimate& Model::node_factor() const {
  if (!node_factor_) node_factor_ = estimate_factor(mesh_.cells, mesh_.n_nodes());
  return *node_factor_;
}

bool Model::region_names_ignore_case() const {
  std::string ext = case_->mesh.file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".inp";
}

bool Model::has_plasticity() const {
  for (const auto& m : materials_)
    if (m.plastic()) return true;
  return false;
}

void Model::check_cells() {
  // Every integration point and every corner must map with a positive Jacobian.
  double dNdx[3 * max_cell_nodes];
  std::vector<Vec3> x(max_cell_nodes);
  for (int e = 0; e < mesh_.cells.size(); ++e) {
    const auto nodes = mesh_.cells.nodes(e);
    for (std::size_t a = 0; a < nodes.size(); ++a) x[a] = mesh_.x[nodes[a]];
    const auto& t = reference_table(mesh_.cells.type[e]);
    std::span<const Vec3> xs(x.data(), nodes.size());
    double det_min = INFINITY, det_max = 0;
    for (int q = 0; q < t.n_points; ++q) {
      const double det = physical_gradients(t, q, xs, dNdx);
      det_min = std::min(det_min, det);
      det_max = std::max(det_max, det);
    }
    if (!(det_min > 1e-12 * det_max) || !(det_max > 0) || !std::isfinite(det_min)) {
      Vec3 centre = Vec3::Zero();
      for (auto& p : xs) centre += p / static_cast<double>(xs.size());
      throw InputError(
          SourceLocation{case_->mesh.file.string(), 0, 0, "mesh.file"},
          fmt::format("element {} ({}) near ({:g}, {:g}, {:g}) is {}: its Jacobian determinant "
                      "is {:.3g} at an integration point; fix the mesh (Gmsh: Mesh > Inspect)",
                      mesh_.cells.tag[e], cell_name(mesh_.cells.type[e]), centre.x(), centre.y(),
                      centre.z(), det_min < 0 ? "inverted" : "degenerate", det_min));
    }
  }
}


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
            prescribed_.push_back({3 * n + d, &*bc.components[d]});
          }
      continue;
    }
    const Region& r = find_region(bc.region, bc.where, 2, 2, "physical surface");
    if (r.cells.empty() && !part_)
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
      const int owner = face_owner(f, nc_ptr, nc_idx);
      if (owner < 0)
        throw InputError(bc.where,
                         fmt::format("face {} of region '{}' is {}; a {} must be applied on the "
                                     "outer surface of the body",
                                     mesh_.faces.tag[f], r.name,
                                     owner == -1 ? "not a face of any volume element"
                                                 : "inside the body (between two elements)",
                                     to_string(bc.kind)));
      Vec3 cell_centre = Vec3::Zero(), face_centre = Vec3::Zero();
      const auto cn = mesh_.cells.nodes(owner);
      for (int n : cn) cell_centre += mesh_.x[n] / static_cast<double>(cn.size());
      for (int n : nodes) face_centre += mesh_.x[n] / static_cast<double>(nodes.size());
      const double sign = normal.dot(face_centre - cell_centre) >= 0 ? 1.0 : -1.0;
      face_loads_.push_back({f, static_cast<int>(b), sign, 1.0});
    }
    if (bc.kind == BoundaryKind::force && part_) {
      part_areas_.emplace_back(static_cast<int>(b), area);  // join() divides by the whole's
    } else if (bc.kind == BoundaryKind::force) {
      if (!(area > 0))
        throw InputError(bc.where, fmt::format("region '{}' has zero area", r.name));
      for (auto it = face_loads_.end() - r.cells.size(); it != face_loads_.end(); ++it)
        it->scale = 1.0 / area;
    }
  }
  dofs_ = DofMap::from_constraints(mesh_.n_nodes(), prescribed);
  if (part_) return;  // a part may hold no support and no free dof: the whole model has both
  bool any = false;
  for (bool p : prescribed) any = any || p;
  if (!any)
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

void Model::bind_heat() {
  const HeatSpec& heat = case_->heat;
  if (!heat.given) return;
  const int n_nodes = mesh_.n_nodes();
  heat_fixed_.assign(n_nodes, -1);
  std::vector<int> nc_ptr, nc_idx;
  node_cell_incidence(mesh_.cells, n_nodes, nc_ptr, nc_idx);
  std::vector<std::vector<HeatFace>> by_cell(mesh_.cells.size());
  for (std::size_t b = 0; b < heat.boundary.size(); ++b) {
    const HeatBoundarySpec& bc = heat.boundary[b];
    if (bc.kind == HeatBoundarySpec::Kind::temperature) {
      const Region& r = find_region(bc.region, bc.where, 0, 3, "region");
      if (r.nodes.empty() && !part_)
        throw InputError(bc.where, fmt::format("region '{}' has no nodes", r.name));
      for (int n : r.nodes) heat_fixed_[n] = static_cast<int>(b);
      continue;
    }
    const Region& r = find_region(bc.region, bc.where, 2, 2, "physical surface");
    if (r.cells.empty() && !part_)
      throw InputError(bc.where, fmt::format("region '{}' has no faces for the {} condition",
                                             r.name, to_string(bc.kind)));
    for (int f : r.cells) {
      const int owner = face_owner(f, nc_ptr, nc_idx);
      if (owner < 0)
        throw InputError(bc.where,
                         fmt::format("face {} of region '{}' is {}; a {} condition acts on the "
                                     "outer surface of the body",
                                     mesh_.faces.tag[f], r.name,
                                     owner == -1 ? "not a face of any volume element"
                                                 : "inside the body (between two elements)",
                                     to_string(bc.kind)));
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
  heat_face_start_.assign(mesh_.cells.size() + 1, 0);
  for (int c = 0; c < mesh_.cells.size(); ++c) {
    heat_face_start_[c + 1] = heat_face_start_[c] + static_cast<int>(by_cell[c].size());
    heat_faces_.insert(heat_faces_.end(), by_cell[c].begin(), by_cell[c].end());
  }
  std::vector<bool> prescribed(n_nodes);
  for (int n = 0; n < n_nodes; ++n) prescribed[n] = heat_fixed_[n] >= 0;
  heat_dofs_ = DofMap::from_constraints(n_nodes, prescribed, 1);
  heat_assembler_ = std::make_unique<Assembler>(mesh_.cells, n_nodes, heat_dofs_);
}

void Model::bind_temperature() {
  const auto& ts = case_->temperature;
  if (!ts.file) return;
  const TemperatureFile& tf = *ts.file;
  std::unordered_map<long, int> row_of_tag;
  for (std::size_t r = 0; r < tf.node_tags.size(); ++r) row_of_tag.emplace(tf.node_tags[r], r);
  temperature_row_.resize(mesh_.n_nodes());
  int n_missing = 0;
  long first_missing = 0;
  for (int n = 0; n < mesh_.n_nodes(); ++n) {
    auto it = row_of_tag.find(mesh_.node_tag[n]);
    if (it == row_of_tag.end()) {
      if (n_missing++ == 0) first_missing = mesh_.node_tag[n];
      continue;
    }
    temperature_row_[n] = it->second;
  }
  if (n_missing > 0)
    throw InputError(SourceLocation{tf.path.string(), 0, 0, "temperature.field.file"},
                     fmt::format("{} nodes of the mesh have no temperature in this file, e.g. "
                                 "Gmsh node {}",
                                 n_missing, first_missing));
}

bool Model::thermal_in_range(int mi, const ElasticConstants& k, double T) const {
  const double strain = k.thermal_strain(T) - reference_strain_[mi];
  return std::isfinite(strain) && std::isfinite(k.E / (1 - 2 * k.nu) * strain);
}

int Model::agreed_cell(int found) const {
  const int lowest = par::min(found >= 0 ? agreed_index(found) : INT_MAX);
  return lowest == INT_MAX ? -1 : lowest;
}

Model::CellFacts Model::cell_facts(int agreed) const {
  if (agreed < 0) return {};
  if (!part_) return {mesh_.cells.tag[agreed], cell_material_[agreed]};
  // The part's cells are in the whole mesh's order: its owner finds it by bisection.
  const auto& g = part_->global_cell;
  const auto it = std::lower_bound(g.begin(), g.end(), agreed);
  const bool mine = it != g.end() && *it == agreed;
  const int e = static_cast<int>(it - g.begin());
  const long long facts[2] = {par::max(mine ? static_cast<long long>(mesh_.cells.tag[e]) : -1LL),
                              par::max(mine ? static_cast<long long>(cell_material_[e]) : -1LL)};
  return {static_cast<long>(facts[0]), static_cast<int>(facts[1])};
}

void Model::thermal_out_of_range(int cell, double T, double t) const {
  thermal_out_of_range(CellFacts{mesh_.cells.tag[cell], cell_material_[cell]}, T, t);
}

void Model::thermal_out_of_range(const CellFacts& cell, double T, double t) const {
  const int mi = cell.material;
  const ElasticConstants k = materials_[mi].at(T);
  const double strain = k.thermal_strain(T) - reference_strain_[mi];
  const auto& ts = case_->temperature;
  throw InputError(
      ts.field_where,
      fmt::format("the temperature {:g} at element {} (material '{}'{}) gives the thermal strain "
                  "alpha(T)*T - alpha(T_ref)*T_ref = {:g} (alpha = {:g}, T_ref = {:g}) and, fully "
                  "restrained, the stress E/(1 - 2nu) times that = {:g}: beyond the range of "
                  "floating point; check the temperatures' magnitude and units",
                  T, cell.tag, materials_[mi].spec->name,
                  std::isnan(t) ? std::string() : fmt::format(", t = {:g}", t), strain, k.alpha,
                  reference_temperature_, k.E / (1 - 2 * k.nu) * strain));
}

void Model::check_temperature_range() {
  // What can be known before the first step (so that `hencky check` finds it too); the step
  // loop checks every point's temperature at every step (PointPass::temperatures).
  const auto& ts = case_->temperature;
  auto& ref = reference_strain_;
  ref.clear();
  for (const auto& m : materials_) {
    ref.push_back(m.at(reference_temperature_).thermal_strain(reference_temperature_));
    if (!std::isfinite(ref.back()))
      throw InputError(ts.reference_where,
                       fmt::format("T_ref = {:g} gives material '{}' alpha(T_ref)*T_ref = {:g}: "
                                   "beyond the range of floating point; check its magnitude "
                                   "and units",
                                   reference_temperature_, m.spec->name, ref.back()));
  }
  if (!ts.given) return;
  // Per cell, the lowest and the highest temperature any of its nodes takes: a constant field
  // takes one value; a file, each node's range over its times.
  std::vector<double> lo, hi;
  if (ts.field && ts.field->is_constant()) {
    const double T = (*ts.field)(0, 0, 0, 0);
    lo.assign(mesh_.n_nodes(), T);
    hi.assign(mesh_.n_nodes(), T);
  } else if (ts.file) {
    const std::size_t n_times = ts.file->times.size();
    lo.resize(mesh_.n_nodes());
    hi.resize(mesh_.n_nodes());
    for (int n = 0; n < mesh_.n_nodes(); ++n) {
      const double* v = ts.file->values.data() + temperature_row_[n] * n_times;
      lo[n] = *std::min_element(v, v + n_times);
      hi[n] = *std::max_element(v, v + n_times);
    }
  } else {
    return;  // an expression: known at the steps only
  }
  for (int e = 0; e < mesh_.cells.size(); ++e)
    for (int n : mesh_.cells.nodes(e))
      for (double T : {lo[n], hi[n]})
        if (!thermal_in_range(cell_material_[e], material_of(e).at(T), T))
          thermal_out_of_range(e, T, NAN);
}

void Model::bind_contact() {
  for (const ContactSpec& spec : case_->contact) {
    const Region& region = find_region(spec.nodes, spec.nodes_where, 2, 2, "physical surface");
    ContactBody body;
    body.spec = &spec;
    switch (spec.shape) {
      case ContactSpec::Shape::plane: body.surface = make_plane(spec.point, spec.normal); break;
      case ContactSpec::Shape::sphere: body.surface = make_sphere(spec.center, spec.radius); break;
      case ContactSpec::Shape::cylinder:
        body.surface = make_cylinder(spec.point, spec.axis, spec.radius);
        break;
      case ContactSpec::Shape::mesh: body.surface = make_stl_surface(spec.file, spec.scale); break;
    }
    // A part's points are bound in join(): their areas, element sizes and stiffness sum
    // over the ranks that hold faces and cells at them.
    if (part_) {
      contacts_.push_back(std::move(body));
      continue;
    }
    body.points = contact_points(mesh_, region, spec.nodes_where);
    add_contact_stiffness(body.points);
    const std::string error = start_contact(body, nullptr);
    if (!error.empty()) throw InputError(spec.surface_where, error);
    contacts_.push_back(std::move(body));
  }
}

void Model::add_contact_stiffness(std::vector<ContactPoint>& points) const {
  // Stiffness scale of each point for κ = auto: tr(K_aa)/3 of the elastic matrix at T_ref,
  // Σ over the cells at the node of ∫ (λ + 4μ)/3 |∇N_a|² dV.
  std::vector<int> node_point(mesh_.n_nodes(), -1);
  for (std::size_t i = 0; i < points.size(); ++i) node_point[points[i].node] = static_cast<int>(i);
  CellKinematics kin;
  Vec3 x[max_cell_nodes];
  for (int e = 0; e < mesh_.cells.size(); ++e) {
    const auto nodes = mesh_.cells.nodes(e);
    if (std::none_of(nodes.begin(), nodes.end(), [&](int n) { return node_point[n] >= 0; }))
      continue;
    for (std::size_t a = 0; a < nodes.size(); ++a) x[a] = mesh_.x[nodes[a]];
    kin.compute(reference_table(mesh_.cells.type[e]), std::span<const Vec3>(x, nodes.size()));
    const ElasticConstants k = material_of(e).at(reference_temperature_);
    const double c = (k.lame_lambda() + 4 * k.shear_modulus()) / 3;
    for (int q = 0; q < kin.points; ++q)
      for (std::size_t a = 0; a < nodes.size(); ++a)
        if (const int i = node_point[nodes[a]]; i >= 0) {
          const double* g = kin.grad(q) + 3 * a;
          points[i].stiffness += c * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) * kin.dv[q];
        }
  }
}

std::string Model::start_contact(ContactBody& body, const std::vector<int>* node_owner) const {
  // A node that starts inside the rigid body by more than the allowed penetration is a set-up
  // error (the surface or the mesh is misplaced), not something to push out.
  const ContactSpec& spec = *body.spec;
  const Vec3 m0 = body.motion(0);
  std::string error;
  for (std::size_t i = 0; i < body.points.size(); ++i) {
    const ContactPoint& p = body.points[i];
    const double d = body.points[i].gap0 = body.surface->signed_distance(p.x - m0);
    if (!error.empty() || (node_owner && (*node_owner)[p.node] != par::rank()) ||
        d >= -body.allowed_gap(static_cast<int>(i)))
      continue;
    const Vec3& x = mesh_.x[p.node];
    error = fmt::format(
        "contact '{}': node {} of region '{}' at ({:g}, {:g}, {:g}) starts inside the rigid "
        "surface, {:.3g} below it (allowed: {:.3g}, 'penetration' {:g} of the local element "
        "size); move the surface or the mesh so that they do not overlap at t = 0",
        spec.name, mesh_.node_tag[p.node], spec.nodes, x.x(), x.y(), x.z(), -d,
        body.allowed_gap(static_cast<int>(i)), spec.penetration);
  }
  return error;
}

void Model::bind_contact_of_part() {
  // Each rank has the region's faces of its part, and its own cells. A node of the region is a
  // point on every rank that holds it, also where its faces are all on other ranks: the ranks
  // flag the region's nodes and sum their faces' areas, sizes and cells' stiffness over the
  // copies. A mid-edge point's corners are told by their whole numbers, in increasing order,
  // so that every copy computes its position alike. The points are in the whole mesh's order,
  // owners' first (the order of a whole mesh's region: its nodes are numbered owner by owner).
  const int n = mesh_.n_nodes();
  std::unordered_map<long long, int> local;  // whole node -> this part's
  for (ContactBody& body : contacts_) {
    const ContactSpec& spec = *body.spec;
    const Region& region = find_region(spec.nodes, spec.nodes_where, 2, 2, "physical surface");
    std::vector<double> flag(n, 0.0);
    for (int v : region.nodes) flag[v] = 1;
    exchange_->sum(flag, 1);
    std::vector<int> nodes;
    for (int v = 0; v < n; ++v)
      if (flag[v] > 0) nodes.push_back(v);
    ContactFaceSums sums;
    // The first zero-area face in the whole mesh's order is the lowest rank's first.
    std::string error;
    try {
      sums = contact_face_sums(mesh_, region, nodes, spec.nodes_where);
    } catch (const InputError& e) {
      error = e.message();
    }
    if (error = par::first_error(error); !error.empty()) throw InputError(spec.nodes_where, error);
    add_contact_stiffness(sums.points);  // this rank's cells' share
    constexpr int w = 7;  // area, Σ face area, faces, stiffness, mid-edge count, corners
    std::vector<double> v(static_cast<std::size_t>(w) * n, 0.0);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const ContactPoint& p = sums.points[i];
      double* x = &v[static_cast<std::size_t>(w) * nodes[i]];
      x[0] = p.area;
      x[1] = sums.size2[i];
      x[2] = sums.faces[i];
      x[3] = p.stiffness;
      if (p.terms == 3) {
        const long long a = part_->global_node[p.term_node[1]],
                        b = part_->global_node[p.term_node[2]];
        x[4] = 1;
        x[5] = static_cast<double>(std::min(a, b));
        x[6] = static_cast<double>(std::max(a, b));
      }
    }
    exchange_->sum(v, w);
    if (local.empty())
      for (int k = 0; k < n; ++k) local.emplace(part_->global_node[k], k);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      ContactPoint& p = sums.points[i];
      const double* x = &v[static_cast<std::size_t>(w) * nodes[i]];
      p.area = x[0];
      sums.size2[i] = x[1];
      sums.faces[i] = x[2];
      p.stiffness = x[3];
      if (x[4] > 0)  // every copy that has a face at it gives the same corners
        set_mid_edge_terms(p, local.at(std::llround(x[5] / x[4])),
                           local.at(std::llround(x[6] / x[4])));
    }
    body.points = finish_contact_points(mesh_, std::move(sums));
    // The whole list's index of each point: the place of its node's whole number among the
    // region's (a whole mesh lists them in that order). Root sorts the owners' numbers (the
    // region's, transiently) and tells each its points' places; ghosts take their owners'.
    std::vector<long long> own;
    for (const ContactPoint& p : body.points)
      if (p.node < part_->owned_nodes) own.push_back(part_->global_node[p.node]);
    const auto as_bytes = [](const std::vector<long long>& numbers) {
      return std::string(reinterpret_cast<const char*>(numbers.data()),
                         numbers.size() * sizeof(long long));
    };
    std::vector<std::string> places(par::size());
    if (const auto owners = par::gather_strings(as_bytes(own)); par::root()) {
      std::vector<std::tuple<long long, int, int>> all;  // whole number, rank, place there
      for (int r = 0; r < par::size(); ++r)
        for (std::size_t k = 0; k < owners[r].size() / sizeof(long long); ++k) {
          long long g = 0;
          std::memcpy(&g, owners[r].data() + k * sizeof g, sizeof g);
          all.emplace_back(g, r, static_cast<int>(k));
        }
      std::sort(all.begin(), all.end());
      std::vector<std::vector<long long>> at(par::size());
      for (int r = 0; r < par::size(); ++r) at[r].resize(owners[r].size() / sizeof(long long));
      for (std::size_t i = 0; i < all.size(); ++i)
        at[std::get<1>(all[i])][std::get<2>(all[i])] = static_cast<long long>(i);
      for (int r = 0; r < par::size(); ++r) places[r] = as_bytes(at[r]);
    }
    const std::string mine = par::exchange_bytes(places)[0];
    if (mine.size() != own.size() * sizeof(long long))
      throw std::logic_error("Model::bind_contact_of_part: root sent the wrong number of places");
    std::vector<double> index(n, -1.0);
    std::size_t k = 0;
    for (const ContactPoint& p : body.points)
      if (p.node < part_->owned_nodes) {
        long long place = 0;
        std::memcpy(&place, mine.data() + k++ * sizeof place, sizeof place);
        index[p.node] = static_cast<double>(place);
      }
    exchange_->to_ghosts(index, 1);
    body.whole_points = static_cast<int>(par::sum(static_cast<long long>(own.size())));
    body.whole_index.clear();
    for (const ContactPoint& p : body.points)
      body.whole_index.push_back(static_cast<int>(std::llround(index[p.node])));
    // The first node inside the surface in the whole order is the lowest rank's first own.
    error = par::first_error(start_contact(body, &part_->node_owner));
    if (!error.empty()) throw InputError(spec.surface_where, error);
  }
}

void Model::bind_outputs() {
  const auto& out = case_->output;
  for (const auto& p : out.probes) {
    Probe probe{&p, -1, {0, 0, 0}};
    std::vector<Vec3> x(max_cell_nodes);
    for (int e = 0; e < mesh_.cells.size() && probe.cell < 0; ++e) {
      const auto nodes = mesh_.cells.nodes(e);
      Vec3 lo = mesh_.x[nodes[0]], hi = lo;
      for (int n : nodes) {
        lo = lo.cwiseMin(mesh_.x[n]);
        hi = hi.cwiseMax(mesh_.x[n]);
      }
      const double pad = 1e-9 * (hi - lo).norm();
      if ((p.point.array() < lo.array() - pad).any() || (p.point.array() > hi.array() + pad).any())
        continue;
      for (std::size_t a = 0; a < nodes.size(); ++a) x[a] = mesh_.x[nodes[a]];
      if (locate_in_cell(mesh_.cells.type[e], std::span<const Vec3>(x.data(), nodes.size()),
                         p.point, 1e-8, probe.xi))
        probe.cell = e;
    }
    if (probe.cell < 0 && !part_)
      throw InputError(p.where, fmt::format("probe '{}' at ({:g}, {:g}, {:g}) is outside the mesh",
                                            p.name, p.point.x(), p.point.y(), p.point.z()));
    probes_.push_back(probe);
  }
  for (std::size_t k = 0; k < out.reactions.size(); ++k) {
    const Region& r = find_region(out.reactions[k], out.reaction_where[k], 0, 3, "region");
    bool any = false, heat = false;
    for (int n : r.nodes)
      for (int d = 0; d < 3; ++d) any = any || dofs_.eq[3 * n + d] < 0;
    for (const auto& b : case_->heat.boundary)
      heat = heat || (b.kind == HeatBoundarySpec::Kind::temperature &&
                      Mesh::same_region_name(b.region, r.name, region_names_ignore_case()));
    if (!any && !heat && !part_)
      throw InputError(out.reaction_where[k],
                       fmt::format("region '{}' has no prescribed displacement{}, so it carries "
                                   "no reaction",
                                   r.name, has_heat() ? " or temperature" : ""));
    reactions_.push_back({r.name, &r, any, heat});
  }
}

void Model::nodal_temperature(double t, std::vector<double>& T) const {
  const auto& ts = case_->temperature;
  T.resize(mesh_.n_nodes());
  if (ts.file) {
    for (int n = 0; n < mesh_.n_nodes(); ++n) T[n] = ts.file->at(temperature_row_[n], t);
  } else if (ts.field) {
    for (int n = 0; n < mesh_.n_nodes(); ++n) {
      const Vec3& x = mesh_.x[n];
      T[n] = ts.field->eval_checked(x.x(), x.y(), x.z(), t, "temperature");
    }
  } else if (ts.from_heat) {
    throw std::logic_error("temperature from: heat is the heat analysis's (HeatSolver::at)");
  } else {
    std::fill(T.begin(), T.end(), reference_temperature_);
  }
}

void Model::prescribed_displacement(double t, std::vector<double>& u) const {
  for (const auto& p : prescribed_) {
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
  if (layout_.kind() != NodalLayout::Kind::distributed) return own_external_forces(t, f, config);
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
  layout_.sum(f, 3);
}

void Model::own_external_forces(double t, std::vector<double>& f,
                                const std::vector<Vec3>* config) const {
  f.assign(3 * static_cast<std::size_t>(mesh_.n_nodes()), 0.0);
  std::vector<Vec3> x(max_cell_nodes), xc(max_cell_nodes);
  for (const FaceLoad& load : face_loads_) {
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
