// Internal, per SIMD target (Google Highway's -inl.h pattern: re-included once per target by
// foreach_target.h): ln of one term of the MBK series Sigma(g, c) of eq. 11 (mbk_series.h) in
// vectors of m, g and c. Shared by the per-query blocks (series_simd.cpp) and the per-query lanes
// (asf_batch.cpp).
#if defined(LIBBRDF_SERIES_TERMS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef LIBBRDF_SERIES_TERMS_INL_H_
#undef LIBBRDF_SERIES_TERMS_INL_H_
#else
#define LIBBRDF_SERIES_TERMS_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// ln m! for m = 0..15 (exact where Stirling's series is not yet at double precision).
constexpr double kLogFactorialSmall[16] = {
    0.0, 0.0, 0.69314718055994530942, 1.7917594692280550008, 3.1780538303479456196, 4.7874917427820459943,
    6.5792512120101009951, 8.5251613610654143002, 10.604602902745250228, 12.801827480081469611,
    15.104412573075515295, 17.502307845873885839, 19.987214495661886150, 22.552163853123422886,
    25.191221182738681500, 27.899271383840891566};

// ln of term m of Sigma: ln(e^-g g^m / m!) - ln m - c/m, for lanes with m >= 1 (integers).
template <class D, class V = hn::Vec<D>>
HWY_INLINE V LogTerm(D d, V m, V g, V ln_g, V c) {
  const hn::RebindToSigned<D> di;
  const V one = hn::Set(d, 1.0);
  const V ln_m = hn::Log(d, m);
  const V inv = hn::Div(one, m);
  // m < 16: m ln g - g - ln m! with the exact table (no cancellation worth naming at such m).
  auto small_m = [&] {
    const auto index = hn::ConvertTo(di, hn::Min(m, hn::Set(d, 15.0)));
    return hn::Sub(hn::MulSub(m, ln_g, g), hn::GatherIndex(d, kLogFactorialSmall, index));
  };
  // m >= 16: Loader (2000): -g bd(m/g) - ln(2 pi m)/2 - delta(m), bd(x) = x ln x - x + 1, with
  // g bd written through log1p(y), y = (m - g)/g, where |y| < 1/2 (no cancellation near m ~ g).
  auto large_m = [&] {
    const V y = hn::Div(hn::Sub(m, g), g);
    const auto near_mask = hn::Lt(hn::Abs(y), hn::Set(d, 0.5));
    auto near = [&] { return hn::Mul(g, hn::Sub(hn::Mul(hn::Add(one, y), hn::Log1p(d, hn::Max(y, hn::Set(d, -0.75)))), y)); };
    auto far = [&] { return hn::Add(hn::Sub(hn::Mul(m, hn::Sub(ln_m, ln_g)), m), g); };
    const V deviance = hn::AllTrue(d, near_mask)    ? near()
                       : hn::AllFalse(d, near_mask) ? far()
                                                    : hn::IfThenElse(near_mask, near(), far());
    const V inv2 = hn::Mul(inv, inv);
    // Stirling-series error delta(m) = 1/(12m) - 1/(360m^3) + 1/(1260m^5) - 1/(1680m^7).
    const V delta = hn::Mul(inv, hn::NegMulAdd(inv2, hn::NegMulAdd(inv2, hn::NegMulAdd(inv2, hn::Set(d, 1.0 / 1680), hn::Set(d, 1.0 / 1260)), hn::Set(d, 1.0 / 360)), hn::Set(d, 1.0 / 12)));
    return hn::Sub(hn::Neg(deviance), hn::Add(hn::MulAdd(hn::Set(d, 0.5), ln_m, hn::Set(d, 0.91893853320467274178)), delta));
  };
  const auto small_mask = hn::Lt(m, hn::Set(d, 16.0));
  const V log_weight = hn::AllTrue(d, small_mask)    ? small_m()
                       : hn::AllFalse(d, small_mask) ? large_m()
                                                     : hn::IfThenElse(small_mask, small_m(), large_m());
  return hn::Sub(hn::Sub(log_weight, ln_m), hn::Mul(c, inv));
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#endif  // LIBBRDF_SERIES_TERMS_INL_H_
