#include "parallel/node_exchange.hpp"

#include <petscsf.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "parallel/mpi.hpp"

namespace hencky {

struct NodeExchange::Impl {
  PetscSF sf = nullptr;
  /// One committed MPI type per width (3 doubles a node, 1, 6, ...), made on first use.
  mutable std::map<int, MPI_Datatype> types;
  MPI_Datatype type(int width) const {
    // One value a node is MPI_DOUBLE itself: PETSc's reductions refused Open MPI's contiguous
    // type of one double (MPI_ERR_OP).
    if (width == 1) return MPI_DOUBLE;
    auto it = types.find(width);
    if (it != types.end()) return it->second;
    MPI_Datatype t;
    MPI_Type_contiguous(width, MPI_DOUBLE, &t);
    MPI_Type_commit(&t);
    return types[width] = t;
  }
  ~Impl() {
    for (auto& [width, t] : types) MPI_Type_free(&t);
    if (sf) PetscSFDestroy(&sf);
  }
};

NodeExchange::NodeExchange(const MeshPart& part)
    : impl_(std::make_unique<Impl>()),
      owned_(part.owned_nodes),
      local_(static_cast<int>(part.global_node.size())) {
  if (par::size() == 1) return;
  if (part.node_owner.size() != static_cast<std::size_t>(local_) ||
      part.owner_index.size() != static_cast<std::size_t>(local_))
    throw std::invalid_argument("NodeExchange: the part has no owners for its nodes");
  par::check_petsc(PetscSFCreate(PETSC_COMM_WORLD, &impl_->sf), "PetscSFCreate");
  // Leaf i (local node i) is the root owner_index[i] of rank node_owner[i]; leaves are
  // contiguous (ilocal = NULL).
  std::vector<PetscSFNode> remote(local_);
  for (int i = 0; i < local_; ++i) {
    remote[i].rank = part.node_owner[i];
    remote[i].index = part.owner_index[i];
  }
  par::check_petsc(PetscSFSetGraph(impl_->sf, owned_, local_, nullptr, PETSC_COPY_VALUES,
                                   remote.data(), PETSC_COPY_VALUES),
                   "PetscSFSetGraph");
  par::check_petsc(PetscSFSetUp(impl_->sf), "PetscSFSetUp");
}

NodeExchange::~NodeExchange() = default;

namespace {
void check_size(std::span<double> v, int width, int local) {
  if (width < 1 || v.size() != static_cast<std::size_t>(width) * local)
    throw std::invalid_argument("NodeExchange: " + std::to_string(v.size()) + " values for " +
                                std::to_string(local) + " nodes of width " + std::to_string(width));
}
}  // namespace

void NodeExchange::to_ghosts(std::span<double> v, int width) const {
  check_size(v, width, local_);
  if (!impl_->sf) return;
  // The roots are the owned prefix of v itself; a leaf that is its own root is written with
  // the value it has (PETSc copies through a buffer where root and leaf data overlap).
  const std::vector<double> owned(v.begin(),
                                  v.begin() + static_cast<std::ptrdiff_t>(width) * owned_);
  const MPI_Datatype t = impl_->type(width);
  par::check_petsc(PetscSFBcastBegin(impl_->sf, t, owned.data(), v.data(), MPI_REPLACE),
                   "PetscSFBcastBegin");
  par::check_petsc(PetscSFBcastEnd(impl_->sf, t, owned.data(), v.data(), MPI_REPLACE),
                   "PetscSFBcastEnd");
}

void NodeExchange::sum(std::span<double> v, int width) const {
  check_size(v, width, local_);
  if (!impl_->sf) return;
  // Every copy (the owner's own included) added into a zeroed root, then the sums back out.
  std::vector<double> roots(static_cast<std::size_t>(width) * owned_, 0.0);
  const MPI_Datatype t = impl_->type(width);
  par::check_petsc(PetscSFReduceBegin(impl_->sf, t, v.data(), roots.data(), MPI_SUM),
                   "PetscSFReduceBegin");
  par::check_petsc(PetscSFReduceEnd(impl_->sf, t, v.data(), roots.data(), MPI_SUM),
                   "PetscSFReduceEnd");
  par::check_petsc(PetscSFBcastBegin(impl_->sf, t, roots.data(), v.data(), MPI_REPLACE),
                   "PetscSFBcastBegin");
  par::check_petsc(PetscSFBcastEnd(impl_->sf, t, roots.data(), v.data(), MPI_REPLACE),
                   "PetscSFBcastEnd");
}

}  // namespace hencky
