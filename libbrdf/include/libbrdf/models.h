#pragma once
// Every model of the paper behind one interface: a named quantity evaluated at
// (theta_i, theta_s, phi_s). Which models there are, their formulas, equations, inputs, options
// and factors: one row each in model_registry.h. Conventions: docs/conventions.md (all BRDFs
// use Qbar).
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "libbrdf/fresnel.h"
#include "libbrdf/geometry.h"
#include "libbrdf/mbk_series.h"
#include "libbrdf/microfacet.h"
#include "libbrdf/model_registry.h"
#include "libbrdf/renormalization.h"
#include "libbrdf/surface.h"

namespace libbrdf {

// Command-line names ("mbk-polished", ...). Throws InvalidArgument("model", list) when unknown.
ModelKind model_from_name(std::string_view name);
std::string_view model_name(ModelKind kind);
std::vector<ModelKind> all_models();
// True for the BRDFs (values in 1/sr), the models a bake accepts (model_traits(kind).is_brdf()).
bool is_brdf(ModelKind kind);
// The names of the models whose row satisfies `keep`, joined by `separator` in the rows' order
// ("mbk, mbk-fg, bk, bk-modified"): for messages that list the models an option or layout takes.
template <typename Predicate>
std::string model_names_where(Predicate keep, std::string_view separator = ", ") {
  std::string out;
  for (const ModelTraits& row : kModelRegistry)
    if (keep(row)) out += (out.empty() ? "" : std::string(separator)) + std::string(row.name);
  return out;
}

// Which of eqs 20 / 25 maps sigma_s, l_c to the microfacet sigma_g.
enum class SigmaGMapping {
  automatic,  // polished (eq. 25) when g(0,0) = (4 pi sigma_s/lambda)^2 < 1, else rough (eq. 20)
  rough,      // eq. 20
  polished    // eq. 25
};

// Everything a model may need at one wavelength. Unset optionals are "not given": a model that
// needs them throws InvalidArgument naming the command-line parameter.
struct ModelParameters {
  std::optional<double> sigma_s_um;
  std::optional<double> lc_um;
  double wavelength_um = 0.55;
  std::optional<ComplexIndex> index;  // n + i kappa
  std::optional<double> sigma_g;      // microfacet slope parameter; else mapped from the surface
  std::optional<double> rho_s;        // microfacet amplitude; else K(ti) (conventions.md)
  double rho_d = 0.0;                 // Lambertian part of eq. 2
  GeometricTerm g_term = GeometricTerm::smith;
  SigmaGMapping sigma_g_mapping = SigmaGMapping::automatic;
  KMode k_mode = KMode::plane;
  double tolerance = 1e-6;            // regime choice for mbk: relative error allowed for a closed form
  SeriesOptions series;               // how the ASF series is summed
};

// A validated, ready-to-evaluate model. Construction checks the parameters and builds what is
// reused across queries (K table, permittivity); evaluation is thread-safe.
class Model {
 public:
  Model(ModelKind kind, const ModelParameters& parameters);

  // Value at one query (radians). Throws InvalidArgument for angles outside [0, pi/2) or NaN.
  double evaluate(const ScatterAngles& angles) const;
  // Same with derived geometry already computed (no validation; for bakes and inner loops).
  double evaluate(const ScatterGeometry& geo) const;
  // For callers that reuse one ASF value across geometries with equal (g, c) (eq. 12 and
  // c = pi^2 (l_c/lambda)^2 eta_r^2), e.g. a bake along phi_d at fixed (theta_h, theta_d), where
  // cos ti + cos ts = 2 cos td cos th and eta_r = 2 cos td sin th do not depend on phi_d.
  // uses_asf(): the model contains the ASF A of eq. 11 (its row's asf_based);
  // asf_at(geo): the A that evaluate() uses there; evaluate(geo, asf): evaluate() with A given.
  bool uses_asf() const;
  double asf_at(const ScatterGeometry& geo) const;
  double evaluate(const ScatterGeometry& geo, double asf) const;
  // A span: out[k] = evaluate(geos[k]), or evaluate(geos[k], asf[k]) when `asf` is given (count
  // values). K, Qbar and F(theta_d) are computed over the span in SIMD (Google Highway), the ASF by
  // asf_auto_batch (evaluate()'s method per query, in SIMD lanes; each value depends on its own
  // geometry only, never on the span); the rest of each model's formula is the one evaluate()
  // uses. Agrees with
  // evaluate() to <= 1e-12 relative with `asf` given (tests/cpp/test_models.cpp: grazing angles,
  // n < 1, every model), 3e-10 for |n + i kappa| ~ 1000 at grazing (where the scalar Qbar itself is
  // good to 1e-10 only), and within 2 x the tolerance without `asf` (both ASFs within it of the
  // series). No validation: what evaluate(geo) does not check, this does not either.
  void evaluate_many(const ScatterGeometry* geos, std::size_t count, double* out, const double* asf = nullptr) const;

  // Specular spike reflectance R_spec(ti) = F(ti) exp(-g(ti, ti)) (a delta lobe, not a BRDF
  // value), for the models that have one (their row's spike: the MBK and BK families); 0 otherwise.
  double specular_reflectance(double theta_i_rad) const;
  // K(ti) as used by this model (table), 1 where the model has no K.
  double renormalization(double theta_i_rad) const;
  // The microfacet slope parameter sigma_g in use (given, or mapped by eqs 20/25; 0 when the model
  // needs none). For exporters that map a model onto a renderer's microfacet BSDF.
  double sigma_g() const { return sigma_g_; }

  ModelKind kind() const { return kind_; }
  const ModelParameters& parameters() const { return params_; }
  // The surface at this model's wavelength.
  Surface surface() const { return surface_; }

 private:
  ModelKind kind_;
  ModelParameters params_;
  Surface surface_{};
  Complex permittivity_{1.0, 0.0};
  double sigma_g_ = 0.0;
  std::shared_ptr<const RenormalizationTable> k_table_;

  // The factors a model multiplies, over a span (those it needs; the others are not read): computed
  // per query by evaluate() and over spans by evaluate_many(), then combined by the one formula per
  // model, combine_span (out[j] for j < count).
  struct FactorSpans {
    const double* k;          // K(theta_i), eq. 13 (table)
    const double* q_bar;      // Stover's Qbar
    const double* fresnel_d;  // F(theta_d)
    const double* asf;        // A of eq. 11 (K = 1)
  };
  double evaluate_impl(const ScatterGeometry& geo, const double* asf_given) const;
  void combine_span(const ScatterGeometry* geos, std::size_t count, const FactorSpans& f, double* out) const;
};

// One Model per channel (wavelength) of a multi-channel material, in the channels' order.
std::vector<Model> channel_models(ModelKind kind, const std::vector<ModelParameters>& channels);

}  // namespace libbrdf
