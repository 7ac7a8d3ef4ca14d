#include "input/gmsh_reader.hpp"

#include <gmsh.h>
#include <omp.h>

#include <cctype>
#include <functional>
#include <mutex>

#include "core/error.hpp"
#include "input/msh_data.hpp"
#include "input/msh_reader.hpp"

namespace hencky {
namespace {

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
  return err;
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
  gmsh::option::setNumber("General.AbortOnError", 0);
  try {
    f();
  } catch (...) {
    gmsh::option::setNumber("General.AbortOnError", 2);
    const std::string err = last_gmsh_error();
    throw fail(what + (err.empty() ? std::string("Gmsh failed") : err));
  }
  gmsh::option::setNumber("General.AbortOnError", 2);
  const std::string after = last_gmsh_error();
  if (after != before && !after.empty()) throw fail(what + after);
}

/// The model the Gmsh library holds, in the form to_mesh takes.
MshData model_data() {
  MshData d;
  std::vector<double> param;
  gmsh::model::mesh::getNodes(d.node_tags, d.coords, param, -1, -1, false, false);
  gmsh::vectorpair entities;
  gmsh::model::getEntities(entities, -1);
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> tags, nodes;
  for (auto [dim, tag] : entities) {
    MshData::Entity e{dim, tag, {}};
    gmsh::model::getPhysicalGroupsForEntity(dim, tag, e.physicals);
    d.entities.push_back(std::move(e));
    gmsh::model::mesh::getElements(types, tags, nodes, dim, tag);
    for (std::size_t k = 0; k < types.size(); ++k)
      d.blocks.push_back({dim, tag, types[k], std::move(tags[k]), std::move(nodes[k])});
  }
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, -1);
  for (auto [dim, tag] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(dim, tag, name);
    d.physical_names[{dim, tag}] = name;
  }
  return d;
}

/// Opens `file` in the Gmsh library, meshes it when it is a geometry, converts the element
/// order when asked, and returns the model.
MshData through_gmsh(const std::filesystem::path& file, bool geometry,
                     const MeshReadOptions& options, std::vector<std::string>* gmsh_log) {
  const SourceLocation where{file.string(), 0, 0, ""};
  const std::function<InputError(const std::string&)> fail = [&](const std::string& msg) {
    return InputError(where, msg);
  };
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
    gmsh::model::mesh::getElements(types, tags, nodes, 3, -1);
    if (types.empty()) {
      if (!geometry) throw fail("the mesh has no 3D elements (hencky needs a volume mesh)");
      mesh_without_throwing([] { gmsh::model::mesh::generate(3); }, fail,
                            "Gmsh cannot mesh this geometry: ");
    }
    if (options.order == 1 || options.order == 2) {
      // Serendipity (20-node) hexahedra and 8-node quadrilaterals, as hencky supports those.
      gmsh::option::setNumber("Mesh.SecondOrderIncomplete", 1);
      mesh_without_throwing([&] { gmsh::model::mesh::setOrder(options.order); }, fail,
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

}  // namespace

Mesh read_gmsh(const std::filesystem::path& file, const MeshReadOptions& options,
               std::vector<std::string>* gmsh_log) {
  if (!std::filesystem::exists(file))
    throw InputError(SourceLocation{file.string(), 0, 0, ""}, "mesh file does not exist");
  std::string ext = file.extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (ext == ".geo")
    return to_mesh(through_gmsh(file, true, options, gmsh_log), options, file.string());
  // A .msh file is read by hencky's own reader, which refuses malformed files that would crash
  // Gmsh's. Only an order conversion needs the Gmsh library, and then only for a file that
  // reader accepted. (Gmsh's conversion renumbers the mid-edge nodes even of a file that has
  // the order asked for: it is not skipped then, so that results stay as they were.)
  MshData data = read_msh(file);
  if (options.through_gmsh_library || options.order == 1 || options.order == 2)
    data = through_gmsh(file, false, options, gmsh_log);
  return to_mesh(data, options, file.string());
}

}  // namespace hencky
