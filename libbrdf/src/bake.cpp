// bake(): evaluates a model on a layout's node grid (oneTBB), its R_spec / K side tables, and the
// table's error at random off-grid points; --target-error grows the grid geometrically.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <random>
#include <sstream>

#include "angular_simd.h"
#include "bake_internal.h"
#include "libbrdf/error.h"
#include "libbrdf/lut.h"
#include "libbrdf/version.h"
#include "lut_internal.h"

namespace libbrdf {
std::string shape_text(const std::array<int, 3>& shape, LutLayout layout) {
  std::string text = std::to_string(shape[0]) + "x" + std::to_string(shape[1]);
  if (layout != LutLayout::slice) text += "x" + std::to_string(shape[2]);
  return text;
}

namespace {

void require_direction(const char* parameter, const Direction& d) {
  const double length2 = d.x * d.x + d.y * d.y + d.z * d.z;
  if (!(std::isfinite(length2) && length2 > 0.0))
    throw InvalidArgument(parameter, "must be a finite nonzero vector X,Y,Z (world space, pointing away from the surface)");
}

void validate_request(const BakeRequest& r) {
  if (!is_brdf(r.model))
    throw InvalidArgument("model", std::string(model_name(r.model)) + " is not a BRDF and cannot be baked (one of " +
                                       model_names_where([](const ModelTraits& row) { return row.is_brdf(); }) + ")");
  if (r.channels.empty()) throw InvalidArgument("wavelength", "at least one channel (wavelength) is needed");
  if (r.layout == LutLayout::kernel && !model_traits(r.model).asf_based)
    throw InvalidArgument("layout", "kernel factors the ASF models only (" + detail::asf_model_names() + "), not " +
                                        std::string(model_name(r.model)));
  if (r.channels.size() > 64) throw InvalidArgument("wavelength", "at most 64 channels (got " + std::to_string(r.channels.size()) + ")");
  if (r.resolution && r.target_error)
    throw InvalidArgument("target-error", "give either a resolution or a target error, not both");
  if (r.target_error) {
    if (!(std::isfinite(*r.target_error) && *r.target_error > 0.0 && *r.target_error < 1.0))
      throw InvalidArgument("target-error", "must be a relative error in (0, 1)");
    if (r.layout == LutLayout::merl)
      throw InvalidArgument("target-error", "not available for layout merl (its grid is fixed at 90x90x180)");
  }
  if (r.resolution) {
    const auto& s = *r.resolution;
    const bool slice = r.layout == LutLayout::slice;
    for (int k = 0; k < (slice ? 2 : 3); ++k)
      if (s[k] < 2 || s[k] > 4096)
        throw InvalidArgument("resolution", "nodes per axis must be in [2, 4096] (got " + shape_text(s, r.layout) + ")");
    if (r.layout == LutLayout::merl && s != kMerlShape)
      throw InvalidArgument("resolution", "layout merl is fixed at 90x90x180 (got " + shape_text(s, r.layout) + ")");
    const double nodes = double(s[0]) * s[1] * (slice ? 1 : s[2]);
    if (nodes * double(r.channels.size()) > double(std::size_t{1} << 28))
      throw InvalidArgument("resolution", "table too large: " + shape_text(s, r.layout) + " x " +
                                              std::to_string(r.channels.size()) + " channels exceeds 2^28 values");
  }
  if (r.layout == LutLayout::slice) {
    require_direction("light-dir", r.light);
    require_direction("view-dir", r.view);
    if (!(radians_to_degrees(slice_theta_d(r.light, r.view)) < kHorizonThetaLimitDeg))
      throw InvalidArgument("view-dir", "light and view directions must be less than " +
                                            std::to_string(2 * kHorizonThetaLimitDeg) + " deg apart");
  }
  if (!(r.error_floor_fraction >= 0.0 && r.error_floor_fraction < 1.0))
    throw InvalidArgument("error-floor", "fraction of the table maximum must be in [0, 1)");
  if (r.error_samples < 1 || r.error_samples > 1000000) throw InvalidArgument("error-samples", "must be in [1, 1000000]");
  if (!(r.error_theta_limit_deg > 0.0 && r.error_theta_limit_deg <= 90.0))
    throw InvalidArgument("error-theta-limit", "must be in (0, 90] degrees");
}

void check_cancel(const BakeRequest& r) {
  if (r.cancel && r.cancel->load(std::memory_order_relaxed)) throw BakeCancelled();
}

[[noreturn]] void non_finite(const ScatterAngles& a, int channel, double value) {
  std::ostringstream out;
  out.precision(17);
  out << "bake: the model gave a value that is not a finite float (" << value << ") at theta_i="
      << radians_to_degrees(a.theta_i) << ", theta_s=" << radians_to_degrees(a.theta_s)
      << ", phi_s=" << radians_to_degrees(a.phi_s) << " deg, channel " << channel;
  throw std::runtime_error(out.str());
}

// The geometries of one row of a half/difference layout (rusinkiewicz, merl, slice: fixed theta_h
// and theta_d, phi_d = pi k / span on every node k), as lut_node_angles + make_scatter_geometry
// give them, without their per-node atan2 / remainder / sin / cos: the directions of
// scatter_angles_from_half_difference (lut.cpp) in Cartesian form, i = R_y(theta_h) d and
// s = 2 cos theta_d h - i, read off as cosines and sines (theta = atan2(rho, z) there), with the
// horizon rule (polar angles limited to kHorizonThetaLimitDeg). Near the normal (rho < 1e-4) the
// azimuth is ill-conditioned and the node takes the scalar path: row_geometries lists those nodes.
struct RowFrame {
  std::vector<double> cos_phi_d, sin_phi_d;  // per node of a row
  double cos_limit, sin_limit;                // of the horizon limit
};
RowFrame row_frame(int row_length, double span) {
  RowFrame f;
  for (int k = 0; k < row_length; ++k) {
    const double phi_d = kPi * k / span;  // as detail::angles_at_index
    f.cos_phi_d.push_back(std::cos(phi_d));
    f.sin_phi_d.push_back(std::sin(phi_d));
  }
  const double limit = degrees_to_radians(kHorizonThetaLimitDeg);
  f.cos_limit = std::cos(limit);
  f.sin_limit = std::sin(limit);
  return f;
}

// sin and cos of theta_h, theta_d of a row (lut.h: the axis mappings, as detail::angles_at_index).
struct RowTrig {
  double sin_h, cos_h, sin_d, cos_d;
};
RowTrig row_trig(const Lut& lut, int i0, int i1, const std::array<double, 3>& span) {
  const double t0 = i0 / span[0];
  const double theta_h = 0.5 * kPi * t0 * t0;  // square map (the kernel layout is not baked by rows)
  const double theta_d = lut.layout == LutLayout::slice ? slice_theta_d(lut.light, lut.view) : 0.5 * kPi * i1 / span[1];
  return {std::sin(theta_h), std::cos(theta_h), std::sin(theta_d), std::cos(theta_d)};
}

// Incident and scattered directions of node k of a row (unit up to rounding, z may be <= 0).
detail::HalfDifferenceDirections node_directions(const RowFrame& f, const RowTrig& t, int k) {
  return detail::directions_from_half_difference(t.sin_h, t.cos_h, t.sin_d, t.cos_d, f.cos_phi_d[k], f.sin_phi_d[k]);
}

void row_geometries(const RowFrame& f, const RowTrig& t, int row_length, ScatterGeometry* geos,
                    std::vector<int>& scalar_nodes) {
  scalar_nodes.clear();
  // cos and sin of a polar angle from (rho, z), limited to the horizon rule's angle.
  auto polar = [&](double rho, double z, double& c, double& s) {
    const double r = std::sqrt(rho * rho + z * z);
    c = z / r;
    s = rho / r;
    if (c < f.cos_limit) {
      c = f.cos_limit;
      s = f.sin_limit;
    }
  };
  thread_local std::vector<double> trig;  // 6 per node: the sines and cosines of its three angles
  trig.assign(6 * static_cast<std::size_t>(row_length), 0.0);  // scalar nodes: zeros, overwritten by the caller
  for (int k = 0; k < row_length; ++k) {
    const detail::HalfDifferenceDirections n = node_directions(f, t, k);
    const double rho_i = std::sqrt(n.ix * n.ix + n.iy * n.iy), rho_s = std::sqrt(n.sx * n.sx + n.sy * n.sy);
    if (!(rho_i > 1e-4 && rho_s > 1e-4)) {
      scalar_nodes.push_back(k);
      continue;
    }
    double* node = trig.data() + 6 * k;
    polar(rho_i, n.iz, node[0], node[1]);
    polar(rho_s, n.sz, node[2], node[3]);
    // phi_s = azimuth of s - azimuth of i.
    const double inv = 1.0 / (rho_i * rho_s);
    node[4] = (n.ix * n.sx + n.iy * n.sy) * inv;
    node[5] = (n.ix * n.sy - n.iy * n.sx) * inv;
  }
  detail::geometries_from_trig(trig.data(), static_cast<std::size_t>(row_length), geos);
}

// Node values of every channel, multi-threaded, in ~100 chunks of rows so that the calling thread
// reports progress and honours the cancel flag between chunks (and the workers inside them).
// A row is the phi_d axis (the last axis; the second for the slice). Along phi_d the ASF of eq. 11
// is constant, since g and c depend only on cos ti + cos ts = 2 cos td cos th and
// eta_r = 2 cos td sin th: it is computed once per row (Model::asf_at) and passed to
// Model::evaluate(geo, asf) at every node of the row -- also at nodes whose directions the
// horizon rule limits (lut.h: they hold the ASF of their own (theta_h, theta_d)).
// Kernel layout: a node's P~ = P / K(theta_i) / (the closed-form part of P) (lut.h), P the model
// with A = 1. Where the closed form is all of P, P~ = 1 exactly; where it vanishes (n = 1, k = 0:
// F = Qbar = 0), so does P and the node holds 1 (any finite value gives the same product, 0).
double kernel_node_value(const Lut& lut, const Model& model, int channel, double theta_i, const ScatterGeometry& geo) {
  if (detail::kernel_angular_all_closed(lut.kernel_model, lut.kernel_angular)) return 1.0;
  double closed = 0.0;
  detail::kernel_closed_form_span(lut, channel, 1, &geo, 1, &closed, 1);
  const double divisor = model.renormalization(theta_i) * closed;
  return divisor > 0.0 ? model.evaluate(geo, 1.0) / divisor : 1.0;
}

void bake_nodes(const BakeRequest& r, const std::vector<Model>& models, Lut& lut, detail::BakeNodePath path) {
  const int channels = lut.channels();
  const std::size_t nodes = lut.nodes_per_channel();
  const bool slice = lut.layout == LutLayout::slice;
  const bool kernel = lut.layout == LutLayout::kernel;
  // The kernel layout divides each node by its own K and F (lut.h): node by node.
  const bool span_path = path == detail::BakeNodePath::span && !kernel;
  const int row_length = slice ? lut.shape[1] : lut.shape[2];
  const int rows = static_cast<int>(nodes / row_length);
  const std::array<double, 3> span = detail::lut_axis_spans(lut.layout, lut.shape);
  lut.values.assign(nodes * channels, 0.0f);
  const RowFrame frame = row_frame(row_length, slice ? span[1] : span[2]);
  const int chunks = std::min(rows, 100);
  for (int chunk = 0; chunk < chunks; ++chunk) {
    check_cancel(r);
    const int begin = static_cast<int>(static_cast<long long>(rows) * chunk / chunks);
    const int end = static_cast<int>(static_cast<long long>(rows) * (chunk + 1) / chunks);
    tbb::parallel_for(tbb::blocked_range<int>(begin, end, 1), [&](const tbb::blocked_range<int>& range) {
      std::vector<double> row_asf(channels);
      std::vector<int> scalar_nodes;
      std::vector<ScatterGeometry> row_geos(row_length);
      std::vector<double> asf_values(row_length), values(row_length);
      for (int row = range.begin(); row != range.end(); ++row) {
        if (r.cancel && r.cancel->load(std::memory_order_relaxed)) return;
        const int i0 = slice ? row : row / lut.shape[1];
        const int i1 = slice ? 0 : row % lut.shape[1];
        // The row's ASF at phi_d = pi/2, where ti = ts = acos(cos td cos th): a real geometry for
        // every theta_h, theta_d < 90 deg (rows at 90 deg have none and are evaluated node by node).
        bool row_feasible = false;
        const ScatterAngles middle = slice ? detail::angles_at_index(lut.layout, lut.shape, i0, 0.5 * span[1], 0, lut.light, lut.view, &row_feasible)
                                           : detail::angles_at_index(lut.layout, lut.shape, i0, i1, 0.5 * span[2], lut.light, lut.view, &row_feasible);
        if (row_feasible && !kernel) {
          const ScatterGeometry middle_geo = make_scatter_geometry(middle);
          for (int c = 0; c < channels; ++c) row_asf[c] = models[c].uses_asf() ? models[c].asf_at(middle_geo) : 0.0;
        }
        const std::size_t row_start = static_cast<std::size_t>(row) * row_length;
        auto node_angles = [&](int k) {
          return lut_node_angles(lut.layout, lut.shape, i0, slice ? k : i1, slice ? 0 : k, lut.light, lut.view);
        };
        auto store = [&](int k, int c, double value) {
          if (!(std::abs(value) <= double(FLT_MAX))) non_finite(node_angles(k), c, value);
          lut.values[c * nodes + row_start + k] = static_cast<float>(value);
        };
        if (span_path) {  // the row as one span: its geometries, then Model::evaluate_many per channel
          row_geometries(frame, row_trig(lut, i0, i1, span), row_length, row_geos.data(), scalar_nodes);
          for (int k : scalar_nodes) row_geos[k] = make_scatter_geometry(node_angles(k));
          for (int c = 0; c < channels; ++c) {
            const bool given = row_feasible && models[c].uses_asf();
            if (given) std::fill(asf_values.begin(), asf_values.end(), row_asf[c]);
            models[c].evaluate_many(row_geos.data(), row_length, values.data(), given ? asf_values.data() : nullptr);
            for (int k = 0; k < row_length; ++k) store(k, c, values[k]);
          }
          continue;
        }
        for (int k = 0; k < row_length; ++k) {
          const ScatterAngles angles = node_angles(k);
          const ScatterGeometry geo = make_scatter_geometry(angles);
          for (int c = 0; c < channels; ++c) {
            store(k, c, kernel ? kernel_node_value(lut, models[c], c, angles.theta_i, geo)
                               : row_feasible && models[c].uses_asf() ? models[c].evaluate(geo, row_asf[c])
                                                                      : models[c].evaluate(geo));
          }
        }
      }
    });
    if (r.progress) r.progress(double(chunk + 1) / chunks);
  }
  check_cancel(r);
}

// R_spec(theta_i) and K(theta_i) on the uniform theta_i grid, and their largest relative
// interpolation error at random theta_i (values below 1e-3 of the table's max ignored).
double bake_side_tables(const std::vector<Model>& models, Lut& lut, std::uint64_t seed) {
  const int n = kThetaINodes;
  const int channels = lut.channels();
  lut.specular_reflectance.assign(channels, std::vector<float>(n));
  lut.renormalization.assign(channels, std::vector<float>(n));
  tbb::parallel_for(0, channels, [&](int c) {
    for (int m = 0; m < n; ++m) {
      const double theta_i = 0.5 * kPi * m / (n - 1);
      lut.specular_reflectance[c][m] = static_cast<float>(models[c].specular_reflectance(theta_i));
      lut.renormalization[c][m] = static_cast<float>(models[c].renormalization(theta_i));
    }
  });
  std::mt19937_64 rng(seed ^ 0x5DEECE66DULL);
  std::uniform_real_distribution<double> uniform(0.0, 0.5 * kPi);
  double worst = 0.0;
  for (int c = 0; c < channels; ++c) {
    const double spec_max = *std::max_element(lut.specular_reflectance[c].begin(), lut.specular_reflectance[c].end());
    for (int k = 0; k < 2000; ++k) {
      const double theta_i = uniform(rng);
      const double spec = models[c].specular_reflectance(theta_i), k_value = models[c].renormalization(theta_i);
      if (spec > 1e-3 * double(spec_max)) worst = std::max(worst, std::abs(lut.specular_at(c, theta_i) - spec) / spec);
      worst = std::max(worst, std::abs(lut.renormalization_at(c, theta_i) - k_value) / k_value);
    }
  }
  return worst;
}

Lut bake_table(const BakeRequest& r, const std::vector<Model>& models, const std::array<int, 3>& shape,
               detail::BakeNodePath path) {
  Lut lut;
  lut.layout = r.layout;
  lut.shape = shape;
  if (lut.layout == LutLayout::slice) lut.shape[2] = 1;
  for (const ModelParameters& p : r.channels) lut.wavelengths_um.push_back(p.wavelength_um);
  if (lut.layout == LutLayout::kernel) {
    lut.kernel_model = r.model;
    lut.kernel_angular = r.kernel_angular;
    const bool fg_closed = detail::kernel_closed_form_reads_slopes(r.model, r.kernel_angular);
    for (const Model& m : models) {
      lut.kernel_sigma_over_lambda.push_back(m.surface().sigma_over_lambda());
      lut.kernel_lc_over_lambda.push_back(m.surface().lc_over_lambda());
      lut.kernel_index.push_back(*m.parameters().index);  // every ASF model needs n (validated)
      if (fg_closed) {  // what G/S needs at lookup
        lut.kernel_sigma_g.push_back(m.sigma_g());
        lut.kernel_g_term.push_back(m.parameters().g_term);
      }
    }
  }
  if (lut.layout == LutLayout::slice) {
    lut.light = r.light;
    lut.view = r.view;
  }
  bake_nodes(r, models, lut, path);
  const double side_error = bake_side_tables(models, lut, r.seed);
  lut.error = measure_lut_error(lut, models, r.error_samples, r.error_floor_fraction, r.seed, r.error_theta_limit_deg);
  check_cancel(r);
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", side_error);
  lut.attributes["side_tables_max_relative_error"] = buffer;
  std::snprintf(buffer, sizeof buffer, "%.17g", r.error_floor_fraction);
  lut.attributes["error_floor_fraction"] = buffer;
  lut.attributes["model"] = std::string(model_name(r.model));
  lut.attributes["parameters"] = detail::parameters_json(r.model, r.channels);
  lut.attributes["error_sampling"] =
      "uniform in the table's index space (off the nodes), real geometries only (both directions above the horizon); "
      "relative error |lut - model| / model over values >= error_floor (error_floor_fraction x the largest node "
      "value); max/rms over theta_i, theta_s <= error_theta_limit_deg, max_relative_error_all up to the horizon; "
      "seed " + std::to_string(r.seed);
  return lut;
}

std::array<int, 3> grown(const std::array<int, 3>& shape, LutLayout layout) {
  std::array<int, 3> next = shape;
  for (int k = 0; k < (layout == LutLayout::slice ? 2 : 3); ++k)
    next[k] = static_cast<int>(std::ceil(shape[k] * kTargetGrowthFactor));
  return next;
}

std::size_t node_count(const std::array<int, 3>& s, LutLayout layout) {
  return std::size_t(s[0]) * std::size_t(s[1]) * std::size_t(layout == LutLayout::slice ? 1 : s[2]);
}

}  // namespace

Lut bake(const BakeRequest& r) { return detail::bake(r, detail::BakeNodePath::span); }

Lut detail::bake(const BakeRequest& r, BakeNodePath path) {
  validate_request(r);
  std::vector<Model> models;
  models.reserve(r.channels.size());
  for (const ModelParameters& p : r.channels) {
    check_cancel(r);
    models.emplace_back(r.model, p);  // validates the parameters; builds (or reuses) the K table
  }
  // A kernel table whose angular factor is all closed form holds P~ = 1: the smallest shape.
  const bool ones = r.layout == LutLayout::kernel && r.kernel_angular == KernelAngular::closed_form &&
                    detail::kernel_angular_all_closed(r.model, r.kernel_angular);
  constexpr std::array<int, 3> kOnesShape{2, 2, 2};
  if (!r.target_error) {
    Lut lut = bake_table(r, models, r.resolution ? *r.resolution : ones ? kOnesShape : default_resolution(r.layout), path);
    detail::check_lut_consistency(lut, "bake");
    return lut;
  }
  std::array<int, 3> shape = ones ? kOnesShape : target_error_start_resolution(r.layout);
  std::string trials;
  char buffer[64];
  for (;;) {
    Lut lut = bake_table(r, models, shape, path);
    if (r.trial_done) r.trial_done(lut.shape, lut.error);
    std::snprintf(buffer, sizeof buffer, "%.3g", lut.error.max_relative);
    trials += (trials.empty() ? "" : "; ") + shape_text(lut.shape, r.layout) + ": " + buffer;
    if (lut.error.max_relative <= *r.target_error) {
      std::snprintf(buffer, sizeof buffer, "%.17g", *r.target_error);
      lut.attributes["target_error"] = buffer;
      lut.attributes["target_error_trials"] = trials;
      detail::check_lut_consistency(lut, "bake");
      return lut;
    }
    const std::array<int, 3> next = grown(shape, r.layout);
    if (node_count(next, r.layout) > kMaxTargetNodes) {
      std::snprintf(buffer, sizeof buffer, "%.3g", lut.error.max_relative);
      throw InvalidArgument("target-error", "not reached: the largest table tried (" + shape_text(lut.shape, r.layout) +
                                                ") has a measured max relative error of " + buffer);
    }
    shape = next;
  }
}

std::vector<ScatterAngles> random_table_geometries(LutLayout layout, int count, double theta_limit_deg,
                                                   std::uint64_t seed, const Direction& light, const Direction& view) {
  if (count < 0) throw InvalidArgument("count", "must be >= 0");
  if (!(theta_limit_deg > 0.0 && theta_limit_deg <= 90.0)) throw InvalidArgument("theta limit", "must be in (0, 90] degrees");
  const double limit = degrees_to_radians(theta_limit_deg);
  // A two-node grid per axis: index coordinates in [0, 1] are the axis fractions.
  const std::array<int, 3> unit_shape = layout == LutLayout::slice ? std::array<int, 3>{2, 2, 1} : std::array<int, 3>{2, 2, 2};
  const LutLayout grid = layout == LutLayout::merl ? LutLayout::rusinkiewicz : layout;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<ScatterAngles> out;
  out.reserve(count);
  for (long long attempt = 0; static_cast<int>(out.size()) < count; ++attempt) {
    if (attempt > 1000LL * (count + 1)) throw InvalidArgument("theta limit", "no geometry of this table lies inside the limit");
    const double x0 = uniform(rng), x1 = uniform(rng), x2 = uniform(rng);
    bool feasible = false;
    const ScatterAngles a = detail::angles_at_index(grid, unit_shape, x0, x1, grid == LutLayout::slice ? 0.0 : x2, light, view, &feasible);
    if (feasible && a.theta_i <= limit && a.theta_s <= limit) out.push_back(a);
  }
  return out;
}

LutError measure_lut_error(const Lut& lut, const std::vector<Model>& channel_models, int samples, double floor_fraction,
                           std::uint64_t seed, double theta_limit_deg) {
  if (static_cast<int>(channel_models.size()) != lut.channels())
    throw InvalidArgument("models", "one model per channel is needed (" + std::to_string(lut.channels()) + ")");
  if (samples < 1) throw InvalidArgument("error-samples", "must be >= 1");
  if (!(theta_limit_deg > 0.0 && theta_limit_deg <= 90.0))
    throw InvalidArgument("error-theta-limit", "must be in (0, 90] degrees");
  // The reference is the full series (tolerance 0: no closed form, no kernel table), so that a
  // table that itself evaluates Sigma from the kernel table (the kernel layout) is not measured
  // against that same table: the error stated is against the series. K comes from the model's
  // K table either way (same surface: reused, not rebuilt).
  std::vector<Model> models;
  for (const Model& m : channel_models) {
    ModelParameters exact = m.parameters();
    exact.tolerance = 0.0;
    models.emplace_back(m.kind(), exact);
  }
  const double theta_limit = degrees_to_radians(theta_limit_deg);
  auto inside = [theta_limit](const ScatterAngles& a) { return a.theta_i <= theta_limit && a.theta_s <= theta_limit; };
  const int channels = lut.channels();
  const std::size_t nodes = lut.nodes_per_channel();
  const bool slice = lut.layout == LutLayout::slice;
  const int row_length = slice ? lut.shape[1] : lut.shape[2];

  // The floor: floor_fraction x the largest node value among the nodes inside the measured
  // domain (nodes near or below the horizon may hold much larger values for models that
  // diverge there, e.g. bk's F_bk^2; they must not raise the floor over the whole table).
  // Rows of the half/difference layouts decide "feasible and inside" from the node directions
  // (no per-node atan2); nodes within 1e-12 of either boundary in cosine take the angles.
  const std::array<double, 3> axis_span = detail::lut_axis_spans(lut.layout, lut.shape);
  const bool by_directions = lut.layout != LutLayout::kernel;
  const RowFrame frame = row_frame(row_length, slice ? axis_span[1] : axis_span[2]);
  const double cos_theta_limit = std::cos(theta_limit);
  auto classify = [&](double x, double y, double z) {  // 1 inside, 0 not, -1 undecided
    const double c = z / std::sqrt(x * x + y * y + z * z);
    if (std::abs(c - cos_theta_limit) < 1e-12 || std::abs(c) < 1e-12 || !std::isfinite(c)) return -1;
    return c > cos_theta_limit && c > 0.0 ? 1 : 0;
  };
  std::vector<float> row_max(nodes / row_length, 0.0f);
  tbb::parallel_for(0, static_cast<int>(row_max.size()), [&](int row) {
    const RowTrig trig = by_directions ? row_trig(lut, slice ? row : row / lut.shape[1], slice ? 0 : row % lut.shape[1], axis_span)
                                       : RowTrig{};
    for (int k = 0; k < row_length; ++k) {
      const int i0 = slice ? row : row / lut.shape[1], i1 = slice ? k : row % lut.shape[1], i2 = slice ? 0 : k;
      if (by_directions) {
        const detail::HalfDifferenceDirections n = node_directions(frame, trig, k);
        const int incident = classify(n.ix, n.iy, n.iz), scattered = classify(n.sx, n.sy, n.sz);
        if (incident == 0 || scattered == 0) continue;
        if (incident == 1 && scattered == 1) {
          const std::size_t index = static_cast<std::size_t>(row) * row_length + k;
          for (int c = 0; c < channels; ++c) row_max[row] = std::max(row_max[row], lut.values[c * nodes + index]);
          continue;
        }
      }
      bool feasible = false;
      const ScatterAngles a = detail::angles_at_index(lut.layout, lut.shape, i0, i1, i2, lut.light, lut.view, &feasible);
      if (!feasible || !inside(a)) continue;
      const std::size_t index = static_cast<std::size_t>(row) * row_length + k;
      if (lut.layout == LutLayout::kernel) {  // the nodes hold the angular factor: the BRDF is rebuilt
        const ScatterGeometry geo = make_scatter_geometry(a);
        detail::TableAngles angles;
        detail::table_angles_for(lut, &geo, 1, &angles);
        std::vector<double> brdf(channels);
        detail::lookup_channels(lut, geo, angles, 0, channels, brdf.data());
        for (double v : brdf) row_max[row] = std::max(row_max[row], static_cast<float>(v));
        continue;
      }
      for (int c = 0; c < channels; ++c) row_max[row] = std::max(row_max[row], lut.values[c * nodes + index]);
    }
  });
  LutError error;
  error.floor = floor_fraction * double(*std::max_element(row_max.begin(), row_max.end()));
  error.theta_limit_deg = theta_limit_deg;

  // Batches of points drawn sequentially (reproducible from the seed) and evaluated in parallel,
  // until `samples` values above the floor inside the domain are compared (or 50 x samples
  // points were drawn: lobes that fill a small part of the table get a fair share of samples).
  std::mt19937_64 rng(seed);
  const std::array<double, 3> span = detail::lut_axis_spans(lut.layout, lut.shape);
  std::array<std::uniform_real_distribution<double>, 3> axis{
      std::uniform_real_distribution<double>(0.0, span[0]), std::uniform_real_distribution<double>(0.0, span[1]),
      std::uniform_real_distribution<double>(0.0, span[2])};
  const std::size_t batch = std::max<std::size_t>(1000, static_cast<std::size_t>(samples / channels));
  double sum_squares = 0.0;
  for (std::size_t drawn = 0; error.samples < samples && drawn < 50 * static_cast<std::size_t>(samples);) {
    std::vector<ScatterAngles> points;
    points.reserve(batch);
    while (points.size() < batch) {
      const double x0 = axis[0](rng), x1 = axis[1](rng), x2 = slice ? 0.0 : axis[2](rng);
      bool feasible = false;
      const ScatterAngles a = detail::angles_at_index(lut.layout, lut.shape, x0, x1, x2, lut.light, lut.view, &feasible);
      ++drawn;
      if (feasible) points.push_back(a);
    }
    std::vector<double> relative(points.size() * channels, -1.0);  // -1: below the floor
    // The model values of a range as spans (Model::evaluate_many: SIMD factors, batched ASF).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()), [&](const tbb::blocked_range<std::size_t>& range) {
      const std::size_t n = range.size();
      std::vector<ScatterGeometry> geos(n);
      std::vector<double> model(n);
      make_scatter_geometries(points.data() + range.begin(), n, geos.data());
      for (int c = 0; c < channels; ++c) {
        models[c].evaluate_many(geos.data(), n, model.data());
        for (std::size_t j = 0; j < n; ++j) {
          if (!(model[j] >= error.floor) || model[j] <= 0.0) continue;
          relative[(range.begin() + j) * channels + c] = std::abs(lut.lookup(c, geos[j]) - model[j]) / model[j];
        }
      }
    });
    for (std::size_t p = 0; p < points.size() && error.samples < samples; ++p) {
      for (int c = 0; c < channels; ++c) {
        const double e = relative[p * channels + c];
        if (e < 0.0) continue;
        error.max_relative_all = std::max(error.max_relative_all, e);
        if (!inside(points[p])) continue;
        error.max_relative = std::max(error.max_relative, e);
        sum_squares += e * e;
        ++error.samples;
      }
    }
  }
  error.rms_relative = error.samples ? std::sqrt(sum_squares / error.samples) : 0.0;
  return error;
}

}  // namespace libbrdf
