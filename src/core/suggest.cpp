#include "core/suggest.hpp"

#include <algorithm>
#include <cctype>

namespace hencky {

namespace {
char lower(char c) {
  return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
}
}  // namespace

std::size_t edit_distance(const std::string& a, const std::string& b) {
  // Two-row dynamic programme.
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t subst = prev[j - 1] + (lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, subst});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string closest(const std::string& word, const std::vector<std::string>& candidates) {
  const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  std::string best;
  std::size_t best_d = limit + 1;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d && d < std::max(word.size(), c.size())) {
      best = c;
      best_d = d;
    }
  }
  return best;
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string c = closest(word, candidates);
  return c.empty() ? std::string() : "did you mean '" + c + "'?";
}

std::string name_list(const std::vector<std::string>& names, std::size_t max_names) {
  if (names.empty()) return "(none)";
  std::string s;
  const std::size_t n = std::min(names.size(), std::max<std::size_t>(max_names, 1));
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) s += ", ";
    s += "'" + names[i] + "'";
  }
  if (n < names.size()) s += " ... and " + std::to_string(names.size() - n) + " more";
  return s;
}

std::string suggestion(const std::string& word, const std::vector<std::string>& candidates,
                       const std::string& what) {
  const std::string hint = did_you_mean(word, candidates);
  const std::string list = "valid " + what + ": " + name_list(candidates);
  return hint.empty() ? list : hint + " " + list;
}

}  // namespace hencky
