#pragma once
// Restarted GMRES with right preconditioning (Saad, Iterative Methods for Sparse Linear
// Systems, 2nd ed., section 9.3.2): for an operator given only as its product with a vector,
// such as a Jacobian applied cell by cell without assembling it. The heat analysis solves its
// whole Newton step dG/dT x = b with it, preconditioned by the factorized symmetric part
// (solve/heat.hpp).
//
// Vectors are std::vector<double> of one length n. The inner product is the caller's, so that
// the same code runs on a vector distributed over MPI ranks (each rank's dot product over its
// own entries, summed over the ranks) or whole on every rank.
#include <functional>
#include <vector>

namespace hencky {

/// y = A x. On entry y has the length of x (its values are to be overwritten). May be
/// collective; may throw (the exception leaves gmres).
using LinearOperator = std::function<void(const std::vector<double>& x, std::vector<double>& y)>;
/// The inner product of two vectors (the same on every rank when they are distributed).
using InnerProduct =
    std::function<double(const std::vector<double>& u, const std::vector<double>& w)>;

struct GmresOptions {
  double rtol = 1e-8;   ///< converged when ‖b − A x‖ <= rtol ‖b‖
  int restart = 30;     ///< Krylov vectors per cycle (m); their preconditioned images are kept
  int max_cycles = 3;   ///< cycles of `restart` iterations at most
};

/// Solves A x = b by GMRES(m) on A M⁻¹ y = b, x = x0 + M⁻¹ y, from the x given (x0; its length
/// is b's). M⁻¹ is `precondition` (a LinearOperator: z = M⁻¹ v, z zero on entry); the vectors
/// z_j = M⁻¹ v_j are kept, so that the update of x takes no further solve. Orthogonalization
/// by modified Gram–Schmidt, the least-squares problem by Givens rotations.
///
/// @param[in] apply          y = A x
/// @param[in] precondition   z = M⁻¹ v (right preconditioner)
/// @param[in] dot            the inner product (norms are its square roots)
/// @param[in] b              the right-hand side; b = 0 returns true at once, x untouched
/// @param[in,out] x          the first iterate on entry, the solution on return
/// @param[in] options        tolerance, restart length, cycles
/// @param[in,out] iterations increased by one per Krylov iteration (one product with A and
///                           one preconditioner solve each), as they are taken: the count
///                           stands when `apply` or `precondition` throws
/// @return whether ‖b − A x‖ <= rtol ‖b‖ on return (false: not in max_cycles cycles).
/// Collective when `apply`, `precondition` or `dot` is.
bool gmres(const LinearOperator& apply, const LinearOperator& precondition,
           const InnerProduct& dot, const std::vector<double>& b, std::vector<double>& x,
           const GmresOptions& options, int& iterations);

}  // namespace hencky
