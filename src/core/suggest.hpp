#pragma once
// "Did you mean ...?" for misspelt keys, enumeration values and region names.
#include <cstddef>
#include <string>
#include <vector>

namespace hencky {

/// Levenshtein distance between a and b, ignoring ASCII case.
std::size_t edit_distance(const std::string& a, const std::string& b);

/// The candidate closest to `word` (case-insensitive Levenshtein distance), or "" when none is
/// reasonably close: the distance must be at most max(2, word.size()/3) and smaller than the
/// longer of the two lengths (so that 'q' is not "corrected" into 'E').
/// Ties go to the earlier candidate.
std::string closest(const std::string& word, const std::vector<std::string>& candidates);

/// "did you mean 'xxx'?", or "" when closest() finds nothing.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

/// The names quoted and comma separated: "'a', 'b', 'c'"; after `max_names` names the rest are
/// counted ("... and 12 more"). "(none)" for an empty list.
std::string name_list(const std::vector<std::string>& names, std::size_t max_names = 30);

/// The full hint for an unknown name: "did you mean 'xxx'? valid <what>: 'a', 'b', 'c'", or only
/// "valid <what>: ..." when nothing is close. `what` is e.g. "keys here", "regions", "schemes".
std::string suggestion(const std::string& word, const std::vector<std::string>& candidates,
                       const std::string& what);

}  // namespace hencky
