// CalculiX result file (.frd) writer: the node orders against the deck reader's tables and the
// geometry of the cells, and the text of a file with a 20-node hexahedron and a 10-node
// tetrahedron, two steps of DISP and STRESS, column by column as ccx 2.20 writes its own.
//
// Set HENCKY_FRD_TEST_OUTDIR=dir to keep the written files (dir/two_cells.frd, dir/long.frd) for
// a look with CalculiX GraphiX (Debian's calculix-cgx): cgx -v dir/two_cells.frd, or without a
// display in its batch mode, cgx -bg check.fbd, with check.fbd holding e.g. "read
// two_cells.frd", "prnt e 7", "ds 2 e 6", "prnt n 797", "volu all" and "quit" (the volume is
// 1.25: a cell in a wrong node order changes it).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "input/inp_elements.hpp"
#include "output/frd_writer.hpp"

// A namespace of its own: the unity build compiles this file in one unit with others that
// have helpers of the same names (gmsh_edges) in their anonymous namespaces.
namespace hencky::frd_test {
namespace {

namespace fs = std::filesystem;

constexpr std::array<CellType, 5> volume_types{CellType::tet4, CellType::tet10, CellType::hex8,
                                               CellType::hex20, CellType::wedge6};

// ---- node orders ----------------------------------------------------------------------------

/// The deck's node (from 0) that ccx writes at position j of a cell's .frd record: ccx's frd.c
/// writes the 20-node hexahedron's nodes 1-12, 17-20, 13-16 and every other cell as in the deck.
int deck_node_at_frd(CellType t, int j) {
  if (t != CellType::hex20 || j < 12) return j;
  return j < 16 ? j + 4 : j - 4;
}

// The writer's own tables are the deck reader's (input/inp_elements.hpp) inverted, composed with
// ccx's hexahedron reordering.
TEST(FrdOrder, AgreesWithTheDeckReader) {
  for (CellType t : volume_types) {
    const auto frd = frd_from_gmsh(t);
    const auto gmsh_from_deck = inp::gmsh_from_abaqus(t);
    ASSERT_EQ(static_cast<int>(frd.size()), cell_n_nodes(t)) << cell_name(t);
    for (int j = 0; j < cell_n_nodes(t); ++j)
      EXPECT_EQ(gmsh_from_deck[frd[j]], deck_node_at_frd(t, j)) << cell_name(t) << " node " << j;
  }
  EXPECT_TRUE(frd_from_gmsh(CellType::tri6).empty());
}

TEST(FrdOrder, ElementTypes) {
  EXPECT_EQ(frd_element_type(CellType::hex8), 1);
  EXPECT_EQ(frd_element_type(CellType::wedge6), 2);
  EXPECT_EQ(frd_element_type(CellType::tet4), 3);
  EXPECT_EQ(frd_element_type(CellType::hex20), 4);
  EXPECT_EQ(frd_element_type(CellType::tet10), 6);
  EXPECT_EQ(frd_element_type(CellType::quad8), 0);
}

// ---- a mesh by hand ---------------------------------------------------------------------------

/// Gmsh's edges of the quadratic cells (node cell_n_corners + k sits on edge k).
std::vector<std::array<int, 2>> gmsh_edges(CellType t) {
  if (t == CellType::tet10) return {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
  return {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5}, {2, 3},
          {2, 6}, {3, 7}, {4, 5}, {4, 7}, {5, 6}, {6, 7}};
}

/// ccx's order of a cell's mid-edge nodes in its .frd record, as the corners they join (from 0).
std::vector<std::array<int, 2>> ccx_edges(CellType t) {
  if (t == CellType::tet10) return {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  return {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 4}, {1, 5},
          {2, 6}, {3, 7}, {4, 5}, {5, 6}, {6, 7}, {7, 4}};
}

/// Adds a cell with its own nodes: the corners at `corners`, the mid-edge nodes at the middles
/// of Gmsh's edges. Node labels are 1000 - 7 * index (descending in the mesh's order, so that
/// the writer has to sort them), the cell label `tag`.
void add_cell(Mesh& m, CellType t, const std::vector<Vec3>& corners, long tag, int region) {
  std::vector<int> nodes;
  auto add_node = [&](const Vec3& x) {
    nodes.push_back(m.n_nodes());
    m.node_tag.push_back(1000 - 7 * m.n_nodes());
    m.x.push_back(x);
  };
  for (const Vec3& c : corners) add_node(c);
  for (const auto& [a, b] : gmsh_edges(t)) add_node(0.5 * (corners[a] + corners[b]));
  m.cells.add(t, nodes, tag);
  m.cell_region.push_back(region);
}

Mesh two_cells() {
  Mesh m;
  m.regions.push_back({"FIX", 0, {}, {}});  // not a volume: not numbered
  m.regions.push_back({"Steel", 3, {}, {}});
  m.regions.push_back({"Aluminium", 3, {}, {}});
  add_cell(m, CellType::hex20,
           {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
           7, 2);
  add_cell(m, CellType::tet10, {{2, 0, 0}, {3, 0, 0}, {2, 1, 0}, {2, 0, 1.5}}, 3, 1);
  return m;
}

// ---- reading the file back --------------------------------------------------------------------

std::vector<std::string> read_lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// The index of the first line at or after `from` that starts with `prefix` (lines.size() if
/// none).
std::size_t find_line(const std::vector<std::string>& lines, const std::string& prefix,
                      std::size_t from = 0) {
  for (std::size_t i = from; i < lines.size(); ++i)
    if (lines[i].rfind(prefix, 0) == 0) return i;
  return lines.size();
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%12.5E", static_cast<double>(static_cast<float>(v)));
  return buf;
}

std::string label10(long v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%10ld", v);
  return buf;
}

class TempFile {
 public:
  explicit TempFile(const std::string& name) {
    if (const char* keep = std::getenv("HENCKY_FRD_TEST_OUTDIR")) {
      fs::create_directories(keep);
      path_ = fs::path(keep) / name;
      keep_ = true;
    } else {
      path_ = fs::temp_directory_path() / ("hencky-frd-" + std::to_string(::getpid()) + name);
    }
  }
  ~TempFile() {
    std::error_code ec;
    if (!keep_) fs::remove(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
  bool keep_ = false;
};

/// The DISP and STRESS of a step: values from the node's coordinates, so that each node's line
/// can be told from the others'.
std::vector<FrdField> fields_of(const Mesh& m, double scale) {
  FrdField disp{"DISP", {"D1", "D2", "D3"}, {}};
  FrdField stress{"STRESS", {"SXX", "SYY", "SZZ", "SXY", "SYZ", "SZX"}, {}};
  for (const Vec3& x : m.x) {
    for (int d = 0; d < 3; ++d) disp.values.push_back(scale * (d + 1) * 1e-3 * x[d]);
    for (int k = 0; k < 6; ++k) stress.values.push_back(scale * (100.0 * k - 250.0 * x[k % 3]));
  }
  return {disp, stress};
}

TEST(FrdWriter, TwoCellsTwoSteps) {
  const Mesh m = two_cells();
  TempFile file("two_cells.frd");
  {
    FrdWriter w(file.path(), m);
    w.step(1, 1.0, fields_of(m, 1.0));
    w.step(2, 0.5, fields_of(m, -2.0));
    w.close();
  }
  const auto lines = read_lines(file.path());
  ASSERT_GT(lines.size(), 10u);

  // Header: the model header, the user header with the date (whose text changes), the regions.
  EXPECT_EQ(lines[0], "    1C");
  EXPECT_EQ(lines[1], "    1UUSER" + std::string(62, ' '));
  EXPECT_EQ(lines[2].substr(0, 24), "    1UDATE              ");
  EXPECT_EQ(lines[5], "    1UPGM               hencky" + std::string(42, ' '));
  const std::size_t mat = find_line(lines, "    1UMAT");
  ASSERT_LT(mat + 1, lines.size());
  EXPECT_EQ(lines[mat], "    1UMAT    1Steel" + std::string(53, ' '));
  EXPECT_EQ(lines[mat + 1], "    1UMAT    2Aluminium" + std::string(49, ' '));

  // Nodes: in ascending order of their labels, long format.
  const std::size_t nodes = find_line(lines, "    2C");
  ASSERT_LT(nodes, lines.size());
  EXPECT_EQ(lines[nodes],
            "    2C                            30                                     1");
  std::vector<int> by_label(m.n_nodes());
  for (int i = 0; i < m.n_nodes(); ++i) by_label[m.n_nodes() - 1 - i] = i;  // labels descend
  for (int k = 0; k < m.n_nodes(); ++k) {
    const int i = by_label[k];
    EXPECT_EQ(lines[nodes + 1 + k], " -1" + label10(m.node_tag[i]) + number(m.x[i][0]) +
                                        number(m.x[i][1]) + number(m.x[i][2]));
  }
  EXPECT_EQ(lines[nodes + 1 + m.n_nodes()], " -3");
  EXPECT_EQ(lines[nodes + 1], " -1       797 2.50000E+00 0.00000E+00 7.50000E-01");

  // Elements: ascending labels (the tetrahedron, 3, first), ccx's type, group 0, the region's
  // number; nodes in ccx's order, checked by where they are: corners, then mid-edge nodes on
  // ccx's edges.
  const std::size_t elements = find_line(lines, "    3C");
  ASSERT_LT(elements + 6, lines.size());
  EXPECT_EQ(lines[elements],
            "    3C                             2                                     1");
  auto label_at = [&](const Vec3& x) {
    for (int i = 0; i < m.n_nodes(); ++i)
      if ((m.x[i] - x).norm() < 1e-12) return m.node_tag[i];
    return -1L;
  };
  auto expected_nodes = [&](int cell) {
    const auto nodes = m.cells.nodes(cell);
    const CellType t = m.cells.type[cell];
    std::vector<Vec3> corners;
    for (int j = 0; j < cell_n_corners(t); ++j) corners.push_back(m.x[nodes[j]]);
    std::vector<long> labels;
    for (const Vec3& c : corners) labels.push_back(label_at(c));
    for (const auto& [a, b] : ccx_edges(t))
      labels.push_back(label_at(0.5 * (corners[a] + corners[b])));
    return labels;
  };
  auto record = [&](const std::vector<long>& labels, std::size_t from, std::size_t to) {
    std::string s = " -2";
    for (std::size_t j = from; j < to; ++j) s += label10(labels[j]);
    return s;
  };
  const auto tet = expected_nodes(1), hex = expected_nodes(0);
  EXPECT_EQ(lines[elements + 1], " -1         3    6    0    1");
  EXPECT_EQ(lines[elements + 2], record(tet, 0, 10));
  EXPECT_EQ(lines[elements + 3], " -1         7    4    0    2");
  EXPECT_EQ(lines[elements + 4], record(hex, 0, 10));
  EXPECT_EQ(lines[elements + 5], record(hex, 10, 20));
  EXPECT_EQ(lines[elements + 6], " -3");
  // The same spelled out: the hexahedron's nodes are 1000 - 7 * (Gmsh's index).
  EXPECT_EQ(lines[elements + 4],
            " -2      1000       993       986       979       972       965"
            "       958       951       944       923");
  EXPECT_EQ(lines[elements + 5],
            " -2       909       937       930       916       902       895"
            "       888       874       867       881");

  // Step 1, DISP: the parameter record, the set header, the entities, the values.
  std::size_t at = find_line(lines, "    1PSTEP", elements);
  ASSERT_LT(at + 8 + m.n_nodes(), lines.size());
  EXPECT_EQ(lines[at], "    1PSTEP                         1           1           1          ");
  EXPECT_EQ(lines[at + 1],
            "  100CL  101 1.000000000          30                     0    1           1");
  EXPECT_EQ(lines[at + 2], " -4  DISP        4    1");
  EXPECT_EQ(lines[at + 3], " -5  D1          1    2    1    0");
  EXPECT_EQ(lines[at + 4], " -5  D2          1    2    2    0");
  EXPECT_EQ(lines[at + 5], " -5  D3          1    2    3    0");
  EXPECT_EQ(lines[at + 6], " -5  ALL         1    2    0    0    1ALL");
  const auto step1 = fields_of(m, 1.0);
  for (int k = 0; k < m.n_nodes(); ++k) {
    const int i = by_label[k];
    std::string expected = " -1" + label10(m.node_tag[i]);
    for (int d = 0; d < 3; ++d) expected += number(step1[0].values[3 * i + d]);
    EXPECT_EQ(lines[at + 7 + k], expected);
  }
  EXPECT_EQ(lines[at + 7], " -1       797 2.50000E-03 0.00000E+00 2.25000E-03");
  EXPECT_EQ(lines[at + 7 + m.n_nodes()], " -3");

  // Step 1, STRESS: a symmetric tensor with ccx's rows and columns.
  at = find_line(lines, "    1PSTEP", at + 1);
  ASSERT_LT(at + 10 + m.n_nodes(), lines.size());
  EXPECT_EQ(lines[at], "    1PSTEP                         2           1           1          ");
  EXPECT_EQ(lines[at + 1],
            "  100CL  101 1.000000000          30                     0    1           1");
  EXPECT_EQ(lines[at + 2], " -4  STRESS      6    1");
  EXPECT_EQ(lines[at + 3], " -5  SXX         1    4    1    1");
  EXPECT_EQ(lines[at + 4], " -5  SYY         1    4    2    2");
  EXPECT_EQ(lines[at + 5], " -5  SZZ         1    4    3    3");
  EXPECT_EQ(lines[at + 6], " -5  SXY         1    4    1    2");
  EXPECT_EQ(lines[at + 7], " -5  SYZ         1    4    2    3");
  EXPECT_EQ(lines[at + 8], " -5  SZX         1    4    3    1");
  for (int k = 0; k < m.n_nodes(); ++k) {
    const int i = by_label[k];
    std::string expected = " -1" + label10(m.node_tag[i]);
    for (int c = 0; c < 6; ++c) expected += number(step1[1].values[6 * i + c]);
    EXPECT_EQ(lines[at + 9 + k], expected);
  }
  EXPECT_EQ(lines[at + 9],
            " -1       797-6.25000E+02 1.00000E+02 1.25000E+01-3.25000E+02 4.00000E+02"
            " 3.12500E+02");
  EXPECT_EQ(lines[at + 9 + m.n_nodes()], " -3");

  // Step 2: set 102, the time below 1 in E notation, the step as the increment.
  at = find_line(lines, "    1PSTEP", at + 1);
  ASSERT_LT(at + 2, lines.size());
  EXPECT_EQ(lines[at], "    1PSTEP                         3           2           1          ");
  EXPECT_EQ(lines[at + 1],
            "  100CL  102 5.00000E-01          30                     0    2           1");
  at = find_line(lines, "    1PSTEP", at + 1);
  ASSERT_LT(at + 1, lines.size());
  EXPECT_EQ(lines[at], "    1PSTEP                         4           2           1          ");
  EXPECT_EQ(find_line(lines, "    1PSTEP", at + 1), lines.size());

  EXPECT_EQ(lines.back(), " 9999");
  EXPECT_EQ(std::count(lines.begin(), lines.end(), " 9999"), 1);
}

// More than six components: a node's values go on " -2" records, six to a record.
// With the cells' materials given (a deck's, as ccx numbers them), the header lists them and
// each element record carries its material's number, not its volume region's.
TEST(FrdWriter, MaterialsAsGiven) {
  const Mesh m = two_cells();
  TempFile file("materials.frd");
  {
    FrdWriter w(file.path(), m, FrdWriter::Materials{{2, 1}, {"EL", "HY"}});
    w.close();
  }
  const auto lines = read_lines(file.path());
  EXPECT_NE(find_line(lines, "    1UMAT    1EL"), lines.size());
  EXPECT_NE(find_line(lines, "    1UMAT    2HY"), lines.size());
  EXPECT_EQ(find_line(lines, "    1UMAT    1Steel"), lines.size());
  // Cell 7 (the hexahedron, he20 = 4) has material 2, cell 3 (te10 = 6) material 1.
  EXPECT_NE(find_line(lines, " -1" + label10(7) + "    4    0    2"), lines.size());
  EXPECT_NE(find_line(lines, " -1" + label10(3) + "    6    0    1"), lines.size());
}

TEST(FrdWriter, LongFieldsAndScalars) {
  Mesh m;
  add_cell(m, CellType::hex20,
           {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
           1, -1);
  FrdField pe{"PE", {"PE"}, std::vector<double>(m.n_nodes(), 0.25)};
  FrdField many{"MANY", {"A1", "A2", "A3", "A4", "A5", "A6", "A7", "A8"}, {}};
  for (int i = 0; i < m.n_nodes(); ++i)
    for (int k = 0; k < 8; ++k) many.values.push_back(k + 1);
  TempFile file("long.frd");
  {
    FrdWriter w(file.path(), m);
    w.step(4, 12345.678, {pe, many});
  }  // closed by the destructor
  const auto lines = read_lines(file.path());
  EXPECT_EQ(find_line(lines, "    1UMAT"), lines.size());  // no regions
  const std::size_t elements = find_line(lines, "    3C");
  ASSERT_LT(elements + 1, lines.size());
  EXPECT_EQ(lines[elements + 1], " -1         1    4    0    0");
  std::size_t at = find_line(lines, "  100CL");
  ASSERT_LT(at + 4, lines.size());
  EXPECT_EQ(lines[at],
            "  100CL  101 12345.67800          20                     0    1           1");
  EXPECT_EQ(lines[at + 1], " -4  PE          1    1");
  EXPECT_EQ(lines[at + 2], " -5  PE          1    1    0    0");
  EXPECT_EQ(lines[at + 3], " -1       867 2.50000E-01");
  at = find_line(lines, " -4  MANY");
  ASSERT_LT(at + 11, lines.size());
  EXPECT_EQ(lines[at], " -4  MANY        8    1");
  EXPECT_EQ(lines[at + 1], " -5  A1          1    1    0    0");
  EXPECT_EQ(
      lines[at + 9],
      " -1       867 1.00000E+00 2.00000E+00 3.00000E+00 4.00000E+00 5.00000E+00 6.00000E+00");
  EXPECT_EQ(lines[at + 10], " -2           7.00000E+00 8.00000E+00");
  EXPECT_EQ(lines.back(), " 9999");
}

TEST(FrdWriter, Errors) {
  const Mesh m = two_cells();
  EXPECT_THROW(FrdWriter(fs::path("/nonexistent-dir/x.frd"), m), InputError);
  TempFile file("errors.frd");
  FrdWriter w(file.path(), m);
  EXPECT_THROW(w.step(1, 0.0, {FrdField{"DISP", {"D1", "D2", "D3"}, {1.0, 2.0}}}),
               std::invalid_argument);
  EXPECT_THROW(w.step(1, 0.0, {FrdField{"TOOLONGNAME", {"A"}, std::vector<double>(30)}}),
               std::invalid_argument);
  EXPECT_THROW(w.step(0, 0.0, {}), std::invalid_argument);
  Mesh twice = two_cells();
  twice.node_tag[3] = twice.node_tag[4];
  EXPECT_THROW(FrdWriter(file.path(), twice), std::invalid_argument);
}

}  // namespace
}  // namespace hencky::frd_test
