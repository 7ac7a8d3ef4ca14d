// A rank's model of its part of a distributed mesh (Model(const Case&, MeshPart, Log&) and
// Model::join, issue 21) against the model of the whole mesh. Run with the unit tests on one
// process (one part: the whole), and on 3 MPI ranks by ctest's mpi_node_exchange, where every
// rank reads the same box, takes its part of the same METIS split and builds its model of it.
// What a part cannot know alone comes from join: the counts of the whole, a total force's whole
// area, a probe's one owner, a region's reaction; the loads of the shared nodes are the sums over
// the ranks' faces and cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "input/case_reader.hpp"
#include "input/gmsh_reader.hpp"
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

/// The case `yaml` on the box of box_geo(2, 1, 1, 0.25), read whole on every rank, and this
/// rank's model of its part of the whole mesh's METIS split, joined (its contact points bound
/// together by the ranks).
struct WholeAndPart {
  explicit WholeAndPart(const char* name, const std::string& yaml) : dir(name) {
    par::ensure_petsc();
    write_file(dir / "box.geo", box_geo(2, 1, 1, 0.25));
    write_file(dir / "case.yaml", yaml);
    log.silent = true;
    whole = load_case(dir / "case.yaml", log);
    const Model& w = *whole.model;
    const int ranks = par::size();
    const Partition partition =
        partition_from(w.mesh(), split_cells(w.mesh(), ranks), ranks, par::rank());
    MeshPart p = extract_part(w.mesh(), partition);
    global_node = p.global_node;
    owned = p.owned_nodes;
    part = std::make_unique<Model>(*whole.spec, std::move(p), log);
    part->join(log);
  }
  TempDir dir;
  Log log;
  LoadedCase whole;
  std::vector<int> global_node;  ///< of the part's nodes
  int owned = 0;
  std::unique_ptr<Model> part;
};

}  // namespace

TEST(PartModel, CountsLoadsAndProbesAreTheWholeModels) {
  const WholeAndPart run("part_model", case_yaml);
  const Model& w = *run.whole.model;
  const Model& m = *run.part;
  const std::vector<int>& global_node = run.global_node;
  const int owned = run.owned;
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

// A contact surface on a distributed mesh (Model::bind_contact_of_part): each rank holds every
// point whose node its part holds, also where the node's faces are all on other ranks, with the
// whole model's tributary area, element size, stiffness and quadratic-face terms (a part's own
// faces and cells would give a node on its border a share of them), at its place in the whole
// model's list; each point is owned by one rank.
TEST(PartModel, ContactPointsAreTheWholeModels) {
  const WholeAndPart run("part_model_contact", R"yaml(title: part model, contact
mesh: {file: box.geo, order: 2}
materials:
  - {name: steel, E: 2.0e11, nu: 0.3}
boundary:
  - {region: x0, displacement: {x: 0, y: 0, z: 0}}
contact:
  - name: floor
    nodes: z0
    surface: {plane: {point: [0, 0, -0.001], normal: [0, 0, 1]}}
solver: {steps: 1}
)yaml");
  const Model& w = *run.whole.model;
  const Model& m = *run.part;
  const std::vector<int>& global_node = run.global_node;
  const ContactBody& all = w.contacts().at(0);
  const ContactBody& mine = m.contacts().at(0);
  ASSERT_EQ(mine.whole_points, static_cast<int>(all.points.size()));
  ASSERT_EQ(mine.whole_index.size(), mine.points.size());
  // Every local node of the whole region has its point, and no other node.
  std::vector<char> in_region(w.mesh().n_nodes(), 0);
  for (const ContactPoint& q : all.points) in_region[q.node] = 1;
  std::size_t expected = 0;
  for (int g : global_node) expected += in_region[g];
  EXPECT_EQ(mine.points.size(), expected);
  int owned = 0, quadratic = 0;
  for (std::size_t i = 0; i < mine.points.size(); ++i) {
    const ContactPoint& p = mine.points[i];
    const ContactPoint& q = all.points.at(mine.whole_index[i]);
    EXPECT_EQ(global_node[p.node], q.node);
    // Summed over the copies in another order than the whole mesh's faces and cells.
    EXPECT_NEAR(p.area, q.area, 1e-14 * q.area);
    EXPECT_NEAR(p.size, q.size, 1e-14 * q.size);
    EXPECT_NEAR(p.stiffness, q.stiffness, 1e-13 * q.stiffness);
    EXPECT_NEAR(p.gap0, q.gap0, 1e-14 * q.size);
    ASSERT_EQ(p.terms, q.terms);
    EXPECT_EQ(global_node[p.term_node[0]], q.term_node[0]);
    for (int k = 0; k < p.terms; ++k) EXPECT_EQ(p.term_coef[k], q.term_coef[k]);
    if (p.terms == 3) {  // the edge's corners, in any order
      EXPECT_EQ(std::minmax(global_node[p.term_node[1]], global_node[p.term_node[2]]),
                std::minmax(q.term_node[1], q.term_node[2]));
    }
    owned += m.partition().node_owner[p.node] == par::rank();
    quadratic += p.terms == 3;
  }
  EXPECT_GT(par::sum(static_cast<long long>(quadratic)), 0);  // a rank may hold none of them
  EXPECT_EQ(par::sum(static_cast<long long>(owned)), static_cast<long long>(all.points.size()));
}

// A load on a face inside the body is refused (it must be on the outer surface). On a whole
// mesh the face's two cells show it; on a distributed mesh whose ranks hold one cell each, only
// the ranks together can (Model::join, check_outer_faces): the region "inner" here is faces
// between two cells of different ranks under the split, or between any two cells on one rank.
TEST(PartModel, ALoadInsideTheBodyIsRefusedWhereItsCellsAreOnTwoRanks) {
  par::ensure_petsc();
  TempDir dir("inner_face");
  write_file(dir / "box.geo", box_geo(2, 1, 1, 0.25));
  write_file(dir / "case.yaml", R"yaml(title: inner face
mesh: {file: box.geo}
materials:
  - {name: steel, E: 2.0e11, nu: 0.3}
boundary:
  - {region: x0, displacement: {x: 0, y: 0, z: 0}}
  - {region: inner, pressure: "1e5*t"}
solver: {steps: 1}
)yaml");
  const Case spec = read_case(dir / "case.yaml");
  Mesh mesh = read_gmsh(spec.mesh.file, {});
  const int ranks = par::size();
  const std::vector<int> owner = split_cells(mesh, ranks);
  // The faces of the cells by their sorted corners; an inner face has two cells.
  std::map<std::array<int, 3>, std::vector<int>> cells_at;
  const int faces_of_tet[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  for (int c = 0; c < mesh.cells.size(); ++c) {
    const auto n = mesh.cells.nodes(c);
    for (const auto& f : faces_of_tet) {
      std::array<int, 3> key{n[f[0]], n[f[1]], n[f[2]]};
      std::sort(key.begin(), key.end());
      cells_at[key].push_back(c);
    }
  }
  Region inner;
  inner.name = "inner";
  inner.dim = 2;
  for (const auto& [key, cells] : cells_at)
    if (cells.size() == 2 && (ranks == 1 || owner[cells[0]] != owner[cells[1]])) {
      inner.cells.push_back(mesh.faces.size());
      mesh.faces.add(CellType::tri3, key, 900000 + mesh.faces.size());
      inner.nodes.insert(inner.nodes.end(), key.begin(), key.end());
      if (inner.cells.size() == 5) break;
    }
  ASSERT_EQ(inner.cells.size(), 5u);
  std::sort(inner.nodes.begin(), inner.nodes.end());
  inner.nodes.erase(std::unique(inner.nodes.begin(), inner.nodes.end()), inner.nodes.end());
  mesh.regions.push_back(inner);
  Log log;
  log.silent = true;
  const std::string refused =
      "is inside the body (between two elements); a pressure must be "
      "applied on the outer surface of the body";
  std::string key;  // where the whole mesh's message points
  try {
    Model whole(spec, Mesh(mesh), log);
    ADD_FAILURE() << "the whole mesh's model took a load inside the body";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find(refused), std::string::npos) << e.what();
    key = e.where().key;
  }
  if (ranks == 1) return;
  // Each rank's part holds a face with one of its cells: only join can tell.
  Model part(spec, extract_part(mesh, partition_from(mesh, owner, ranks, par::rank())), log);
  try {
    part.join(log);
    ADD_FAILURE() << "the parts took a load inside the body";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find(refused), std::string::npos) << e.what();
    EXPECT_EQ(e.where().key, key) << e.what();
  }
}
