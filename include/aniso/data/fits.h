// aniso/data/fits.h: published fits carried inside the binary (data/fits/*.csv, embedded at build time by
// cmake/embed_text.cmake, so nothing is read from disk at run time).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace aniso {

// One row of a CSV file, split on commas; lines starting with '#' and the header are skipped.
using CsvRow = std::vector<std::string>;
std::vector<CsvRow> parse_csv(std::string_view text, std::string_view source, size_t columns);

// pbrt-v1's Lafortune fits (Cornell measurements): material,term,lobe,r,g,b.
std::vector<CsvRow> pbrt_v1_lafortune_rows();
// Ngan, Durand & Matusik 2005 fits of the MERL materials, from bbm: model,material,kd_r..ks_b,params.
std::vector<CsvRow> ngan2005_rows();

}  // namespace aniso
