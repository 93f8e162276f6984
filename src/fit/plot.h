// fit/plot.h: measured against fitted BRDF in the plane of incidence (`aniso fit --plot`).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "measured/samples.h"

namespace aniso {

// One panel per incidence angle (the most populated theta_i of the data's in-plane samples, or
// 0, 30, 60, 75 degrees when the data have none): f (log scale) against the signed outgoing angle
// in the plane of incidence (positive towards the mirror direction), the fitted material as lines,
// the measured samples within 1.5 degrees of the plane (and of the panel's theta_i) as dots, one
// colour per channel. Written as PNG (render/image.h, atomically).
void write_slices_plot(const std::string& path, const SampleSet& data, const nlohmann::json& material,
                       const std::string& title);

}  // namespace aniso
