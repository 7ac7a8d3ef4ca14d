// summary.json (summary.hpp). nlohmann::json keeps an object's keys sorted: the file's order is
// the keys', whatever the order they are set in here.
#include "output/summary.hpp"

#include <fmt/format.h>

#include "hencky/version.hpp"

namespace hencky {
namespace {

nlohmann::json linear_solver_json(const LinearSolverStats& st) {
  return {{"method", st.description},
          {"analyses", st.n_analyses},
          {"factorizations", st.n_factorizations},
          {"solves", st.n_solves},
          {"factor_flops", st.factor_flops},
          {"factor_nonzeros", st.factor_nnz},
          {"matrix_nonzeros", st.matrix_nnz},
          {"iterations", st.iterations}};
}

nlohmann::json wall_seconds_json(const RunFigures& r) {
  const Timings& t = r.timings;
  return {{"mesh", r.mesh_seconds}, {"setup", r.setup_seconds},
          {"assembly", t.assembly}, {"factorization", t.factorization},
          {"solve", t.solve},       {"material", t.material},
          {"output", t.output},     {"contact", t.contact},
          {"heat", t.heat},         {"total", r.total_seconds}};
}

}  // namespace

nlohmann::json summary_json(const RunFigures& r, const nlohmann::json& final_values,
                            const nlohmann::json& report) {
  nlohmann::json summary;
  summary["peak_memory_bytes"] = r.peak_memory_bytes;
  if (r.peak_memory_bytes_all_ranks)
    summary["peak_memory_bytes_all_ranks"] = *r.peak_memory_bytes_all_ranks;
  summary["hencky"] = HENCKY_VERSION;
  summary["title"] = r.title;
  summary["status"] = r.status == 0 ? "converged" : r.status == 4 ? "interrupted" : "not-converged";
  if (r.restart)
    summary["restart"] = {
        {"from", r.restart->dir}, {"step", r.restart->step}, {"time", r.restart->time}};
  if (r.checkpoints) summary["checkpoints"] = *r.checkpoints;
  if (!r.result.failure.empty()) summary["failure"] = r.result.failure;
  summary["steps"] = r.result.steps;
  summary["iterations"] = r.result.iterations;
  summary["factorizations"] = r.result.factorizations;
  summary["scheme"] = r.scheme;
  summary["formulation"] = r.formulation;
  summary["dofs"] = r.dofs;
  summary["nodes"] = r.nodes;
  summary["elements"] = r.elements;
  summary["integration_points"] = r.integration_points;
  summary["threads"] = r.threads;
  summary["ranks"] = r.ranks;
  const LinearSolverStats& st = r.linear_solver;
  summary["linear_solver"] = linear_solver_json(st);
  if (!r.blas_kernels.empty())
    summary["linear_solver"]["blas_kernels"] = r.blas_kernels;  // OpenBLAS's, after any restart
  if (st.n_factorizations > 0 && r.timings.factorization > 0)
    summary["linear_solver"]["factor_gflops_per_second"] =
        st.factor_flops * st.n_factorizations / r.timings.factorization * 1e-9;
  summary["warnings"] = r.warnings;
  for (const auto& [k, v] : final_values.items()) summary[k] = v;
  summary["wall_seconds"] = wall_seconds_json(r);
  if (r.heat) {
    const LinearSolverStats& hs = r.heat->linear_solver;
    summary["heat"] = {{"steps", r.heat->steps},
                       {"iterations", r.heat->iterations},
                       {"linear_solver",
                        {{"method", hs.description},
                         {"factorizations", hs.n_factorizations},
                         {"solves", hs.n_solves},
                         {"iterations", hs.iterations}}}};
  }
  // The short report a user reads first (issue 22): the largest values and where, the balance
  // of reactions and loads, the contact forces and the time per phase.
  summary["report"] = report;
  return summary;
}

void finish_results(ResultWriter& writer, const RunFigures& figures, Log& log) {
  const nlohmann::json summary = summary_json(figures, writer.final_values(), writer.report());
  for (const std::string& line : writer.report_lines()) log.info("report: {}", line);
  std::string phases;
  for (const char* k : {"mesh", "setup", "assembly", "factorization", "solve", "material",
                        "contact", "heat", "output"})
    if (const double s = summary.at("wall_seconds").at(k).get<double>(); s >= 0.005)
      phases += fmt::format("{}{} {:.2f}", phases.empty() ? "" : ", ", k, s);
  // Every phase under 5 ms: the line says so rather than stand empty.
  log.info("report: time (s): {}", phases.empty() ? "every phase under 0.005" : phases);
  writer.finish(summary);
}

}  // namespace hencky
