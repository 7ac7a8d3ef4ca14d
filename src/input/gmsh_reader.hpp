#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace hencky {

struct MeshReadOptions {
  int order =
      0;  ///< 0: keep the file's order; 1 or 2: convert (Gmsh setOrder, serendipity hexahedra)
  double scale = 1.0;             ///< multiply coordinates
  /// Read a .msh file through the Gmsh library, as hencky did before it had its own reader
  /// (after that reader has checked the file). For comparisons between the two.
  bool through_gmsh_library = false;
  /// One file of a mesh Gmsh split into files, read as the part it holds (msh_reader.hpp):
  /// a .msh of the file's own order (no conversion).
  bool piece = false;
};

/// Reads a Gmsh .msh (format 2.2, 4.0 ASCII or 4.1, ASCII or binary) with hencky's own reader
/// (msh_reader.hpp), or meshes a .geo with the Gmsh library. An order conversion of a .msh goes
/// through the Gmsh library too, once hencky's reader has accepted the file.
/// Physical groups become regions by name (unnamed groups by their number). The body is the
/// union of the physical volumes, or every 3D element when the file has none. Only nodes of the
/// body are kept and renumbered 0..n-1 in the order of their Gmsh tags. Gmsh's messages are
/// appended to `gmsh_log` when given. Throws InputError naming the file on any failure.
Mesh read_gmsh(const std::filesystem::path& file, const MeshReadOptions& options,
               std::vector<std::string>* gmsh_log = nullptr);

}  // namespace hencky
