// The parts of a distributed mesh (parallel/mesh_part.hpp): every rank's part of a box of
// 10-node tetrahedra, split by METIS into 1, 2 and 3, must put the whole mesh back together:
// each cell in one part with its nodes, each node owned once and a ghost where another rank's
// cells touch it, each ghost findable at its owner, each region and boundary face accounted for.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "fem/reference_element.hpp"
#include "input/gmsh_reader.hpp"
#include "mesh_part_support.hpp"
#include "parallel/mesh_part.hpp"
#include "verify_support.hpp"

using namespace hencky;
using namespace hencky::verify;

namespace {

class MeshParts : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    TempDir dir("mesh_part");
    write_file(dir / "box.geo", box_geo(2, 1, 1, 0.25));
    MeshReadOptions opt;
    opt.order = 2;
    mesh_ = new Mesh(read_gmsh(dir / "box.geo", opt));
  }
  static void TearDownTestSuite() { delete mesh_; }
  static Mesh* mesh_;
};
Mesh* MeshParts::mesh_ = nullptr;

TEST_F(MeshParts, OnePartIsTheWholeMesh) {
  const Mesh& whole = *mesh_;
  const MeshPart p = extract_part(whole, partition_from(whole, split_cells(whole, 1), 1, 0));
  EXPECT_EQ(p.owned_nodes, whole.n_nodes());
  EXPECT_EQ(p.mesh.x, whole.x);
  EXPECT_EQ(p.mesh.cells.conn, whole.cells.conn);
  EXPECT_EQ(p.mesh.faces.conn, whole.faces.conn);
  EXPECT_EQ(p.mesh.cell_region, whole.cell_region);
  ASSERT_EQ(p.mesh.regions.size(), whole.regions.size());
  for (std::size_t r = 0; r < whole.regions.size(); ++r) {
    EXPECT_EQ(p.mesh.regions[r].cells, whole.regions[r].cells) << whole.regions[r].name;
    EXPECT_EQ(p.mesh.regions[r].nodes, whole.regions[r].nodes) << whole.regions[r].name;
  }
}

TEST_F(MeshParts, PartsPutTheWholeMeshBackTogether) {
  const Mesh& whole = *mesh_;
  const int n_nodes = whole.n_nodes(), n_cells = whole.cells.size();
  ASSERT_GT(n_cells, 100);
  std::vector<long long> first_point(n_cells + 1, 0);
  for (int e = 0; e < n_cells; ++e)
    first_point[e + 1] = first_point[e] + reference_table(whole.cells.type[e]).n_points;
  for (int parts : {2, 3}) {
    SCOPED_TRACE(std::to_string(parts) + " parts");
    const std::vector<int> owner = split_cells(whole, parts);
    std::vector<MeshPart> p;
    for (int rank = 0; rank < parts; ++rank)
      p.push_back(extract_part(whole, partition_from(whole, owner, parts, rank)));
    std::vector<int> cell_seen(n_cells, 0), owned_seen(n_nodes, 0),
        face_seen(whole.faces.size(), 0);
    int ghosts = 0;
    for (int rank = 0; rank < parts; ++rank) {
      const MeshPart& q = p[rank];
      const int n_local = q.mesh.n_nodes();
      ASSERT_EQ(static_cast<int>(q.global_node.size()), n_local);
      // The cells: the rank's own, with their nodes, in the whole mesh's order.
      ASSERT_EQ(static_cast<int>(q.global_cell.size()), q.mesh.cells.size());
      EXPECT_TRUE(std::is_sorted(q.global_cell.begin(), q.global_cell.end()));
      for (int c = 0; c < q.mesh.cells.size(); ++c) {
        const int g = q.global_cell[c];
        EXPECT_EQ(owner[g], rank);
        ++cell_seen[g];
        const auto local = q.mesh.cells.nodes(c), global = whole.cells.nodes(g);
        ASSERT_EQ(local.size(), global.size());
        for (std::size_t a = 0; a < local.size(); ++a)
          EXPECT_EQ(q.global_node[local[a]], global[a]);
        EXPECT_EQ(q.mesh.cells.tag[c], whole.cells.tag[g]);
        EXPECT_EQ(q.mesh.cell_region[c], whole.cell_region[g]);
        // Its points start after those of the whole mesh's cells before it.
        EXPECT_EQ(q.global_point.at(c), first_point[g]);
      }
      // The nodes: owned first, then ghosts; each ghost is at its owner where owner_index says.
      for (int n = 0; n < n_local; ++n) {
        const int g = q.global_node[n];
        EXPECT_EQ(q.mesh.x[n], whole.x[g]);
        EXPECT_EQ(q.mesh.node_tag[n], whole.node_tag[g]);
        if (n < q.owned_nodes) {
          EXPECT_EQ(q.node_owner[n], rank);
          EXPECT_EQ(q.owner_index[n], n);
          ++owned_seen[g];
        } else {
          ASSERT_NE(q.node_owner[n], rank);
          const MeshPart& at = p[q.node_owner[n]];
          ASSERT_LT(q.owner_index[n], at.owned_nodes);
          EXPECT_EQ(at.global_node[q.owner_index[n]], g);
          ++ghosts;
        }
      }
      // The faces: the whole mesh's, with their nodes and tags.
      for (int f = 0; f < q.mesh.faces.size(); ++f) {
        const int g = q.global_face[f];
        ++face_seen[g];
        const auto local = q.mesh.faces.nodes(f), global = whole.faces.nodes(g);
        for (std::size_t a = 0; a < local.size(); ++a)
          EXPECT_EQ(q.global_node[local[a]], global[a]);
        EXPECT_EQ(q.mesh.faces.tag[f], whole.faces.tag[g]);
      }
    }
    for (int c = 0; c < n_cells; ++c) ASSERT_EQ(cell_seen[c], 1) << "cell " << c;
    for (int n = 0; n < n_nodes; ++n) ASSERT_EQ(owned_seen[n], 1) << "node " << n;
    EXPECT_GT(ghosts, 0);
    // Every face of the box's regions is on its outer surface: in exactly one part.
    for (int f = 0; f < whole.faces.size(); ++f) ASSERT_EQ(face_seen[f], 1) << "face " << f;
    // Each region: the parts' pieces together are the region, by cells (faces) and nodes.
    for (std::size_t r = 0; r < whole.regions.size(); ++r) {
      const Region& wr = whole.regions[r];
      std::set<int> cells, nodes;
      for (int rank = 0; rank < parts; ++rank) {
        const Region& pr = p[rank].mesh.regions[r];
        ASSERT_EQ(pr.name, wr.name);
        ASSERT_EQ(pr.dim, wr.dim);
        EXPECT_TRUE(std::is_sorted(pr.nodes.begin(), pr.nodes.end()));
        const auto& to_global = wr.dim == 3 ? p[rank].global_cell : p[rank].global_face;
        for (int e : pr.cells) cells.insert(to_global[e]);
        for (int n : pr.nodes) nodes.insert(p[rank].global_node[n]);
      }
      EXPECT_EQ(cells, std::set<int>(wr.cells.begin(), wr.cells.end())) << wr.name;
      EXPECT_EQ(nodes, std::set<int>(wr.nodes.begin(), wr.nodes.end())) << wr.name;
    }
  }
}

TEST_F(MeshParts, APackedPartUnpacksToItself) {
  const Mesh& whole = *mesh_;
  const std::vector<int> owner = split_cells(whole, 3);
  for (int rank = 0; rank < 3; ++rank) {
    const MeshPart p = extract_part(whole, partition_from(whole, owner, 3, rank));
    const std::string bytes = pack(p);
    const MeshPart q = unpack(bytes);
    EXPECT_TRUE(same_part(p, q)) << "rank " << rank;
    // Cut short anywhere, or with a byte too many, it is refused.
    for (std::size_t cut : {std::size_t{0}, std::size_t{7}, bytes.size() / 2, bytes.size() - 1})
      EXPECT_THROW(unpack(std::string_view(bytes).substr(0, cut)), std::invalid_argument) << cut;
    EXPECT_THROW(unpack(bytes + "x"), std::invalid_argument);
  }
  EXPECT_THROW(unpack(std::string(64, 'x')), std::invalid_argument);
}

TEST_F(MeshParts, APartitionOfAnotherMeshIsRefused) {
  Partition p;
  p.cell_owner.assign(3, 0);
  EXPECT_THROW(extract_part(*mesh_, p), std::invalid_argument);
}

}  // namespace
