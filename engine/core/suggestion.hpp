#pragma once
// "Did you mean": the candidate closest to a misspelt name, by edit distance
// (insertions, deletions, substitutions and swaps of neighbours) or by
// naming only the last part of a dotted key ("restitution" for
// "collision.restitution"). None where nothing is close.

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

namespace granflow {

inline std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

inline std::optional<std::string> closest_name(const std::string& name, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = std::max<std::size_t>(2, name.size() / 3) + 1;
  for (const auto& candidate : candidates) {
    const auto dot = candidate.rfind('.');
    if (dot != std::string::npos && candidate.substr(dot + 1) == name) return candidate;
    const std::size_t distance = edit_distance(name, candidate);
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  return best;
}

// "; did you mean 'x'?" or, with nothing close, "; known NOUN: a, b, c".
inline std::string suggestion_text(const std::string& name, const std::vector<std::string>& candidates,
                                   const std::string& noun) {
  if (const auto close = closest_name(name, candidates)) return "; did you mean '" + *close + "'?";
  std::string list;
  for (const auto& candidate : candidates) list += (list.empty() ? "" : ", ") + candidate;
  return "; known " + noun + ": " + list;
}

}  // namespace granflow
