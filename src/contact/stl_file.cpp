#include "contact/stl_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cmath>
#include <fstream>
#include <iterator>

namespace hencky::stl {

namespace fs = std::filesystem;

namespace {

std::uint32_t le_u32(const char* p) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(p[i]);
  return v;
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return (x | 0x20) == (y | 0x20);  // ASCII letters only, which is all we compare
         });
}

void check_finite(const Vec3& x, int triangle, const SourceLocation& where) {
  if (x.allFinite()) return;
  throw InputError(where, fmt::format("triangle {} has a vertex with a non-finite coordinate {} "
                                      "(NaN, infinite, or too large for the scale factor); "
                                      "re-export or repair the file",
                                      triangle, point_str(x)));
}

/// Binary STL: 80-byte header, uint32 triangle count, then per triangle 12 little-endian
/// float32 (normal, three vertices) and a 2-byte attribute.
Soup read_binary(std::string_view bytes, const SourceLocation& where, double scale) {
  const std::size_t n = le_u32(bytes.data() + 80);
  Soup soup;
  soup.corners.reserve(3 * n);
  for (std::size_t t = 0; t < n; ++t) {
    const char* v = bytes.data() + 84 + 50 * t + 12;  // the stored normal is ignored
    for (int k = 0; k < 3; ++k) {
      Vec3 x;
      for (int j = 0; j < 3; ++j) x[j] = scale * std::bit_cast<float>(le_u32(v + 12 * k + 4 * j));
      check_finite(x, static_cast<int>(t) + 1, where);
      soup.corners.push_back(x);
    }
  }
  return soup;
}

/// Tokens of an ASCII STL with their line numbers; every failure names the line.
class AsciiReader {
 public:
  AsciiReader(std::string_view text, const SourceLocation& where) : text_(text), where_(where) {}

  /// The next whitespace-separated token, empty at the end of the file.
  std::string_view next() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    token_line_ = line_;
    return text_.substr(start, pos_ - start);
  }
  /// Skips the rest of the current line (the name after "solid" and "endsolid").
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  void expect(std::string_view keyword, std::string_view why = "") {
    const std::string_view tok = next();
    if (!iequals(tok, keyword))
      fail(fmt::format("expected '{}'{}, found {}", keyword, why, quote(tok)));
  }
  /// Three numbers on the line of the keyword just read.
  Vec3 triple(std::string_view keyword, std::string_view what) {
    const int keyword_line = token_line_;
    Vec3 v;
    for (int j = 0; j < 3; ++j) {
      std::string_view tok = next();
      if (tok.empty() || token_line_ != keyword_line) {
        token_line_ = keyword_line;
        fail(fmt::format("expected three numbers after '{}' on this line, found {}", keyword, j));
      }
      const std::string_view shown = tok;
      if (tok.front() == '+') tok.remove_prefix(1);  // from_chars rejects a '+' sign
      const auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v[j]);
      if (ec == std::errc::result_out_of_range)
        fail(fmt::format("{} {} is out of the range of double precision", what, quote(shown)));
      if (ec != std::errc() || end != tok.data() + tok.size())
        fail(fmt::format("expected a number ({}), found {}", what, quote(shown)));
    }
    return v;
  }
  int line() const { return token_line_; }
  SourceLocation here() const { return SourceLocation{where_.file, token_line_, 0, ""}; }
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(here(), "malformed ASCII STL: " + message);
  }

 private:
  static std::string quote(std::string_view tok) {
    if (tok.empty()) return "the end of the file";
    if (tok.size() > 40) return fmt::format("'{}...'", tok.substr(0, 40));
    return fmt::format("'{}'", tok);
  }

  std::string_view text_;
  SourceLocation where_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int token_line_ = 1;
};

/// ASCII STL: one or more "solid name ... endsolid name" blocks of
/// "facet normal n n n / outer loop / vertex x y z (3x) / endloop / endfacet".
Soup read_ascii(std::string_view text, const SourceLocation& where, double scale) {
  AsciiReader in(text, where);
  Soup soup;
  in.expect("solid");
  in.skip_line();
  for (;;) {
    const std::string_view tok = in.next();
    if (iequals(tok, "facet")) {
      const int facet_line = in.line();
      in.expect("normal", " after 'facet'");
      in.triple("normal", "a component of the facet normal");
      in.expect("outer", " (each facet starts 'outer loop')");
      in.expect("loop", " after 'outer'");
      for (int k = 0; k < 3; ++k) {
        in.expect("vertex", " (each facet has three vertices)");
        const Vec3 x = scale * in.triple("vertex", "a vertex coordinate");
        check_finite(x, static_cast<int>(soup.line.size()) + 1, in.here());
        soup.corners.push_back(x);
      }
      in.expect("endloop", " (a facet has exactly three vertices)");
      in.expect("endfacet", " after 'endloop'");
      soup.line.push_back(facet_line);
    } else if (iequals(tok, "endsolid")) {
      in.skip_line();
      const std::string_view after = in.next();
      if (after.empty()) break;
      if (!iequals(after, "solid"))
        in.fail(fmt::format("expected 'solid' or the end of the file after 'endsolid', found '{}'",
                            after.substr(0, 40)));
      in.skip_line();
    } else if (tok.empty()) {
      in.fail("the file ends before 'endsolid' (is it truncated?)");
    } else {
      in.fail(fmt::format("expected 'facet' or 'endsolid', found '{}'", tok.substr(0, 40)));
    }
  }
  return soup;
}

}  // namespace

std::string point_str(const Vec3& x) {
  return fmt::format("({:.9g}, {:.9g}, {:.9g})", x[0], x[1], x[2]);
}

void check_scale(const SourceLocation& where, double scale) {
  if (!(std::isfinite(scale) && scale > 0))
    throw InputError(where, fmt::format("the scale of the STL surface must be a positive number, "
                                        "not {}",
                                        scale));
}

std::string read_stl_file(const fs::path& file, double scale) {
  const SourceLocation where{file.string(), 0, 0, ""};
  check_scale(where, scale);
  std::error_code ec;
  if (!fs::exists(file, ec)) throw InputError(where, "the STL file does not exist; check the path");
  if (fs::is_directory(file, ec))
    throw InputError(where, "this is a directory, not an STL file; check the path");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(where, "cannot open the STL file for reading; check its permissions");
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError(where, "reading the STL file failed (I/O error)");
  return bytes;
}

Soup parse_stl(std::string_view bytes, const SourceLocation& where, double scale) {
  if (bytes.empty()) throw InputError(where, "the STL file is empty");

  // A binary file may begin with "solid" too, so the size decides: a binary STL is exactly
  // 84 + 50 n bytes. An ASCII STL starts with "solid" and holds no NUL byte.
  if (bytes.size() >= 84 && 84 + 50 * std::uint64_t{le_u32(bytes.data() + 80)} == bytes.size())
    return read_binary(bytes, where, scale);
  const std::size_t first = bytes.find_first_not_of(" \t\r\n");
  const bool ascii = first != std::string_view::npos && bytes.size() - first >= 5 &&
                     iequals(bytes.substr(first, 5), "solid") &&
                     (bytes.size() - first == 5 || is_space(bytes[first + 5])) &&
                     bytes.find('\0') == std::string_view::npos;
  if (ascii) return read_ascii(bytes, where, scale);
  if (bytes.size() < 84)
    throw InputError(where, fmt::format("not an STL file: it has {} bytes, fewer than the 84 of a "
                                        "binary STL header, and does not start with 'solid' as an "
                                        "ASCII STL does",
                                        bytes.size()));
  const std::uint64_t n = le_u32(bytes.data() + 80);
  throw InputError(where, fmt::format("truncated or corrupt binary STL: its header announces {} "
                                      "triangles, which take 84 + 50 x {} = {} bytes, but the file "
                                      "has {} bytes; re-export the file",
                                      n, n, 84 + 50 * n, bytes.size()));
}

}  // namespace hencky::stl
