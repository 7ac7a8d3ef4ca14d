#pragma once
// Nodal values between the ranks of a distributed mesh (issue 21): a rank's part has its own
// nodes and ghost copies of the nodes its cells share with other ranks (parallel/mesh_part.hpp).
// Two exchanges keep the copies consistent:
//   - to_ghosts: each ghost takes its owner's value (a solution, a state: owned values are
//     the truth);
//   - sum: each copy of a node ends with the sum over all copies (a vector assembled from each
//     rank's cells: internal or external forces, the recovered nodal sums).
// Built on PETSc's star forest (PetscSF): the roots are each rank's own nodes, the leaves all
// its local nodes (its own map onto themselves), as DMPlex's point SF describes a distributed
// mesh. Both exchanges are collective; on one rank they cost nothing and change nothing.
#include <memory>
#include <span>

#include "parallel/mesh_part.hpp"

namespace hencky {

class NodeExchange {
 public:
  /// The exchange of `part`'s nodes (collective: every rank passes its own part).
  explicit NodeExchange(const MeshPart& part);
  ~NodeExchange();
  NodeExchange(const NodeExchange&) = delete;
  NodeExchange& operator=(const NodeExchange&) = delete;

  /// v holds `width` values per local node (local order). Every ghost copy takes its owner's.
  void to_ghosts(std::span<double> v, int width) const;
  /// Every copy of a node takes the sum of all copies' values (owners' first, then sent back).
  void sum(std::span<double> v, int width) const;
  int owned_nodes() const { return owned_; }
  int local_nodes() const { return local_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int owned_ = 0, local_ = 0;
};

}  // namespace hencky
