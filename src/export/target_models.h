// export/target_models.h (private): GGX -> each target, the parameters a target writes and the model
// the target renders with them (targets.h). target_model (target_models.cpp) calls one function per
// target, each in its writer's file: blender.cpp, mitsuba3.cpp (Mitsuba 3 and pbrt-v4, one model with
// their masking and names apart; Mitsuba 3's principled), materialx.cpp (standard_surface and
// OpenPBR), gltf.cpp; what they share is here, defined in target_models.cpp.
#pragma once

#include <string>
#include <vector>

#include "export/common.h"

namespace aniso::exporter {

// The anisotropic GGX of the target's "major axis along the tangent" convention: the larger alpha
// along the (rotated) tangent; returns the extra rotation (0 or 90 degrees) this needs.
double major_first(double& ax, double& ay);

// A fraction of a turn in [0, 1), -0 as 0.
double wrap_turn(double t);

// The exact Fresnel (a dielectric of index eta, or a conductor of eta 1 and extinction k) closest
// to Schlick's curve s(c) = (f0 + (1 - f0)(1 - c)^5) / scale over c in [0, 1] (least squares on 64
// points, a 1-D golden-section search per form): the targets that have no Schlick Fresnel get the
// curve, not only its F0 (F0 = 0 with Schlick's grazing rise is not eta = 1, which reflects nothing).
struct ExactFresnel {
  double eta = 1.5, k = 0.0;
};
ExactFresnel match_schlick(double f0, double scale, bool allow_conductor);

// A dielectric F0 colour for the targets whose dielectric Fresnel takes a tint (Blender 4.x's Specular
// Tint, OpenPBR's and MaterialX standard_surface's specular_color; targets.h): the index whose exact Fresnel is closest to
// Schlick's curve of the largest channel (match_schlick; a grey F0 gets the index of its own curve, as before the tint) and the
// tint F0 / max(F0), every channel in [0, 1]: the written reflectance at normal incidence has the source's hue exactly, its
// largest channel the index's F0.
struct TintedDielectric {
  double eta = 1.5;
  glm::dvec3 tint{1.0};
};
TintedDielectric tinted_dielectric(const glm::dvec3& f0_in);

// The source's reflectance at normal incidence: the conductor's F(1; n, k), else Schlick's F0.
inline glm::dvec3 source_f0(const GgxSource& g) {
  return g.conductor ? glm::dvec3(F_Conductor(1.0, RGBT<double>(g.eta), RGBT<double>(g.k))) : g.f0;
}

// The models, one per target (their files above).
TargetBrdf blender_model(const GgxSource& g, json& p, std::vector<std::string>& notes, double blender_version,
                         BlenderV1Nodes nodes);
TargetBrdf mitsuba_pbrt_model(Target t, const GgxSource& g, json& p, std::vector<std::string>& notes);
TargetBrdf materialx_model(const GgxSource& g, json& p, std::vector<std::string>& notes);
TargetBrdf openpbr_model(const GgxSource& g, json& p, std::vector<std::string>& notes);
TargetBrdf gltf_model(const GgxSource& g, json& p, std::vector<std::string>& notes);

}  // namespace aniso::exporter
