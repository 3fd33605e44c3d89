#pragma once
// The models, one constexpr row each: what every part of libbrdf and its tools knows about a model
// (the core's inputs and factors, the CLI's and the Python module's option checks, the bake, the
// table metadata, the exporters) is read from its row. Adding a model: docs/models.md (this file,
// its formula in models.cpp's Model::combine_span, a test). Conventions: docs/conventions.md
// (every BRDF uses Qbar = (Q_s + Q_p)/2, which is F at specular).
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace libbrdf {

// In the rows' order (checked below).
enum class ModelKind {
  fresnel, q, q_ss, q_sp, q_ps, q_pp, s, rd, g, eta_r2, asf, k, r_spec,
  mbk, mbk_polished, mbk_rough, mbk_fg, bk, bk_modified, microfacet, microfacet_q
};

// Bit sets of a row. Inputs: surface values a model requires (missing: InvalidArgument naming the
// option). A model that reads rho_s and sigma_g needs sigma_s and l_c only to map what is not given.
enum ModelInput : std::uint8_t { kNoInput = 0, kSigmaS = 1, kLc = 2, kIndex = 4 };
// Options only some models read: given to another model they are an error, never ignored. A model
// that reads rho_s takes it in place of K (its K factor is then not computed).
enum ModelOption : std::uint8_t { kNoOption = 0, kRhoS = 1, kRhoD = 2, kSigmaG = 4, kGTerm = 8, kSigmaGMapping = 16 };
// The factors a formula multiplies, computed over spans by Model::evaluate_many (the others are not
// computed): K(theta_i) of eq. 13 (a table), Stover's Qbar, F(theta_d), the ASF A of eq. 11 (K = 1).
enum ModelFactor : std::uint8_t { kNoFactor = 0, kFactorK = 1, kFactorQBar = 2, kFactorFresnelD = 4, kFactorAsf = 8 };

// How directional_albedo (albedo.h) integrates a model: `none` for a quantity that is not a BRDF
// (no albedo, no bake); a lobe as narrow as the ASF's m = 1 Gaussian (eq. 11); or also as narrow as
// the facet distribution D_g (eq. 7, width sigma_g).
enum class AlbedoPath { none, surface_lobe, facet_lobe };

// ASF models (P x A): the angular factor P when it is a closed form needing no table at all (the
// kernel layout's P~ = 1; the exporters' shaders compute it). The values are the OSL shader's
// LIBBRDF_CLOSED_FORM (exporters/src/osl.cpp).
enum class ClosedAngularForm : int { none = 0, bk_eq26 = 1, bk_modified_eq28 = 2 };

struct ModelTraits {
  ModelKind kind;
  std::string_view name;      // the CLI's --model and Python's Model(name)
  std::string_view formula;   // in the paper's symbols, 1/sr for BRDFs
  std::string_view equation;  // where the paper has it
  std::uint8_t inputs;        // ModelInput bits
  std::uint8_t options;       // ModelOption bits
  std::uint8_t factors;       // ModelFactor bits
  bool spike;                 // a specular delta F(ti) exp(-g(ti, ti)) beside the values (R_spec)
  bool asf_based;             // P x A with the ASF of eq. 11: the kernel layout and shaders factor it
  AlbedoPath albedo;
  ClosedAngularForm closed_angular = ClosedAngularForm::none;

  constexpr bool is_brdf() const { return albedo != AlbedoPath::none; }
  constexpr bool reads(ModelOption option) const { return (options & option) != 0; }
  constexpr bool needs(ModelInput input) const { return (inputs & input) != 0; }
  constexpr bool multiplies(ModelFactor factor) const { return (factors & factor) != 0; }
  // K is always part of the formula (not replaceable by a given rho_s).
  constexpr bool always_renormalized() const { return multiplies(kFactorK) && !reads(kRhoS); }
};

namespace detail {
constexpr std::uint8_t bits(std::uint8_t a, std::uint8_t b = 0, std::uint8_t c = 0, std::uint8_t d = 0) {
  return static_cast<std::uint8_t>(a | b | c | d);
}
inline constexpr std::uint8_t kSurface = bits(kSigmaS, kLc, kIndex);
inline constexpr std::uint8_t kFacetOptions = bits(kRhoS, kRhoD, bits(kSigmaG, kGTerm, kSigmaGMapping));
inline constexpr std::uint8_t kSlopeOptions = bits(kSigmaG, kGTerm, kSigmaGMapping);  // sigma_g and G (eqs 7, 31)
}  // namespace detail

// clang-format off
inline constexpr ModelTraits kModelRegistry[] = {
  // Quantities (not BRDFs): the paper's terms, for checks and plots.
  {ModelKind::fresnel, "fresnel", "F(td)", "Fresnel reflectance at theta_d", kIndex, kNoOption, kFactorFresnelD, false, false, AlbedoPath::none},
  {ModelKind::q, "q", "Qbar = (Q_s + Q_p)/2", "Stover's Q, unpolarized", kIndex, kNoOption, kFactorQBar, false, false, AlbedoPath::none},
  {ModelKind::q_ss, "q-ss", "Q_ss", "Stover's Q", kIndex, kNoOption, kNoFactor, false, false, AlbedoPath::none},
  {ModelKind::q_sp, "q-sp", "Q_sp", "Stover's Q", kIndex, kNoOption, kNoFactor, false, false, AlbedoPath::none},
  {ModelKind::q_ps, "q-ps", "Q_ps", "Stover's Q", kIndex, kNoOption, kNoFactor, false, false, AlbedoPath::none},
  {ModelKind::q_pp, "q-pp", "Q_pp", "Stover's Q", kIndex, kNoOption, kNoFactor, false, false, AlbedoPath::none},
  {ModelKind::s, "s", "S = 4 ci cs cos^4 th / (ci + cs)^2 (~ 2F/Q)", "eq. 22", kNoInput, kNoOption, kNoFactor, false, false, AlbedoPath::none},
  {ModelKind::rd, "rd", "R_d = |2F/Q - S| / (2F/Q)", "eq. 23", kIndex, kNoOption, kNoFactor, false, false, AlbedoPath::none},
  {ModelKind::g, "g", "g = (2 pi sigma_s / lambda)^2 (cos ti + cos ts)^2", "eq. 12", kSigmaS, kNoOption, kNoFactor, true, false, AlbedoPath::none},
  {ModelKind::eta_r2, "eta-r2", "eta_r^2", "eq. 10", kNoInput, kNoOption, kNoFactor, false, false, AlbedoPath::none},
  {ModelKind::asf, "asf", "A (K = 1)", "eq. 11", detail::bits(kSigmaS, kLc), kNoOption, kFactorAsf, true, false, AlbedoPath::none},
  {ModelKind::k, "k", "K(ti), computed directly", "eq. 13", detail::bits(kSigmaS, kLc), kNoOption, kNoFactor, true, false, AlbedoPath::none},
  {ModelKind::r_spec, "r-spec", "R_spec = F(ti) exp(-g(ti, ti))", "specular spike", detail::bits(kSigmaS, kIndex), kNoOption, kNoFactor, true, false, AlbedoPath::none},
  // BRDFs (1/sr).
  {ModelKind::mbk, "mbk", "K(ti) Qbar A", "eq. 11 x Q, K of eq. 13", detail::kSurface, kNoOption,
   detail::bits(kFactorK, kFactorQBar, kFactorAsf), true, true, AlbedoPath::surface_lobe},
  {ModelKind::mbk_polished, "mbk-polished", "Qbar A_polished (K = 1, e^-g = 1)", "eq. 14", detail::kSurface, kNoOption,
   kFactorQBar, true, false, AlbedoPath::surface_lobe},
  {ModelKind::mbk_rough, "mbk-rough", "K Qbar A_rough", "eq. 15", detail::kSurface, kNoOption,
   detail::bits(kFactorK, kFactorQBar), true, false, AlbedoPath::surface_lobe},
  {ModelKind::mbk_fg, "mbk-fg", "K F(td) G / S * A", "eq. 31's form", detail::kSurface, detail::kSlopeOptions,
   detail::bits(kFactorK, kFactorFresnelD, kFactorAsf), true, true, AlbedoPath::surface_lobe},
  {ModelKind::bk, "bk", "F(td) F_bk^2 A", "eq. 26 (original BK; not reciprocal)", detail::kSurface, kNoOption,
   detail::bits(kFactorFresnelD, kFactorAsf), true, true, AlbedoPath::surface_lobe, ClosedAngularForm::bk_eq26},
  {ModelKind::bk_modified, "bk-modified", "F(td) (1/S) A", "eq. 28 (the paper's proposal)", detail::kSurface, kNoOption,
   detail::bits(kFactorFresnelD, kFactorAsf), true, true, AlbedoPath::surface_lobe, ClosedAngularForm::bk_modified_eq28},
  {ModelKind::microfacet, "microfacet", "rho_s F(td) D_g G / (4 ci cs) + rho_d / pi", "eqs 2, 3, 7", detail::kSurface,
   detail::kFacetOptions, detail::bits(kFactorK, kFactorFresnelD), false, false, AlbedoPath::facet_lobe},
  // The paper's suggestion after eq. 22 (2F/Q ~ S): "Q/2 could be used in place of F".
  {ModelKind::microfacet_q, "microfacet-q", "rho_s Qbar D_g G / (4 ci cs) + rho_d / pi", "eqs 2, 3, 7 with Q/2 for F (sec. 3.1)",
   detail::kSurface, detail::kFacetOptions, detail::bits(kFactorK, kFactorQBar), false, false, AlbedoPath::facet_lobe},
};
// clang-format on

inline constexpr std::size_t kModelCount = sizeof(kModelRegistry) / sizeof(kModelRegistry[0]);

namespace detail {
constexpr bool rows_in_enum_order() {
  for (std::size_t k = 0; k < kModelCount; ++k)
    if (static_cast<std::size_t>(kModelRegistry[k].kind) != k) return false;
  return true;
}
}  // namespace detail
static_assert(detail::rows_in_enum_order(), "kModelRegistry: one row per ModelKind, in the enum's order");

// The row of a model.
constexpr const ModelTraits& model_traits(ModelKind kind) { return kModelRegistry[static_cast<std::size_t>(kind)]; }

}  // namespace libbrdf
