#include "output/vtu_writer.hpp"

#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <type_traits>

#include "core/error.hpp"

namespace hencky {

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");

// ---- Cell types and node orders --------------------------------------------------------

constexpr int n_cell_types = 9;

constexpr std::array<int, 4> perm_tet4{0, 1, 2, 3};
// Gmsh edge nodes 4..9 on (0,1),(1,2),(2,0),(3,0),(3,2),(3,1);
// VTK on (0,1),(1,2),(2,0),(0,3),(1,3),(2,3).
constexpr std::array<int, 10> perm_tet10{0, 1, 2, 3, 4, 5, 6, 7, 9, 8};
constexpr std::array<int, 8> perm_hex8{0, 1, 2, 3, 4, 5, 6, 7};
// Gmsh edge nodes 8..19 on (0,1),(0,3),(0,4),(1,2),(1,5),(2,3),(2,6),(3,7),(4,5),(4,7),(5,6),(6,7);
// VTK: 8..11 on (0,1),(1,2),(2,3),(3,0), 12..15 on (4,5),(5,6),(6,7),(7,4),
// 16..19 on (0,4),(1,5),(2,6),(3,7).
constexpr std::array<int, 20> perm_hex20{0,  1, 2,  3,  4,  5,  6,  7,  8,  11,
                                         13, 9, 16, 18, 19, 17, 10, 12, 14, 15};
// Gmsh: triangle (0,1,2) at the bottom, counter-clockwise seen from the top face (3,4,5).
// VTK: the right-hand normal of (0,1,2) points away from (3,4,5) (parametric coordinates of
// VTK's nodes 1 and 2 are (0,1,0) and (1,0,0)), so both triangles are reversed.
// Checked with ParaView 5.11: positive CellSize volume, outward face normals.
constexpr std::array<int, 6> perm_wedge6{0, 2, 1, 3, 5, 4};
constexpr std::array<int, 3> perm_tri3{0, 1, 2};
constexpr std::array<int, 6> perm_tri6{0, 1, 2, 3, 4, 5};
constexpr std::array<int, 4> perm_quad4{0, 1, 2, 3};
constexpr std::array<int, 8> perm_quad8{0, 1, 2, 3, 4, 5, 6, 7};

struct TypeInfo {
  std::span<const int> perm;
  std::uint8_t vtk_type;
};

// Indexed by the CellType enum value.
const std::array<TypeInfo, n_cell_types> type_info{{
    {perm_tet4, 10},    // tet4: VTK_TETRA
    {perm_tet10, 24},   // tet10: VTK_QUADRATIC_TETRA
    {perm_hex8, 12},    // hex8: VTK_HEXAHEDRON
    {perm_hex20, 25},   // hex20: VTK_QUADRATIC_HEXAHEDRON
    {perm_wedge6, 13},  // wedge6: VTK_WEDGE
    {perm_tri3, 5},     // tri3: VTK_TRIANGLE
    {perm_tri6, 22},    // tri6: VTK_QUADRATIC_TRIANGLE
    {perm_quad4, 9},    // quad4: VTK_QUAD
    {perm_quad8, 23},   // quad8: VTK_QUADRATIC_QUAD
}};

const TypeInfo& info(CellType t) {
  const auto i = static_cast<std::size_t>(t);
  if (i >= type_info.size()) throw std::invalid_argument("vtu writer: unknown cell type");
  return type_info[i];
}

// ---- Output ------------------------------------------------------------------------------

std::string describe(const std::filesystem::path& p) {
  std::string s(1, '\'');  // appended piecewise: "'" + s + "'" trips GCC 12's -Wrestrict
  s += p.string();
  s += '\'';
  return s;
}

/// A file written to path.tmp through a large buffer, renamed to path by commit().
/// Removed again if destroyed without commit() (an exception on the way).
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path) : path_(std::move(path)), tmp_(path_) {
    tmp_ += ".tmp";
    errno = 0;
    f_ = std::fopen(tmp_.c_str(), "wb");
    if (!f_) fail("cannot open " + describe(tmp_) + " for writing");
    buf_.resize(std::size_t{1} << 20);
  }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile() {
    if (f_) std::fclose(f_);
    if (!committed_) {
      std::error_code ec;
      std::filesystem::remove(tmp_, ec);
    }
  }

  void write(const void* p, std::size_t n) {
    if (n == 0) return;  // an empty array may come with a null pointer
    if (n_ + n > buf_.size()) {
      flush();
      if (n > buf_.size()) {
        raw_write(p, n);
        return;
      }
    }
    std::memcpy(buf_.data() + n_, p, n);
    n_ += n;
  }
  void write(std::string_view s) { write(s.data(), s.size()); }

  template <class T>
  void put(T v) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (n_ + sizeof(T) > buf_.size()) flush();
    std::memcpy(buf_.data() + n_, &v, sizeof(T));
    n_ += sizeof(T);
  }

  void commit() {
    flush();
    std::FILE* f = f_;
    f_ = nullptr;
    errno = 0;
    if (std::fclose(f) != 0) fail("cannot write " + describe(tmp_));
    std::error_code ec;
    std::filesystem::rename(tmp_, path_, ec);
    if (ec)
      throw OutputError("cannot rename " + describe(tmp_) + " to " + describe(path_) + ": " +
                        ec.message());
    committed_ = true;
  }

 private:
  void flush() {
    if (n_ > 0) raw_write(buf_.data(), n_);
    n_ = 0;
  }
  void raw_write(const void* p, std::size_t n) {
    errno = 0;
    if (std::fwrite(p, 1, n, f_) != n) fail("cannot write " + describe(tmp_));
  }
  [[noreturn]] void fail(const std::string& what) const {
    const int e = errno;
    std::string msg = what + " (writing " + describe(path_) + ")";
    if (e != 0) msg += ": " + std::string(std::strerror(e));
    throw OutputError(msg);
  }

  std::filesystem::path path_, tmp_;
  std::FILE* f_ = nullptr;
  std::vector<char> buf_;
  std::size_t n_ = 0;
  bool committed_ = false;
};

std::string xml_escape(std::string_view s) {
  std::string r;
  r.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        r += "&amp;";
        break;
      case '<':
        r += "&lt;";
        break;
      case '>':
        r += "&gt;";
        break;
      case '"':
        r += "&quot;";
        break;
      case '\'':
        r += "&apos;";
        break;
      default:
        r += c;
    }
  }
  return r;
}

constexpr const char* byte_order() {
  return std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
}

/// Appends a <DataArray .../> line to the XML header and advances the appended-data offset
/// by the block it describes (UInt64 byte count + data).
void data_array(std::string& xml, std::uint64_t& offset, const char* type, const std::string& name,
                int n_components, std::uint64_t n_bytes) {
  xml += "        <DataArray type=\"";
  xml += type;
  xml += "\" Name=\"";
  xml += xml_escape(name);
  xml += "\"";
  if (n_components != 1) xml += " NumberOfComponents=\"" + std::to_string(n_components) + "\"";
  xml += " format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
  offset += sizeof(std::uint64_t) + n_bytes;
}

void check_field(const VtuField& f, std::size_t n_entities, const char* what) {
  if (f.n_components < 1)
    throw std::invalid_argument("vtu writer: " + std::string(what) + " field '" + f.name +
                                "' has " + std::to_string(f.n_components) + " components");
  if (f.data.size() != n_entities * static_cast<std::size_t>(f.n_components))
    throw std::invalid_argument("vtu writer: " + std::string(what) + " field '" + f.name +
                                "' has " + std::to_string(f.data.size()) + " values, expected " +
                                std::to_string(n_entities) + " x " +
                                std::to_string(f.n_components));
}

std::string format_double(double v) {
  std::array<char, 64> b{};
  const auto r = std::to_chars(b.data(), b.data() + b.size(), v);
  return std::string(b.data(), r.ptr);
}

}  // namespace

std::span<const int> gmsh_to_vtk_permutation(CellType t) {
  return info(t).perm;
}

int vtk_cell_type(CellType t) {
  return info(t).vtk_type;
}

void write_vtu(const std::filesystem::path& path, std::span<const Vec3> points,
               const CellSet& cells, std::span<const VtuField> point_fields,
               std::span<const VtuField> cell_fields, std::span<const VtuIntField> cell_int_fields,
               const VtuGlobalIds& ids) {
  const std::size_t n_points = points.size();
  const std::size_t n_cells = static_cast<std::size_t>(cells.size());

  // ---- Checks (cheap: no pass over the connectivity, which is checked while writing) ----
  if (cells.offset.size() != n_cells + 1 || cells.offset.front() != 0 ||
      static_cast<std::size_t>(cells.offset.back()) != cells.conn.size())
    throw std::invalid_argument("vtu writer: inconsistent cell set offsets");
  for (const auto& f : point_fields) check_field(f, n_points, "point");
  for (const auto& f : cell_fields) check_field(f, n_cells, "cell");
  for (const auto& f : cell_int_fields)
    if (f.data.size() != n_cells)
      throw std::invalid_argument("vtu writer: cell field '" + f.name + "' has " +
                                  std::to_string(f.data.size()) + " values, expected " +
                                  std::to_string(n_cells));
  static_assert(sizeof(long) == sizeof(std::int64_t), "Gmsh tags are written as Int64");
  if (!ids.nodes.empty() && ids.nodes.size() != n_points)
    throw std::invalid_argument("vtu writer: " + std::to_string(ids.nodes.size()) +
                                " node ids for " + std::to_string(n_points) + " points");
  if (!ids.cells.empty() && ids.cells.size() != n_cells)
    throw std::invalid_argument("vtu writer: " + std::to_string(ids.cells.size()) +
                                " cell ids for " + std::to_string(n_cells) + " cells");

  // ---- XML header, with the offsets of the appended blocks ----
  const std::uint64_t n_conn = cells.conn.size();
  std::uint64_t offset = 0;
  std::string xml;
  xml.reserve(4096);
  xml +=
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"";
  xml += byte_order();
  xml += "\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" +
         std::to_string(n_points) + "\" NumberOfCells=\"" + std::to_string(n_cells) + "\">\n";
  xml += ids.nodes.empty() ? "      <PointData>\n" : "      <PointData GlobalIds=\"node_tag\">\n";
  for (const auto& f : point_fields)
    data_array(xml, offset, "Float64", f.name, f.n_components, f.data.size() * sizeof(double));
  if (!ids.nodes.empty())
    data_array(xml, offset, "Int64", "node_tag", 1, n_points * sizeof(std::int64_t));
  xml += "      </PointData>\n";
  xml += ids.cells.empty() ? "      <CellData>\n" : "      <CellData GlobalIds=\"element_tag\">\n";
  for (const auto& f : cell_fields)
    data_array(xml, offset, "Float64", f.name, f.n_components, f.data.size() * sizeof(double));
  for (const auto& f : cell_int_fields)
    data_array(xml, offset, "Int32", f.name, 1, f.data.size() * sizeof(std::int32_t));
  if (!ids.cells.empty())
    data_array(xml, offset, "Int64", "element_tag", 1, n_cells * sizeof(std::int64_t));
  xml += "      </CellData>\n      <Points>\n";
  data_array(xml, offset, "Float64", "Points", 3, n_points * 3 * sizeof(double));
  xml += "      </Points>\n      <Cells>\n";
  data_array(xml, offset, "Int64", "connectivity", 1, n_conn * sizeof(std::int64_t));
  data_array(xml, offset, "Int64", "offsets", 1, n_cells * sizeof(std::int64_t));
  data_array(xml, offset, "UInt8", "types", 1, n_cells * sizeof(std::uint8_t));
  xml +=
      "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   "
      "_";

  // ---- One pass over everything ----
  AtomicFile out(path);
  out.write(xml);

  auto block = [&out](const void* p, std::uint64_t n_bytes) {
    out.put<std::uint64_t>(n_bytes);
    out.write(p, n_bytes);
  };
  for (const auto& f : point_fields) block(f.data.data(), f.data.size() * sizeof(double));
  if (!ids.nodes.empty()) block(ids.nodes.data(), n_points * sizeof(std::int64_t));
  for (const auto& f : cell_fields) block(f.data.data(), f.data.size() * sizeof(double));
  static_assert(sizeof(int) == sizeof(std::int32_t));
  for (const auto& f : cell_int_fields) block(f.data.data(), f.data.size() * sizeof(std::int32_t));
  if (!ids.cells.empty()) block(ids.cells.data(), n_cells * sizeof(std::int64_t));
  block(points.data(), n_points * 3 * sizeof(double));

  // Connectivity, permuted to VTK's node order; node indices are checked on the way.
  out.put<std::uint64_t>(n_conn * sizeof(std::int64_t));
  const int* conn = cells.conn.data();
  for (std::size_t c = 0; c < n_cells; ++c) {
    const CellType t = cells.type[c];
    const auto perm = gmsh_to_vtk_permutation(t);
    const int* nodes = conn + cells.offset[c];
    if (static_cast<std::size_t>(cells.offset[c + 1] - cells.offset[c]) != perm.size())
      throw std::invalid_argument("vtu writer: cell " + std::to_string(c) + " (" +
                                  std::string(cell_name(t)) + ") has " +
                                  std::to_string(cells.offset[c + 1] - cells.offset[c]) + " nodes");
    for (const int p : perm) {
      const int n = nodes[p];
      if (n < 0 || static_cast<std::size_t>(n) >= n_points)
        throw std::invalid_argument("vtu writer: cell " + std::to_string(c) + " refers to node " +
                                    std::to_string(n) + " of " + std::to_string(n_points));
      out.put<std::int64_t>(n);
    }
  }
  out.put<std::uint64_t>(n_cells * sizeof(std::int64_t));
  for (std::size_t c = 0; c < n_cells; ++c) out.put<std::int64_t>(cells.offset[c + 1]);
  out.put<std::uint64_t>(n_cells * sizeof(std::uint8_t));
  for (std::size_t c = 0; c < n_cells; ++c) out.put<std::uint8_t>(info(cells.type[c]).vtk_type);

  out.write("\n  </AppendedData>\n</VTKFile>\n");
  out.commit();
}

void write_pvtu(const std::filesystem::path& path, std::span<const VtuField> point_fields,
                std::span<const VtuField> cell_fields, std::span<const VtuIntField> cell_int_fields,
                bool with_ids, std::span<const std::string> pieces) {
  auto array = [](std::string& xml, const char* type, const std::string& name, int n_components) {
    xml += "      <PDataArray type=\"";
    xml += type;
    xml += "\" Name=\"" + xml_escape(name) + "\"";
    if (n_components != 1) xml += " NumberOfComponents=\"" + std::to_string(n_components) + "\"";
    xml += "/>\n";
  };
  std::string xml =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" "
      "byte_order=\"";
  xml += byte_order();
  xml += "\" header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n";
  xml += with_ids ? "    <PPointData GlobalIds=\"node_tag\">\n" : "    <PPointData>\n";
  for (const auto& f : point_fields) array(xml, "Float64", f.name, f.n_components);
  if (with_ids) array(xml, "Int64", "node_tag", 1);
  xml += "    </PPointData>\n";
  xml += with_ids ? "    <PCellData GlobalIds=\"element_tag\">\n" : "    <PCellData>\n";
  for (const auto& f : cell_fields) array(xml, "Float64", f.name, f.n_components);
  for (const auto& f : cell_int_fields) array(xml, "Int32", f.name, 1);
  if (with_ids) array(xml, "Int64", "element_tag", 1);
  xml += "    </PCellData>\n    <PPoints>\n";
  array(xml, "Float64", "Points", 3);
  xml += "    </PPoints>\n";
  for (const auto& p : pieces) xml += "    <Piece Source=\"" + xml_escape(p) + "\"/>\n";
  xml += "  </PUnstructuredGrid>\n</VTKFile>\n";
  AtomicFile out(path);
  out.write(xml);
  out.commit();
}

// ---- PvdWriter ------------------------------------------------------------------------------

PvdWriter::PvdWriter(std::filesystem::path pvd_path) : path_(std::move(pvd_path)) {}

void PvdWriter::add(double time, const std::string& vtu_file_name) {
  steps_.emplace_back(time, vtu_file_name);
  try {
    write();
  } catch (...) {
    steps_.pop_back();  // so that a retry of the same step does not list it twice
    throw;
  }
}

void PvdWriter::adopt(std::vector<std::pair<double, std::string>> steps) {
  steps_ = std::move(steps);
  write();
}

void PvdWriter::write() const {
  std::string xml =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"";
  xml += byte_order();
  xml += "\" header_type=\"UInt64\">\n  <Collection>\n";
  for (const auto& [t, file] : steps_)
    xml += "    <DataSet timestep=\"" + format_double(t) + "\" group=\"\" part=\"0\" file=\"" +
           xml_escape(file) + "\"/>\n";
  xml += "  </Collection>\n</VTKFile>\n";
  AtomicFile out(path_);
  out.write(xml);
  out.commit();
}

}  // namespace hencky
