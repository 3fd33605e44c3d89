#pragma once
// Native-lobe fit (issue 10, item 2): a mixture of a renderer's own glossy lobes FITTED to a
// libbrdf model, for scenes with any lights, shadows and world lighting (Blender FIT mode,
// POV-Ray NAME_Fit). Nothing is mapped from eqs 20/25: every lobe's roughness and weight are
// least-squares fitted to the model's radiance f_r cos(theta_i).
//
// Why several lobes: the MBK series (eq. 11) is a Poisson-weighted sum of Gaussians in eta_r,
// term m weighing e^-g g^m / (m! m) with width ~ sqrt(m) lambda / (pi l_c); groups of terms are
// natural lobes of different widths (a polished surface: one narrow halo; intermediate: a sum of
// narrow and broad; rough: one broad lobe). The fit starts each lobe at the width of one group of
// terms (equal Poisson mass per group, at theta_i = theta_s = 30 deg), or from the optimum with one
// lobe fewer plus one lobe when that starts lower, and then refines all roughnesses together
// (Nelder-Mead on log roughness) with the colours solved exactly for each trial (non-negative
// least squares, or plain least squares for signed colours). Narrow lobes get a second, finer block
// of fitting pixels around the half vector, and a validation grid fine enough to resolve them.
//
// Colour follows the angle: each lobe's colour per channel is a non-negative combination of the
// Bernstein polynomials of degree kColourDegree in mu_v = N.V (the renderer knows N.V at the
// shading point; near a lobe's peak theta_i ~ theta_s, so this carries Fresnel, K(theta_i), Qbar and
// the shift of the Poisson weights with g(theta_i, theta_s) ~ cos^2). Non-negative coefficients keep
// every colour >= 0 at every angle.
//
// The measure fitted and reported is the one of the one-sun check: pixels of an
// orthographic sphere lit by one sun, per channel, relative error |fit - exact| / exact over the
// pixels whose exact radiance (every channel) exceeds 1% of the scene's maximum and whose
// theta_i, theta_s <= 70 deg. Fitting scenes put the sun at 5..138 deg from the camera (a random
// sun and camera leave pixels with theta_i, theta_s <= 70 deg below 140 deg); the reported quality
// is measured on other scenes (two suns inside each band of kSunAngleBands, another pixel grid),
// pooled and band by band (NativeFit::by_sun_angle), since the error grows with the angle.
// Cycles' lobes (FitRequest::view_dependent_roughness) take alpha(N.V) (lobe_alpha): a polished MBK
// lobe is exp(-c_scale 4 cos^2(theta_d) sin^2(theta_h)), its width in theta_h ~ 1/cos(theta_d), and
// N.V = cos(theta_d) at its peak (docs/fit.md: Cycles at random suns, medians 8.0% -> 1.9%, 12.5% ->
// 1.6% at 64 and 86 deg). Beyond ~90 deg (theta_d > 45 deg) no lobe over the half vector follows
// MBK well: across the lobe its radiance goes with cos(theta_i) where a microfacet lobe's goes with
// 1/cos(theta_s), and the renderer's colour and roughness may depend on N.V only (FIT works with
// any lights, so L is unknown): the stated error per band says how far.
// The lobe count is the smallest (1..max_lobes) whose measured p95 meets target_error.
// The specular spike (the m = 0 delta, R_spec) is not part of this fit: exporters add it as a
// mirror lobe weighted by R_spec.
#include <array>
#include <cstddef>
#include <vector>

#include "libbrdf/models.h"

namespace libbrdf::fit {

enum class LobeShape {
  // Blender's Glossy BSDF, GGX (Cycles' evaluation; EEVEE's LTC approximates the same lobe):
  //   radiance / E = C(mu_v) D(h) G1(L) G1(V) / (4 N.V),  D = a^2 / (pi ((N.H)^2 (a^2 - 1) + 1)^2),
  //   G1(x) = 2 x / (x + sqrt(a^2 + (1 - a^2) x^2)),  a = alpha = (Blender roughness)^2.
  ggx,
  // Blender's Glossy BSDF, Beckmann, as Cycles evaluates it (EEVEE renders it as GGX):
  //   D = exp(-tan^2 theta_h / a^2) / (pi a^2 cos^4 theta_h), Smith G1 in Walter et al.'s rational form.
  beckmann,
  // POV-Ray 3.7's highlights with metallic 1 (checked against renders: tests/povray/), each lobe
  // either the Blinn specular or the Phong highlight (Lobe::phong):
  //   radiance / E = S h (F_m(N.L) + (1 - F_m(N.L)) c(mu_v)),  h = (N.H)^n (specular S, POV-Ray
  //   roughness = 1/n) or h = (R.L)^n (phong S, phong_size n; R = V mirrored about N),
  //   F_m POV-Ray's empirical metallic weight; the pigment c is a slope { view } colour_map.
  // Why Phong too: at fixed N.H, (R.L)^n still varies with N.L and N.V (R.L = 2 N.V N.L - V.L), the
  // dependence a rough MBK lobe's radiance f_r cos(theta_i) has and a Blinn lobe times c(N.V) lacks
  // (POV-Ray renders, tests/povray/test_fit_render.py, median: rough Au 21% -> 18%, BK7 7.9% -> 7.1%).
  blinn,
};

inline constexpr int kColourDegree = 5;
inline constexpr int kColourTerms = kColourDegree + 1;

struct Lobe {
  double roughness = 0.1;  // ggx/beckmann: alpha at mu_v = 1 (lobe_alpha); blinn: exponent n
  // ggx/beckmann: alpha(mu_v) = roughness mu_v^-roughness_slope (lobe_alpha; 0: a fixed alpha);
  // blinn: exponent roughness mu_v^(2 roughness_slope) at the view nodes (blinn_exponent_at_node).
  double roughness_slope = 0.0;
  double specular = 1.0;   // blinn: S (shared by the channels); ggx: 1
  bool phong = false;      // blinn shape only: the Phong highlight (R.L)^n instead of (N.H)^n
  // Per channel, the Bernstein coefficients (>= 0) of the colour in mu_v = N.V (ggx: the BSDF's
  // colour; blinn: the pigment c).
  std::array<std::array<double, kColourTerms>, 3> colour{};
};

// B_k(mu) = C(D, k) mu^k (1 - mu)^(D - k), D = kColourDegree.
double bernstein(int k, double mu);
double lobe_colour(const Lobe& lobe, int channel, double mu_v);
// A ggx/beckmann lobe's alpha at mu_v = N.V: roughness max(mu_v, kMinViewCosine)^-roughness_slope,
// at most 1 (Blender's largest roughness). Why N.V: MBK's polished lobe is a Gaussian in
// eta = |N x (L + V)| = 2 cos(theta_d) sin(theta_h), so its width in theta_h goes as 1/cos(theta_d),
// and near the lobe's peak N = H, N.V = cos(theta_d); the renderer knows N.V for any light.
inline constexpr double kMinViewCosine = 0.05;
double lobe_alpha(const Lobe& lobe, double mu_v);
// blinn: POV-Ray cannot vary a finish's exponent continuously; a lobe with roughness_slope != 0 is a
// texture_map over slope { view } of kViewNodes textures (the include), node k at
// mu_v = view_node_cosine(k) = sin(pi/2 k/(kViewNodes - 1)) with exponent
// blinn_exponent_at_node(lobe, k) = roughness max(mu_k, kMinViewCosine)^(2 roughness_slope) (the width
// ~ 1/exponent^(1/2) following 1/N.V), blended linearly in the slope value 1/2 + asin(N.V)/pi as
// POV-Ray blends the entries (lobe_radiance does the same).
inline constexpr int kViewNodes = 24;
double view_node_cosine(int k);
double blinn_exponent_at_node(const Lobe& lobe, int k);
// POV-Ray 3.7's metallic weight F_m at N.L (empirical formula of its source).
double povray_metallic_weight(double n_dot_l);
// One lobe's radiance per unit irradiance (both cosines > 0; else 0).
double lobe_radiance(LobeShape shape, const Lobe& lobe, int channel, double n_dot_l, double n_dot_v, double n_dot_h);

struct FitQuality {
  double median = 0.0, p95 = 0.0, max = 0.0;  // relative per pixel and channel
  std::size_t values = 0;                     // pixel-channel values measured
  double lowest = 0.0;  // min over all lit, visible pixels of fit / scene maximum (< 0: dips below 0)
};

// Bands of the angle between the sun and the camera (deg) in which the fit's error is measured
// and stated (NativeFit::by_sun_angle); the fit's scenes reach 138 deg (theta_i, theta_s <= 70 deg
// leaves pixels only below 140 deg).
inline constexpr std::array<double, 6> kSunAngleBands = {0.0, 30.0, 60.0, 90.0, 120.0, 140.0};

struct SunAngleQuality {
  double from_deg = 0.0, to_deg = 0.0;  // sun-camera angle band
  FitQuality quality;                   // on two suns inside it (at 30% and 70% of the band)
};

struct NativeFit {
  LobeShape shape = LobeShape::ggx;
  std::vector<Lobe> lobes;
  FitQuality quality;                  // of the chosen lobe count, on the validation scenes
  std::vector<FitQuality> tried;       // quality with 1, 2, ... lobes (the last is the chosen one)
  std::vector<SunAngleQuality> by_sun_angle;  // the chosen fit's quality per band of kSunAngleBands
  double target_error = 0.0;
  bool target_met = false;
  int channels = 3;
  bool signed_colours = false;         // as requested (FitRequest)
  // Radiance per unit irradiance of the whole mixture.
  double radiance(int channel, double n_dot_l, double n_dot_v, double n_dot_h) const;
};

struct FitRequest {
  LobeShape shape = LobeShape::ggx;
  double target_error = 0.1;  // p95 of the per-pixel relative error, in (0, 1]
  int max_lobes = 5;          // 1..8
  // Colour coefficients of either sign (plain least squares): a difference of GGX lobes can fall
  // off like a Gaussian, which no non-negative GGX mixture can. The total may then dip below 0 far
  // from the lobe (measured: FitQuality). Default: non-negative (NNLS).
  bool signed_colours = false;
  // GGX only: an open band (excluded_alpha_low, excluded_alpha_high) of alpha that the renderer does
  // not render as GGX (EEVEE 3.4's LTC: Blender roughness 0.375-0.875, docs/renderers.md); every lobe stays out
  // of it. Default: none.
  double excluded_alpha_low = 0.0, excluded_alpha_high = 0.0;
  // Fit each lobe's roughness_slope too (ggx/beckmann: alpha following N.V, lobe_alpha; blinn: the
  // exponent at the view nodes, blinn_exponent_at_node). Default: fixed roughnesses (EEVEE: a
  // varying alpha would cross the excluded band).
  bool view_dependent_roughness = false;
};

// The default --target-error of `brdf export blender --mode fit` and `brdf export povray`.
inline constexpr double kDefaultTargetError = 0.1;

// Fits models (one per channel, 1 or 3 channels; a single channel is used for R, G and B) and
// measures the result. Throws InvalidArgument("target-error") outside (0, 1], ("wavelength") for
// another channel count.
NativeFit fit_native_lobes(const std::vector<Model>& models, const FitRequest& request);

// Validates --target-error (InvalidArgument "target-error" unless finite and in (0, 1]).
void validate_target_error(double target_error);

}  // namespace libbrdf::fit
