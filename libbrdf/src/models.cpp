#include "libbrdf/models.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "angular_simd.h"
#include "libbrdf/beckmann_kirchhoff.h"
#include "libbrdf/error.h"

namespace libbrdf {
namespace {

struct ModelName {
  ModelKind kind;
  std::string_view name;
};
constexpr std::array<ModelName, 20> kModelNames{{
    {ModelKind::fresnel, "fresnel"}, {ModelKind::q, "q"}, {ModelKind::q_ss, "q-ss"}, {ModelKind::q_sp, "q-sp"},
    {ModelKind::q_ps, "q-ps"}, {ModelKind::q_pp, "q-pp"}, {ModelKind::s, "s"}, {ModelKind::rd, "rd"},
    {ModelKind::g, "g"}, {ModelKind::eta_r2, "eta-r2"}, {ModelKind::asf, "asf"}, {ModelKind::k, "k"},
    {ModelKind::r_spec, "r-spec"}, {ModelKind::mbk, "mbk"}, {ModelKind::mbk_polished, "mbk-polished"},
    {ModelKind::mbk_rough, "mbk-rough"}, {ModelKind::mbk_fg, "mbk-fg"}, {ModelKind::bk, "bk"},
    {ModelKind::bk_modified, "bk-modified"}, {ModelKind::microfacet, "microfacet"},
}};

// What a model reads from ModelParameters.
struct Needs {
  bool sigma_s = false, lc = false, index = false, k_table = false;
};

Needs needs_of(ModelKind kind, const ModelParameters& p) {
  Needs needs;
  switch (kind) {
    case ModelKind::fresnel: case ModelKind::q: case ModelKind::q_ss: case ModelKind::q_sp:
    case ModelKind::q_ps: case ModelKind::q_pp: case ModelKind::rd:
      needs.index = true;
      break;
    case ModelKind::s: case ModelKind::eta_r2:
      break;
    case ModelKind::g:
      needs.sigma_s = true;
      break;
    case ModelKind::asf: case ModelKind::k:
      needs.sigma_s = needs.lc = true;
      break;
    case ModelKind::r_spec:
      needs.sigma_s = needs.index = true;
      break;
    case ModelKind::mbk_polished: case ModelKind::bk: case ModelKind::bk_modified:
      needs.sigma_s = needs.lc = needs.index = true;
      break;
    case ModelKind::mbk: case ModelKind::mbk_rough: case ModelKind::mbk_fg:
      needs.sigma_s = needs.lc = needs.index = needs.k_table = true;
      break;
    case ModelKind::microfacet:
      needs.index = true;
      // Without an explicit sigma_g and rho_s the surface statistics map onto them (eqs 20, 25).
      needs.sigma_s = needs.lc = !p.sigma_g.has_value() || !p.rho_s.has_value();
      needs.k_table = !p.rho_s.has_value();
      break;
  }
  return needs;
}

[[noreturn]] void missing(const char* parameter, ModelKind kind, const char* hint = "") {
  throw InvalidArgument(parameter, std::string("required by model ") + std::string(model_name(kind)) + hint);
}

}  // namespace

ModelKind model_from_name(std::string_view name) {
  for (const ModelName& entry : kModelNames)
    if (entry.name == name) return entry.kind;
  std::ostringstream known;
  for (const ModelName& entry : kModelNames) known << (entry.kind == ModelKind::fresnel ? "" : ", ") << entry.name;
  throw InvalidArgument("model", "unknown model '" + std::string(name) + "' (one of: " + known.str() + ")");
}

std::string_view model_name(ModelKind kind) {
  for (const ModelName& entry : kModelNames)
    if (entry.kind == kind) return entry.name;
  return "?";
}

std::vector<ModelKind> all_models() {
  std::vector<ModelKind> out;
  for (const ModelName& entry : kModelNames) out.push_back(entry.kind);
  return out;
}

bool is_brdf(ModelKind kind) {
  switch (kind) {
    case ModelKind::mbk: case ModelKind::mbk_polished: case ModelKind::mbk_rough: case ModelKind::mbk_fg:
    case ModelKind::bk: case ModelKind::bk_modified: case ModelKind::microfacet:
      return true;
    default:
      return false;
  }
}

std::vector<Model> channel_models(ModelKind kind, const std::vector<ModelParameters>& channels) {
  std::vector<Model> models;
  models.reserve(channels.size());
  for (const ModelParameters& p : channels) models.emplace_back(kind, p);
  return models;
}

Model::Model(ModelKind kind, const ModelParameters& p) : kind_(kind), params_(p) {
  const Needs needs = needs_of(kind, p);
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

  const bool uses_g_term = kind == ModelKind::microfacet || kind == ModelKind::mbk_fg;
  if (uses_g_term || kind == ModelKind::microfacet) {
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
  switch (kind_) {
    case ModelKind::microfacet: case ModelKind::fresnel: case ModelKind::q: case ModelKind::q_ss:
    case ModelKind::q_sp: case ModelKind::q_ps: case ModelKind::q_pp: case ModelKind::s: case ModelKind::rd:
    case ModelKind::eta_r2:
      return 0.0;
    default:
      break;
  }
  const double ci = std::cos(theta_i);
  // The m = 0 term of the series: a delta of weight F(ti) exp(-g(ti, ti)) (conventions.md).
  return fresnel_reflectance(permittivity_, ci) * std::exp(-roughness_g(surface_.sigma_over_lambda(), ci, ci));
}

double Model::evaluate(const ScatterGeometry& geo) const { return evaluate_impl(geo, nullptr); }

double Model::evaluate(const ScatterGeometry& geo, double asf) const { return evaluate_impl(geo, &asf); }

bool Model::uses_asf() const {
  return kind_ == ModelKind::mbk || kind_ == ModelKind::mbk_fg || kind_ == ModelKind::bk || kind_ == ModelKind::bk_modified;
}

double Model::asf_at(const ScatterGeometry& geo) const {
  return asf_auto(asf_arguments(surface_, geo), params_.tolerance, nullptr, params_.series);
}

namespace {
// Which factors a model multiplies (the formulas in Model::combine_span).
struct FactorNeeds {
  bool k = false, q_bar = false, fresnel_d = false, asf = false;
};
FactorNeeds factor_needs(ModelKind kind, const ModelParameters& p, double sigma_g) {
  FactorNeeds needs;
  switch (kind) {
    case ModelKind::fresnel: needs.fresnel_d = true; break;
    case ModelKind::q: case ModelKind::mbk_polished: needs.q_bar = true; break;
    case ModelKind::asf: needs.asf = true; break;
    case ModelKind::mbk: needs.k = needs.q_bar = needs.asf = true; break;
    case ModelKind::mbk_rough: needs.k = needs.q_bar = true; break;
    case ModelKind::mbk_fg: needs.k = needs.fresnel_d = needs.asf = true; break;
    case ModelKind::bk: case ModelKind::bk_modified: needs.fresnel_d = needs.asf = true; break;
    case ModelKind::microfacet:
      needs.k = !p.rho_s.has_value();  // rho_s = K (conventions.md)
      needs.fresnel_d = sigma_g > 0.0;
      break;
    default: break;  // the other quantities are computed whole by combine_span()
  }
  return needs;
}
// theta_i only for the quantities tabulated over it (K, R_spec): an atan2 the others skip.
double theta_i_of(const ScatterGeometry& geo) { return std::atan2(geo.sin_theta_i, geo.cos_theta_i); }
}  // namespace

double Model::evaluate_impl(const ScatterGeometry& geo, const double* asf_given) const {
  const FactorNeeds needs = factor_needs(kind_, params_, sigma_g_);
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
  const FactorNeeds needs = factor_needs(kind_, params_, sigma_g_);
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
    case ModelKind::microfacet:  // eq. 2 surface term + Lambertian
      return each([&](std::size_t j) {
        const ScatterGeometry& geo = geos[j];
        const double rho_s = params_.rho_s ? *params_.rho_s : f.k[j];  // rho_s = K
        double specular = 0.0;
        if (sigma_g_ > 0.0) {
          specular = rho_s * f.fresnel_d[j] * gaussian_facet_distribution(geo.cos_theta_h, sigma_g_) *
                     geometric_term(params_.g_term, geo, sigma_g_) / (4.0 * geo.cos_theta_i * geo.cos_theta_s);
        }
        return specular + params_.rho_d / kPi;
      });
  }
  std::fill(out, out + count, 0.0);
}

}  // namespace libbrdf
