#pragma once
// The part of a mesh one rank holds once the mesh is distributed (issue 21): the cells the rank
// owns, the nodes they touch and the pieces of the regions, numbered locally. A node touched by
// cells of several ranks is in each of their parts: it is *owned* by one of them (the partition's
// node owner, the lowest of those ranks) and a *ghost* in the others. The local numbering puts
// the owned nodes first, so that a rank's rows of a global vector are a prefix of its local
// vectors:
//
//   local node  0 .. owned_nodes-1   this rank's own nodes, in the whole mesh's order
//               owned_nodes .. n-1   the ghost nodes, in the whole mesh's order
//
// Each local node knows its owner and its index among the owner's own nodes (owner_index): the
// pair is where a ghost's value lives, what a ghost exchange (PetscSF) needs, and with the
// owners' offsets a global number contiguous per rank, as PETSc lays out its vectors.
//
// This is how DMPlex describes a distributed mesh too (a point SF whose leaves are the ghost
// points and whose roots are their owners' copies), without DMPlex's topology: hencky keeps its
// cells in Gmsh's node order (docs/parallel.md says why).
#include <string>
#include <string_view>
#include <vector>

#include "mesh/mesh.hpp"
#include "parallel/partition.hpp"

namespace hencky {

struct MeshPart {
  /// The part, numbered locally: owned nodes first (above). Its regions are the whole mesh's,
  /// in the same order and with the same names (an empty one where the rank holds none of it):
  /// a volume region lists its local cells, a surface region the local faces, every region its
  /// local nodes (sorted). node_tag, cells.tag and faces.tag keep the mesh file's numbers.
  Mesh mesh;
  int owned_nodes = 0;
  std::vector<int> global_node;  ///< the whole mesh's index of each local node
  std::vector<int> node_owner;   ///< the rank that owns each local node
  std::vector<int> owner_index;  ///< each local node's index among its owner's own nodes
  std::vector<int> global_cell;  ///< the whole mesh's index of each local cell
  /// Where each local cell's integration points start among the whole mesh's points, taken
  /// cell by cell in the whole mesh's order with reference_table's points (the order of a
  /// checkpoint's point data).
  std::vector<long long> global_point;
  std::vector<int> global_face;  ///< the whole mesh's index of each local face
};

/// Rank `partition.rank`'s part of `whole` under `partition` (whose node owners are those of
/// partition_from). The cells are the rank's own cells, in the whole mesh's order. A boundary
/// face is in the part of every rank that owns a cell holding all its corner nodes: an outer
/// face in one part, a face between two ranks' cells in both. Reads arrays of the whole mesh's
/// length: the reading rank's work before it sends the parts (transient).
MeshPart extract_part(const Mesh& whole, const Partition& partition);

/// The part as bytes and back (for sending it to its rank): unpack(pack(p)) == p.
std::string pack(const MeshPart& part);
/// Throws std::invalid_argument when `bytes` are not a packed part.
MeshPart unpack(std::string_view bytes);

/// The first way in of a distributed mesh: root holds the whole mesh and the owner of each cell
/// (`whole` and `cell_owner` are read on root only), extracts each rank's part in turn, sends
/// it and frees it; every rank returns its own part. Collective. Root's peak is the whole mesh
/// plus one part.
MeshPart scatter_parts(const Mesh* whole, const std::vector<int>& cell_owner);

/// The second way in: this rank read one file of a mesh that Gmsh split into files (one file
/// per rank, input/gmsh_reader.hpp's MeshReadOptions::piece), and no rank holds the whole. The
/// nodes the files share are found by their tags (share_nodes): each is owned by the lowest
/// rank that holds it and is a ghost in the others. The whole numbering of nodes, cells, faces
/// and points is contiguous per rank in rank order (not the whole mesh's own order: there is
/// none). Collective.
MeshPart part_of_piece(Mesh piece);

}  // namespace hencky
