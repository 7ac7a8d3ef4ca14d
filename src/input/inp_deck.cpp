#include "input/inp_deck.hpp"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hencky::inp {

namespace fs = std::filesystem;

std::string read_text(const std::filesystem::path& file, const char* what) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw InputError(SourceLocation{file.string(), 0, 0, ""},
                     std::string("cannot open the ") + what);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return u;
}

std::string_view trim(std::string_view s) {
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return s;
}

std::string unquote(std::string_view s) {
  s = trim(s);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return std::string(s);
}

std::vector<std::string_view> fields(std::string_view s) {
  std::vector<std::string_view> out;
  bool quoted = false;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= s.size(); ++i) {
    if (i < s.size() && s[i] == '"') quoted = !quoted;
    if (i == s.size() || (s[i] == ',' && !quoted)) {
      out.push_back(trim(s.substr(start, i - start)));
      start = i + 1;
    }
  }
  return out;
}

Keyword parse_keyword(std::string_view text) {
  Keyword k;
  const auto f = fields(text.substr(1));
  std::string name;
  for (char c : upper(f[0]))
    if (c != ' ' && c != '\t')
      name += c;
    else if (!name.empty() && name.back() != ' ')
      name += ' ';
  k.name = std::string(trim(name));
  for (std::size_t i = 1; i < f.size(); ++i) {
    if (f[i].empty()) continue;
    const auto eq = f[i].find('=');
    if (eq == std::string_view::npos)
      k.params.emplace_back(upper(trim(f[i])), "");
    else
      k.params.emplace_back(upper(trim(f[i].substr(0, eq))), unquote(f[i].substr(eq + 1)));
  }
  return k;
}

void Deck::add(std::string_view text, int file, int depth) {
  int number = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const Line l{file, ++number, trim(text.substr(pos, end - pos))};
    pos = end + 1;
    if (l.text.empty() || l.text.rfind("**", 0) == 0) continue;
    if (l.text.front() == '*' && parse_keyword(l.text).name == "INCLUDE") {
      include(l, depth);
      continue;
    }
    lines.push_back(l);
  }
}

void Deck::include(const Line& l, int depth) {
  const Keyword k = parse_keyword(l.text);
  const std::string* input = k.get("INPUT");
  if (!input || input->empty()) throw fail(l, "*INCLUDE needs INPUT=<file>");
  if (depth >= 16) throw fail(l, "*INCLUDE nested more than 16 deep (does a file include itself?)");
  fs::path path(*input);
  if (path.is_relative()) path = fs::path(names[l.file]).parent_path() / path;
  std::error_code ec;
  std::ifstream in;
  if (fs::is_regular_file(path, ec)) in.open(path, std::ios::binary);
  if (!in.is_open() || !in)
    throw fail(l, "*INCLUDE: cannot open " + path.string() +
                      " as a file (a relative path is taken from the including file's folder)");
  std::ostringstream ss;
  ss << in.rdbuf();
  names.push_back(path.string());
  texts.push_back(std::make_unique<std::string>(ss.str()));
  add(*texts.back(), static_cast<int>(names.size()) - 1, depth + 1);
}

}  // namespace hencky::inp
