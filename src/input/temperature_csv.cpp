#include "input/temperature_csv.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <system_error>
#include <vector>

namespace hencky::case_input {

namespace fs = std::filesystem;

namespace {

struct CsvCell {
  std::string text;
  int column;  // 1-based
};

std::vector<CsvCell> split_csv(const std::string& line) {
  std::vector<CsvCell> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::string raw =
        line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::size_t lead = raw.find_first_not_of(" \t");
    cells.push_back(
        {trim(raw), static_cast<int>(start + (lead == std::string::npos ? 0 : lead)) + 1});
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cells;
}

/// The file in messages and the case's key that names it.
struct CsvFile {
  const std::string& label;
  const std::string& key;

  [[noreturn]] void fail_at(int line, int column, const std::string& msg) const {
    throw InputError(SourceLocation{label, line, column, key}, msg);
  }
};

/// The header row "node,<time 1>,<time 2>,...": the times, strictly increasing.
void read_header(const CsvFile& f, int line_no, const std::vector<CsvCell>& cells,
                 std::vector<double>& times) {
  if (lower(cells[0].text) != "node")
    f.fail_at(line_no, cells[0].column,
              "expected the header row 'node,<time 1>,<time 2>,...', found '" + cells[0].text +
                  "' as the first column name");
  if (cells.size() < 2)
    f.fail_at(line_no, 0, "the header row lists no times: expected 'node,<time 1>,<time 2>,...'");
  for (std::size_t j = 1; j < cells.size(); ++j) {
    double t = 0;
    if (!parse_double(cells[j].text, t) || !std::isfinite(t))
      f.fail_at(line_no, cells[j].column,
                "expected a time in the header row, found '" + cells[j].text + "'");
    if (!times.empty() && !(t > times.back()))
      f.fail_at(line_no, cells[j].column,
                "the times in the header row must be strictly increasing, found " + num(t) +
                    " after " + num(times.back()));
    times.push_back(t);
  }
}

}  // namespace

TemperatureFile read_temperature_csv(const Reader& r, const Val& v) {
  TemperatureFile tf;
  const std::string name = r.string(v, "a file name");
  tf.path = r.resolve(name);
  std::error_code ec;
  if (!fs::is_regular_file(tf.path, ec))
    r.fail(v, "temperature file not found: " + tf.path.string() +
                  " (relative paths are taken from the case file's folder)");
  std::ifstream in(tf.path);
  if (!in) r.fail(v, "cannot open the temperature file " + tf.path.string());
  read_temperature_rows(in, tf.path.string(), v.path, tf);
  return tf;
}

void read_temperature_rows(std::istream& in, const std::string& label, const std::string& key,
                           TemperatureFile& tf) {
  const CsvFile f{label, key};
  std::string line;
  int line_no = 0;
  bool header = false;
  std::size_t n_cols = 0;
  std::map<long, int> seen;  // node tag -> line
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 BOM
    if (trim(line).empty()) continue;
    const auto cells = split_csv(line);
    if (!header) {
      read_header(f, line_no, cells, tf.times);
      n_cols = cells.size();
      header = true;
      continue;
    }
    if (cells.size() != n_cols)
      f.fail_at(line_no, 0,
                "expected " + std::to_string(n_cols) +
                    " values (the node tag, then one per time), found " +
                    std::to_string(cells.size()));
    long tag = 0;
    if (!parse_long(cells[0].text, tag) || tag <= 0)
      f.fail_at(line_no, cells[0].column,
                "expected a node tag (a whole number > 0), found '" + cells[0].text + "'");
    if (auto prev = seen.find(tag); prev != seen.end())
      f.fail_at(line_no, cells[0].column,
                "node " + std::to_string(tag) + " is listed twice (first at line " +
                    std::to_string(prev->second) + ")");
    seen.emplace(tag, line_no);
    tf.node_tags.push_back(tag);
    for (std::size_t j = 1; j < cells.size(); ++j) {
      double T = 0;
      if (!parse_double(cells[j].text, T) || !std::isfinite(T))
        f.fail_at(line_no, cells[j].column,
                  "expected a temperature (a number), found '" + cells[j].text + "'");
      tf.values.push_back(T);
    }
  }
  if (!header)
    f.fail_at(0, 0,
              "the temperature file is empty: expected 'node,<time 1>,...' then one row per node");
  if (tf.node_tags.empty())
    f.fail_at(line_no, 0, "the temperature file has a header but no node rows");
}

}  // namespace hencky::case_input
