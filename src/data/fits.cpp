#include "aniso/data/fits.h"

#include <fmt/format.h>

#include "aniso/io/input_error.h"

namespace aniso {
namespace embedded {
extern const std::string_view pbrt_v1_lafortune_csv;
extern const std::string_view ngan2005_csv;
}  // namespace embedded

std::vector<CsvRow> parse_csv(std::string_view text, std::string_view source, size_t columns) {
  std::vector<CsvRow> rows;
  bool header_seen = false;
  size_t line_no = 0;
  while (!text.empty()) {
    const size_t eol = text.find('\n');
    std::string_view line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || line.front() == '#') continue;
    if (!header_seen) {
      header_seen = true;
      continue;
    }
    CsvRow row;
    size_t start = 0;
    while (true) {
      const size_t comma = line.find(',', start);
      row.emplace_back(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (row.size() != columns)
      throw InputError(
          fmt::format("{}: line {}: expected {} comma-separated fields, got {}", source, line_no, columns, row.size()));
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<CsvRow> pbrt_v1_lafortune_rows() {
  return parse_csv(embedded::pbrt_v1_lafortune_csv, "data/fits/lafortune-pbrt-v1/pbrt_v1_lafortune_materials.csv", 6);
}

std::vector<CsvRow> ngan2005_rows() {
  return parse_csv(embedded::ngan2005_csv, "data/fits/ngan2005/ngan2005_all_models_from_bbm.csv", 9);
}

}  // namespace aniso
