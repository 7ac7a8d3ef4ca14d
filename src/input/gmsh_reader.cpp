#include "input/gmsh_reader.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cctype>
#include <functional>
#include <mutex>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "core/error.hpp"
#include "input/gmsh_child.hpp"
#include "input/gmsh_library.hpp"
#include "input/msh_data.hpp"
#include "input/msh_reader.hpp"

namespace hencky {
namespace {

namespace gmsh = gmsh_library;

/// The Gmsh library is a global singleton: one reader at a time, initialized once per read.
std::mutex gmsh_mutex;

struct GmshSession {
  explicit GmshSession(std::vector<std::string>* log) : log_(log), threads_(omp_get_max_threads()) {
    gmsh::initialize();
    gmsh::set_number("General.Terminal", 0);
    gmsh::set_number("General.Verbosity", 3);
    gmsh::logger_start();
  }
  ~GmshSession() {
    try {
      if (log_) {
        const std::vector<std::string> lines = gmsh::logger_get();
        log_->insert(log_->end(), lines.begin(), lines.end());
      }
      gmsh::logger_stop();
      gmsh::finalize();
    } catch (...) {
    }
    omp_set_num_threads(threads_);  // Gmsh sets the OpenMP thread count to its own option
  }
  std::vector<std::string>* log_;
  int threads_;
};

std::string last_gmsh_error() {
  return gmsh::last_error();
}

/// Runs Gmsh's meshing or order conversion `f`. Gmsh reports an error by throwing a
/// std::string from inside its OpenMP regions, where no handler of ours can catch it and the
/// process aborts (Gmsh 4.8, General.AbortOnError = 2, the API's default). With
/// AbortOnError = 0 Gmsh logs the error and goes on; the error it logged is then thrown here,
/// on this thread, as an input error.
template <class F>
void mesh_without_throwing(F&& f, const std::function<InputError(const std::string&)>& fail,
                           const std::string& what) {
  const std::string before = last_gmsh_error();
  gmsh::set_number("General.AbortOnError", 0);
  try {
    f();
  } catch (...) {
    gmsh::set_number("General.AbortOnError", 2);
    const std::string err = last_gmsh_error();
    throw fail(what + (err.empty() ? std::string("Gmsh failed") : err));
  }
  gmsh::set_number("General.AbortOnError", 2);
  const std::string after = last_gmsh_error();
  if (after != before && !after.empty()) throw fail(what + after);
}

/// The model the Gmsh library holds, in the form to_mesh takes.
MshData model_data() {
  MshData d;
  gmsh::get_nodes(d.node_tags, d.coords);
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> tags, nodes;
  for (auto [dim, tag] : gmsh::get_entities(-1)) {
    // A partitioned mesh's boundaries between partitions are entities of a lower dimension
    // than their parent, with elements that are not the model's (msh_reader.cpp).
    const int parent_dim = gmsh::parent(dim, tag).first;
    if (parent_dim >= 0 && parent_dim != dim) continue;
    d.entities.push_back(MshData::Entity{dim, tag, gmsh::physical_groups_for_entity(dim, tag)});
    gmsh::get_elements(dim, tag, types, tags, nodes);
    for (std::size_t k = 0; k < types.size(); ++k)
      d.blocks.push_back({dim, tag, types[k], std::move(tags[k]), std::move(nodes[k])});
  }
  for (auto [dim, tag] : gmsh::physical_groups(-1))
    d.physical_names[{dim, tag}] = gmsh::physical_name(dim, tag);
  return d;
}

/// Opens `file` in the Gmsh library, meshes it when it is a geometry, converts the element
/// order when asked, and returns the model.
MshData through_gmsh(const std::filesystem::path& file, bool geometry, int order,
                     std::vector<std::string>* gmsh_log) {
  const SourceLocation where{file.string(), 0, 0, ""};
  const std::function<InputError(const std::string&)> fail = [&](const std::string& msg) {
    return InputError(where, msg);
  };
  try {
    gmsh::load();
  } catch (const std::runtime_error& e) {
    throw fail(std::string(geometry ? "meshing a geometry" : "converting the element order") +
               " needs the Gmsh library, and " + e.what());
  }
  std::lock_guard lock(gmsh_mutex);
  GmshSession session(gmsh_log);
  try {
    gmsh::open(file.string());
  } catch (...) {
    const std::string err = last_gmsh_error();
    throw fail("Gmsh cannot read this file: " +
               (err.empty() ? "Gmsh could not process the file" : err));
  }
  try {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> tags, nodes;
    gmsh::get_elements(3, -1, types, tags, nodes);
    if (types.empty()) {
      if (!geometry) throw fail("the mesh has no 3D elements (hencky needs a volume mesh)");
      mesh_without_throwing([] { gmsh::generate(3); }, fail, "Gmsh cannot mesh this geometry: ");
    }
    if (order == 1 || order == 2) {
      // Serendipity (20-node) hexahedra and 8-node quadrilaterals, as hencky supports those.
      gmsh::set_number("Mesh.SecondOrderIncomplete", 1);
      mesh_without_throwing([&] { gmsh::set_order(order); }, fail,
                            "Gmsh cannot convert the element order: ");
    }
    return model_data();
  } catch (const InputError&) {
    throw;
  } catch (...) {
    const std::string err = last_gmsh_error();
    throw fail("Gmsh failed to mesh or convert the model: " +
               (err.empty() ? "Gmsh could not process the file" : err));
  }
}

/// through_gmsh, in a child process where the program has enabled it (gmsh_child.hpp).
MshData gmsh_step(const std::filesystem::path& file, bool geometry, int order,
                  std::vector<std::string>* gmsh_log) {
  if (gmsh_child::enabled()) return gmsh_child::run(file, geometry, order, gmsh_log);
  return through_gmsh(file, geometry, order, gmsh_log);
}

}  // namespace

void run_gmsh_in_child_processes() {
  gmsh_child::enable(through_gmsh);
}

Mesh read_gmsh(const std::filesystem::path& file, const MeshReadOptions& options,
               std::vector<std::string>* gmsh_log) {
  if (!std::filesystem::exists(file))
    throw InputError(SourceLocation{file.string(), 0, 0, ""}, "mesh file does not exist");
  std::string ext = file.extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (options.piece &&
      (ext == ".geo" || options.order == 1 || options.order == 2 || options.through_gmsh_library))
    throw InputError(SourceLocation{file.string(), 0, 0, ""},
                     "one file of a split mesh is read as it is: a .msh, without an order "
                     "conversion (convert the order before Gmsh splits the mesh)");
  if (ext == ".geo")
    return to_mesh(gmsh_step(file, true, options.order, gmsh_log), options, file.string());
  // A .msh file is read by hencky's own reader, which refuses malformed files that would crash
  // Gmsh's. Only an order conversion needs the Gmsh library, and then only for a file that
  // reader accepted. (Gmsh's conversion renumbers the mid-edge nodes even of a file that has
  // the order asked for: it is not skipped then, so that results stay as they were.)
  MshData data = read_msh(file, options.piece);
  if (options.piece && options.pieces > 0 &&
      (data.piece != options.piece_number || data.partitions != options.pieces))
    throw InputError(SourceLocation{file.string(), 0, 0, ""},
                     fmt::format("the file holds partition {} of {}, but as file {} of the {} "
                                 "files of the split mesh it should hold partition {} of {}: the "
                                 "files are not one split of one mesh (split it again, "
                                 "gmsh -part N -part_split, and remove the files of other splits)",
                                 data.piece, data.partitions, options.piece_number, options.pieces,
                                 options.piece_number, options.pieces));
  if (options.through_gmsh_library || options.order == 1 || options.order == 2)
    data = gmsh_step(file, false, options.order, gmsh_log);
  return to_mesh(data, options, file.string());
}

Mesh read_pieces(const std::vector<std::filesystem::path>& files, const MeshReadOptions& options) {
  MeshReadOptions one = options;
  one.piece = true;
  one.pieces = static_cast<int>(files.size());
  std::vector<Mesh> pieces;
  for (const auto& f : files) {
    ++one.piece_number;
    pieces.push_back(read_gmsh(f, one));
  }
  // Each node's index: by the first piece that holds it, then by tag (a piece's nodes are in
  // the order of their tags already).
  std::unordered_map<long, int> index_of_tag;
  Mesh whole;
  for (const Mesh& p : pieces)
    for (int n = 0; n < p.n_nodes(); ++n)
      if (index_of_tag.emplace(p.node_tag[n], whole.n_nodes()).second) {
        whole.x.push_back(p.x[n]);
        whole.node_tag.push_back(p.node_tag[n]);
      }
  std::set<std::pair<int, std::string>> names;
  for (const Mesh& p : pieces)
    for (const Region& r : p.regions) names.insert({r.dim, r.name});
  for (const auto& [dim, name] : names) {
    Region& r = whole.regions.emplace_back();
    r.dim = dim;
    r.name = name;
  }
  auto region_index = [&](const Region& r) {
    return static_cast<int>(std::distance(names.begin(), names.find({r.dim, r.name})));
  };
  std::unordered_set<long> cell_tags, face_tags;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const Mesh& p = pieces[k];
    const int first_cell = whole.cells.size(), first_face = whole.faces.size();
    auto add = [&](const CellSet& from, CellSet& to, std::unordered_set<long>& tags,
                   const char* what) {
      std::vector<int> nodes;
      for (int c = 0; c < from.size(); ++c) {
        if (!tags.insert(from.tag[c]).second)
          throw InputError(SourceLocation{files[k].string(), 0, 0, ""},
                           fmt::format("{} {} is in this file and in an earlier one of the split "
                                       "mesh: the files are not the pieces of one mesh",
                                       what, from.tag[c]));
        nodes.clear();
        for (int n : from.nodes(c)) nodes.push_back(index_of_tag.at(p.node_tag[n]));
        to.add(from.type[c], nodes, from.tag[c]);
      }
    };
    add(p.cells, whole.cells, cell_tags, "element");
    add(p.faces, whole.faces, face_tags, "face element");
    for (int c = 0; c < p.cells.size(); ++c)
      whole.cell_region.push_back(p.cell_region[c] < 0 ? -1
                                                       : region_index(p.regions[p.cell_region[c]]));
    for (const Region& r : p.regions) {
      Region& to = whole.regions[region_index(r)];
      const int first = r.dim == 3 ? first_cell : first_face;
      for (int c : r.cells) to.cells.push_back(first + c);
      for (int n : r.nodes) to.nodes.push_back(index_of_tag.at(p.node_tag[n]));
    }
  }
  for (Region& r : whole.regions) {
    std::sort(r.nodes.begin(), r.nodes.end());
    r.nodes.erase(std::unique(r.nodes.begin(), r.nodes.end()), r.nodes.end());
  }
  return whole;
}

}  // namespace hencky
