// aniso/fit/plot.h: measured against fitted BRDF in the plane of incidence (`aniso fit --plot`).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "aniso/measured/samples.h"

namespace aniso {

struct PlotMaterial {
  nlohmann::json material;
  std::string label;
};

// One panel per incidence angle (the most populated theta_i of the data's in-plane samples, or
// 0, 30, 60, 75 degrees when the data have none): f (log scale) against the signed outgoing angle
// in the plane of incidence (positive towards the mirror direction), the fitted material as lines,
// the measured samples within 1.5 degrees of the plane (and of the panel's theta_i) as dots. An
// anisotropic material (one with rotation_deg) adds two rows, with the light at phi_i = 0: the
// slice across the plane of incidence through the mirror direction, and the mirror cone
// (theta_o = theta_i, all phi_o), where its two widths show; their dots are the samples whose light
// is within 5 degrees of phi_i = 0. One material: a colour per channel; several (--compare): a
// colour per material, the mean of the channels, and a legend. Written as PNG (image/image_io.h,
// atomically).
void write_slices_plot(const std::string& path, const SampleSet& data, const std::vector<PlotMaterial>& materials);

}  // namespace aniso
