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
  /// With `piece`, when > 0: the file is file `piece_number` (from 1) of `pieces` (the names
  /// Gmsh gives them, mesh_1.msh ..), and must say it holds that partition of that many.
  int piece_number = 0, pieces = 0;
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

/// From now on, Gmsh's part of read_gmsh (meshing a .geo, converting an element order) runs in
/// a child process, where a crash inside Gmsh is an input error naming the file
/// (input/gmsh_child.hpp). For hencky's main(), which also hands the child's start to
/// gmsh_child::child_main; other programs run Gmsh in their own process.
void run_gmsh_in_child_processes();

/// The whole mesh of the files Gmsh split a mesh into (`-part N -part_split`), each read as a
/// piece (MeshReadOptions::piece; `options.scale` applies). Its order is the one the ranks'
/// parts give it when each rank reads one file (parallel/mesh_part.hpp, part_of_piece), so that
/// checkpoints pass between the two: the nodes by the first file that holds them, then by tag;
/// the cells and faces file by file, each in its file's order; the regions by dimension and
/// name. A face or cell in two files is an error.
Mesh read_pieces(const std::vector<std::filesystem::path>& files, const MeshReadOptions& options);

}  // namespace hencky
