// VTU/PVD writer: Gmsh -> VTK node permutations checked against VTK's own cell definitions
// (faces and edges as vtkCell::GetFace/GetEdge give them in ParaView 5.11 / VTK 9.2), and a
// round trip of the written files through a small reader of the raw appended format.
//
// Set HENCKY_VTU_TEST_OUTDIR=dir to keep the written files (one per cell type, a mixed file
// and a .pvd) for a check with ParaView: pvpython scripts/check_vtu.py dir/cell_wedge6.vtu ...
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "output/vtu_writer.hpp"

namespace hencky {
namespace {

constexpr std::array<CellType, 9> all_types{CellType::tet4,   CellType::tet10, CellType::hex8,
                                            CellType::hex20,  CellType::wedge6, CellType::tri3,
                                            CellType::tri6,   CellType::quad4, CellType::quad8};

std::string short_name(CellType t) {
  switch (t) {
    case CellType::tet4: return "tet4";
    case CellType::tet10: return "tet10";
    case CellType::hex8: return "hex8";
    case CellType::hex20: return "hex20";
    case CellType::wedge6: return "wedge6";
    case CellType::tri3: return "tri3";
    case CellType::tri6: return "tri6";
    case CellType::quad4: return "quad4";
    case CellType::quad8: return "quad8";
  }
  return "?";
}

// ---- Gmsh reference elements -------------------------------------------------------------

/// Edges carrying the mid-edge nodes of the quadratic cells, in Gmsh order
/// (node cell_n_corners + k sits on edge k).
std::vector<std::array<int, 2>> gmsh_edges(CellType t) {
  switch (t) {
    case CellType::tet10: return {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
    case CellType::hex20:
      return {{0, 1}, {0, 3}, {0, 4}, {1, 2}, {1, 5}, {2, 3},
              {2, 6}, {3, 7}, {4, 5}, {4, 7}, {5, 6}, {6, 7}};
    case CellType::tri6: return {{0, 1}, {1, 2}, {2, 0}};
    case CellType::quad8: return {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
    default: return {};
  }
}

/// Gmsh reference nodes: tet unit simplex, hex [-1,1]^3, wedge unit triangle x [-1,1],
/// triangle unit, quad [-1,1]^2; mid-edge nodes at the edge midpoints.
std::vector<Vec3> gmsh_reference_nodes(CellType t) {
  std::vector<Vec3> x;
  switch (cell_linear(t)) {
    case CellType::tet4: x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; break;
    case CellType::hex8:
      x = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
           {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
      break;
    case CellType::wedge6:
      x = {{0, 0, -1}, {1, 0, -1}, {0, 1, -1}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
      break;
    case CellType::tri3: x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}; break;
    case CellType::quad4: x = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}; break;
    default: ADD_FAILURE() << "no reference element";
  }
  for (const auto& e : gmsh_edges(t)) x.push_back(0.5 * (x[e[0]] + x[e[1]]));
  EXPECT_EQ(static_cast<int>(x.size()), cell_n_nodes(t));
  return x;
}

/// Reference measure: volume of the 3D reference cells, area of the 2D ones.
double reference_measure(CellType t) {
  switch (cell_linear(t)) {
    case CellType::tet4: return 1.0 / 6.0;
    case CellType::hex8: return 8.0;
    case CellType::wedge6: return 1.0;
    case CellType::tri3: return 0.5;
    case CellType::quad4: return 4.0;
    default: return 0;
  }
}

/// A distortion with positive determinant.
Mat3 affine_matrix() {
  Mat3 a;
  a << 1.2, 0.3, 0.1,  //
      -0.2, 0.9, 0.25,  //
      0.15, -0.1, 1.1;
  return a;
}
const Vec3 affine_shift{0.5, -0.25, 2.0};

std::vector<Vec3> mapped_nodes(CellType t) {
  std::vector<Vec3> x = gmsh_reference_nodes(t);
  const Mat3 a = affine_matrix();
  for (auto& p : x) p = a * p + affine_shift;
  return x;
}

// ---- VTK's cell definitions (from vtkCell::GetFace / GetEdge, ParaView 5.11) ----------

/// Faces (corner nodes only) of the linear 3D VTK cells; VTK lists them with the right-hand
/// normal pointing out of the cell.
std::vector<std::vector<int>> vtk_faces(CellType t) {
  switch (cell_linear(t)) {
    case CellType::tet4: return {{0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 2, 1}};
    case CellType::hex8:
      return {{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}};
    case CellType::wedge6: return {{0, 1, 2}, {3, 5, 4}, {0, 3, 4, 1}, {1, 4, 5, 2}, {2, 5, 3, 0}};
    default: return {};
  }
}

/// Edges of the quadratic VTK cells as {end, end, mid-edge node}.
std::vector<std::array<int, 3>> vtk_quadratic_edges(CellType t) {
  switch (t) {
    case CellType::tet10: return {{0, 1, 4}, {1, 2, 5}, {2, 0, 6}, {0, 3, 7}, {1, 3, 8}, {2, 3, 9}};
    case CellType::hex20:
      return {{0, 1, 8},  {1, 2, 9},  {3, 2, 10}, {0, 3, 11}, {4, 5, 12}, {5, 6, 13},
              {7, 6, 14}, {4, 7, 15}, {0, 4, 16}, {1, 5, 17}, {3, 7, 19}, {2, 6, 18}};
    case CellType::tri6: return {{0, 1, 3}, {1, 2, 4}, {2, 0, 5}};
    case CellType::quad8: return {{0, 1, 4}, {1, 2, 5}, {2, 3, 6}, {3, 0, 7}};
    default: return {};
  }
}

std::vector<Vec3> to_vtk_order(CellType t, const std::vector<Vec3>& gmsh) {
  const auto perm = gmsh_to_vtk_permutation(t);
  std::vector<Vec3> v;
  for (int p : perm) v.push_back(gmsh[p]);
  return v;
}

Vec3 polygon_normal(const std::vector<Vec3>& x, const std::vector<int>& f) {
  Vec3 n = Vec3::Zero();  // Newell's method
  for (std::size_t i = 0; i < f.size(); ++i) n += x[f[i]].cross(x[f[(i + 1) % f.size()]]);
  return n;
}

Vec3 centroid(const std::vector<Vec3>& x, const std::vector<int>& ids) {
  Vec3 c = Vec3::Zero();
  for (int i : ids) c += x[i];
  return c / static_cast<double>(ids.size());
}

// ---- A reader of what write_vtu writes ---------------------------------------------------

struct ArrayRead {
  std::string type;
  int n_components = 1;
  std::vector<char> bytes;
  template <class T>
  std::vector<T> as() const {
    std::vector<T> v(bytes.size() / sizeof(T));
    std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
    return v;
  }
};

struct VtuRead {
  std::size_t n_points = 0, n_cells = 0;
  std::map<std::string, ArrayRead> arrays;  ///< key: "Section/Name"
};

std::string read_all(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const auto b = tag.find(key);
  if (b == std::string::npos) return {};
  const auto e = tag.find('"', b + key.size());
  return tag.substr(b + key.size(), e - b - key.size());
}

VtuRead read_vtu(const std::filesystem::path& path) {
  VtuRead r;
  const std::string s = read_all(path);
  const auto appended = s.find("<AppendedData encoding=\"raw\">");
  if (appended == std::string::npos) {
    ADD_FAILURE() << "no raw AppendedData in " << path;
    return r;
  }
  const auto base = s.find('_', appended) + 1;
  const std::string header = s.substr(0, appended);
  EXPECT_NE(header.find("type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_NE(header.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(header.find("byte_order=\"LittleEndian\""), std::string::npos);
  EXPECT_EQ(s.substr(s.size() - 30), "\n  </AppendedData>\n</VTKFile>\n");

  std::string section;
  std::size_t pos = 0;
  while ((pos = header.find('<', pos)) != std::string::npos) {
    const auto end = header.find('>', pos);
    const std::string tag = header.substr(pos, end - pos + 1);
    pos = end;
    for (const char* sec : {"PointData", "CellData", "Points", "Cells"}) {
      if (tag.rfind(std::string("<") + sec, 0) == 0 &&
          (tag[std::strlen(sec) + 1] == '>' || tag[std::strlen(sec) + 1] == ' '))
        section = sec;
      if (tag == std::string("</") + sec + ">") section.clear();
    }
    if (tag.rfind("<Piece ", 0) == 0) {
      r.n_points = std::stoul(attribute(tag, "NumberOfPoints"));
      r.n_cells = std::stoul(attribute(tag, "NumberOfCells"));
    }
    if (tag.rfind("<DataArray ", 0) == 0) {
      EXPECT_FALSE(section.empty()) << tag;
      EXPECT_EQ(attribute(tag, "format"), "appended") << tag;
      ArrayRead a;
      a.type = attribute(tag, "type");
      const std::string nc = attribute(tag, "NumberOfComponents");
      a.n_components = nc.empty() ? 1 : std::stoi(nc);
      const std::size_t off = base + std::stoull(attribute(tag, "offset"));
      std::uint64_t n_bytes = 0;
      EXPECT_LE(off + sizeof n_bytes, s.size());
      std::memcpy(&n_bytes, s.data() + off, sizeof n_bytes);
      EXPECT_LE(off + sizeof n_bytes + n_bytes, s.size());
      a.bytes.assign(s.data() + off + sizeof n_bytes, s.data() + off + sizeof n_bytes + n_bytes);
      r.arrays[section + "/" + attribute(tag, "Name")] = std::move(a);
    }
  }
  return r;
}

// ---- Fixture: an output directory ----------------------------------------------------------

class VtuWriter : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const char* keep = std::getenv("HENCKY_VTU_TEST_OUTDIR"); keep && *keep) {
      dir_ = keep;
      keep_ = true;
    } else {
      dir_ = std::filesystem::temp_directory_path() /
             ("hencky_vtu_test_" + std::to_string(::getpid()) + "_" +
              ::testing::UnitTest::GetInstance()->current_test_info()->name());
    }
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    if (!keep_) std::filesystem::remove_all(dir_);
  }
  std::filesystem::path dir_;
  bool keep_ = false;
};

/// One cell of type t, nodes 0..n-1 in Gmsh order at the distorted reference positions.
void single_cell(CellType t, std::vector<Vec3>& x, CellSet& cells) {
  x = mapped_nodes(t);
  std::vector<int> nodes(x.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i] = static_cast<int>(i);
  cells = CellSet{};
  cells.add(t, nodes, 1);
}

// ---- Tests -----------------------------------------------------------------------------------

TEST(VtuPermutation, IsAPermutationOfTheCellsNodes) {
  for (CellType t : all_types) {
    const auto perm = gmsh_to_vtk_permutation(t);
    ASSERT_EQ(static_cast<int>(perm.size()), cell_n_nodes(t)) << cell_name(t);
    std::vector<int> seen(perm.size(), 0);
    for (int p : perm) {
      ASSERT_GE(p, 0);
      ASSERT_LT(p, static_cast<int>(perm.size()));
      ++seen[p];
    }
    for (int s : seen) EXPECT_EQ(s, 1) << cell_name(t);
    // Corners stay corners (the quadratic cells' corners are the linear cell's).
    for (int i = 0; i < cell_n_corners(t); ++i) EXPECT_LT(perm[i], cell_n_corners(t));
    if (t != cell_linear(t)) {
      const auto lin = gmsh_to_vtk_permutation(cell_linear(t));
      for (int i = 0; i < cell_n_corners(t); ++i) EXPECT_EQ(perm[i], lin[i]) << cell_name(t);
    }
  }
}

TEST(VtuPermutation, VtkCellTypeNumbers) {
  EXPECT_EQ(vtk_cell_type(CellType::tet4), 10);
  EXPECT_EQ(vtk_cell_type(CellType::tet10), 24);
  EXPECT_EQ(vtk_cell_type(CellType::hex8), 12);
  EXPECT_EQ(vtk_cell_type(CellType::hex20), 25);
  EXPECT_EQ(vtk_cell_type(CellType::wedge6), 13);
  EXPECT_EQ(vtk_cell_type(CellType::tri3), 5);
  EXPECT_EQ(vtk_cell_type(CellType::tri6), 22);
  EXPECT_EQ(vtk_cell_type(CellType::quad4), 9);
  EXPECT_EQ(vtk_cell_type(CellType::quad8), 23);
}

TEST(VtuPermutation, MidEdgeNodesOnVtksEdges) {
  for (CellType t : all_types) {
    const auto x = to_vtk_order(t, mapped_nodes(t));
    for (const auto& e : vtk_quadratic_edges(t))
      EXPECT_LT((x[e[2]] - 0.5 * (x[e[0]] + x[e[1]])).norm(), 1e-14)
          << cell_name(t) << ": VTK node " << e[2] << " is not the midpoint of " << e[0] << "-"
          << e[1];
  }
}

TEST(VtuPermutation, VtkFacesPointOutwardForPositiveGmshCells) {
  ASSERT_GT(affine_matrix().determinant(), 0);
  for (CellType t : all_types) {
    if (cell_dim(t) != 3) continue;
    const auto x = to_vtk_order(t, mapped_nodes(t));
    std::vector<int> corners(cell_n_corners(t));
    for (int i = 0; i < cell_n_corners(t); ++i) corners[i] = i;
    const Vec3 c = centroid(x, corners);
    double volume = 0;  // divergence theorem: V = 1/3 sum over faces of (x_f . n_f)
    for (const auto& f : vtk_faces(t)) {
      const Vec3 n = polygon_normal(x, f);  // = 2 * area * unit normal (planar faces here)
      EXPECT_GT(n.dot(centroid(x, f) - c), 0) << cell_name(t) << ": a VTK face points inward";
      volume += centroid(x, f).dot(n) / 6.0;
    }
    EXPECT_NEAR(volume, reference_measure(t) * affine_matrix().determinant(), 1e-12) << cell_name(t);
  }
}

TEST(VtuPermutation, SurfaceCellsKeepTheirOrientation) {
  for (CellType t : all_types) {
    if (cell_dim(t) != 2) continue;
    const auto g = mapped_nodes(t);
    const auto v = to_vtk_order(t, g);
    std::vector<int> corners(cell_n_corners(t));
    for (int i = 0; i < cell_n_corners(t); ++i) corners[i] = i;
    EXPECT_GT(polygon_normal(v, corners).dot(polygon_normal(g, corners)), 0) << cell_name(t);
  }
}

TEST_F(VtuWriter, SingleCellRoundTrip) {
  for (CellType t : all_types) {
    SCOPED_TRACE(std::string(cell_name(t)));
    std::vector<Vec3> x;
    CellSet cells;
    single_cell(t, x, cells);
    const auto n = x.size();
    std::vector<double> disp(3 * n), temp(n);
    for (std::size_t i = 0; i < n; ++i) {
      disp[3 * i] = 0.01 * static_cast<double>(i);
      disp[3 * i + 1] = -0.5 + static_cast<double>(i);
      disp[3 * i + 2] = 1e-300 * static_cast<double>(i + 1);
      temp[i] = 20.0 + static_cast<double>(i) / 3.0;
    }
    const double measure = reference_measure(t) * affine_matrix().determinant();
    const std::vector<double> vol{measure};
    const std::vector<int> region{7};
    const std::vector<VtuField> pf{{"displacement", 3, disp}, {"temperature", 1, temp}};
    const std::vector<VtuField> cf{{"expected_measure", 1, vol}};
    const std::vector<VtuIntField> cif{{"region", region}};
    const auto file = dir_ / ("cell_" + short_name(t) + ".vtu");
    write_vtu(file, x, cells, pf, cf, cif);
    EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));

    const VtuRead r = read_vtu(file);
    EXPECT_EQ(r.n_points, n);
    EXPECT_EQ(r.n_cells, 1u);
    ASSERT_EQ(r.arrays.size(), 8u);
    const auto& pts = r.arrays.at("Points/Points");
    EXPECT_EQ(pts.type, "Float64");
    EXPECT_EQ(pts.n_components, 3);
    const auto pv = pts.as<double>();
    ASSERT_EQ(pv.size(), 3 * n);
    for (std::size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(pv[3 * i + k], x[i][k]);

    const auto& conn = r.arrays.at("Cells/connectivity");
    EXPECT_EQ(conn.type, "Int64");
    const auto perm = gmsh_to_vtk_permutation(t);
    EXPECT_EQ(conn.as<std::int64_t>(), std::vector<std::int64_t>(perm.begin(), perm.end()));
    EXPECT_EQ(r.arrays.at("Cells/offsets").type, "Int64");
    EXPECT_EQ(r.arrays.at("Cells/offsets").as<std::int64_t>(),
              std::vector<std::int64_t>{static_cast<std::int64_t>(n)});
    EXPECT_EQ(r.arrays.at("Cells/types").type, "UInt8");
    EXPECT_EQ(r.arrays.at("Cells/types").as<std::uint8_t>(),
              std::vector<std::uint8_t>{static_cast<std::uint8_t>(vtk_cell_type(t))});

    EXPECT_EQ(r.arrays.at("PointData/displacement").n_components, 3);
    EXPECT_EQ(r.arrays.at("PointData/displacement").as<double>(), disp);
    EXPECT_EQ(r.arrays.at("PointData/temperature").n_components, 1);
    EXPECT_EQ(r.arrays.at("PointData/temperature").as<double>(), temp);
    EXPECT_EQ(r.arrays.at("CellData/expected_measure").as<double>(), vol);
    EXPECT_EQ(r.arrays.at("CellData/region").type, "Int32");
    EXPECT_EQ(r.arrays.at("CellData/region").as<std::int32_t>(), region);
  }
}

TEST_F(VtuWriter, MixedCellsRoundTripAndSeries) {
  // Every cell type once, each with its own nodes, shifted apart; node numbers shuffled so
  // that the permutation acts on non-trivial indices.
  std::vector<Vec3> x;
  CellSet cells;
  std::vector<double> expected;
  std::vector<int> region;
  double total_volume = 0;
  for (CellType t : all_types) {
    auto xt = mapped_nodes(t);
    const int first = static_cast<int>(x.size());
    std::vector<int> nodes;
    for (std::size_t i = 0; i < xt.size(); ++i) {
      nodes.push_back(first + static_cast<int>(xt.size() - 1 - i));  // reversed numbering
      x.push_back(Vec3::Zero());
    }
    for (std::size_t i = 0; i < xt.size(); ++i)
      x[nodes[i]] = xt[i] + Vec3(3.0 * cells.size(), 0, 0);
    cells.add(t, nodes, 100 + cells.size());
    expected.push_back(reference_measure(t) * affine_matrix().determinant());
    if (cell_dim(t) == 3) total_volume += expected.back();
    region.push_back(static_cast<int>(t));
  }
  const auto n = x.size();
  std::vector<double> disp(3 * n), stress(6 * cells.size());
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) disp[3 * i + k] = 0.05 * x[i][k] * (k + 1);
  for (std::size_t i = 0; i < stress.size(); ++i) stress[i] = 1e6 * static_cast<double>(i);
  std::vector<double> von_mises(cells.size());
  for (std::size_t c = 0; c < von_mises.size(); ++c) von_mises[c] = 100.0 * static_cast<double>(c);
  const std::vector<VtuField> pf{{"displacement", 3, disp}};
  const std::vector<VtuField> cf{{"stress", 6, stress}, {"von_mises", 1, von_mises},
                                 {"expected_measure", 1, expected}};
  const std::vector<VtuIntField> cif{{"region", region}};

  PvdWriter pvd(dir_ / "series.pvd");
  std::vector<double> written;
  for (int step = 0; step < 2; ++step) {
    const std::string name = "series_" + std::to_string(step) + ".vtu";
    written = disp;
    write_vtu(dir_ / name, x, cells, pf, cf, cif);
    pvd.add(0.5 * (step + 1), name);
    for (auto& d : disp) d *= 2;  // the next step's field, through the same span
  }
  EXPECT_EQ(pvd.size(), 2u);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "series.pvd.tmp"));
  const std::string p = read_all(dir_ / "series.pvd");
  EXPECT_NE(p.find("type=\"Collection\""), std::string::npos);
  EXPECT_NE(p.find("<DataSet timestep=\"0.5\" group=\"\" part=\"0\" file=\"series_0.vtu\"/>"),
            std::string::npos)
      << p;
  EXPECT_NE(p.find("<DataSet timestep=\"1\" group=\"\" part=\"0\" file=\"series_1.vtu\"/>"),
            std::string::npos)
      << p;

  const VtuRead r = read_vtu(dir_ / "series_1.vtu");
  EXPECT_EQ(r.n_points, n);
  EXPECT_EQ(r.n_cells, all_types.size());
  std::vector<std::int64_t> conn, offsets;
  std::vector<std::uint8_t> types;
  for (int c = 0; c < cells.size(); ++c) {
    const auto nodes = cells.nodes(c);
    for (int p : gmsh_to_vtk_permutation(cells.type[c])) conn.push_back(nodes[p]);
    offsets.push_back(static_cast<std::int64_t>(conn.size()));
    types.push_back(static_cast<std::uint8_t>(vtk_cell_type(cells.type[c])));
  }
  EXPECT_EQ(r.arrays.at("Cells/connectivity").as<std::int64_t>(), conn);
  EXPECT_EQ(r.arrays.at("Cells/offsets").as<std::int64_t>(), offsets);
  EXPECT_EQ(r.arrays.at("Cells/types").as<std::uint8_t>(), types);
  EXPECT_EQ(r.arrays.at("PointData/displacement").as<double>(), written);
  EXPECT_EQ(r.arrays.at("CellData/stress").n_components, 6);
  EXPECT_EQ(r.arrays.at("CellData/stress").as<double>(), stress);
  EXPECT_EQ(r.arrays.at("CellData/von_mises").as<double>(), von_mises);
  EXPECT_EQ(r.arrays.at("CellData/region").as<std::int32_t>(), region);
  // 3D volume of the file: det(A) * (1/6 + 1/6 + 8 + 8 + 1).
  EXPECT_NEAR(total_volume, affine_matrix().determinant() * (52.0 / 3.0), 1e-12);
}

TEST_F(VtuWriter, EmptyMeshAndNoFields) {
  const CellSet cells;
  write_vtu(dir_ / "empty.vtu", std::span<const Vec3>{}, cells, {}, {}, {});
  const VtuRead r = read_vtu(dir_ / "empty.vtu");
  EXPECT_EQ(r.n_points, 0u);
  EXPECT_EQ(r.n_cells, 0u);
  EXPECT_EQ(r.arrays.size(), 4u);
  EXPECT_TRUE(r.arrays.at("Cells/connectivity").bytes.empty());
}

TEST_F(VtuWriter, NamesAreEscaped) {
  std::vector<Vec3> x;
  CellSet cells;
  single_cell(CellType::tet4, x, cells);
  const std::vector<double> v(4, 1.0);
  const std::vector<VtuField> pf{{"a<b & \"c\"", 1, v}};
  write_vtu(dir_ / "names.vtu", x, cells, pf, {}, {});
  const std::string s = read_all(dir_ / "names.vtu");
  EXPECT_NE(s.find("Name=\"a&lt;b &amp; &quot;c&quot;\""), std::string::npos);
}

TEST_F(VtuWriter, BadInputIsRejectedAndLeavesNoFile) {
  std::vector<Vec3> x;
  CellSet cells;
  single_cell(CellType::hex8, x, cells);
  const std::vector<double> short_field(7, 0.0);
  const std::vector<VtuField> bad{{"u", 1, short_field}};
  const auto file = dir_ / "bad.vtu";
  EXPECT_THROW(write_vtu(file, x, cells, bad, {}, {}), std::invalid_argument);
  EXPECT_THROW(write_vtu(file, x, cells, {}, bad, {}), std::invalid_argument);
  const std::vector<VtuField> zero{{"u", 0, {}}};
  EXPECT_THROW(write_vtu(file, x, cells, zero, {}, {}), std::invalid_argument);

  CellSet out_of_range = cells;
  out_of_range.conn[5] = 8;
  EXPECT_THROW(write_vtu(file, x, out_of_range, {}, {}, {}), std::invalid_argument);
  out_of_range.conn[5] = -1;
  EXPECT_THROW(write_vtu(file, x, out_of_range, {}, {}, {}), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(file));
  EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));

  // An existing file is replaced only by a complete one.
  write_vtu(file, x, cells, {}, {}, {});
  const std::string before = read_all(file);
  EXPECT_THROW(write_vtu(file, x, out_of_range, {}, {}, {}), std::invalid_argument);
  EXPECT_EQ(read_all(file), before);
  EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));
}

TEST_F(VtuWriter, IoFailureNamesThePath) {
  std::vector<Vec3> x;
  CellSet cells;
  single_cell(CellType::tet4, x, cells);
  const auto file = dir_ / "no_such_dir" / "out.vtu";
  try {
    write_vtu(file, x, cells, {}, {}, {});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  PvdWriter pvd(dir_ / "no_such_dir" / "results.pvd");
  try {
    pvd.add(1.0, "a.vtu");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("results.pvd"), std::string::npos) << e.what();
  }
  EXPECT_EQ(pvd.size(), 0u);
}

TEST_F(VtuWriter, LargeMeshIsWrittenInOnePass) {
  // 200k hexahedra on a structured block: checks the buffered path and the offsets of blocks
  // larger than the buffer.
  constexpr int m = 59;  // 59^3 = 205379 cells
  std::vector<Vec3> x;
  for (int k = 0; k <= m; ++k)
    for (int j = 0; j <= m; ++j)
      for (int i = 0; i <= m; ++i) x.emplace_back(i, j, k);
  auto id = [](int i, int j, int k) { return i + (m + 1) * (j + (m + 1) * k); };
  CellSet cells;
  cells.type.reserve(m * m * m);
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const std::array<int, 8> nodes{id(i, j, k),         id(i + 1, j, k),
                                       id(i + 1, j + 1, k), id(i, j + 1, k),
                                       id(i, j, k + 1),     id(i + 1, j, k + 1),
                                       id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
        cells.add(CellType::hex8, nodes, 0);
      }
  std::vector<double> u(3 * x.size());
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = static_cast<double>(i);
  std::vector<double> s(cells.type.size(), 2.5);
  const std::vector<VtuField> pf{{"displacement", 3, u}};
  const std::vector<VtuField> cf{{"von_mises", 1, s}};
  write_vtu(dir_ / "block.vtu", x, cells, pf, cf, {});
  const VtuRead r = read_vtu(dir_ / "block.vtu");
  EXPECT_EQ(r.n_cells, cells.type.size());
  const auto conn = r.arrays.at("Cells/connectivity").as<std::int64_t>();
  ASSERT_EQ(conn.size(), cells.conn.size());
  for (std::size_t i = 0; i < conn.size(); ++i) ASSERT_EQ(conn[i], cells.conn[i]);
  EXPECT_EQ(r.arrays.at("PointData/displacement").as<double>(), u);
  EXPECT_EQ(r.arrays.at("CellData/von_mises").as<double>(), s);
  EXPECT_EQ(r.arrays.at("Cells/offsets").as<std::int64_t>().back(),
            static_cast<std::int64_t>(cells.conn.size()));
}

// Two pieces of a strip of two hexahedra, sharing the face of nodes 4..7 (numbered 1004..1007),
// with their Gmsh numbers, and the .pvtu that lists them: the ids are Int64 arrays declared as
// VTK's GlobalIds, the .pvtu declares every array of the pieces with its type and width.
TEST_F(VtuWriter, PiecesWithGlobalIdsAndTheirPvtu) {
  std::vector<Vec3> x;
  for (int k = 0; k < 3; ++k)
    for (auto [a, b] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) x.emplace_back(a, b, k);
  const std::vector<std::array<int, 8>> global{{0, 1, 2, 3, 4, 5, 6, 7},
                                               {4, 5, 6, 7, 8, 9, 10, 11}};
  std::vector<std::string> pieces;
  for (int piece = 0; piece < 2; ++piece) {
    // The piece's nodes, numbered locally 0..7, and their global numbers.
    std::vector<Vec3> px;
    std::vector<long> node_tag;
    for (int g : global[piece]) {
      px.push_back(x[g]);
      node_tag.push_back(1000 + g);
    }
    CellSet cells;
    const std::array<int, 8> local{0, 1, 2, 3, 4, 5, 6, 7};
    cells.add(CellType::hex8, local, 500 + piece);
    const std::vector<long> cell_tag{500 + piece};
    std::vector<double> u(3 * px.size());
    for (std::size_t i = 0; i < px.size(); ++i)
      for (int d = 0; d < 3; ++d) u[3 * i + d] = 0.1 * px[i][d];
    const std::vector<double> s{1.0 + piece};
    const std::vector<int> region{piece};
    const std::vector<VtuField> pf{{"displacement", 3, u}}, cf{{"von_mises", 1, s}};
    const std::vector<VtuIntField> cif{{"region", region}};
    const std::string name = "piece_" + std::to_string(piece) + ".vtu";
    write_vtu(dir_ / name, px, cells, pf, cf, cif, VtuGlobalIds{node_tag, cell_tag});
    pieces.push_back(name);
    const VtuRead r = read_vtu(dir_ / name);
    EXPECT_EQ(r.arrays.at("PointData/node_tag").type, "Int64");
    EXPECT_EQ(r.arrays.at("PointData/node_tag").as<std::int64_t>(),
              std::vector<std::int64_t>(node_tag.begin(), node_tag.end()));
    EXPECT_EQ(r.arrays.at("CellData/element_tag").as<std::int64_t>(),
              std::vector<std::int64_t>{500 + piece});
    EXPECT_EQ(r.arrays.at("PointData/displacement").as<double>(), u);
    const std::string text = read_all(dir_ / name);
    EXPECT_NE(text.find("<PointData GlobalIds=\"node_tag\">"), std::string::npos);
    EXPECT_NE(text.find("<CellData GlobalIds=\"element_tag\">"), std::string::npos);
  }
  // A node id count that does not match the points is refused.
  CellSet one;
  one.add(CellType::hex8, std::array<int, 8>{0, 1, 2, 3, 4, 5, 6, 7}, 1);
  const std::vector<long> three{1, 2, 3};
  EXPECT_THROW(write_vtu(dir_ / "bad.vtu", std::span<const Vec3>(x.data(), 8), one, {}, {}, {},
                         VtuGlobalIds{three, {}}),
               std::invalid_argument);

  const std::vector<VtuField> pf{{"displacement", 3, {}}}, cf{{"von_mises", 1, {}}};
  const std::vector<VtuIntField> cif{{"region", {}}};
  write_pvtu(dir_ / "both.pvtu", pf, cf, cif, true, pieces);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "both.pvtu.tmp"));
  const std::string p = read_all(dir_ / "both.pvtu");
  for (const char* expected :
       {"<VTKFile type=\"PUnstructuredGrid\"", "<PUnstructuredGrid GhostLevel=\"0\">",
        "<PPointData GlobalIds=\"node_tag\">",
        "<PDataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\"/>",
        "<PDataArray type=\"Int64\" Name=\"node_tag\"/>", "<PCellData GlobalIds=\"element_tag\">",
        "<PDataArray type=\"Float64\" Name=\"von_mises\"/>",
        "<PDataArray type=\"Int32\" Name=\"region\"/>",
        "<PDataArray type=\"Int64\" Name=\"element_tag\"/>",
        "<PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>",
        "<Piece Source=\"piece_0.vtu\"/>\n    <Piece Source=\"piece_1.vtu\"/>"})
    EXPECT_NE(p.find(expected), std::string::npos) << expected << "\n" << p;
}

}  // namespace
}  // namespace hencky
