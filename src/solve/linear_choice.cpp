#include "solve/linear_choice.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace hencky {

namespace {

double gib(double bytes) { return bytes / (1024.0 * 1024.0 * 1024.0); }

}  // namespace

LinearChoiceRule LinearChoiceRule::from_environment() {
  LinearChoiceRule rule;
  if (const char* v = std::getenv("HENCKY_AUTO_ANALYZE_FROM"))
    rule.analyze_from = std::strtoll(v, nullptr, 10);
  if (const char* v = std::getenv("HENCKY_AUTO_CROSSOVER"))
    rule.crossover_flops = std::strtod(v, nullptr);
  return rule;
}

double available_memory_bytes() {
  if (const char* v = std::getenv("HENCKY_AUTO_MEMORY")) return std::strtod(v, nullptr);
  std::ifstream in("/proc/meminfo");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    double kib = 0;
    if (words >> key >> kib && key == "MemAvailable:") return kib * 1024.0;
  }
  return 0;
}

double LinearChoiceRule::crossover_at(double n) const {
  return crossover_flops * std::pow(n / 1e5, crossover_growth);
}

namespace {

/// A temperature system is measured against the thresholds by its nodes, as if each had the
/// displacement's 3 dofs: the graph, and so the factor's structure, is the same.
double equivalent_unknowns(const LinearChoiceInputs& in) {
  return 3.0 * static_cast<double>(in.unknowns) / in.per_node;
}

}  // namespace

bool wants_factor_estimate(const LinearChoiceInputs& in, const LinearChoiceRule& rule) {
  return in.ranks == 1 && equivalent_unknowns(in) >= static_cast<double>(rule.analyze_from);
}

LinearChoice choose_linear(const LinearChoiceInputs& in, const LinearChoiceRule& rule) {
  LinearChoice c;
  const double nodes = static_cast<double>(in.unknowns) / in.per_node;
  const bool analysed = in.factor_entries > 0;
  c.predicted_direct_bytes =
      rule.bytes_per_factor_entry *
      (analysed ? in.factor_entries
                : rule.factor_coefficient * std::pow(nodes, 4.0 / 3.0) * in.per_node * in.per_node);
  // A temperature system's factor, against the crossover measured on displacements: its flops
  // per unknown as those of the displacement system on the same mesh (× (3 / per_node)²).
  const double scale = 9.0 / (in.per_node * in.per_node);
  const double flops_per_unknown = analysed ? scale * in.factor_flops / in.unknowns : 0;
  const char* as_displacement = in.per_node == 3 ? "" : " (as a displacement on this mesh)";
  const double crossover = rule.crossover_at(equivalent_unknowns(in));
  const std::string memory =
      in.available_bytes > 0 ? fmt::format(" of the {:.1f} GiB available", gib(in.available_bytes))
                             : std::string();
  if (in.ranks > 1) {
    c.linear = SolverSpec::Linear::petsc;
    c.reason = fmt::format("{} MPI ranks: the PETSc back end, CG + GAMG", in.ranks);
  } else if (in.available_bytes > 0 &&
             c.predicted_direct_bytes > rule.memory_fraction * in.available_bytes) {
    c.linear = SolverSpec::Linear::petsc;
    c.reason = fmt::format(
        "{} unknowns: a sparse Cholesky factorization would take about {:.1f} GiB, more than "
        "{:.0f} % of the {:.1f} GiB available",
        in.unknowns, gib(c.predicted_direct_bytes), 100 * rule.memory_fraction,
        gib(in.available_bytes));
  } else if (analysed && flops_per_unknown >= crossover) {
    c.linear = SolverSpec::Linear::petsc;
    c.reason = fmt::format(
        "{} unknowns: the factorization would cost {:.3g} Gflop, {:.2g} Mflop per unknown{}, at "
        "least the {:.2g} from which CG + GAMG is faster at this size",
        in.unknowns, in.factor_flops / 1e9, flops_per_unknown / 1e6, as_displacement,
        crossover / 1e6);
  } else if (analysed) {
    c.linear = SolverSpec::Linear::direct;
    c.reason = fmt::format(
        "{} unknowns: the factorization should cost {:.3g} Gflop, {:.2g} Mflop per unknown{}, "
        "below the {:.2g} from which CG + GAMG would be faster at this size, and take about "
        "{:.2g} GiB{}",
        in.unknowns, in.factor_flops / 1e9, flops_per_unknown / 1e6, as_displacement,
        crossover / 1e6, gib(c.predicted_direct_bytes), memory);
  } else {
    c.linear = SolverSpec::Linear::direct;
    c.reason = fmt::format(
        "{} unknowns, fewer than the {} from which CG + GAMG may be faster; the factor should "
        "take about {:.2g} GiB{}",
        in.unknowns, rule.analyze_from, gib(c.predicted_direct_bytes), memory);
  }
  if (in.nonlinear && in.ranks == 1)
    c.reason += " (plasticity or contact: the same rule, measured on elastic solves)";
  return c;
}

}  // namespace hencky
