#pragma once
// Which rank owns the nodes that several ranks hold, when no rank holds the whole mesh (issue
// 21: each rank reading its own file of a mesh that Gmsh split into files, where the nodes on
// the boundaries between the files are in each of them, with the same tag).
//
// A rendezvous by tag: each tag has a meeting rank (tag mod ranks), to which every rank that
// holds the tag says so; the meeting rank names the lowest of them the owner (the rule of
// partition_from for a whole mesh) and tells them. A second meeting gives a ghost its owner's
// index for the node. Memory is each rank's own nodes and the tags it meets for, about as many:
// no array has the length of the whole mesh. (PETSc's PetscSFCreateByMatchingIndices pairs
// indices across ranks in the same way; this needs the lowest holder, which it does not give.)
#include <span>
#include <vector>

namespace hencky {

struct SharedNodes {
  std::vector<int> owner;        ///< per local node, the lowest rank that holds its tag
  std::vector<int> owner_index;  ///< its index among the owner's own nodes, in the owner's order
  std::vector<long long> global; ///< a whole numbering, contiguous per owner in rank order
  int owned = 0;                 ///< the local nodes this rank owns
  long long total = 0;           ///< the nodes of all ranks, each once
};

/// `tags`: this rank's nodes by tag (positive, each once on a rank; the same node has the same
/// tag on every rank that holds it). A rank's own nodes are numbered in the order of `tags`.
/// Collective; throws std::invalid_argument (on every rank) for a tag that is not positive or
/// appears twice on one rank.
SharedNodes share_nodes(std::span<const long long> tags);

}  // namespace hencky
