#include "output/frd_writer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iterator>
#include <numeric>
#include <stdexcept>
#include <string_view>

#include "core/error.hpp"
#include "hencky/version.hpp"

namespace hencky {
namespace {

// output/ may not include input/ (tests/tools/check_layers.py: siblings in one layer), so the
// orders are tables of their own here. They are input/inp_elements.cpp's gmsh_from_abaqus
// inverted, and for the 20-node hexahedron then reordered as ccx's frd.c writes its record:
// the deck's nodes 1-12, 17-20, 13-16. tests/unit/test_frd_writer.cpp checks that they agree.
constexpr int frd_order_identity[8] = {0, 1, 2, 3, 4, 5, 6, 7};
// Gmsh and ccx number the tetrahedron's edges alike but for the last two (Gmsh 4-3, 4-2;
// ccx 2-4, 3-4).
constexpr int frd_order_tet10[10] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};
// ccx's .frd record: edges 1-2, 2-3, 3-4, 4-1, then 1-5, 2-6, 3-7, 4-8, then 5-6, 6-7, 7-8,
// 8-5; Gmsh numbers them 1-2, 1-4, 1-5, 2-3, 2-6, 3-4, 3-7, 4-8, 5-6, 5-8, 6-7, 7-8.
constexpr int frd_order_hex20[20] = {0,  1, 2,  3,  4,  5,  6,  7,  8,  11,
                                     13, 9, 10, 12, 14, 15, 16, 18, 19, 17};

/// The record ends a block of the ASCII format (cgx manual: Format:(1X,'-3')).
constexpr std::string_view frd_block_end = " -3\n";

/// Columns of a label (the long format's I10).
constexpr long frd_max_label = 9'999'999'999L;

/// A number as ccx writes it: single precision (frd.c casts to float) in 12 columns. The cast
/// also bounds the exponent to two digits, so that the fixed columns always hold the number.
void frd_put_number(std::string& s, double v) {
  fmt::format_to(std::back_inserter(s), "{:12.5E}", static_cast<float>(v));
}

/// A line of the user header (cgx manual: Format:(1X,'   1','U',A66)): the key in 18 columns
/// and its value, as ccx lays them out.
void frd_user_line(std::string& s, std::string_view key, std::string_view value) {
  fmt::format_to(std::back_inserter(s), "    1U{:<18}{:<48.48}\n", key, value);
}

/// The time of a result set as frdheader.c writes it: ten significant digits in fixed notation
/// from 1 to 1e10, else (and for 0) %12.5E.
std::string frd_time(double time) {
  if (time > 0 && std::log10(time) >= 0 && std::log10(time) < 10) {
    const int decimals = 10 - static_cast<int>(std::floor(std::log10(time)) + 1);
    return fmt::format("{:12.{}f}", time, std::max(decimals, 0));
  }
  return fmt::format("{:12.5E}", time);
}

/// Indices 0..n-1 in ascending order of their labels (`labels` empty: labels 1..n). Throws if a
/// label is not positive, repeated, or does not fit the format's 10 columns.
std::vector<int> frd_label_order(const std::vector<long>& labels, int n, const char* what) {
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  if (labels.empty()) return order;
  if (static_cast<int>(labels.size()) != n)
    throw std::invalid_argument(
        fmt::format("frd: {} {} labels for {} {}s", labels.size(), what, n, what));
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return labels[a] < labels[b]; });
  for (int k = 0; k < n; ++k) {
    const long label = labels[order[k]];
    if (label < 1 || label > frd_max_label)
      throw std::invalid_argument(
          fmt::format("frd: {} label {} is not in 1..{}", what, label, frd_max_label));
    if (k > 0 && labels[order[k - 1]] == label)
      throw std::invalid_argument(fmt::format("frd: two {}s have the label {}", what, label));
  }
  return order;
}

/// "28.november.2026" and "14:52:42", as ccx's frd.c writes the date and the time.
std::pair<std::string, std::string> frd_date_time() {
  static constexpr const char* months[12] = {"january",   "february", "march",    "april",
                                             "may",       "june",     "july",     "august",
                                             "september", "october",  "november", "december"};
  const std::time_t now = std::time(nullptr);
  std::tm t{};
  localtime_r(&now, &t);
  return {fmt::format("{:02d}.{}.{:04d}", t.tm_mday, months[t.tm_mon], t.tm_year + 1900),
          fmt::format("{:02d}:{:02d}:{:02d}", t.tm_hour, t.tm_min, t.tm_sec)};
}

}  // namespace

int frd_element_type(CellType t) {
  switch (t) {
    case CellType::hex8:
      return 1;
    case CellType::wedge6:
      return 2;
    case CellType::tet4:
      return 3;
    case CellType::hex20:
      return 4;
    case CellType::tet10:
      return 6;
    default:
      return 0;
  }
}

std::span<const int> frd_from_gmsh(CellType t) {
  switch (t) {
    case CellType::tet10:
      return frd_order_tet10;
    case CellType::hex20:
      return frd_order_hex20;
    case CellType::tet4:
    case CellType::hex8:
    case CellType::wedge6:
      // Gmsh's corners are ccx's (CalculiX manual, section 6.2).
      return {frd_order_identity, static_cast<std::size_t>(cell_n_nodes(t))};
    default:
      return {};
  }
}

FrdWriter::FrdWriter(const std::filesystem::path& file, const Mesh& mesh)
    : FrdWriter(file, mesh, nullptr) {}

FrdWriter::FrdWriter(const std::filesystem::path& file, const Mesh& mesh,
                     const Materials& materials)
    : FrdWriter(file, mesh, &materials) {}

FrdWriter::FrdWriter(const std::filesystem::path& file, const Mesh& mesh,
                     const Materials* materials)
    : file_(file) {
  const int n_nodes = mesh.n_nodes();
  const CellSet& cells = mesh.cells;
  // Checked before the file is created, so that a mesh the format cannot hold leaves none.
  node_order_ = frd_label_order(mesh.node_tag, n_nodes, "node");
  const std::vector<int> cell_order = frd_label_order(cells.tag, cells.size(), "cell");
  for (int c = 0; c < cells.size(); ++c)
    if (frd_element_type(cells.type[c]) == 0)
      throw std::invalid_argument(
          fmt::format("frd: a {} is not a volume cell", cell_name(cells.type[c])));
  node_label_.resize(n_nodes);
  for (int i = 0; i < n_nodes; ++i)
    node_label_[i] = mesh.node_tag.empty() ? i + 1 : mesh.node_tag[i];

  out_.open(file_, std::ios::binary | std::ios::trunc);
  if (!out_)
    throw InputError(SourceLocation{file_.string(), 0, 0, {}},
                     fmt::format("cannot write the result file: {}", std::strerror(errno)));

  try {
    write_mesh(mesh, cell_order, materials);
  } catch (const OutputError& e) {
    throw InputError(e.what());  // the message names the file
  }
}

void FrdWriter::write_mesh(const Mesh& mesh, const std::vector<int>& cell_order,
                           const Materials* materials) {
  const int n_nodes = mesh.n_nodes();
  const CellSet& cells = mesh.cells;
  std::string s;
  auto put = std::back_inserter(s);
  // The model header (its name left empty, as ccx leaves it) and the user header.
  s += "    1C\n";
  const auto [date, clock] = frd_date_time();
  frd_user_line(s, "USER", "");
  frd_user_line(s, "DATE", date);
  frd_user_line(s, "TIME", clock);
  frd_user_line(s, "HOST", "");
  frd_user_line(s, "PGM", "hencky");
  frd_user_line(s, "VERSION", "Version " HENCKY_VERSION);
  frd_user_line(s, "DIR", "");
  frd_user_line(s, "DBN", "");
  // ccx lists its materials here, numbered from 1. Without them hencky's counterpart is the
  // volume region: the volume regions (dimension 3) are numbered from 1 in the order of
  // Mesh::regions, a cell carries its region's number (0 without one), and each number that cells
  // carry is listed with the region's name. A deck whose one ELSET of volumes holds the body gets
  // 1, as from ccx.
  std::vector<int> number(static_cast<std::size_t>(cells.size()), 0);
  std::vector<std::string> names;
  if (materials) {
    number = materials->of_cell;
    number.resize(static_cast<std::size_t>(cells.size()), 0);
    names = materials->names;
  } else {
    std::vector<int> volume_number(mesh.regions.size(), 0);
    for (int r = 0; r < static_cast<int>(mesh.regions.size()); ++r)
      if (mesh.regions[r].dim == 3) {
        names.push_back(mesh.regions[r].name);
        volume_number[r] = static_cast<int>(names.size());
      }
    for (int c = 0; c < cells.size(); ++c) {
      const int r = c < static_cast<int>(mesh.cell_region.size()) ? mesh.cell_region[c] : -1;
      number[c] = r >= 0 && r < static_cast<int>(volume_number.size()) ? volume_number[r] : 0;
    }
  }
  auto material = [&](int c) { return number[static_cast<std::size_t>(c)]; };
  std::vector<bool> listed(names.size() + 1, false);
  for (int c = 0; c < cells.size(); ++c)
    if (material(c) > 0 && material(c) <= static_cast<int>(names.size()))
      listed[material(c)] = true;
  for (std::size_t k = 1; k <= names.size(); ++k)
    if (listed[k]) fmt::format_to(put, "    1UMAT{:5d}{:<58.58}\n", k, names[k - 1]);

  // Nodal point coordinate block (cgx manual: Format:(1X,'   2','C',18X,I12,37X,I1), the last
  // field 1 for the long ASCII format).
  fmt::format_to(put, "    2C{:18}{:12d}{:37}1\n", "", n_nodes, "");
  for (int i : node_order_) {
    fmt::format_to(put, " -1{:10d}", node_label_[i]);
    for (int d = 0; d < 3; ++d) frd_put_number(s, mesh.x[i][d]);
    s += '\n';
    if (s.size() > (1 << 20)) flush(s);
  }
  s += frd_block_end;

  // Element definition block: per element its header record and its nodes, ten to a record
  // (the long format's 10I10).
  fmt::format_to(put, "    3C{:18}{:12d}{:37}1\n", "", cells.size(), "");
  for (int c : cell_order) {
    const long label = cells.tag.empty() ? c + 1 : cells.tag[c];
    fmt::format_to(put, " -1{:10d}{:5d}{:5d}{:5d}\n", label, frd_element_type(cells.type[c]), 0,
                   material(c));
    const auto nodes = cells.nodes(c);
    const auto order = frd_from_gmsh(cells.type[c]);
    for (std::size_t j = 0; j < order.size(); ++j) {
      if (j % 10 == 0) s += j == 0 ? " -2" : "\n -2";
      fmt::format_to(put, "{:10d}", node_label_[nodes[order[j]]]);
    }
    s += '\n';
    if (s.size() > (1 << 20)) flush(s);
  }
  s += frd_block_end;
  flush(s);
}

void FrdWriter::step(int step, double time, const std::vector<FrdField>& fields) {
  if (closed_) throw std::logic_error("frd: step() after close()");
  if (step < 1) throw std::invalid_argument(fmt::format("frd: step {} is not 1 or more", step));
  // The set number is written as 100 + k in five columns.
  if (sets_ + 1 > 99'899) throw std::invalid_argument("frd: more result sets than 99899");
  const std::size_t n_nodes = node_label_.size();
  // All fields are checked first: a bad call writes nothing.
  for (const FrdField& f : fields) {
    if (f.name.empty() || f.name.size() > 8 || f.components.empty())
      throw std::invalid_argument(fmt::format(
          "frd: field '{}': a name of 1 to 8 characters and components are needed", f.name));
    for (const std::string& c : f.components)
      if (c.empty() || c.size() > 8)
        throw std::invalid_argument(
            fmt::format("frd: field {}: component '{}' is not 1 to 8 characters", f.name, c));
    if (f.values.size() != n_nodes * f.components.size())
      throw std::invalid_argument(
          fmt::format("frd: field {} has {} values for {} nodes and {} "
                      "components",
                      f.name, f.values.size(), n_nodes, f.components.size()));
  }
  ++sets_;
  std::string s;
  auto put = std::back_inserter(s);
  for (const FrdField& f : fields) {
    const int nc = static_cast<int>(f.components.size());
    const bool vector = nc == 3, tensor = nc == 6;
    // The parameter record ccx writes before each block: the block's running number, the
    // increment and the step.
    fmt::format_to(put, "    1PSTEP{:14}{:12d}{:12d}{:12d}{:10}\n", "", ++blocks_, step, 1, "");
    // Nodal results block, first record (cgx manual: Format:(1X,' 100','C',6A1,E12.5,I12,20A1,
    // I2,I5,10A1,I2)): set name "L" and 100 + the set number, the time, the node count, no
    // text, analysis type 0 (static), the set number, no analysis name, format 1 (long ASCII).
    fmt::format_to(put, "  100CL{:5d}{:>12}{:12d}{:20}{:2d}{:5d}{:10}{:2d}\n", 100 + sets_,
                   frd_time(time), n_nodes, "", 0, sets_, "", 1);
    // The entities: a vector declares cgx's magnitude "ALL" as a fourth, computed one
    // (IEXIST 1), as frd.c does for DISP; a tensor gives each component its row and column.
    fmt::format_to(put, " -4  {:<8}{:5d}{:5d}\n", f.name, vector ? 4 : nc, 1);
    static constexpr int row[6] = {1, 2, 3, 1, 2, 3}, column[6] = {1, 2, 3, 2, 3, 1};
    for (int k = 0; k < nc; ++k) {
      const int type = vector ? 2 : tensor ? 4 : 1;
      const int index1 = vector ? k + 1 : tensor ? row[k] : 0;
      const int index2 = tensor ? column[k] : 0;
      fmt::format_to(put, " -5  {:<8}{:5d}{:5d}{:5d}{:5d}\n", f.components[k], 1, type, index1,
                     index2);
    }
    if (vector)
      fmt::format_to(put, " -5  {:<8}{:5d}{:5d}{:5d}{:5d}{:5d}ALL\n", "ALL", 1, 2, 0, 0, 1);
    // Values: six to a record; a node's further ones on " -2" records (frdselect.c).
    for (int i : node_order_) {
      fmt::format_to(put, " -1{:10d}", node_label_[i]);
      for (int k = 0; k < nc; ++k) {
        if (k > 0 && k % 6 == 0) s += "\n -2          ";
        frd_put_number(s, f.values[static_cast<std::size_t>(i) * nc + k]);
      }
      s += '\n';
      if (s.size() > (1 << 20)) flush(s);
    }
    s += frd_block_end;
  }
  flush(s);
}

void FrdWriter::close() {
  if (closed_) return;
  closed_ = true;
  // cgx manual: the file ends with Format:(1X,'9999').
  out_ << " 9999\n";
  out_.close();
  if (!out_)
    throw OutputError(fmt::format("cannot write {}: {}", file_.string(), std::strerror(errno)));
}

FrdWriter::~FrdWriter() {
  try {
    close();
  } catch (...) {
    // A destructor must not throw; a caller that wants to know calls close().
  }
}

int FrdWriter::adopt(const std::filesystem::path& old, double up_to) {
  std::ifstream in(old);
  std::string line, block, s;
  bool in_results = false, keep = false;
  int last_set = 0;
  const double slack = 1e-6 * std::max(1.0, std::abs(up_to));  // the time's printed digits
  auto end_block = [&] {
    if (keep) s += block;
    block.clear();
  };
  while (std::getline(in, line)) {
    if (line.rfind("    1PSTEP", 0) == 0) {  // a block's parameter record
      end_block();
      in_results = true;
      keep = false;
    } else if (!in_results) {
      continue;  // the header and the mesh: this writer wrote its own
    } else if (line.rfind(" 9999", 0) == 0) {
      break;
    } else if (line.rfind("  100CL", 0) == 0 && line.size() >= 24) {
      // "  100CL" and the set's 100 + k in five columns, then the time in twelve.
      const double t = std::strtod(line.substr(12, 12).c_str(), nullptr);
      keep = t <= up_to + slack;
      if (keep) {
        last_set = std::atoi(line.substr(7, 5).c_str()) - 100;
        ++blocks_;
      }
    }
    block += line;
    block += '\n';
  }
  end_block();
  flush(s);
  sets_ = std::max(sets_, last_set);
  return sets_;
}

void FrdWriter::flush(std::string& text) {
  out_.write(text.data(), static_cast<std::streamsize>(text.size()));
  text.clear();
  if (!out_)
    throw OutputError(fmt::format("cannot write {}: {}", file_.string(), std::strerror(errno)));
}

}  // namespace hencky
