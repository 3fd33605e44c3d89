// The table behind NAME_Exact: R = f_r cos(theta_i) over (a = N.H, u = N.L). See povray.h for why
// these coordinates and nodes (and not lut.h's slice from bake()) and for POV-Ray's slope pattern.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <random>

#include <tbb/parallel_for.h>

#include "exporters/povray.h"
#include "libbrdf/error.h"
#include "povray_internal.h"

namespace libbrdf::povray {

using namespace detail;  // NOLINT: this file is the detail's main user

namespace {

// Greedy node placement in slope-value space (POV-Ray interpolates linearly in s): repeatedly
// halve the interval with the largest relative interpolation error until `budget` nodes or
// every interval is below `tolerance`. `forced` holds nodes that must be present (ends included).
std::vector<double> place_nodes(std::vector<double> forced, int budget, double tolerance,
                                const std::function<double(double, double)>& interval_error) {
  std::sort(forced.begin(), forced.end());
  forced.erase(std::unique(forced.begin(), forced.end(), [](double p, double q) { return std::abs(p - q) < 1e-12; }),
               forced.end());
  struct Interval {
    double error, s0, s1;
    bool operator<(const Interval& o) const { return error < o.error; }
  };
  std::priority_queue<Interval> queue;
  std::vector<double> nodes = forced;
  for (std::size_t i = 0; i + 1 < forced.size(); ++i)
    queue.push({interval_error(forced[i], forced[i + 1]), forced[i], forced[i + 1]});
  while (static_cast<int>(nodes.size()) < budget && !queue.empty() && queue.top().error > tolerance) {
    const Interval worst = queue.top();
    queue.pop();
    const double mid = 0.5 * (worst.s0 + worst.s1);
    if (worst.s1 - worst.s0 < 1e-9) continue;  // cannot usefully split further
    nodes.push_back(mid);
    queue.push({interval_error(worst.s0, mid), worst.s0, mid});
    queue.push({interval_error(mid, worst.s1), mid, worst.s1});
  }
  std::sort(nodes.begin(), nodes.end());
  return nodes;
}

// Piecewise-linear interpolation in x over sorted nodes, clamped to the ends (POV-Ray blend maps).
struct Bracket {
  std::size_t i0, i1;
  double w1;  // weight of i1
};
Bracket bracket(const std::vector<double>& nodes, double x) {
  if (x <= nodes.front()) return {0, 0, 0.0};
  if (x >= nodes.back()) return {nodes.size() - 1, nodes.size() - 1, 0.0};
  const std::size_t i1 = static_cast<std::size_t>(std::upper_bound(nodes.begin(), nodes.end(), x) - nodes.begin());
  const std::size_t i0 = i1 - 1;
  return {i0, i1, (x - nodes[i0]) / (nodes[i1] - nodes[i0])};
}

}  // namespace

SliceGeometry make_slice_geometry(const Direction& light, const Direction& view) {
  SliceGeometry g;
  g.light = unit(light, "light-dir");
  g.view = unit(view, "view-dir");
  const Vec3 sum{g.light[0] + g.view[0], g.light[1] + g.view[1], g.light[2] + g.view[2]};
  const double sum_norm = std::sqrt(dot(sum, sum));
  if (sum_norm < 1e-6)
    throw InvalidArgument("light-dir", "must not be opposite to view-dir (no surface point is both lit and seen)");
  g.half = {sum[0] / sum_norm, sum[1] / sum_norm, sum[2] / sum_norm};
  g.cos_2theta_d = std::clamp(dot(g.light, g.view), -1.0, 1.0);  // eq. 5
  g.cos_theta_d = 0.5 * sum_norm;
  const Vec3 diff{g.light[0] - g.view[0], g.light[1] - g.view[1], g.light[2] - g.view[2]};
  g.sin_theta_d = 0.5 * std::sqrt(dot(diff, diff));
  return g;
}

ScatterAngles angles_at(const SliceGeometry& g, double n_dot_h, double n_dot_l) {
  const double u = std::clamp(n_dot_l, 0.0, 1.0);
  const double v = std::clamp(2.0 * g.cos_theta_d * n_dot_h - n_dot_l, 0.0, 1.0);
  const double sin_i = std::sqrt(1.0 - u * u), sin_s = std::sqrt(1.0 - v * v);
  // eq. 5: cos 2theta_d = cos ti cos ts + sin ti sin ts cos phi_s. At normal incidence or view
  // phi_s is immaterial; on the fold it is 0 or pi up to rounding.
  double cos_phi = -1.0;
  if (sin_i * sin_s > 1e-12) cos_phi = std::clamp((g.cos_2theta_d - u * v) / (sin_i * sin_s), -1.0, 1.0);
  ScatterAngles angles;
  angles.theta_i = std::acos(u);
  angles.theta_s = std::acos(v);
  angles.phi_s = std::acos(cos_phi);
  return angles;
}

double slope_value(double x) { return 0.5 + std::asin(std::clamp(x, -1.0, 1.0)) / kPi; }
double slope_inverse(double s) { return std::sin(kPi * (s - 0.5)); }

double HalfVectorSlice::lookup(int channel, double n_dot_h, double n_dot_l) const {
  // POV-Ray blends the entries linearly in the pattern value, so do the same in s.
  const Bracket ba = bracket(half_slopes, slope_value(n_dot_h));
  const Bracket bu = bracket(light_slopes, slope_value(n_dot_l));
  auto row = [&](std::size_t i) {
    return (1.0 - bu.w1) * value(channel, i, bu.i0) + bu.w1 * value(channel, i, bu.i1);
  };
  return (1.0 - ba.w1) * row(ba.i0) + ba.w1 * row(ba.i1);
}

namespace {

void validate_slice_request(const SliceRequest& request) {
  if (!is_brdf(request.model))
    throw InvalidArgument("model", "'" + std::string(model_name(request.model)) +
                                       "' is not a BRDF (choose mbk, bk, bk-modified, microfacet, ...)");
  if (request.entries < 8 || request.entries > kMaxMapEntries)
    throw InvalidArgument("resolution", "must be an integer in [8, 256] (POV-Ray 3.7 map entries per axis; got " +
                                            std::to_string(request.entries) + ")");
  if (request.channels.empty()) throw InvalidArgument("wavelength", "at least one channel is required");
  if (!(request.error_floor_fraction > 0.0 && request.error_floor_fraction < 1.0))
    throw InvalidArgument("error-floor", "must be in (0, 1)");
}

// The error floor per channel: error_floor_fraction x the largest |R| among the peak (N = H,
// `peak`) and a coarse survey of the lit, visible normals.
std::vector<double> error_floor(const SliceGeometry& g, const SliceRadiance& radiance, const std::vector<double>& peak,
                                double fraction) {
  const auto nc = static_cast<std::size_t>(radiance.channels());
  std::vector<double> floor(nc, 0.0), r(nc);
  for (int i = 0; i <= 64; ++i)
    for (int j = 0; j < 16; ++j) {
      const NormalCosines n = normal_at(g, 0.5 * kPi * i / 64.0, 2.0 * kPi * j / 16.0);
      if (radiance.evaluate(n.a, n.u, r.data()))
        for (std::size_t k = 0; k < nc; ++k) floor[k] = std::max(floor[k], std::abs(r[k]));
    }
  for (std::size_t k = 0; k < nc; ++k) floor[k] = fraction * std::max({floor[k], peak[k], 1e-300});
  return floor;
}

// Error of one table interval along a probe curve p(t), t in [0, 1] between the interval's ends:
// the chord of the end values against the exact value at interior points, counted where the point
// lies in the error domain (theta <= 85 deg), so cells reaching towards the horizon are still
// right inside the domain. `at` gives the cosines of p(t), or false when p(t) is not lit and seen.
struct ChordError {
  const SliceRadiance& radiance;
  const std::vector<double>& floor;

  double operator()(const std::function<bool(double, NormalCosines&)>& at,
                    const std::function<bool(const NormalCosines&, double*)>& value) const {
    const std::size_t nc = floor.size();
    std::vector<double> r0(nc), r1(nc), rx(nc);
    NormalCosines c0{}, c1{}, cx{};
    if (!at(0.0, c0) || !at(1.0, c1) || !value(c0, r0.data()) || !value(c1, r1.data())) return 0.0;
    double worst = 0.0;
    for (double w : {0.125, 0.25, 0.5, 0.75, 0.875}) {
      if (!at(w, cx) || !radiance.in_error_domain(cx.a, cx.u) || !value(cx, rx.data())) continue;
      for (std::size_t k = 0; k < nc; ++k)
        worst = std::max(worst, std::abs((1.0 - w) * r0[k] + w * r1[k] - rx[k]) / std::max(std::abs(rx[k]), floor[k]));
    }
    return worst;
  }
};
constexpr double kNodeTolerance = 2e-4;

// Half-vector axis (slope values of a = N.H): probes along curves of constant azimuth psi around H
// (alpha = angle from H, s_H = 1 - alpha/pi, so t is linear in alpha as POV-Ray's interpolation is).
std::vector<double> place_half_nodes(const SliceGeometry& g, const ChordError& chord_worst, int entries) {
  auto exact = [&](const NormalCosines& c, double* out) { return chord_worst.radiance.evaluate(c.a, c.u, out); };
  const std::vector<double> psi_probes{0.0, kPi / 6, kPi / 3, kPi / 2, 2 * kPi / 3, 5 * kPi / 6, kPi};
  auto half_error = [&](double s0, double s1) {
    const double alpha0 = kPi * (1.0 - s0), alpha1 = kPi * (1.0 - s1);
    double worst = 0.0;
    for (double psi : psi_probes)
      worst = std::max(worst, chord_worst([&](double t, NormalCosines& c) {
        c = normal_at(g, alpha0 + (alpha1 - alpha0) * t, psi);
        return true;
      }, exact));
    return worst;
  };
  // Forced: a = 0, 1; a = sin(theta_d), below which the terminator and the horizon are reachable
  // (so no interval mixes rows that end at N.L = 0 with rows that do not); a uniform start every
  // 90/32 deg of alpha, whose first interval holds no normal of the error domain (there
  // N.L + N.V = 2 cos(theta_d) a < 2 cos(85 deg)), so no probe needs the unevaluable row a = 0.
  std::vector<double> forced_half{slope_value(0.0), slope_value(1.0), slope_value(g.sin_theta_d)};
  for (int i = 1; i < 32; ++i) forced_half.push_back(0.5 + 0.5 * i / 32.0);
  return place_nodes(forced_half, entries, kNodeTolerance, half_error);
}

// Light axis (slope values of u = N.L): probes along rows of constant a, each clipped to the row's
// feasible interval (an interval that only partly overlaps a row still carries that row's curvature).
std::vector<double> place_light_nodes(const SliceGeometry& g, const ChordError& chord_worst, int entries) {
  const std::size_t nc = chord_worst.floor.size();
  std::vector<double> probe_rows;
  for (int i = 1; i < 32; ++i) probe_rows.push_back(std::cos(0.5 * kPi * i / 32.0));
  for (double alpha : {0.002, 0.005, 0.01, 0.02, 0.05}) probe_rows.push_back(std::cos(alpha));
  probe_rows.push_back(g.cos_theta_d);  // alpha = theta_d: the row through N = L (u = 1)
  auto light_error = [&](double s0, double s1) {
    double worst = 0.0;
    for (double a : probe_rows) {
      const FeasibleInterval f = feasible_u(g, a);
      const double c0 = std::max(s0, slope_value(f.lo)), c1 = std::min(s1, slope_value(f.hi));
      if (!(c1 - c0 > 1e-9)) continue;
      worst = std::max(worst, chord_worst([&](double t, NormalCosines& c) {
        c = {a, slope_inverse(c0 + (c1 - c0) * t)};
        return true;
      }, [&](const NormalCosines& c, double* out) {
        if (c.u <= 0.0 && f.terminator) {  // R = 0 at the terminator itself
          std::fill(out, out + nc, 0.0);
          return true;
        }
        return chord_worst.radiance.evaluate(c.a, c.u, out);
      }));
    }
    return worst;
  };
  std::vector<double> forced_light{slope_value(0.0), slope_value(1.0)};
  for (int i = 1; i < 32; ++i) forced_light.push_back(0.5 + 0.5 * i / 32.0);
  return place_nodes(forced_light, entries, kNodeTolerance, light_error);
}

// Row i (constant a = half_nodes[i]) of the table: exact at the feasible nodes, linear
// continuations of the row's ends beyond them.
void fill_slice_row(HalfVectorSlice& slice, const SliceRadiance& radiance, std::size_t i) {
  const SliceGeometry& g = slice.geometry;
  const auto nc_size = static_cast<std::size_t>(radiance.channels());
  const std::size_t na = slice.half_nodes.size(), nu = slice.light_nodes.size();
  const double a = slice.half_nodes[i];
  const FeasibleInterval f = feasible_u(g, a);
  // Known points of this row: feasible nodes and the interval's ends (value 0 at the terminator,
  // none at the horizon where f may diverge).
  std::vector<double> known_u;
  std::vector<std::vector<double>> known_r;
  std::vector<double> rr(nc_size);
  auto add = [&](double u, const std::vector<double>& values) {
    known_u.push_back(u);
    known_r.push_back(values);
  };
  if (f.terminator) add(0.0, std::vector<double>(nc_size, 0.0));
  else if (radiance.evaluate(a, f.lo, rr.data())) add(f.lo, rr);
  for (double u : slice.light_nodes)
    if (u > f.lo && u < f.hi && radiance.evaluate(a, u, rr.data())) add(u, rr);
  if (!f.horizon && f.hi > f.lo && radiance.evaluate(a, f.hi, rr.data())) add(f.hi, rr);
  if (known_u.empty()) add(f.lo, std::vector<double>(nc_size, 0.0));  // a = 0: only N.L = N.V = 0

  // A second point for the slope of the continuation: at least a quarter node spacing away, so
  // that a regime switch inside the model cannot turn a tiny difference into a wild slope.
  const double min_gap = 0.25 / static_cast<double>(nu);
  auto partner = [&](std::size_t from, int step) -> std::ptrdiff_t {
    std::ptrdiff_t best = -1;
    const auto count = static_cast<std::ptrdiff_t>(known_u.size());
    for (auto j = static_cast<std::ptrdiff_t>(from) + step; j >= 0 && j < count; j += step) {
      best = j;
      if (std::abs(known_u[static_cast<std::size_t>(j)] - known_u[from]) >= min_gap) break;
    }
    return best;
  };
  const std::size_t first = 0, last = known_u.size() - 1;
  const std::ptrdiff_t first_partner = partner(first, +1), last_partner = partner(last, -1);
  for (std::size_t j = 0; j < nu; ++j) {
    const double u = slice.light_nodes[j];
    for (std::size_t k = 0; k < nc_size; ++k) {
      double value;
      if (u >= known_u[first] && u <= known_u[last]) {
        // Inside: exact at feasible nodes (found among the known points), else interpolated
        // between the known neighbours (only happens for nodes within rounding of the ends).
        const auto hi = static_cast<std::size_t>(std::lower_bound(known_u.begin(), known_u.end(), u) - known_u.begin());
        if (hi < known_u.size() && known_u[hi] == u) value = known_r[hi][k];
        else {
          const std::size_t lo = hi - 1;
          const double w = (u - known_u[lo]) / (known_u[hi] - known_u[lo]);
          value = (1.0 - w) * known_r[lo][k] + w * known_r[hi][k];
        }
      } else if (u < known_u[first]) {
        // Below the fold: linear continuation (never the terminator: that is u = 0 itself).
        value = known_r[first][k];
        if (first_partner >= 0) {
          const auto p = static_cast<std::size_t>(first_partner);
          value += (known_r[p][k] - known_r[first][k]) / (known_u[p] - known_u[first]) * (u - known_u[first]);
        }
      } else if (f.horizon) {
        value = known_r[last][k];  // beyond N.V = 0: only silhouette pixels blend this in
      } else {
        value = known_r[last][k];
        if (last_partner >= 0) {
          const auto p = static_cast<std::size_t>(last_partner);
          value += (known_r[last][k] - known_r[p][k]) / (known_u[last] - known_u[p]) * (u - known_u[last]);
        }
      }
      slice.values[(k * na + i) * nu + j] = std::max(0.0, value);  // a continuation may undershoot
    }
  }
}

// Error at random lit, visible normals: half uniform on the sphere, half uniform in the angle
// from H (which samples the specular peak densely).
LutError measure_slice_error(const HalfVectorSlice& slice, const SliceRadiance& radiance, const std::vector<double>& floor,
                             const SliceRequest& request) {
  const SliceGeometry& g = slice.geometry;
  std::vector<double> r(floor.size());
  std::mt19937_64 rng(request.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double max_rel = 0.0, max_rel_all = 0.0, sum_sq = 0.0;
  int counted = 0;
  for (int n = 0; n < request.error_samples; ++n) {
    NormalCosines c{};
    if (n % 2 == 0) {
      const double z = 2.0 * uniform(rng) - 1.0, phi = 2.0 * kPi * uniform(rng), rho = std::sqrt(1.0 - z * z);
      const Vec3 N{rho * std::cos(phi), rho * std::sin(phi), z};
      c = {dot(N, g.half), dot(N, g.light)};
    } else {
      c = normal_at(g, 0.5 * kPi * uniform(rng), 2.0 * kPi * uniform(rng));
    }
    if (!radiance.evaluate(c.a, c.u, r.data())) continue;
    const bool in_domain = radiance.in_error_domain(c.a, c.u);
    for (int k = 0; k < radiance.channels(); ++k) {
      const auto ku = static_cast<std::size_t>(k);
      if (std::abs(r[ku]) < floor[ku]) continue;
      const double rel = std::abs(slice.lookup(k, c.a, c.u) - r[ku]) / std::abs(r[ku]);
      max_rel_all = std::max(max_rel_all, rel);
      if (!in_domain) continue;
      max_rel = std::max(max_rel, rel);
      sum_sq += rel * rel;
      ++counted;
    }
  }
  LutError error;
  error.max_relative = max_rel;
  error.rms_relative = counted > 0 ? std::sqrt(sum_sq / counted) : 0.0;
  error.floor = *std::max_element(floor.begin(), floor.end());
  error.samples = counted;
  error.theta_limit_deg = kErrorThetaLimitDeg;
  error.max_relative_all = max_rel_all;
  return error;
}

}  // namespace

HalfVectorSlice bake_half_vector_slice(const SliceRequest& request) {
  validate_slice_request(request);
  HalfVectorSlice slice;
  slice.geometry = make_slice_geometry(request.light, request.view);
  const SliceGeometry& g = slice.geometry;
  const std::vector<Model> models = channel_models(request.model, request.channels);
  for (const ModelParameters& p : request.channels) slice.wavelengths_um.push_back(p.wavelength_um);
  const SliceRadiance radiance(g, models);

  slice.peak.assign(static_cast<std::size_t>(radiance.channels()), 0.0);
  radiance.evaluate(1.0, g.cos_theta_d, slice.peak.data());  // N = H
  const std::vector<double> floor = error_floor(g, radiance, slice.peak, request.error_floor_fraction);

  const ChordError chord_worst{radiance, floor};
  std::vector<double> s_half = place_half_nodes(g, chord_worst, request.entries);
  std::vector<double> s_light = place_light_nodes(g, chord_worst, request.entries);
  slice.half_nodes.resize(s_half.size());
  slice.light_nodes.resize(s_light.size());
  std::transform(s_half.begin(), s_half.end(), slice.half_nodes.begin(), slope_inverse);
  std::transform(s_light.begin(), s_light.end(), slice.light_nodes.begin(), slope_inverse);
  slice.half_nodes.front() = slice.light_nodes.front() = 0.0;  // exact ends (sin rounding)
  slice.half_nodes.back() = slice.light_nodes.back() = 1.0;
  slice.half_slopes = std::move(s_half);
  slice.light_slopes = std::move(s_light);

  // Fill, one row of constant a per task.
  slice.values.assign(floor.size() * slice.half_nodes.size() * slice.light_nodes.size(), 0.0);
  tbb::parallel_for(std::size_t{0}, slice.half_nodes.size(), [&](std::size_t i) { fill_slice_row(slice, radiance, i); });
  slice.error = measure_slice_error(slice, radiance, floor, request);
  return slice;
}

}  // namespace libbrdf::povray
