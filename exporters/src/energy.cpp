// energy.h: the albedo statement of an export.
#include "exporters/energy.h"

#include <algorithm>
#include <cstdio>

#include "libbrdf/albedo.h"

namespace exporters {

using libbrdf::ModelKind;

namespace {
// Albedo rows [channel][angle] of the model with the channels' parameters, K mode overridden.
std::vector<std::vector<double>> albedo_rows(ModelKind kind, std::vector<libbrdf::ModelParameters> channels,
                                             const std::vector<double>& angles_deg, const libbrdf::KMode* k_mode,
                                             double* max_albedo) {
  std::vector<std::vector<double>> rows;
  *max_albedo = 0.0;
  for (libbrdf::ModelParameters& p : channels) {
    if (k_mode) p.k_mode = *k_mode;
    const libbrdf::Model model(kind, p);
    std::vector<double> row;
    for (double t : angles_deg) {
      row.push_back(libbrdf::directional_albedo(model, libbrdf::degrees_to_radians(t)).total);
      *max_albedo = std::max(*max_albedo, row.back());
    }
    rows.push_back(row);
  }
  return rows;
}
}  // namespace

EnergySummary energy_summary(ModelKind kind, const std::vector<libbrdf::ModelParameters>& channels) {
  EnergySummary s;
  s.theta_i_deg = {0.0, 30.0, 60.0, 80.0, 85.0};
  s.albedo = albedo_rows(kind, channels, s.theta_i_deg, nullptr, &s.max_albedo);
  const bool has_k = libbrdf::model_traits(kind).always_renormalized();
  char text[200];
  if (has_k) {
    const bool tis = channels.front().k_mode == libbrdf::KMode::tis;
    s.k_mode = tis ? "tis" : "plane";
    const libbrdf::KMode other = tis ? libbrdf::KMode::plane : libbrdf::KMode::tis;
    albedo_rows(kind, channels, s.theta_i_deg, &other, &s.other_k_mode_max_albedo);
  }
  if (s.max_albedo <= 1.0) {
    s.advice = "albedo <= 1 at every angle stated: conserves energy";
  } else if (has_k && s.k_mode == "plane" && s.other_k_mode_max_albedo <= 1.0) {
    std::snprintf(text, sizeof text, "albedo > 1: the plane K (eq. 13) creates energy near grazing; --k-mode tis conserves it "
                  "(albedo max %.3f)", s.other_k_mode_max_albedo);
    s.advice = text;
  } else if (has_k) {
    std::snprintf(text, sizeof text, "albedo > 1 with either K (this %.3f, the other %.3f): Qbar exceeds F away from "
                  "specular on this rough surface; no K mode conserves energy here", s.max_albedo, s.other_k_mode_max_albedo);
    s.advice = text;
  } else if (kind == ModelKind::bk) {
    s.advice = "albedo > 1: F_bk^2 (eq. 26) grows towards the horizon; bk-modified conserves better";
  } else {
    s.advice = "albedo > 1 at some angle stated (README, brdf albedo)";
  }
  return s;
}

}  // namespace exporters
