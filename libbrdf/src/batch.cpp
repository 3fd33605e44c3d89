// Batch evaluation (batch.h): validation first, then fixed chunks in parallel.
#include "libbrdf/batch.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "libbrdf/error.h"
#include "lut_internal.h"

namespace libbrdf {
namespace {

// Chunks of this many queries are the unit of parallel work: big enough to amortize scheduling,
// fixed so that the split does not depend on the thread count.
constexpr std::size_t kChunk = 1024;

template <typename Body>
void for_each_chunk(std::size_t count, const Body& body) {
  if (count < kBatchParallelThreshold) {
    body(std::size_t{0}, count);
    return;
  }
  const std::size_t chunks = (count + kChunk - 1) / kChunk;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t chunk = r.begin(); chunk != r.end(); ++chunk)
      body(chunk * kChunk, std::min(count, (chunk + 1) * kChunk));
  });
}

// Geometries are derived and evaluated in blocks of this many queries: stack buffers that stay in
// the L1/L2 cache (Model::evaluate_many works in blocks of the same size).
constexpr std::size_t kBlock = 256;

// body(geos, n, first): the geometries of the validated angles[first, first + n), for every block
// of [0, count).
template <typename Body>
void for_each_geometry_block(const ScatterAngles* angles, std::size_t count, const Body& body) {
  ScatterGeometry geos[kBlock];
  for (std::size_t begin = 0; begin < count; begin += kBlock) {
    const std::size_t n = std::min(kBlock, count - begin);
    make_scatter_geometries(angles + begin, n, geos);
    body(geos, n, begin);
  }
}

// values[k] = model at angles[k] for k < count (validated), block by block.
void evaluate_validated(const Model& model, const ScatterAngles* angles, std::size_t count, double* values) {
  for_each_geometry_block(angles, count,
                          [&](const ScatterGeometry* geos, std::size_t n, std::size_t first) { model.evaluate_many(geos, n, values + first); });
}

bool query_valid(const ScatterAngles& a) {
  return polar_angle_valid(a.theta_i) && polar_angle_valid(a.theta_s) && std::isfinite(a.phi_s);
}

// Throws InvalidQuery (index first_index + k) at the first bad query.
void validate_angles(const ScatterAngles* angles, std::size_t count, std::size_t first_index = 0) {
  for (std::size_t k = 0; k < count; ++k) {
    if (query_valid(angles[k])) continue;  // the common case, inline
    try {
      require_polar_angle("theta_i", angles[k].theta_i);
      require_polar_angle("theta_s", angles[k].theta_s);
      require_finite("phi_s", angles[k].phi_s);
    } catch (const InvalidArgument& e) {
      throw InvalidQuery(e, first_index + k);
    }
  }
}

}  // namespace

InvalidQuery::InvalidQuery(const InvalidArgument& cause, std::size_t index)
    : InvalidArgument(cause.parameter(), std::string(cause.what() + cause.parameter().size() + 2) + " (query " + std::to_string(index) + ")"),
      index_(index),
      reason_(cause.what() + cause.parameter().size() + 2) {}

void evaluate_batch(const Model& model, const ScatterAngles* angles, std::size_t count, double* values) {
  validate_angles(angles, count);
  // Per chunk: the geometry span (SIMD sines and cosines), then the model over the span (SIMD
  // angular factors, batched ASF): no per-query virtual call or scalar trigonometry.
  for_each_chunk(count, [&](std::size_t begin, std::size_t end) { evaluate_validated(model, angles + begin, end - begin, values + begin); });
}

void evaluate_degrees_batch(const Model& model, const double* theta_i_deg, const double* theta_s_deg, const double* phi_s_deg,
                            std::size_t count, double* values) {
  auto angles_at = [&](std::size_t k) { return scatter_angles_from_degrees(theta_i_deg[k], theta_s_deg[k], phi_s_deg[k]); };
  for (std::size_t k = 0; k < count; ++k) {  // every query first: nothing is written on a bad one
    const ScatterAngles a = angles_at(k);
    if (!query_valid(a)) validate_angles(&a, 1, k);
  }
  for_each_chunk(count, [&](std::size_t begin, std::size_t end) {
    ScatterAngles angles[kBlock];
    ScatterGeometry geos[kBlock];
    std::uint32_t grazing[kBlock];
    for (std::size_t block = begin; block < end; block += kBlock) {
      const std::size_t n = std::min(kBlock, end - block);
      std::size_t grazing_count = 0;
      for (std::size_t k = 0; k < n; ++k) {
        angles[k] = angles_at(block + k);
        if (theta_i_deg[block + k] > kGrazingDegrees || theta_s_deg[block + k] > kGrazingDegrees)
          grazing[grazing_count++] = static_cast<std::uint32_t>(k);
      }
      make_scatter_geometries(angles, n, geos);
      // Polar angles near 90 deg: cos theta from the degrees (geometry.h), which radians cannot carry.
      for (std::size_t j = 0; j < grazing_count; ++j) {
        const std::size_t k = block + grazing[j];
        geos[grazing[j]] = make_scatter_geometry_degrees(theta_i_deg[k], theta_s_deg[k], phi_s_deg[k]);
      }
      model.evaluate_many(geos, n, values + block);
    }
  });
}

void evaluate_directions_batch(const Model& model, const double* to_light, const double* to_view, std::size_t count,
                               double* values) {
  // Directions -> angles in the frame where the light's azimuth is 0 (phi_i = 0, conventions.md).
  std::vector<ScatterAngles> angles(count);
  for (std::size_t k = 0; k < count; ++k) {
    const double* l = to_light + 3 * k;
    const double* v = to_view + 3 * k;
    for (int axis = 0; axis < 3; ++axis) {
      if (!std::isfinite(l[axis])) throw InvalidQuery(InvalidArgument("to_light", "components must be finite"), k);
      if (!std::isfinite(v[axis])) throw InvalidQuery(InvalidArgument("to_view", "components must be finite"), k);
    }
    if (!(l[2] > 0.0)) throw InvalidQuery(InvalidArgument("to_light", "must point above the surface (z > 0)"), k);
    if (!(v[2] > 0.0)) throw InvalidQuery(InvalidArgument("to_view", "must point above the surface (z > 0)"), k);
    angles[k].theta_i = std::atan2(std::hypot(l[0], l[1]), l[2]);
    angles[k].theta_s = std::atan2(std::hypot(v[0], v[1]), v[2]);
    angles[k].phi_s = std::atan2(v[1], v[0]) - std::atan2(l[1], l[0]);
  }
  evaluate_batch(model, angles.data(), count, values);
}

void lookup_all_batch(const Lut& lut, const ScatterGeometry* geometries, std::size_t count, double* values) {
  detail::lookup_all_span(lut, geometries, count, values);
}

namespace {
// A slice holds only the geometries with cos 2theta_d = L.V (eq. 5; lut.h): throws InvalidQuery at
// the first other one (serially, before any lookup, so that the index is the first).
void validate_slice_geometries(const Lut& lut, const ScatterAngles* angles, std::size_t count) {
  const double cos_lv = detail::slice_cos_2theta_d(lut.light, lut.view);
  for (std::size_t k = 0; k < count; ++k) {
    const double cos_2theta_d = make_scatter_geometry(angles[k]).cos_2theta_d;
    if (std::abs(cos_2theta_d - cos_lv) > 1e-6)
      throw InvalidQuery(InvalidArgument("phi_s", "not a geometry of this slice table: cos 2theta_d = " + std::to_string(cos_2theta_d) +
                                                      ", the table's L.V = " + std::to_string(cos_lv) + " (eq. 5)"),
                         k);
  }
}
}  // namespace

void lookup_all_batch(const LutSampler& sampler, const ScatterAngles* angles, std::size_t count, double* values) {
  const Lut& lut = sampler.lut();
  validate_angles(angles, count);
  if (lut.layout == LutLayout::slice) validate_slice_geometries(lut, angles, count);
  const std::size_t channels = static_cast<std::size_t>(lut.channels());
  for_each_chunk(count, [&](std::size_t begin, std::size_t end) {
    for_each_geometry_block(angles + begin, end - begin, [&](const ScatterGeometry* geos, std::size_t n, std::size_t first) {
      sampler.lookup_all(geos, n, values + (begin + first) * channels);
    });
  });
}

void lookup_batch(const Lut& lut, int channel, const ScatterAngles* angles, std::size_t count, double* values) {
  if (channel < 0 || channel >= lut.channels())
    throw InvalidArgument("channel", "must be in [0, " + std::to_string(lut.channels() - 1) + "] (got " + std::to_string(channel) + ")");
  validate_angles(angles, count);
  if (lut.layout == LutLayout::slice) validate_slice_geometries(lut, angles, count);
  for_each_chunk(count, [&](std::size_t begin, std::size_t end) {
    for_each_geometry_block(angles + begin, end - begin, [&](const ScatterGeometry* geos, std::size_t n, std::size_t first) {
      detail::TableAngles table[kBlock];
      detail::table_angles_for(lut, geos, n, table, begin + first);
      detail::lookup_span(lut, geos, table, n, channel, 1, values + begin + first);
    });
  });
}

}  // namespace libbrdf
