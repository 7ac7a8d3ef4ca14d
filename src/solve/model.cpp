// The model bound together: materials, cells, outputs, and the points each rank holds.
#include "solve/model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/invariant.hpp"
#include "core/suggest.hpp"
#include "fem/geometry.hpp"
#include "fem/reference_element.hpp"
#include "parallel/mpi.hpp"

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
                    fmt::format("material '{}': the integration points' temperatures, {:.6g} .. "
                                "{:.6g}, reach outside the table of '{}' ({:.6g} .. {:.6g}); "
                                "its end values are used there (warned once)",
                                spec->name, T_min, T_max, p->where.key, p->temperature.front(),
                                p->temperature.back()));
  }
}

/// Everything the case says, bound to the mesh (or the part) and checked.
void Model::bind(Log& log) {
  temperature_.reference = case_->temperature.given ? case_->temperature.reference : 0.0;
  bind_materials(log);
  check_cells();
  bind_boundary();
  bind_temperature();
  check_temperature_range();
  bind_heat();
  bind_outputs();
  bind_contact();
  if (!dist_.part && !case_->heat.only) check_held(log);  // nothing mechanical to hold
}

Model::Model(const Case& c, Mesh mesh, Log& log) : case_(&c), mesh_(std::move(mesh)) {
  bind(log);
  set_partition(partition_from(mesh_, std::vector<int>(mesh_.cells.size(), 0), 1, 0));
  points_.total = n_points();
  assembler_ = std::make_unique<Assembler>(mesh_.cells, mesh_.n_nodes(), dofs_);
  dist_.global[0] = mesh_.n_nodes();
  dist_.global[1] = mesh_.cells.size();
  dist_.global[2] = dofs_.n_free;
  dist_.global[3] = static_cast<long long>(mesh_.cells.conn.size());
}

Model::Model(const Case& c, MeshPart part, Log& log) : case_(&c), mesh_(std::move(part.mesh)) {
  part.mesh = Mesh();
  dist_.part = std::move(part);
  HENCKY_VERIFY(dist_.part->node_owner.size() == static_cast<std::size_t>(mesh_.n_nodes()) &&
                    dist_.part->owned_nodes <= mesh_.n_nodes(),
                "Model: the part's owners do not match its nodes");
  bind(log);
  // Every cell of the part is this rank's, and so are its points.
  dist_.partition.parts = par::size();
  dist_.partition.rank = par::rank();
  dist_.partition.cell_owner.assign(mesh_.cells.size(), dist_.partition.rank);
  dist_.partition.owned_cell.assign(mesh_.cells.size(), 1);
  dist_.partition.node_owner = dist_.part->node_owner;
  dist_.partition.owned_cells = mesh_.cells.size();
  dist_.partition.owned_nodes = dist_.part->owned_nodes;
  hold_points(dist_.partition.owned_cell);
  assembler_ = std::make_unique<Assembler>(mesh_.cells, mesh_.n_nodes(), dofs_);
}

void Model::set_partition(Partition partition) {
  dist_.partition = std::move(partition);
  dist_.layout = dist_.partition.parts > 1 ? NodalLayout::replicated() : NodalLayout();
  hold_points(dist_.partition.owned_cell);
}

void Model::hold_points(const std::vector<char>& held) {
  points_.offset.assign(mesh_.cells.size() + 1, 0);
  for (int e = 0; e < mesh_.cells.size(); ++e)
    points_.offset[e + 1] =
        points_.offset[e] + (held[e] ? reference_table(mesh_.cells.type[e]).n_points : 0);
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
  // A deck's regions are its sets and surfaces: its user is told in its words (issue 48).
  std::string ext = case_->mesh.file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const bool deck = ext == ".inp";
  const std::string kind =
      !deck                          ? "a " + std::string(what)
      : dim_min == 2 && dim_max == 2 ? "a *SURFACE (element faces, or an ELSET of face elements)"
      : dim_min == 3                 ? "an ELSET of volume elements"
                                     : "an NSET, ELSET or *SURFACE";
  std::string msg = fmt::format("region '{}' is not {} of the mesh {}", name, kind,
                                case_->mesh.file.filename().string());
  if (const Region* other = mesh_.find_region(name, 0, 3, ignore_case)) {
    if (!deck) {
      msg += fmt::format(" (it is a {}D physical group)", other->dim);
    } else {
      msg += other->dim == 0   ? " (it is an NSET, or a node-based *SURFACE: nodes only)"
             : other->dim == 2 ? " (it is a *SURFACE or an ELSET of face elements)"
                               : " (it is an ELSET of volume elements)";
      if (other->dim == 0 && dim_min == 2)
        msg += "; a force on each of its nodes is `nodal_force` (*CLOAD); a pressure, traction "
               "or total force needs the element faces: a *SURFACE, TYPE=ELEMENT of lines "
               "'element or ELSET, S1 .. S6'";
    }
  }
  const std::string valid = !deck                             ? std::string(what) + "s"
                            : dim_min == 2 && dim_max == 2 ? "*SURFACEs and ELSETs of faces"
                            : dim_min == 3                 ? "ELSETs of volume elements"
                                                           : "sets and surfaces";
  throw InputError(where, msg + "; " + suggestion(name, names, valid));
}

void Model::bind_materials(Log& log) {
  const auto& specs = case_->materials;
  cell_material_.assign(mesh_.cells.size(), -1);
  for (std::size_t m = 0; m < specs.size(); ++m) {
    materials_.push_back(MaterialModel{&specs[m], nullptr, true, nullptr});
    if (const auto& pl = specs[m].plasticity) {
      materials_.back().hardening = std::make_shared<Hardening>(*pl, specs[m].E, specs[m].nu);
      materials_.back().elastic_unloading =
          pl->unloading == PlasticitySpec::Unloading::elastic;
      materials_.back().law = make_point_law(*pl);
      check_scheme(specs[m], *materials_.back().law);
      bind_law_state(specs[m], materials_.back().law);
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

/// The report's five schemes need its structure, one isotropic curve along Z: a law without it
/// runs under newton alone.
void Model::check_scheme(const MaterialSpec& mat, const PointLaw& law) const {
  const SolverSpec& solver = case_->solver;
  if (law.runs_report_schemes() || solver.scheme == SchemeKind::newton) return;
  throw InputError(mat.plasticity->law.where,
                   fmt::format("material '{}' has {} hardening, which solver.scheme '{}' cannot "
                               "run: the report's schemes need one isotropic curve along the "
                               "flow direction Z; use scheme: newton",
                               mat.name, mat.plasticity->law.law, scheme_name(solver.scheme)));
}

/// The state each point keeps for its law: one law with internal variables per model (the
/// outputs name its variables; two such laws would need a layout per material).
void Model::bind_law_state(const MaterialSpec& mat, const std::shared_ptr<const PointLaw>& law) {
  if (law->state_size() == 0) return;
  const auto same = [](std::span<const LawVariable> a, std::span<const LawVariable> b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const auto& x, const auto& y) {
      return x.name == y.name && x.size == y.size;
    });
  };
  if (points_.stateful && !same(points_.stateful->variables(), law->variables()))
    throw InputError(mat.plasticity->law.where,
                     fmt::format("material '{}' has {} hardening, and another material a "
                                 "different law with internal variables: one such law per "
                                 "model is supported",
                                 mat.name, mat.plasticity->law.law));
  if (!points_.stateful) points_.stateful = law;
  points_.law_state = std::max(points_.law_state, law->state_size());
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
    if (probe.cell < 0 && !dist_.part)
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
    if (!any && !heat && !dist_.part)
      throw InputError(out.reaction_where[k],
                       fmt::format("region '{}' has no prescribed displacement{}, so it carries "
                                   "no reaction",
                                   r.name, has_heat() ? " or temperature" : ""));
    reactions_.push_back({r.name, &r, any, heat});
  }
}

}  // namespace hencky
