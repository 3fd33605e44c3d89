// The angular factors over spans of geometries (angular_simd.h) in SIMD through Google Highway
// with run-time dispatch (as series_simd.cpp). Complex arithmetic is written out in real and
// imaginary vectors; every operation is lane-wise, so a value never depends on its neighbours.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "angular_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "angular_simd.h"
#include "geometry_records-inl.h"  // GeoField, Field, LoadRecords, StoreRecords

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// kVectors vectors of one row's values (ForEachBlockRows' blocks of kVectors vectors).
template <class V, std::size_t kVectors>
struct VectorRun {
  V v[kVectors];
};

// out[r stride + k] = value(load(geos + block start), r)[lane] for rows r < rows over the span, in
// blocks of kVectors vectors (value returns a vector, or a VectorRun of kVectors): full blocks, the
// last one shifted back to end at `count` (it recomputes a few values identically), or a padded
// copy when the span is shorter than one block. load reads what the rows share (several channels'
// Qbar: the sines and cosines) once per block. Each function is called (and inlined) at one place
// only: inlined at two, the compiler contracted their multiply-adds differently, and F(theta_d)
// of one query alone differed in its last bits from the same query's in a longer span (7320 of
// 20000 random geometries, gold at 0.55 um).
template <std::size_t kVectors = 1, class D, class Load, class Value>
HWY_INLINE void ForEachBlockRows(D d, const ScatterGeometry* geos, std::size_t count, int rows, double* out, std::size_t stride,
                                 const Load& load, const Value& value) {
  const std::size_t n = hn::Lanes(d), width = kVectors * n;
  if (count == 0) return;
  constexpr std::size_t kMaxWidth = kVectors * HWY_MAX_BYTES / sizeof(double);
  const bool short_span = count < width;
  ScatterGeometry pad[kMaxWidth];
  double padded_out[kMaxWidth];
  if (short_span)
    for (std::size_t k = 0; k < width; ++k) pad[k] = geos[std::min(k, count - 1)];  // the last geometry repeated
  const ScatterGeometry* in = short_span ? pad : geos;
  const std::size_t span = short_span ? width : count;
  for (std::size_t k = 0; k < span; k += width) {
    const std::size_t at = std::min(k, span - width);
    const auto shared = load(in + at);
    for (int r = 0; r < rows; ++r) {
      double* row = (short_span ? padded_out : out + r * stride) + at;
      if constexpr (kVectors == 1) {
        hn::StoreU(value(shared, r), d, row);
      } else {
        const auto run = value(shared, r);
        for (std::size_t j = 0; j < kVectors; ++j) hn::StoreU(run.v[j], d, row + j * n);
      }
      if (short_span) std::copy(padded_out, padded_out + count, out + r * stride);
    }
  }
}
// One row: out[k] = kernel(geos + block start)[lane].
template <class D, class Kernel>
HWY_INLINE void ForEachBlock(D d, const ScatterGeometry* geos, std::size_t count, double* out, const Kernel& kernel) {
  ForEachBlockRows(
      d, geos, count, 1, out, 0, [](const ScatterGeometry* g) { return g; }, [&](const ScatterGeometry* g, int) { return kernel(g); });
}

// Principal square root of a + i b for b >= 0 (Im eps = 2 n kappa >= 0), as std::sqrt, in two
// steps so that two roots can share one division (ComplexSqrtPair): t = sqrt((|z| + |a|)/2) has
// no cancellation; the other part is b / 2t, from a given 1/(2t) (0 where t = 0, z = 0: w = 0).
template <class D, class V = hn::Vec<D>>
HWY_INLINE V RootMagnitudePart(D d, V a, V b, V* modulus) {
  *modulus = hn::Sqrt(hn::MulAdd(a, a, hn::Mul(b, b)));
  return hn::Sqrt(hn::Mul(hn::Set(d, 0.5), hn::Add(*modulus, hn::Abs(a))));
}
template <class D, class V = hn::Vec<D>>
HWY_INLINE void AssembleRoot(D d, V a, V b, V t, V inv_2t, V* re, V* im) {
  const V other = hn::Mul(b, inv_2t);
  const auto negative = hn::Lt(a, hn::Zero(d));
  *re = hn::IfThenElse(negative, other, t);
  *im = hn::IfThenElse(negative, t, other);
}
// t with 1 where t = 0 (whose root is 0: its 1/(2t) must come out 0, not inf).
template <class D, class V = hn::Vec<D>>
HWY_INLINE V NonzeroOr1(D d, V t) {
  return hn::IfThenElse(hn::Eq(t, hn::Zero(d)), hn::Set(d, 1.0), t);
}
template <class D, class V = hn::Vec<D>>
HWY_INLINE void ComplexSqrt(D d, V a, V b, V* re, V* im) {
  V modulus;
  const V t = RootMagnitudePart(d, a, b, &modulus);
  const V inv_2t = hn::IfThenZeroElse(hn::Eq(t, hn::Zero(d)), hn::Div(hn::Set(d, 0.5), NonzeroOr1(d, t)));
  AssembleRoot(d, a, b, t, inv_2t, re, im);
}
// The roots of a1 + i b and a2 + i b with one division, 1/(2 t1 t2) (the divider, not the
// arithmetic, bounds Stover's Qbar: StoverQBarSpan); also |a + i b| of each.
template <class D, class V = hn::Vec<D>>
HWY_INLINE void ComplexSqrtPair(D d, V a1, V a2, V b, V* re1, V* im1, V* modulus1, V* re2, V* im2, V* modulus2) {
  const V t1 = RootMagnitudePart(d, a1, b, modulus1), t2 = RootMagnitudePart(d, a2, b, modulus2);
  const V safe1 = NonzeroOr1(d, t1), safe2 = NonzeroOr1(d, t2);
  const V inv_2t1t2 = hn::Div(hn::Set(d, 0.5), hn::Mul(safe1, safe2));
  const V zero = hn::Zero(d);
  AssembleRoot(d, a1, b, t1, hn::IfThenZeroElse(hn::Eq(t1, zero), hn::Mul(inv_2t1t2, safe2)), re1, im1);
  AssembleRoot(d, a2, b, t2, hn::IfThenZeroElse(hn::Eq(t2, zero), hn::Mul(inv_2t1t2, safe1)), re2, im2);
}

template <class V>
HWY_INLINE V Norm(V re, V im) {
  return hn::MulAdd(re, re, hn::Mul(im, im));
}

// cos and sin of theta_i, theta_s, phi_s (angle[0 .. 2]) into field[0 .. 5], ScatterGeometry's
// order (and trig's): the one place both geometry paths take them from.
template <class D, class V>
HWY_INLINE void SinesCosines(D d, const V* angle, V* field) {
  for (int a = 0; a < 3; ++a) field[2 * a] = hn::Cos(d, angle[a]), field[2 * a + 1] = hn::Sin(d, angle[a]);
}

void ScatterTrig(const ScatterAngles* angles, std::size_t count, double* trig) {
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  const std::size_t n = hn::Lanes(d);
  alignas(64) std::int64_t in_offsets[HWY_MAX_BYTES / sizeof(double)], out_offsets[HWY_MAX_BYTES / sizeof(double)];
  for (std::size_t k = 0; k < n; ++k) {
    in_offsets[k] = static_cast<std::int64_t>(3 * k);
    out_offsets[k] = static_cast<std::int64_t>(6 * k);
  }
  const auto in = hn::Load(di, in_offsets), out = hn::Load(di, out_offsets);
  static_assert(sizeof(ScatterAngles) == 3 * sizeof(double), "ScatterAngles: three doubles");
  auto block = [&](const ScatterAngles* block_angles, double* t) {
    const double* a = reinterpret_cast<const double*>(block_angles);
    hn::Vec<decltype(d)> angle[3], field[6];
    for (int k = 0; k < 3; ++k) angle[k] = hn::GatherIndex(d, a + k, in);
    SinesCosines(d, angle, field);
    for (int f = 0; f < 6; ++f) hn::ScatterIndex(field[f], d, t + f, out);
  };
  std::size_t k = 0;
  for (; k + n <= count; k += n) block(angles + k, trig + 6 * k);
  if (k < count) {  // the remainder through a padded block: the same vector code for every query
    constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
    ScatterAngles pad[kMaxLanes];
    double t[6 * kMaxLanes];
    for (std::size_t j = 0; j < n; ++j) pad[j] = angles[std::min(k + j, count - 1)];
    block(pad, t);
    for (std::size_t j = 0; j < 6 * (count - k); ++j) trig[6 * k + j] = t[j];
  }
  // Azimuths outside Highway's range through the C library.
  for (std::size_t j = 0; j < count; ++j) {
    if (std::abs(angles[j].phi_s) <= 39000.0) continue;
    trig[6 * j + 4] = std::cos(angles[j].phi_s);
    trig[6 * j + 5] = std::sin(angles[j].phi_s);
  }
}

// The derived fields of ScatterGeometry (eqs 5, 6, 10; geometry.h) from its first six (the sines
// and cosines), lane by lane: the one formula of every path (GeometriesFromTrig, ScatterGeometries).
template <class D, class V>
HWY_INLINE void DeriveFields(D d, V* field) {
  const V one = hn::Set(d, 1.0), half = hn::Set(d, 0.5), two = hn::Set(d, 2.0);
  const V ci = field[kCosI], si = field[kSinI], cs = field[kCosS], ss = field[kSinS], cp = field[kCosPhi], sp = field[kSinPhi];
  // eq. 5, clamped to [-1, 1] only against rounding (|cos 2td| <= 1 holds for real angles).
  field[kCos2D] = hn::Min(hn::Max(hn::Add(hn::Mul(ci, cs), hn::Mul(hn::Mul(si, ss), cp)), hn::Neg(one)), one);
  field[kCosD] = hn::Sqrt(hn::Mul(half, hn::Add(one, field[kCos2D])));
  // eq. 6. cos td > 0 because both directions lie strictly above the horizon (ci + cs > 0).
  field[kCosH] = hn::Min(one, hn::Div(hn::Add(ci, cs), hn::Mul(two, field[kCosD])));
  // eq. 10 as |Delta alpha|^2 + |Delta beta|^2 (eq. 9): >= 0 under rounding.
  const V d_alpha = hn::Mul(ss, sp), d_beta = hn::Add(hn::Mul(ss, cp), si);
  field[kEta2] = hn::Add(hn::Mul(d_alpha, d_alpha), hn::Mul(d_beta, d_beta));
}

// The derived quantities of ScatterGeometry (eqs 5, 6, 10; geometry.h) from the sines and cosines
// trig[6 k .. 6 k + 5], lane by lane, stored into geos[k]: scatter_geometry_from_trig, the bake's
// rows and ScatterGeometries' fallback. Every path derives the fields by DeriveFields, so a query
// gives the same bits on every path (the compiler may fuse a multiply and an add on targets with FMA).
void GeometriesFromTrig(const double* trig, std::size_t count, ScatterGeometry* geos) {
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  const std::size_t n = hn::Lanes(d);
  alignas(64) std::int64_t in_offsets[HWY_MAX_BYTES / sizeof(double)];
  for (std::size_t k = 0; k < n; ++k) in_offsets[k] = static_cast<std::int64_t>(6 * k);
  const auto in = hn::Load(di, in_offsets);
  auto block = [&](const double* t, ScatterGeometry* g) {
    V field[10];
    for (int f = 0; f < 6; ++f) field[f] = hn::GatherIndex(d, t + f, in);
    DeriveFields(d, field);
    StoreRecords(d, field, g);
  };
  std::size_t k = 0;
  for (; k + n <= count; k += n) block(trig + 6 * k, geos + k);
  if (k < count) {  // the remainder through a padded block: the same vector code for every query
    constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
    double t[6 * kMaxLanes];
    ScatterGeometry g[kMaxLanes];
    for (std::size_t j = 0; j < n; ++j)
      for (int f = 0; f < 6; ++f) t[6 * j + f] = trig[6 * std::min(k + j, count - 1) + f];
    block(t, g);
    for (std::size_t j = 0; j < count - k; ++j) geos[k + j] = g[j];
  }
}

// make_scatter_geometries in one pass: each vector of queries' angles loaded de-interleaved, their
// sines and cosines (SinesCosines, as ScatterTrig) and DeriveFields in registers, then stored. The
// sines and cosines no longer go through a buffer (6 scatters and 6 gathers per vector), and the
// angles are read without gathers. Vectors with an azimuth beyond Highway's range and the
// remainder go through ScatterTrig + GeometriesFromTrig: the same values either way (bit for bit
// on the AVX3, AVX2, SSE4, SSSE3 targets, checked with hwy::DisableTargets). The fields go into
// the records by transposition where a run of n fields fits (8 of the 10 on AVX3), not by 10
// scatters. 256-query blocks in cache, one core, same run: 13.9 -> 5.8 ns per query (the fused
// pass with scatters alone: ~8-10).
void ScatterGeometries(const ScatterAngles* angles, std::size_t count, ScatterGeometry* geos) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t n = hn::Lanes(d);
  const V phi_limit = hn::Set(d, 39000.0);
  constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
  auto two_step = [&](std::size_t k, std::size_t m) {
    double trig[6 * kMaxLanes];
    ScatterTrig(angles + k, m, trig);
    GeometriesFromTrig(trig, m, geos + k);
  };
  static_assert(sizeof(ScatterAngles) == 3 * sizeof(double), "ScatterAngles: three doubles");
  const double* a = reinterpret_cast<const double*>(angles);
  std::size_t k = 0;
  for (; k + n <= count; k += n) {
    V angle[3];
    hn::LoadInterleaved3(d, a + 3 * k, angle[0], angle[1], angle[2]);
    if (!hn::AllTrue(d, hn::Le(hn::Abs(angle[2]), phi_limit))) {
      two_step(k, n);
      continue;
    }
    V field[10];
    SinesCosines(d, angle, field);
    DeriveFields(d, field);
    StoreRecords(d, field, geos + k);
  }
  if (k < count) two_step(k, count - k);
}

// Stover's Qbar (fresnel.h, stover_q) of one vector of geometries from their sines and cosines,
// the real parts of z = eps - sin^2 theta of both directions (Im z = Im eps) and |eps - 1|^2 / 2:
// the one formula of StoverQBarSpan's double and single-precision lanes.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V StoverQBarOf(D d, const V* trig, V z_i_re, V z_s_re, V er, V ei, V half_e2) {
  const V ci = trig[kCosI], si = trig[kSinI], cs = trig[kCosS], ss = trig[kSinS], cphi = trig[kCosPhi], sphi = trig[kSinPhi];
  // w = sqrt(eps - sin^2 theta) for i and s, and |w|^2 = |eps - sin^2 theta|.
  V wir, wii, wsr, wsi, w2i, w2s;
  ComplexSqrtPair(d, z_i_re, z_s_re, ei, &wir, &wii, &w2i, &wsr, &wsi, &w2s);
  const V n_si = Norm(hn::Add(ci, wir), wii), n_ss = Norm(hn::Add(cs, wsr), wsi);  // |cos + w|^2
  const V n_pi = Norm(hn::MulAdd(er, ci, wir), hn::MulAdd(ei, ci, wii));            // |eps cos + w|^2
  const V n_ps = Norm(hn::MulAdd(er, cs, wsr), hn::MulAdd(ei, cs, wsi));
  // Stover's azimuth phi = phi_s - pi: cos phi = -cos phi_s; only squares and the pp term use it.
  const V cos_phi = hn::Sub(hn::Zero(d), cphi);
  const V sin2 = hn::Mul(sphi, sphi);
  // pp's numerator: |wi ws cos phi - eps sin ti sin ts|^2. Its two parts are ~|eps| each and can
  // cancel to ~1: the numerator's error grows as |eps| times the rounding (QBarPrecision).
  const V sin_product = hn::Mul(si, ss);
  const V prod_re = hn::NegMulAdd(wii, wsi, hn::Mul(wir, wsr)), prod_im = hn::MulAdd(wir, wsi, hn::Mul(wii, wsr));
  const V a_re = hn::NegMulAdd(er, sin_product, hn::Mul(prod_re, cos_phi));
  const V a_im = hn::NegMulAdd(ei, sin_product, hn::Mul(prod_im, cos_phi));
  // (Q_ss + Q_sp + Q_ps + Q_pp) / 2 over the one denominator n_si n_ss n_pi n_ps (|eps| <= ~1e6:
  // products of four norms stay far inside the double range). Four sqrt and two divisions per
  // vector, where the four Q's and two roots each divided (the divider bounds this loop): per
  // query, `brdf eval --timing` minus `--model g`, 1e6 queries, one CPU, best of 5, same run,
  // Qbar 6.0 -> 4.2 ns and mbk 17.3 -> 15.2 ns (polished); errors against stover_q unchanged,
  // 9.6e-14 at most over 300 indices n in [1e-3, 1e3], kappa 0 or in [1e-4, 1e3]. (The one
  // denominator alone, with the roots' two divisions, had measured no change.)
  const V sum = hn::MulAdd(hn::Mul(cos_phi, cos_phi), hn::Mul(n_pi, n_ps),
                           hn::MulAdd(hn::Mul(w2s, sin2), hn::Mul(n_pi, n_ss),
                                      hn::MulAdd(hn::Mul(w2i, sin2), hn::Mul(n_si, n_ps), hn::Mul(Norm(a_re, a_im), hn::Mul(n_si, n_ss)))));
  return hn::Mul(half_e2, hn::Div(sum, hn::Mul(hn::Mul(n_si, n_ss), hn::Mul(n_pi, n_ps))));
}

// |eps - 1|^2 / 2, the common factor of the four Q's, in double (no cancellation where eps ~ 1).
inline double HalfNormEpsMinusOne(double eps_re, double eps_im) {
  const double er1 = eps_re - 1.0;
  return 0.5 * (er1 * er1 + eps_im * eps_im);
}

// Several channels' Qbar at once (the kernel layout's wavelengths): the sines and cosines are
// read from the records once per block for every channel. 3-channel closed-form kernel lookups
// (gold, sigma_s = 0.02 um, 8000 cached geometries, best of 2000 passes, four alternated runs):
// 24.6-25.4 -> 24.1-24.4 ns; each channel's bits as its own span's.
void StoverQBarSpan(const double* eps_re, const double* eps_im, int channels, const ScatterGeometry* geos, std::size_t count, double* out,
                    std::size_t channel_stride) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  struct Trig {
    V field[6];
  };
  auto load = [&](const ScatterGeometry* g) {
    Trig t;
    LoadRecords(d, g, 6, t.field);
    return t;
  };
  ForEachBlockRows(d, geos, count, channels, out, channel_stride, load, [&](const Trig& t, int channel) {
    const V er = hn::Set(d, eps_re[channel]), ei = hn::Set(d, eps_im[channel]);
    const V si = t.field[kSinI], ss = t.field[kSinS];
    return StoverQBarOf(d, t.field, hn::NegMulAdd(si, si, er), hn::NegMulAdd(ss, ss, er), er, ei,
                        hn::Set(d, HalfNormEpsMinusOne(eps_re[channel], eps_im[channel])));
  });
}

// The same in single-precision lanes (QBarPrecision::single, angular_simd.h): two vectors of
// geometries (2 x 8 queries on AVX3) in one vector of floats, which has twice the lanes and cheaper
// square roots and divisions. z = eps - sin^2 theta is taken in double and then rounded: near a
// critical angle (n < 1) its real part cancels, and its root would carry the square root of the
// single-precision rounding. AVX3, one core, same run: Qbar of 3 metals, 4000 cached geometries
// in spans of 256, 7.0 -> 4.5 ns per query; 3-channel closed-form kernel lookups (gold,
// sigma_s = 0.005 um, 4000 cached geometries) 24.2-24.3 -> 21.7-21.9 ns.
void StoverQBarSingleSpan(const double* eps_re, const double* eps_im, int channels, const ScatterGeometry* geos, std::size_t count,
                          double* out, std::size_t channel_stride) {
#if HWY_TARGET == HWY_SCALAR  // one lane: no vector of two halves; the double lanes
  StoverQBarSpan(eps_re, eps_im, channels, geos, count, out, channel_stride);
#else
  const hn::ScalableTag<double> d;
  const hn::Rebind<float, decltype(d)> dh;  // as many floats as d has doubles
  const hn::Twice<decltype(dh)> df;         // both vectors' floats
  using V = hn::Vec<decltype(d)>;
  using VF = hn::Vec<decltype(df)>;
  const std::size_t n = hn::Lanes(d);
  auto single = [&](V lower, V upper) { return hn::Combine(df, hn::DemoteTo(dh, upper), hn::DemoteTo(dh, lower)); };
  struct Trig {
    V sin_i[2], sin_s[2];
    VF field[6];
  };
  auto load = [&](const ScatterGeometry* g) {
    V lower[6], upper[6];
    LoadRecords(d, g, 6, lower);
    LoadRecords(d, g + n, 6, upper);
    Trig t;
    for (int f = 0; f < 6; ++f) t.field[f] = single(lower[f], upper[f]);
    t.sin_i[0] = lower[kSinI], t.sin_i[1] = upper[kSinI], t.sin_s[0] = lower[kSinS], t.sin_s[1] = upper[kSinS];
    return t;
  };
  ForEachBlockRows<2>(d, geos, count, channels, out, channel_stride, load, [&](const Trig& t, int channel) {
    const V er = hn::Set(d, eps_re[channel]);
    const VF z_i = single(hn::NegMulAdd(t.sin_i[0], t.sin_i[0], er), hn::NegMulAdd(t.sin_i[1], t.sin_i[1], er));
    const VF z_s = single(hn::NegMulAdd(t.sin_s[0], t.sin_s[0], er), hn::NegMulAdd(t.sin_s[1], t.sin_s[1], er));
    const VF q = StoverQBarOf(df, t.field, z_i, z_s, hn::Set(df, static_cast<float>(eps_re[channel])),
                              hn::Set(df, static_cast<float>(eps_im[channel])),
                              hn::Set(df, static_cast<float>(HalfNormEpsMinusOne(eps_re[channel], eps_im[channel]))));
    return VectorRun<V, 2>{{hn::PromoteTo(d, hn::LowerHalf(dh, q)), hn::PromoteTo(d, hn::UpperHalf(dh, q))}};
  });
#endif
}

void FresnelDSpan(double eps_re, double eps_im, const ScatterGeometry* geos, std::size_t count, double* out) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const V er = hn::Set(d, eps_re), ei = hn::Set(d, eps_im), one = hn::Set(d, 1.0);
  ForEachBlock(d, geos, count, out, [&](const ScatterGeometry* g) {
    const V c = Field(d, g, kCosD);
    const V sin2 = hn::Max(hn::Zero(d), hn::NegMulAdd(c, c, one));
    V wr, wi;
    ComplexSqrt(d, hn::Sub(er, sin2), ei, &wr, &wi);
    // |a/b|^2 as |a|^2/|b|^2 (fresnel.cpp): = 1 exactly under total internal reflection.
    const V r_s = hn::Div(Norm(hn::Sub(c, wr), wi), Norm(hn::Add(c, wr), wi));
    const V ecr = hn::Mul(er, c), eci = hn::Mul(ei, c);
    const V r_p = hn::Div(Norm(hn::Sub(ecr, wr), hn::Sub(eci, wi)), Norm(hn::Add(ecr, wr), hn::Add(eci, wi)));
    return hn::Mul(hn::Set(d, 0.5), hn::Add(r_s, r_p));
  });
}

void RenormalizationSpan(const KTableView& table, const ScatterGeometry* geos, std::size_t count, double* out) {
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0), three = hn::Set(d, 3.0);
  const V last_cell = hn::Set(d, double(table.nodes - 2)), scale = hn::Set(d, table.scale);
  const V base = hn::Set(d, table.base);
  ForEachBlock(d, geos, count, out, [&](const ScatterGeometry* g) {
    const V ci = hn::Min(one, hn::Max(zero, Field(d, g, kCosI)));
    // The node coordinate u = 1 - sqrt(cos theta_i) of renormalization.cpp, in node units.
    const V x = hn::Mul(hn::Sub(one, hn::Sqrt(ci)), scale);
    const V cell = hn::Min(hn::Floor(x), last_cell);
    const V t = hn::Sub(x, cell), t2 = hn::Mul(t, t), t3 = hn::Mul(t2, t);
    // (q, q') of nodes j and j + 1 are the 4 doubles from 2 j on: each lane's 4 loaded and
    // transposed into columns (LoadColumns, as the kernel table's lookups), not 4 gathers.
    alignas(64) hn::TFromD<decltype(di)> at[hn::MaxLanes(d)];
    hn::Store(hn::ShiftLeft<1>(hn::ConvertTo(di, cell)), di, at);
    V values[4];
    LoadColumns<4>(d, [&](std::size_t q) { return table.dense + at[q]; }, values);
    auto value = [&](int e) { return values[e]; };
    // Cubic Hermite basis (as renormalization.cpp's hermite_cell).
    const V h00 = hn::Add(hn::Sub(hn::Mul(two, t3), hn::Mul(three, t2)), one);
    const V h10 = hn::Add(hn::Sub(t3, hn::Mul(two, t2)), t);
    const V h01 = hn::Add(hn::Mul(hn::Set(d, -2.0), t3), hn::Mul(three, t2));
    const V h11 = hn::Sub(t3, t2);
    const V q = hn::Add(hn::Add(hn::Add(hn::Mul(h00, value(0)), hn::Mul(h10, value(1))), hn::Mul(h01, value(2))),
                        hn::Mul(h11, value(3)));
    return hn::Add(base, hn::Mul(hn::Mul(ci, ci), hn::Max(zero, q)));
  });
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace libbrdf::detail {
HWY_EXPORT(ScatterTrig);
HWY_EXPORT(GeometriesFromTrig);
HWY_EXPORT(ScatterGeometries);
HWY_EXPORT(StoverQBarSpan);
HWY_EXPORT(StoverQBarSingleSpan);
HWY_EXPORT(FresnelDSpan);
HWY_EXPORT(RenormalizationSpan);

void scatter_trig(const ScatterAngles* angles, std::size_t count, double* trig) {
  HWY_DYNAMIC_DISPATCH(ScatterTrig)(angles, count, trig);
}
void scatter_geometries(const ScatterAngles* angles, std::size_t count, ScatterGeometry* geos) {
  HWY_DYNAMIC_DISPATCH(ScatterGeometries)(angles, count, geos);
}
void geometries_from_trig(const double* trig, std::size_t count, ScatterGeometry* geos) {
  HWY_DYNAMIC_DISPATCH(GeometriesFromTrig)(trig, count, geos);
}
void stover_q_bar_span(const double* eps_re, const double* eps_im, int channels, const ScatterGeometry* geos, std::size_t count,
                       double* out, std::size_t channel_stride, QBarPrecision precision) {
  if (precision == QBarPrecision::single)
    HWY_DYNAMIC_DISPATCH(StoverQBarSingleSpan)(eps_re, eps_im, channels, geos, count, out, channel_stride);
  else
    HWY_DYNAMIC_DISPATCH(StoverQBarSpan)(eps_re, eps_im, channels, geos, count, out, channel_stride);
}
void fresnel_d_span(double eps_re, double eps_im, const ScatterGeometry* geos, std::size_t count, double* out) {
  HWY_DYNAMIC_DISPATCH(FresnelDSpan)(eps_re, eps_im, geos, count, out);
}
void renormalization_span(const KTableView& table, const ScatterGeometry* geos, std::size_t count, double* out) {
  HWY_DYNAMIC_DISPATCH(RenormalizationSpan)(table, geos, count, out);
}
}  // namespace libbrdf::detail
#endif
