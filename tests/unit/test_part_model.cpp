// A rank's model of its part of a distributed mesh (Model(const Case&, MeshPart, Log&) and
// Model::join, issue 21) against the model of the whole mesh. Run with the unit tests on one
// process (one part: the whole), and on 3 MPI ranks by ctest's mpi_node_exchange, where every
// rank reads the same box, takes its part of the same METIS split and builds its model of it.
// What a part cannot know alone comes from join: the counts of the whole, a total force's whole
// area, a probe's one owner, a region's reaction; the loads of the shared nodes are the sums over
// the ranks' faces and cells.
#include <gtest/gtest.h>

#include <cmath>

#include "input/load_case.hpp"
#include "parallel/mpi.hpp"
#include "verify_support.hpp"

using namespace hencky;
using namespace hencky::verify;

namespace {

const char* const case_yaml = R"yaml(title: part model
mesh: {file: box.geo, order: 2}
materials:
  - {name: steel, E: 2.0e11, nu: 0.3, alpha: 1.2e-5}
boundary:
  - {region: x0, displacement: {x: 0, y: 0, z: 0}}
  - {region: p100, displacement: {z: 0}}
  - {region: x1, force: [0, 0, "-1000*t*(1 + y)"]}
  - {region: z1, pressure: "1e5*t*(1 + x)"}
  - {region: y1, traction: ["2e4*t", 0, "3e4*x"]}
body_force: [0, "-9.81*7850", "100*z"]
solver: {steps: 1}
output:
  probes:
    - {name: middle, point: [1.0, 0.5, 0.5]}
    - {name: corner, point: [2.0, 1.0, 1.0]}
  reactions: [x0, p100]
)yaml";

}  // namespace

TEST(PartModel, CountsLoadsAndProbesAreTheWholeModels) {
  par::ensure_petsc();
  TempDir dir("part_model");
  write_file(dir / "box.geo", box_geo(2, 1, 1, 0.25));
  write_file(dir / "case.yaml", case_yaml);
  Log log;
  log.silent = true;
  const LoadedCase whole = load_case(dir / "case.yaml", log);
  const Model& w = *whole.model;
  const int ranks = par::size();
  const Partition partition =
      partition_from(w.mesh(), split_cells(w.mesh(), ranks), ranks, par::rank());
  MeshPart part = extract_part(w.mesh(), partition);
  const std::vector<int> global_node = part.global_node;
  const int owned = part.owned_nodes;
  Model m(*whole.spec, std::move(part), log);
  m.join();
  ASSERT_NE(m.part(), nullptr);
  EXPECT_EQ(m.global_nodes(), w.mesh().n_nodes());
  EXPECT_EQ(m.global_cells(), w.mesh().cells.size());
  EXPECT_EQ(m.global_free(), w.dofs().n_free);
  EXPECT_EQ(m.total_points(), w.total_points());

  // Every local node, its own and its ghosts, holds the whole model's loads at that node.
  std::vector<double> fw, fp;
  w.external_forces(1.0, fw);
  m.external_forces(1.0, fp);
  ASSERT_EQ(fp.size(), 3 * global_node.size());
  double scale = 0, total_part = 0, total_whole = 0;
  for (double f : fw) scale = std::max(scale, std::abs(f));
  ASSERT_GT(scale, 0);
  for (std::size_t n = 0; n < global_node.size(); ++n)
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(fp[3 * n + d], fw[3 * global_node[n] + d], 1e-12 * scale)
          << "rank " << par::rank() << ", node " << m.mesh().node_tag[n];
  // Counted once, by the owners, they add up to the whole's total.
  for (int n = 0; n < owned; ++n) total_part += fp[3 * n + 2];
  for (std::size_t i = 2; i < fw.size(); i += 3) total_whole += fw[i];
  EXPECT_NEAR(m.layout().total(total_part), total_whole, 1e-12 * scale * fw.size());

  // One rank owns each probe, and it is in that rank's part.
  ASSERT_EQ(m.probes().size(), w.probes().size());
  for (std::size_t k = 0; k < m.probes().size(); ++k)
    EXPECT_EQ(par::sum(static_cast<long long>(m.probes()[k].cell >= 0)), 1) << "probe " << k;
  // A region carries a reaction on every rank when it does on the whole mesh.
  ASSERT_EQ(m.reaction_regions().size(), w.reaction_regions().size());
  for (std::size_t k = 0; k < m.reaction_regions().size(); ++k)
    EXPECT_EQ(m.reaction_regions()[k].force, w.reaction_regions()[k].force);
}
