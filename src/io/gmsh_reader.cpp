#include "io/gmsh_reader.hpp"

#include <gmsh.h>
#include <omp.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <unordered_map>

#include "core/error.hpp"

namespace hencky {
namespace {

bool gmsh_type_to_cell(int gmsh_type, CellType& t) {
  switch (gmsh_type) {
    case 4: t = CellType::tet4; return true;
    case 11: t = CellType::tet10; return true;
    case 5: t = CellType::hex8; return true;
    case 17: t = CellType::hex20; return true;
    case 6: t = CellType::wedge6; return true;
    case 2: t = CellType::tri3; return true;
    case 9: t = CellType::tri6; return true;
    case 3: t = CellType::quad4; return true;
    case 16: t = CellType::quad8; return true;
    default: return false;
  }
}

std::string gmsh_type_name(int gmsh_type) {
  std::string name;
  int dim = 0, order = 0, n_nodes = 0, n_primary = 0;
  std::vector<double> local;
  try {
    gmsh::model::mesh::getElementProperties(gmsh_type, name, dim, order, n_nodes, local, n_primary);
  } catch (...) {
    return "Gmsh element type " + std::to_string(gmsh_type);
  }
  return name + " (Gmsh type " + std::to_string(gmsh_type) + ")";
}

/// The Gmsh library is a global singleton: one reader at a time, initialized once per read.
std::mutex gmsh_mutex;

struct GmshSession {
  explicit GmshSession(std::vector<std::string>* log) : log_(log), threads_(omp_get_max_threads()) {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 3);
    gmsh::logger::start();
  }
  ~GmshSession() {
    try {
      if (log_) {
        std::vector<std::string> lines;
        gmsh::logger::get(lines);
        log_->insert(log_->end(), lines.begin(), lines.end());
      }
      gmsh::logger::stop();
      gmsh::finalize();
    } catch (...) {
    }
    omp_set_num_threads(threads_);  // Gmsh sets the OpenMP thread count to its own option
  }
  std::vector<std::string>* log_;
  int threads_;
};

std::string last_gmsh_error() {
  std::string err;
  try {
    gmsh::logger::getLastError(err);
  } catch (...) {
  }
  return err.empty() ? "Gmsh could not process the file" : err;
}

}  // namespace

Mesh read_gmsh(const std::filesystem::path& file, const MeshReadOptions& options,
               std::vector<std::string>* gmsh_log) {
  const SourceLocation where{file.string(), 0, 0, ""};
  auto fail = [&](const std::string& msg) -> InputError { return InputError(where, msg); };
  if (!std::filesystem::exists(file)) throw fail("mesh file does not exist");

  std::lock_guard lock(gmsh_mutex);
  GmshSession session(gmsh_log);

  const std::string ext = file.extension().string();
  try {
    gmsh::open(file.string());
  } catch (...) {
    throw fail("Gmsh cannot read this file: " + last_gmsh_error());
  }
  try {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> tags, nodes;
    gmsh::model::mesh::getElements(types, tags, nodes, 3, -1);
    if (types.empty()) {
      if (ext == ".geo") {
        gmsh::model::mesh::generate(3);
      } else {
        throw fail("the mesh has no 3D elements (hencky needs a volume mesh)");
      }
    }
    if (options.order == 1 || options.order == 2) {
      // Serendipity (20-node) hexahedra and 8-node quadrilaterals, as hencky supports those.
      gmsh::option::setNumber("Mesh.SecondOrderIncomplete", 1);
      gmsh::model::mesh::setOrder(options.order);
    }
  } catch (const InputError&) {
    throw;
  } catch (...) {
    throw fail("Gmsh failed to mesh or convert the model: " + last_gmsh_error());
  }

  Mesh mesh;
  try {
    // All nodes once (includeBoundary = false avoids duplicates, see DEPENDENCIES.md).
    std::vector<std::size_t> node_tags;
    std::vector<double> coord, param;
    gmsh::model::mesh::getNodes(node_tags, coord, param, -1, -1, false, false);
    std::unordered_map<std::size_t, std::size_t> gmsh_node_index;  // Gmsh tag -> position in coord
    gmsh_node_index.reserve(node_tags.size());
    for (std::size_t i = 0; i < node_tags.size(); ++i) gmsh_node_index.emplace(node_tags[i], i);

    // Physical groups by dimension.
    gmsh::vectorpair groups;
    gmsh::model::getPhysicalGroups(groups, -1);
    auto group_name = [](int dim, int tag) {
      std::string name;
      gmsh::model::getPhysicalName(dim, tag, name);
      return name.empty() ? std::to_string(tag) : name;
    };
    auto elements_of = [](int dim, int entity, std::vector<int>& types,
                          std::vector<std::vector<std::size_t>>& etags,
                          std::vector<std::vector<std::size_t>>& enodes) {
      gmsh::model::mesh::getElements(types, etags, enodes, dim, entity);
    };

    // Body cells: physical volumes, or all 3D entities.
    std::vector<std::pair<int, std::vector<int>>> volume_groups;  // (region index, entities)
    for (auto [dim, tag] : groups) {
      if (dim != 3) continue;
      std::vector<int> ents;
      gmsh::model::getEntitiesForPhysicalGroup(dim, tag, ents);
      Region r;
      r.name = group_name(dim, tag);
      r.dim = 3;
      mesh.regions.push_back(r);
      volume_groups.emplace_back(static_cast<int>(mesh.regions.size()) - 1, ents);
    }
    if (volume_groups.empty()) {
      gmsh::vectorpair ents;
      gmsh::model::getEntities(ents, 3);
      std::vector<int> all;
      for (auto [d, t] : ents) all.push_back(t);
      volume_groups.emplace_back(-1, all);
    }

    std::unordered_map<std::size_t, int> node_index;  // Gmsh tag -> hencky node
    std::vector<std::size_t> body_node_tags;
    std::unordered_map<std::size_t, int> cell_of_tag;  // Gmsh element tag -> cell, for duplicates
    std::vector<std::vector<std::size_t>> cell_gmsh_nodes;
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> etags, enodes;
    for (auto& [region, ents] : volume_groups) {
      for (int ent : ents) {
        elements_of(3, ent, types, etags, enodes);
        for (std::size_t k = 0; k < types.size(); ++k) {
          CellType ct;
          if (!gmsh_type_to_cell(types[k], ct))
            throw fail("unsupported volume element " + gmsh_type_name(types[k]) +
                       "; hencky supports 4/10-node tetrahedra, 8/20-node hexahedra and 6-node "
                       "wedges (use mesh.order: 2 for serendipity quadratic elements)");
          const int nn = cell_n_nodes(ct);
          for (std::size_t e = 0; e < etags[k].size(); ++e) {
            auto [it, fresh] = cell_of_tag.emplace(etags[k][e], mesh.cells.size());
            if (!fresh) continue;  // element in two physical volumes: first one wins
            int local[max_cell_nodes];
            for (int a = 0; a < nn; ++a) {
              const std::size_t gt = enodes[k][e * nn + a];
              auto [nit, nfresh] = node_index.emplace(gt, static_cast<int>(body_node_tags.size()));
              if (nfresh) body_node_tags.push_back(gt);
              local[a] = nit->second;
            }
            mesh.cells.add(ct, std::span<const int>(local, nn), static_cast<long>(etags[k][e]));
            mesh.cell_region.push_back(region);
            if (region >= 0) mesh.regions[region].cells.push_back(mesh.cells.size() - 1);
          }
        }
      }
    }
    if (mesh.cells.size() == 0) throw fail("the mesh has no 3D elements in its physical volumes");

    // Renumber nodes by Gmsh tag so that the numbering does not depend on traversal order.
    std::vector<int> order(body_node_tags.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return body_node_tags[a] < body_node_tags[b]; });
    std::vector<int> new_of_old(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) new_of_old[order[i]] = static_cast<int>(i);
    for (auto& n : mesh.cells.conn) n = new_of_old[n];
    mesh.x.resize(order.size());
    mesh.node_tag.resize(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
      const std::size_t gt = body_node_tags[order[i]];
      const auto ci = gmsh_node_index.at(gt);
      mesh.x[i] = Vec3(coord[3 * ci], coord[3 * ci + 1], coord[3 * ci + 2]) * options.scale;
      mesh.node_tag[i] = static_cast<long>(gt);
      node_index[gt] = static_cast<int>(i);
    }

    // Lower-dimensional regions: faces for surfaces, node sets for all.
    for (auto [dim, tag] : groups) {
      if (dim == 3) continue;
      Region r;
      r.name = group_name(dim, tag);
      r.dim = dim;
      std::vector<int> ents;
      gmsh::model::getEntitiesForPhysicalGroup(dim, tag, ents);
      for (int ent : ents) {
        elements_of(dim, ent, types, etags, enodes);
        for (std::size_t k = 0; k < types.size(); ++k) {
          int dim_k = 0, order_k = 0, nn = 0, n_primary = 0;
          std::string name;
          std::vector<double> local_coord;
          gmsh::model::mesh::getElementProperties(types[k], name, dim_k, order_k, nn, local_coord,
                                                  n_primary);
          CellType ct{};
          const bool is_face = dim == 2 && gmsh_type_to_cell(types[k], ct);
          if (dim == 2 && !is_face)
            throw fail("region '" + r.name + "': unsupported surface element " +
                       gmsh_type_name(types[k]));
          for (std::size_t e = 0; e < etags[k].size(); ++e) {
            int local[max_cell_nodes];
            for (int a = 0; a < nn; ++a) {
              const std::size_t gt = enodes[k][e * nn + a];
              auto it = node_index.find(gt);
              if (it == node_index.end())
                throw fail("region '" + r.name + "': element " + std::to_string(etags[k][e]) +
                           " has node " + std::to_string(gt) +
                           " which is not a node of the volume mesh (the surface is not on the body)");
              if (a < max_cell_nodes) local[a] = it->second;
              r.nodes.push_back(it->second);
            }
            if (is_face) {
              mesh.faces.add(ct, std::span<const int>(local, nn), static_cast<long>(etags[k][e]));
              r.cells.push_back(mesh.faces.size() - 1);
            }
          }
        }
      }
      mesh.regions.push_back(std::move(r));
    }
    for (auto& r : mesh.regions) {
      if (r.dim == 3)
        for (int c : r.cells)
          for (int n : mesh.cells.nodes(c)) r.nodes.push_back(n);
      std::sort(r.nodes.begin(), r.nodes.end());
      r.nodes.erase(std::unique(r.nodes.begin(), r.nodes.end()), r.nodes.end());
    }
  } catch (const InputError&) {
    throw;
  } catch (...) {
    throw fail("Gmsh failed while reading the mesh: " + last_gmsh_error());
  }
  return mesh;
}

}  // namespace hencky
