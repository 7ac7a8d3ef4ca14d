// A part model joined with the other ranks' (issue 21, docs/parallel.md): the whole model's
// counts and checks, and the cells the ranks agree on.
#include "solve/model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <climits>
#include <sstream>
#include <unordered_map>

#include "core/invariant.hpp"
#include "parallel/mpi.hpp"
#include "parallel/node_exchange.hpp"

namespace hencky {

void Model::join(Log& log) {
  if (!dist_.part) return;
  dist_.exchange = std::make_shared<const NodeExchange>(*dist_.part);
  dist_.layout = NodalLayout::distributed(dist_.exchange);
  // The whole model's counts: each node counted by its owner.
  points_.total = static_cast<int>(par::sum(static_cast<long long>(n_points())));
  dist_.global[0] = par::sum(static_cast<long long>(dist_.part->owned_nodes));
  dist_.global[1] = par::sum(static_cast<long long>(mesh_.cells.size()));
  dist_.global[2] = par::sum(static_cast<long long>(dist_.layout.owned_free(dofs_.eq, 3)));
  dist_.global[3] = par::sum(static_cast<long long>(mesh_.cells.conn.size()));
  // Where each cell's points start in the whole mesh's order: the reading rank counted them
  // (MeshPart::global_point), with the points this model holds.
  points_.whole_offset = dist_.part->global_point;
  HENCKY_VERIFY(points_.whole_offset.size() == static_cast<std::size_t>(mesh_.cells.size()),
                "Model::join: the part has no point offsets for its cells");
  long long end = 0;
  for (int e = 0; e < mesh_.cells.size(); ++e)
    end = std::max(end, points_.whole_offset[e] + points_.offset[e + 1] - points_.offset[e]);
  HENCKY_VERIFY(par::max(end) == points_.total,
                "Model::join: the part's point offsets are not the model's points");
  check_outer_faces();
  check_whole();
  // A total force spreads over its region's whole area.
  std::vector<double> area(case_->boundary.size(), 0.0);
  for (const auto& [b, a] : loads_.part_areas) area[b] += a;
  par::sum_in_place(std::span<double>(area));
  for (FaceLoad& load : loads_.faces)
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
    const int owner = par::min(p.cell >= 0 ? dist_.partition.rank : INT_MAX);
    if (owner == INT_MAX)
      throw InputError(
          p.spec->where,
          fmt::format("probe '{}' at ({:g}, {:g}, {:g}) is outside the mesh", p.spec->name,
                      p.spec->point.x(), p.spec->point.y(), p.spec->point.z()));
    if (owner != dist_.partition.rank) p.cell = -1;
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
  if (!case_->heat.only) check_held(log);
}

void Model::check_outer_faces() const {
  // A loaded face between two ranks' cells: each rank that holds it finds one cell at it
  // (face_owner), so the ranks count together the cells at every loaded face whose corners
  // all have copies on other ranks (only such a face can have a cell elsewhere).
  std::vector<double> copies(mesh_.n_nodes(), 1.0);
  dist_.exchange->sum(copies, 1);
  std::string mine;  // per candidate: heat?, condition, face tag, corners' whole numbers
  const auto add = [&](int f, int b, bool heat) {
    const auto nodes = mesh_.faces.nodes(f);
    const int corners = cell_n_corners(mesh_.faces.type[f]);
    std::array<long long, 4> key{-1, -1, -1, -1};
    for (int a = 0; a < corners; ++a) {
      if (copies[nodes[a]] < 1.5) return;
      key[a] = dist_.part->global_node[nodes[a]];
    }
    mine += fmt::format("{} {} {} {} {} {} {}\n", int(heat), b, mesh_.faces.tag[f], key[0], key[1],
                        key[2], key[3]);
  };
  for (const FaceLoad& load : loads_.faces) add(load.face, load.boundary, false);
  for (const HeatFace& face : heat_.faces) add(face.face, face.boundary, true);
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
  for (int n = 0; n < mesh_.n_nodes(); ++n) local.emplace(dist_.part->global_node[n], n);
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
  for (const BoundarySpec& bc : bcs) {
    if (bc.kind == BoundaryKind::nodal_force &&
        par::sum(static_cast<long long>(
            mesh_.find_region(bc.region, 0, 3, region_names_ignore_case())->nodes.size())) == 0)
      throw InputError(bc.where, fmt::format("region '{}' has no nodes to load", bc.region));
    if (bc.kind != BoundaryKind::displacement && bc.kind != BoundaryKind::nodal_force &&
        par::sum(static_cast<long long>(
            mesh_.find_region(bc.region, 2, 2, region_names_ignore_case())->cells.size())) == 0)
      throw InputError(bc.where, fmt::format("region '{}' has no faces to load", bc.region));
  }
  if (!par::any(!loads_.prescribed.empty()) && !case_->heat.only)
    throw InputError(SourceLocation{case_->file.string(), 0, 0, "boundary"},
                     "no displacement condition: the body is free to move as a rigid body; "
                     "prescribe displacements on some region");
  for (const HeatBoundarySpec& bc : case_->heat.boundary) {
    const bool nodes = bc.kind == HeatBoundarySpec::Kind::temperature ||
                       bc.kind == HeatBoundarySpec::Kind::nodal_flux;
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

int Model::agreed_cell(int found) const {
  const int lowest = par::min(found >= 0 ? agreed_index(found) : INT_MAX);
  return lowest == INT_MAX ? -1 : lowest;
}

Model::CellFacts Model::cell_facts(int agreed) const {
  if (agreed < 0) return {};
  if (!dist_.part) return {mesh_.cells.tag[agreed], cell_material_[agreed]};
  // The part's cells are in the whole mesh's order: its owner finds it by bisection.
  const auto& g = dist_.part->global_cell;
  const auto it = std::lower_bound(g.begin(), g.end(), agreed);
  const bool mine = it != g.end() && *it == agreed;
  const int e = static_cast<int>(it - g.begin());
  const long long facts[2] = {par::max(mine ? static_cast<long long>(mesh_.cells.tag[e]) : -1LL),
                              par::max(mine ? static_cast<long long>(cell_material_[e]) : -1LL)};
  return {static_cast<long>(facts[0]), static_cast<int>(facts[1])};
}

}  // namespace hencky
