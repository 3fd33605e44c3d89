// Internal, per SIMD target (Google Highway's -inl.h pattern: re-included once per target by
// foreach_target.h): ScatterGeometry records (geometry.h: ten doubles) read and written a vector of
// queries at a time, one field per vector. Shared by the angular factors (angular_simd.cpp) and the
// table coordinates (table_angles_simd.cpp).
#if defined(LIBBRDF_GEOMETRY_RECORDS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef LIBBRDF_GEOMETRY_RECORDS_INL_H_
#undef LIBBRDF_GEOMETRY_RECORDS_INL_H_
#else
#define LIBBRDF_GEOMETRY_RECORDS_INL_H_
#endif

#include <cstddef>
#include <cstdint>

#include <hwy/highway.h>

#include "libbrdf/geometry.h"
#include "simd_transpose-inl.h"  // TransposeSquare

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// ScatterGeometry as an array of doubles: field offsets.
constexpr std::int64_t kGeoStride = sizeof(ScatterGeometry) / sizeof(double);
static_assert(sizeof(ScatterGeometry) == 10 * sizeof(double), "ScatterGeometry: ten doubles, no padding");
enum GeoField : std::int64_t { kCosI = 0, kSinI, kCosS, kSinS, kCosPhi, kSinPhi, kCos2D, kCosD, kCosH, kEta2 };

// One field of `lanes` consecutive geometries: lane by lane into a buffer, then one load. An
// 8-lane gather (vgatherqpd) cost more here: K's span lookup 3.8 -> 3.5 ns per query without it,
// mbk minus g 14.9 -> 14.3 ns (polished), 14.1 -> 13.6 (rough), one CPU, same run.
template <class D>
HWY_INLINE hn::Vec<D> Field(D d, const ScatterGeometry* geos, GeoField field) {
  alignas(64) double lanes[HWY_MAX_BYTES / sizeof(double)];
  const double* base = reinterpret_cast<const double*>(geos) + field;
  for (std::size_t q = 0; q < hn::MaxLanes(d); ++q) lanes[q] = base[kGeoStride * q];
  return hn::Load(d, lanes);
}

template <class D>
HWY_INLINE hn::Vec<hn::RebindToSigned<D>> GeoOffsets(D d) {
  const hn::RebindToSigned<D> di;
  alignas(64) std::int64_t offsets[HWY_MAX_BYTES / sizeof(double)];
  for (std::size_t k = 0; k < hn::Lanes(d); ++k) offsets[k] = static_cast<std::int64_t>(k) * kGeoStride;
  return hn::Load(di, offsets);
}

// The 10 fields of one vector of geometries into records geos[0 .. lanes): each run of `lanes`
// fields transposed (lane q of the run is then record q's consecutive fields: one store), the
// fields left over (2 of 10 with 8 lanes) scattered.
template <class D, class V>
HWY_INLINE void StoreRecords(D d, const V* field, ScatterGeometry* geos) {
  constexpr std::size_t kLanes = hn::MaxLanes(d);  // = Lanes(d) on the fixed-width targets of Highway 1.0
  double* base = reinterpret_cast<double*>(geos);
  std::size_t f0 = 0;
  for (; f0 + kLanes <= kGeoStride; f0 += kLanes) {
    V run[kLanes];
    for (std::size_t q = 0; q < kLanes; ++q) run[q] = field[f0 + q];
    TransposeSquare(d, run);
    for (std::size_t q = 0; q < kLanes; ++q) hn::StoreU(run[q], d, base + kGeoStride * q + f0);
  }
  for (; f0 < kGeoStride; ++f0) hn::ScatterIndex(field[f0], d, base + f0, GeoOffsets(d));
}

// Fields [0, count) of `lanes` consecutive records into field[0 .. count) by transposition (the
// inverse of StoreRecords): each run of `lanes` fields costs `lanes` loads and one transposition,
// where a gather per field costs ~lanes loads each. count <= 8 (a run never passes a record's end).
template <class D, class V>
HWY_INLINE void LoadRecords(D d, const ScatterGeometry* geos, std::size_t count, V* field) {
  constexpr std::size_t kLanes = hn::MaxLanes(d);
  const double* base = reinterpret_cast<const double*>(geos);
  for (std::size_t f0 = 0; f0 < count; f0 += kLanes) {
    V run[kLanes];
    for (std::size_t q = 0; q < kLanes; ++q) run[q] = hn::LoadU(d, base + kGeoStride * q + f0);
    TransposeSquare(d, run);
    for (std::size_t j = 0; j < kLanes && f0 + j < count; ++j) field[f0 + j] = run[j];
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#endif  // LIBBRDF_GEOMETRY_RECORDS_INL_H_
