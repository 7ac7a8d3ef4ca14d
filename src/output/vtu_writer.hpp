#pragma once
// VTK XML output for ParaView: one UnstructuredGrid .vtu per time step (raw binary appended
// data, written in one buffered pass) and a .pvd collection listing them.
//
// hencky numbers the nodes of a cell in Gmsh's order; VTK uses another one for some cells.
// The writer permutes: vtk_node[i] = gmsh_node[gmsh_to_vtk_permutation(type)[i]].
#include <filesystem>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "fem/cell_type.hpp"
#include "mesh/mesh.hpp"

namespace hencky {

/// A Float64 array with one tuple of n_components values per point (or per cell);
/// data.size() == n_entities * n_components, tuples stored one after the other.
struct VtuField {
  std::string name;
  int n_components = 1;
  std::span<const double> data;
};

/// An Int32 array with one value per entity (region index, material number, ...).
struct VtuIntField {
  std::string name;
  std::span<const int> data;
};

/// The global numbers of a piece's points and cells (the Gmsh node and element tags), written as
/// Int64 arrays "node_tag" and "element_tag" and declared as VTK's GlobalIds: a node shared by
/// two pieces has the same number in both, so that ParaView (and a script) can tell the copies.
/// Empty spans: not written.
struct VtuGlobalIds {
  std::span<const long> nodes, cells;
};

/// Writes an UnstructuredGrid .vtu (format version 1.0, raw binary appended data,
/// header_type UInt64, native byte order): Float64 points and fields, Int64 connectivity and
/// offsets, UInt8 cell types. Cells may mix types; their nodes are in Gmsh order and are
/// permuted to VTK's. The file is written to path + ".tmp" and then renamed to path, so a
/// reader never sees a partial file.
/// Throws std::invalid_argument on inconsistent input (field sizes, node indices out of range)
/// and std::runtime_error naming the path on I/O failure.
void write_vtu(const std::filesystem::path& path, std::span<const Vec3> points,
               const CellSet& cells, std::span<const VtuField> point_fields,
               std::span<const VtuField> cell_fields,
               std::span<const VtuIntField> cell_int_fields = {}, const VtuGlobalIds& ids = {});

/// Writes a parallel .pvtu (PUnstructuredGrid) that lists `pieces` (.vtu files written by
/// write_vtu with the same fields and ids, paths relative to the .pvtu's directory). The fields'
/// names and component counts are used, their data is not. Atomic like write_vtu.
void write_pvtu(const std::filesystem::path& path, std::span<const VtuField> point_fields,
                std::span<const VtuField> cell_fields, std::span<const VtuIntField> cell_int_fields,
                bool with_ids, std::span<const std::string> pieces);

/// A ParaView collection (.pvd) of time steps: <DataSet timestep="t" file="step.vtu"/>.
/// The .pvd is rewritten (atomically, via a .tmp file and a rename) after each add(), so an
/// interrupted run leaves a readable series of the steps written so far.
class PvdWriter {
 public:
  explicit PvdWriter(std::filesystem::path pvd_path);

  /// Appends a step and rewrites the .pvd. vtu_file_name is stored as given: it should be
  /// relative to the directory of the .pvd. Throws std::runtime_error on I/O failure.
  void add(double time, const std::string& vtu_file_name);
  /// Starts the series with `steps` (time, file) of an earlier run (a restart) and writes it.
  void adopt(std::vector<std::pair<double, std::string>> steps);

  const std::filesystem::path& path() const { return path_; }
  std::size_t size() const { return steps_.size(); }

 private:
  void write() const;
  std::filesystem::path path_;
  std::vector<std::pair<double, std::string>> steps_;
};

/// Gmsh -> VTK node order of one cell type: vtk_node[i] = gmsh_node[perm[i]]
/// (perm.size() == cell_n_nodes(t)).
std::span<const int> gmsh_to_vtk_permutation(CellType t);

/// The VTK cell type number (VTK_TETRA = 10, VTK_QUADRATIC_TETRA = 24, VTK_HEXAHEDRON = 12,
/// VTK_QUADRATIC_HEXAHEDRON = 25, VTK_WEDGE = 13, VTK_TRIANGLE = 5, VTK_QUADRATIC_TRIANGLE = 22,
/// VTK_QUAD = 9, VTK_QUADRATIC_QUAD = 23).
int vtk_cell_type(CellType t);

}  // namespace hencky
