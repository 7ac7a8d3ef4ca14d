#pragma once
// A run never reports a NaN or an infinity as an answer (issue 14): the check of an iterate
// and the message that says where the first such value appeared.
#include "solve/model.hpp"
#include "solve/state.hpp"

namespace hencky {

/// Every value of the iterate is a finite number: the forces, the displacement and this
/// rank's points' state.
bool all_finite(const State& s);

/// Stops the step (SolveError, so a failed step) where a NaN or an infinity first appears in
/// the iterate, in the order the values are computed: the external forces, the displacement,
/// a point's state, the internal and the contact forces. Collective (the same decisions and
/// message on every rank).
[[noreturn]] void throw_not_finite(const Model& m, const State& s, int iteration, double residual);

}  // namespace hencky
