// io/names.cpp: aliases and "did you mean" suggestions.
#include "io/names.h"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

namespace aniso {

std::string canonical_spelling(std::string_view name) {
  static const std::pair<std::string_view, std::string_view> kAliases[] = {{"aluminum", "aluminium"}};
  std::string s(name);
  for (const auto& [from, to] : kAliases) {
    // Whole components only (split at '-' and '/'): "aluminum" inside a longer word stays.
    size_t pos = 0;
    while ((pos = s.find(from, pos)) != std::string::npos) {
      const bool starts = pos == 0 || s[pos - 1] == '-' || s[pos - 1] == '/';
      const size_t end = pos + from.size();
      const bool ends = end == s.size() || s[end] == '-' || s[end] == '/';
      if (starts && ends) {
        s.replace(pos, from.size(), to);
        pos += to.size();
      } else {
        pos = end;
      }
    }
  }
  return s;
}

namespace {

// Optimal string alignment distance (Damerau-Levenshtein with adjacent transpositions).
size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

std::string nearest_names(std::string_view query_in, const std::vector<std::string>& candidates, size_t max) {
  if (query_in.empty() || query_in.size() > 200) return {};
  const std::string query = lower(query_in);
  std::vector<std::pair<size_t, const std::string*>> scored;
  for (const std::string& c : candidates) {
    const std::string lc = lower(c);
    const size_t slash = lc.rfind('/');
    const std::string_view last = slash == std::string::npos ? std::string_view(lc) : std::string_view(lc).substr(slash + 1);
    size_t dist = std::min(edit_distance(query, lc), edit_distance(query, last));
    if (lc.rfind(query, 0) == 0 && query.size() >= 3) dist = std::min<size_t>(dist, 1);  // a prefix of the name
    scored.emplace_back(dist, &c);
  }
  std::stable_sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  const size_t limit = std::max<size_t>(2, query.size() / 3);
  std::string out;
  for (size_t i = 0; i < scored.size() && i < max; ++i) {
    if (scored[i].first > limit) break;
    out += fmt::format("{}\"{}\"", out.empty() ? "" : ", ", *scored[i].second);
  }
  return out;
}

}  // namespace aniso
