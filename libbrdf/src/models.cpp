#include "libbrdf/models.h"

#include <algorithm>
#include <cmath>

#include "angular_simd.h"
#include "libbrdf/beckmann_kirchhoff.h"
#include "libbrdf/error.h"

namespace libbrdf {
namespace {

// What a model reads from ModelParameters: its row's inputs, and the K table for a K factor. A
// model that reads rho_s and sigma_g (microfacet) maps the surface statistics onto what is not
// given (eqs 20, 25, K): with both given it needs neither sigma_s nor l_c, with rho_s no K.
struct Needs {
  bool sigma_s = false, lc = false, index = false, k_table = false;
};

bool k_replaced(const ModelTraits& row, const ModelParameters& p) { return row.reads(kRhoS) && p.rho_s.has_value(); }

Needs needs_of(const ModelTraits& row, const ModelParameters& p) {
  const bool surface_given_away = row.reads(kRhoS) && row.reads(kSigmaG) && p.rho_s && p.sigma_g;
  return Needs{row.needs(kSigmaS) && !surface_given_away, row.needs(kLc) && !surface_given_away, row.needs(kIndex),
               row.multiplies(kFactorK) && !k_replaced(row, p)};
}

[[noreturn]] void missing(const char* parameter, ModelKind kind, const char* hint = "") {
  throw InvalidArgument(parameter, std::string("required by model ") + std::string(model_name(kind)) + hint);
}

}  // namespace

ModelKind model_from_name(std::string_view name) {
  for (const ModelTraits& row : kModelRegistry)
    if (row.name == name) return row.kind;
  throw InvalidArgument("model", "unknown model '" + std::string(name) + "' (one of: " +
                                     model_names_where([](const ModelTraits&) { return true; }) + ")");
}

std::string_view model_name(ModelKind kind) { return model_traits(kind).name; }

std::vector<ModelKind> all_models() {
  std::vector<ModelKind> out;
  for (const ModelTraits& row : kModelRegistry) out.push_back(row.kind);
  return out;
}

bool is_brdf(ModelKind kind) { return model_traits(kind).is_brdf(); }

std::vector<Model> channel_models(ModelKind kind, const std::vector<ModelParameters>& channels) {
  std::vector<Model> models;
  models.reserve(channels.size());
  for (const ModelParameters& p : channels) models.emplace_back(kind, p);
  return models;
}

Model::Model(ModelKind kind, const ModelParameters& p) : kind_(kind), params_(p) {
  const ModelTraits& row = model_traits(kind);
  const Needs needs = needs_of(row, p);
  require_positive("wavelength", p.wavelength_um, "um");
  if (needs.sigma_s && !p.sigma_s_um) missing("sigma_s", kind);
  if (needs.lc && !p.lc_um) missing("lc", kind);
  if (needs.index && !p.index) missing("n", kind, " (or give a material)");
  surface_ = Surface{p.sigma_s_um.value_or(0.0), p.lc_um.value_or(1.0), p.wavelength_um};
  validate_surface(surface_);
  if (p.index) {
    validate_index(*p.index);
    permittivity_ = p.index->permittivity();
  }
  if (!std::isfinite(p.tolerance) || p.tolerance < 0.0 || p.tolerance >= 1.0)
    throw InvalidArgument("tolerance", "must be in [0, 1) (relative error; 0 = always the series)");
  // Ranges: microfacet.h (kMinSigmaG, kMaxSigmaG, kMaxRhoS).
  require_in_range("rho_d", p.rho_d, 0.0, 1.0);
  if (p.rho_s) require_in_range("rho_s", *p.rho_s, 0.0, kMaxRhoS);
  if (p.sigma_g) require_in_range("sigma_g", *p.sigma_g, kMinSigmaG, kMaxSigmaG);
  if (!(p.series.relative_tolerance > 0.0 && p.series.relative_tolerance < 1e-3))
    throw InvalidArgument("series tolerance", "must be in (0, 1e-3)");

  if (row.reads(kSigmaG)) {  // given, or mapped from the surface
    if (p.sigma_g) {
      sigma_g_ = *p.sigma_g;
    } else {
      const bool polished =
          p.sigma_g_mapping == SigmaGMapping::polished ||
          (p.sigma_g_mapping == SigmaGMapping::automatic && roughness_g(surface_.sigma_over_lambda(), 1.0, 1.0) < 1.0);
      sigma_g_ = polished ? sigma_g_from_polished_surface(surface_.lc_um, surface_.wavelength_um)
                          : sigma_g_from_rough_surface(surface_.sigma_s_um, surface_.lc_um);
      // A perfect mirror has no slope distribution; the BRDF part is then 0 (sigma_s = 0). The
      // polished mapping (eq. 25) does not depend on sigma_s, so the mirror is checked directly.
      if (surface_.sigma_s_um == 0.0 || !(sigma_g_ > 0.0)) sigma_g_ = 0.0;
      if (sigma_g_ != 0.0 && !(sigma_g_ >= kMinSigmaG))
        throw InvalidArgument("sigma_g", std::string("the slope mapped from the surface (eq. ") + (polished ? "25" : "20") +
                                             ") is below 1e-7, a mirror; give sigma_g in [1e-7, 1000]");
    }
  }
  if (needs.k_table) k_table_ = cached_renormalization_table(surface_, p.k_mode);
}

double Model::evaluate(const ScatterAngles& angles) const { return evaluate(make_scatter_geometry(angles)); }

double Model::renormalization(double theta_i) const { return k_table_ ? (*k_table_)(theta_i) : 1.0; }

double Model::specular_reflectance(double theta_i) const {
  if (!model_traits(kind_).spike) return 0.0;
  const double ci = std::cos(theta_i);
  // The m = 0 term of the series: a delta of weight F(ti) exp(-g(ti, ti)) (conventions.md).
  return fresnel_reflectance(permittivity_, ci) * std::exp(-roughness_g(surface_.sigma_over_lambda(), ci, ci));
}

double Model::evaluate(const ScatterGeometry& geo) const { return evaluate_impl(geo, nullptr); }

double Model::evaluate(const ScatterGeometry& geo, double asf) const { return evaluate_impl(geo, &asf); }

bool Model::uses_asf() const { return model_traits(kind_).asf_based; }

double Model::asf_at(const ScatterGeometry& geo) const {
  return asf_auto(asf_arguments(surface_, geo), params_.tolerance, nullptr, params_.series);
}

namespace {
// Which factors a model multiplies (its row; the formulas in Model::combine_span): K not where a
// given rho_s replaces it.
struct FactorNeeds {
  bool k = false, q_bar = false, fresnel_d = false, asf = false;
};
FactorNeeds factor_needs(ModelKind kind, const ModelParameters& p) {
  const ModelTraits& row = model_traits(kind);
  return FactorNeeds{row.multiplies(kFactorK) && !k_replaced(row, p), row.multiplies(kFactorQBar),
                     row.multiplies(kFactorFresnelD), row.multiplies(kFactorAsf)};
}
// theta_i only for the quantities tabulated over it (K, R_spec): an atan2 the others skip.
double theta_i_of(const ScatterGeometry& geo) { return std::atan2(geo.sin_theta_i, geo.cos_theta_i); }
}  // namespace

double Model::evaluate_impl(const ScatterGeometry& geo, const double* asf_given) const {
  const FactorNeeds needs = factor_needs(kind_, params_);
  double k = 1.0, q_bar = 0.0, fresnel_d = 0.0, asf = 0.0;
  if (needs.k) k = renormalization(theta_i_of(geo));
  if (needs.q_bar) q_bar = stover_q(permittivity_, geo).q_bar();
  if (needs.fresnel_d) fresnel_d = fresnel_reflectance(permittivity_, geo.cos_theta_d);
  if (needs.asf) asf = asf_given ? *asf_given : asf_at(geo);
  double value = 0.0;
  combine_span(&geo, 1, FactorSpans{&k, &q_bar, &fresnel_d, &asf}, &value);
  return value;
}

void Model::evaluate_many(const ScatterGeometry* geos, std::size_t count, double* out, const double* asf) const {
  const FactorNeeds needs = factor_needs(kind_, params_);
  const double eps_re = permittivity_.real(), eps_im = permittivity_.imag();
  constexpr std::size_t kBlock = 256;
  double k[kBlock], q_bar[kBlock], fresnel_d[kBlock], a[kBlock];
  for (std::size_t begin = 0; begin < count; begin += kBlock) {
    const std::size_t n = std::min(kBlock, count - begin);
    const ScatterGeometry* span = geos + begin;
    if (needs.k) {
      if (k_table_) k_table_->at_geometries(span, n, k);
      else std::fill(k, k + n, 1.0);
    }
    if (needs.q_bar) detail::stover_q_bar_span(eps_re, eps_im, span, n, q_bar);
    if (needs.fresnel_d) detail::fresnel_d_span(eps_re, eps_im, span, n, fresnel_d);
    // The ASF of the span in SIMD lanes (asf_auto_batch: asf_auto's method per query, each lane
    // alone, so a value depends on its own geometry only: batch.h's scalar and array calls agree).
    if (needs.asf && !asf) asf_auto_geometries(surface_, span, n, params_.tolerance, params_.series, a);
    combine_span(span, n, FactorSpans{k, q_bar, fresnel_d, asf ? asf + begin : a}, out + begin);
  }
}

void Model::combine_span(const ScatterGeometry* geos, std::size_t count, const FactorSpans& f, double* out) const {
  // One loop per model around its formula (`each`, inlined): the compiler vectorises the factor
  // products. A per-query call of a combine(geo, factors) cost ~2 ns, as much as asf's own table
  // lookup without it (in cache, one thread: asf 9.5 -> 7.4 ns, mbk 16.5 -> 14.4 ns per query).
  auto each = [&](auto&& formula) {
    for (std::size_t j = 0; j < count; ++j) out[j] = formula(j);
  };
  const double sigma_over_lambda = surface_.sigma_over_lambda();
  // Eq. 2's surface term with a facet reflectance R (F(td) in the paper's form) + Lambertian part.
  auto facet_lobe = [&](const double* reflectance) {
    return each([&](std::size_t j) {
      const ScatterGeometry& geo = geos[j];
      const double rho_s = params_.rho_s ? *params_.rho_s : f.k[j];  // rho_s = K
      double specular = 0.0;
      if (sigma_g_ > 0.0) {
        specular = rho_s * reflectance[j] * gaussian_facet_distribution(geo.cos_theta_h, sigma_g_) *
                   geometric_term(params_.g_term, geo, sigma_g_) / (4.0 * geo.cos_theta_i * geo.cos_theta_s);
      }
      return specular + params_.rho_d / kPi;
    });
  };
  switch (kind_) {
    case ModelKind::fresnel: return each([&](std::size_t j) { return f.fresnel_d[j]; });
    case ModelKind::q: return each([&](std::size_t j) { return f.q_bar[j]; });
    case ModelKind::q_ss: return each([&](std::size_t j) { return stover_q(permittivity_, geos[j]).ss; });
    case ModelKind::q_sp: return each([&](std::size_t j) { return stover_q(permittivity_, geos[j]).sp; });
    case ModelKind::q_ps: return each([&](std::size_t j) { return stover_q(permittivity_, geos[j]).ps; });
    case ModelKind::q_pp: return each([&](std::size_t j) { return stover_q(permittivity_, geos[j]).pp; });
    case ModelKind::s: return each([&](std::size_t j) { return s_term(geos[j]); });
    case ModelKind::rd: return each([&](std::size_t j) { return relative_difference_rd(permittivity_, geos[j]); });
    case ModelKind::g:
      return each([&](std::size_t j) { return roughness_g(sigma_over_lambda, geos[j].cos_theta_i, geos[j].cos_theta_s); });
    case ModelKind::eta_r2: return each([&](std::size_t j) { return geos[j].eta_r2; });
    case ModelKind::asf: return each([&](std::size_t j) { return f.asf[j]; });  // K = 1; method by the tolerance (asf_auto)
    case ModelKind::k:
      return each([&](std::size_t j) { return renormalization_direct(surface_, theta_i_of(geos[j]), params_.k_mode).k; });
    case ModelKind::r_spec: return each([&](std::size_t j) { return specular_reflectance(theta_i_of(geos[j])); });
    case ModelKind::mbk:  // K Qbar A, eq. 11 x Q (conventions.md: Qbar)
      return each([&](std::size_t j) { return f.k[j] * f.q_bar[j] * f.asf[j]; });
    case ModelKind::mbk_polished:  // eq. 14 with Qbar: K = 1, e^-g = 1, m = 1
      return each([&](std::size_t j) {
        const AsfArguments a = asf_arguments(surface_, geos[j]);
        return f.q_bar[j] * a.prefactor * mbk_series_polished(a.g, a.c);
      });
    case ModelKind::mbk_rough:  // eq. 15 with Qbar and K
      return each([&](std::size_t j) {
        const AsfArguments a = asf_arguments(surface_, geos[j]);
        return f.k[j] * f.q_bar[j] * a.prefactor * mbk_series_rough(a.g, a.c);
      });
    case ModelKind::mbk_fg:  // eq. 31's form: K F(td) G / S * A
      return each([&](std::size_t j) {
        return f.k[j] * f.fresnel_d[j] * geometric_term(params_.g_term, geos[j], sigma_g_) / s_term(geos[j]) * f.asf[j];
      });
    case ModelKind::bk:  // F(td) F_bk^2 A, eq. 26
      return each([&](std::size_t j) { return f.fresnel_d[j] * bk_geometric_factor_eq26(geos[j]) * f.asf[j]; });
    case ModelKind::bk_modified:  // F(td) (1/S) A, eq. 28
      return each([&](std::size_t j) { return f.fresnel_d[j] * inverse_s_term_eq28(geos[j]) * f.asf[j]; });
    case ModelKind::microfacet: return facet_lobe(f.fresnel_d);  // eqs 2, 3, 7
    case ModelKind::microfacet_q: return facet_lobe(f.q_bar);    // Stover's Qbar = Q/2 in place of F
  }
}

}  // namespace libbrdf
