#pragma once
// How this rank's nodal vectors stand to the whole model's (issue 21). The step loop assembles
// vectors from its own cells, completes them, and measures them; what that takes depends on
// how the mesh is held:
//
//   whole        one rank: its vectors are the model's; nothing to exchange.
//   replicated   every rank holds the whole mesh and assembles its own cells: a vector is
//                completed by summing it whole over the ranks, and every rank then holds the
//                same whole vector (each measures it alone, all get the same figure).
//   distributed  a rank holds its part (parallel/mesh_part.hpp: its own nodes first, then the
//                ghosts): a vector is completed by summing the copies of each node
//                (NodeExchange::sum), and a norm counts each rank's own nodes and is summed over
//                the ranks.
//
// Every nodal vector the step loop keeps is complete: each copy of a node holds the node's
// whole value. Its dofs follow the DofMap, which numbers the free dofs node by node, so that a
// rank's own free dofs are a prefix of its free-dof vectors too.
#include <memory>
#include <span>


namespace hencky {

class NodeExchange;

class NodalLayout {
 public:
  enum class Kind { whole, replicated, distributed };

  /// One rank.
  NodalLayout() = default;
  /// The whole mesh on each of several ranks.
  static NodalLayout replicated();
  /// A part of the mesh on each rank: `exchange` over its nodes, of which the first
  /// exchange->owned_nodes() are this rank's own.
  static NodalLayout distributed(std::shared_ptr<const NodeExchange> exchange);

  Kind kind() const { return kind_; }
  /// Several ranks share the work (replicated or distributed).
  bool shared() const { return kind_ != Kind::whole; }

  /// Completes a vector assembled from this rank's cells (`width` values per node): every
  /// copy of a node then holds the sum over the ranks. Collective.
  void sum(std::span<double> v, int width) const;
  /// sum() of `blocks` vectors of one value per node stored one after the other in `v`.
  void sum_blocks(std::span<double> v, int blocks) const;

  /// How many leading entries of a vector of `width` values per node are this rank's own:
  /// all of them unless distributed.
  std::size_t owned_entries(std::size_t size, int width, int local_nodes) const;
  /// The same for a free-dof vector: `eq` numbers each dof's equation (negative: prescribed),
  /// `per_node` dofs a node, the free ones node by node (DofMap, linalg/sparse.hpp).
  int owned_free(std::span<const int> eq, int per_node) const;

  /// Σ a[i]·b[i] over the first `owned` entries, summed over the ranks when distributed (the
  /// same figure on every rank then). Collective when distributed.
  double dot(std::span<const double> a, std::span<const double> b, std::size_t owned) const;
  /// The sum over the ranks when distributed, else x. Collective when distributed.
  double total(double x) const;
  /// total() of each entry of `x`, in place. Collective when distributed.
  void total(std::span<double> x) const;
  /// The largest over the ranks when distributed, else x. Collective when distributed.
  double largest(double x) const;

 private:
  Kind kind_ = Kind::whole;
  std::shared_ptr<const NodeExchange> exchange_;
};

}  // namespace hencky
