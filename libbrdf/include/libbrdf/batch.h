#pragma once
// Batch evaluation: many queries of one Model (or one table) in, values out. This is the entry
// point that `brdf eval`, `bake`, `bench`, the exporters and the Python module use, so that every
// front end gives bit-identical values for the same query.
//
// Large batches run in parallel (oneTBB) in fixed-size chunks; each value depends only on its own
// query, so results do not depend on the thread count or the chunking.
#include <cstddef>

#include <string>

#include "libbrdf/error.h"
#include "libbrdf/geometry.h"
#include "libbrdf/lut.h"
#include "libbrdf/models.h"

namespace libbrdf {

// A bad query of a batch: InvalidArgument naming the angle (or direction), plus its index.
class InvalidQuery : public InvalidArgument {
 public:
  InvalidQuery(const InvalidArgument& cause, std::size_t index);
  std::size_t index() const noexcept { return index_; }
  const std::string& reason() const noexcept { return reason_; }  // the message without the parameter

 private:
  std::size_t index_;
  std::string reason_;
};

// Batches at least this large are split across threads.
inline constexpr std::size_t kBatchParallelThreshold = 4096;

// values[k] = model.evaluate(angles[k]) for k < count (radians, conventions.md).
// Every query is validated first: theta_i, theta_s in [0, pi/2), all finite. A bad query throws
// InvalidQuery (an InvalidArgument) naming the angle and the query's index; nothing is written
// to `values` then.
void evaluate_batch(const Model& model, const ScatterAngles* angles, std::size_t count, double* values);

// Same, with the angles in degrees as three arrays (what `brdf eval` and the Python module
// receive): query k is (theta_i_deg[k], theta_s_deg[k], phi_s_deg[k]), converted as
// scatter_angles_from_degrees does, so the values are bit-identical to evaluate_batch on the
// converted angles -- except for polar angles above kGrazingDegrees, whose cosines come from the
// degrees (make_scatter_geometry_degrees: relative precision kept up to 90 deg, where radians lose
// it). Each chunk converts its own queries (no converted copy of the batch). Same validation,
// InvalidQuery in radians' terms.
void evaluate_degrees_batch(const Model& model, const double* theta_i_deg, const double* theta_s_deg, const double* phi_s_deg,
                            std::size_t count, double* values);

// Same, with directions in the surface frame (normal +z) instead of angles: to_light and to_view
// are count x 3 doubles (x, y, z), both pointing away from the surface, any nonzero length
// (normalized here). Directions with z <= 0 (on or below the horizon) or non-finite components
// throw InvalidArgument("to_light" / "to_view", ...) with the index. The azimuths are relative:
// only L.V, N.L and N.V enter (isotropic surface).
void evaluate_directions_batch(const Model& model, const double* to_light, const double* to_view, std::size_t count,
                               double* values);

// Every channel of a table at already-derived geometries: values[k * lut.channels() + c]. The
// table coordinates of a chunk come from one vector arctangent call (no acos/atan2 per query). A
// hand-filled geometry with a non-finite field the lookup reads throws InvalidQuery (parameter
// "geometry", its index); make_scatter_geometry's never do.
// Runs on the calling thread only (callers split larger work themselves, e.g. in chunks). For many
// lookups of one table, LutSampler (lut.h) gives the same values faster (channel-interleaved nodes).
void lookup_all_batch(const Lut& lut, const ScatterGeometry* geometries, std::size_t count, double* values);

// Every channel of a prepared table (LutSampler, lut.h) at angles: values[k * channels + c], the
// values of lookup_batch for each channel, bit for bit; the same validation (a slice table's
// off-slice geometries refused too), in parallel for large batches. What the Python module's
// LutSampler calls.
void lookup_all_batch(const LutSampler& sampler, const ScatterAngles* angles, std::size_t count, double* values);

// Table lookups: values[k] = lut.lookup(channel, geometry of angles[k]). Same validation; a slice
// table also rejects (InvalidQuery, parameter phi_s) a geometry off its slice (cos 2theta_d = L.V
// within 1e-6, eq. 5). What `brdf eval --lut` and the Python module's Lut call.
void lookup_batch(const Lut& lut, int channel, const ScatterAngles* angles, std::size_t count, double* values);

}  // namespace libbrdf
