#pragma once
// What an exported material does with energy (issue 11): the directional albedo a(theta_i) of the
// exported model (libbrdf/albedo.h: white-furnace integral, specular spike included) at a few
// incidence angles, stated in the Blender JSON and the POV-Ray include header, with the
// energy-conserving choice where one exists (mbk, mbk-rough, mbk-fg: --k-mode tis, when measured <= 1).
#include <string>
#include <vector>

#include "libbrdf/models.h"

namespace exporters {

struct EnergySummary {
  std::vector<double> theta_i_deg;            // the incidence angles
  std::vector<std::vector<double>> albedo;    // [channel][angle]
  double max_albedo = 0.0;                    // over channels and angles
  double other_k_mode_max_albedo = 0.0;       // models with K: the same with the other K mode
  std::string k_mode;                         // "plane" | "tis" | "" (model without K)
  std::string advice;                         // one line: which choice conserves energy
};

// Albedo at theta_i = 0, 30, 60, 80, 85 deg of each channel's model (and, for models with K, the
// largest albedo with the other K mode, so that the advice is measured, not assumed).
EnergySummary energy_summary(libbrdf::ModelKind kind, const std::vector<libbrdf::ModelParameters>& channels);

}  // namespace exporters
