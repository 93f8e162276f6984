// io/names.h: spelling help for names a user types (presets, metals, models, commands).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace aniso {

// Accepted alternative spellings (docs/presets.md, "Aliases"): American "aluminum" for
// "aluminium", as a whole component of any name ("brushed-aluminum"). Returns the canonical name,
// or `name` unchanged. Callers try the exact name first. ("chrome" is not an alias of "chromium":
// MERL's "chrome" is a different material, ngan/*/chrome.)
std::string canonical_spelling(std::string_view name);

// Up to `max` candidates nearest to `query` (Damerau-Levenshtein distance, plus candidates whose
// last path component or prefix matches), formatted as "\"gold\", \"brushed-gold\""; empty when
// nothing is close (distance above a third of the query's length, at least 2).
std::string nearest_names(std::string_view query, const std::vector<std::string>& candidates, size_t max = 3);

}  // namespace aniso
