// export/common.h (private): what the exporter's files share: colour helpers, the source's
// rotation taken out, the chosen metric of a fit's errors.
#pragma once

#include <algorithm>
#include <string>
#include <string_view>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "aniso/export/export.h"

namespace aniso::exporter {

using json = nlohmann::json;

inline double luminance_avg(const glm::dvec3& c) { return (c.x + c.y + c.z) / 3.0; }
inline double max3(const glm::dvec3& c) { return std::max({c.x, c.y, c.z}); }

inline std::string fmt3(const glm::dvec3& c, const char* sep = ", ") {
  return fmt::format("{:.9g}{}{:.9g}{}{:.9g}", c.x, sep, c.y, sep, c.z);
}
inline json j3(const glm::dvec3& c) { return json::array({c.x, c.y, c.z}); }

inline bool has_scalar(const ParamValues& p, std::string_view key) {
  const auto it = p.values.find(key);
  return it != p.values.end() && std::holds_alternative<double>(it->second);
}

// The source as built, with its tangent rotation (rotation_deg, when the table has it) taken out:
// the exporter fits the unrotated material and writes the rotation into each target's own input.
inline MaterialDesc unrotated(const MaterialDesc& d) {
  MaterialDesc u = d;
  if (has_scalar(u.params, "rotation_deg")) u.params.values["rotation_deg"] = 0.0;
  return u;
}

inline double rotation_of(const MaterialDesc& d) {
  return has_scalar(d.params, "rotation_deg") ? d.params.scalar("rotation_deg") : 0.0;
}

inline double metric_of(const FitErrors& e, FitMetric m) { return m == FitMetric::L2Cos ? e.l2cos_all : e.log_all; }

inline bool no_diffuse(const GgxSource& g) { return max3(g.kd) < 1e-6; }

// The roughness and anisotropy of the targets whose alphas are r^2 / aspect and r^2 aspect with
// aspect^2 = 1 - scale a (Blender's Principled: scale 0.9; MaterialX: 1): r^2 = sqrt(ax ay), a =
// (1 - ay / ax) / scale, the larger alpha first (extra = the tangent's turn); a capped at `cap`
// (keeping the mean alpha) and r at 1, each with a note.
struct RoughAniso {
  double extra, rough, aniso;
};
RoughAniso invert_aspect(double& ax, double& ay, double scale, double cap, std::string_view who, std::vector<std::string>& notes);

// Mitsuba 3's principled (mitsuba3.cpp): the target model with these parameters, the
// parameters of an aniso principled source, and what still differs between the two.
TargetBrdf mitsuba_principled_model(const MitsubaPrincipled& mp, double turn, double rotation_deg, json& p,
                                    std::vector<std::string>& notes);
MitsubaPrincipled principled_params(const PrincipledT<double>& s);
std::vector<std::string> principled_differences(const MitsubaPrincipled& mp);

}  // namespace aniso::exporter
