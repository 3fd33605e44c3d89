// Native-lobe fit (fit.h): sphere-pixel scenes, non-negative least squares for the colours,
// Nelder-Mead for the roughnesses, lobe count by target error.
#include "exporters/fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "libbrdf/batch.h"
#include "libbrdf/error.h"
#include "libbrdf/geometry.h"

namespace libbrdf::fit {

namespace {

constexpr double kPiD = 3.14159265358979323846;
constexpr double kSelectThetaDeg = 70.0;  // the one-sun check's pixel selection (fit.h)
constexpr double kFitThetaDeg = 80.0;     // fitted a little beyond it, so the edge is not free
constexpr double kFloorFraction = 0.01;   // of the scene's maximum radiance
// Below the floor an absolute error of kTailScale x floor counts as much as a 100% error above it:
// the check ignores those pixels, and a GGX lobe's long tail must not pull its core narrow.
constexpr double kTailScale = 3.0;
// Signed colours: a ridge of this fraction of the largest normal-equation diagonal limits how much
// the lobes cancel each other, which EEVEE's GGX (not quite GGX) does not reproduce. Measured in
// EEVEE (tests/blender/test_blender_fit.py, medians): polished n = 1.5 + 1i 8.3% at 1e-9, 2.6% at
// 1e-6, 2.5% at 1e-5, 3.9% at 1e-4, 7.5% at 1e-3; BK7 4.9%, 2.4%, 2.2%, 1.5%, 2.5%.
constexpr double kSignedRidge = 1e-5;
// POV-Ray (blinn shape): S / the largest S c (solve_colours): pigments up to 1/kWhiteFraction
// (POV-Ray's colours are unbounded floats).
constexpr double kWhiteFraction = 1e-3;
// Roughness bounds: Blender clamps its roughness to [0, 1] (alpha = roughness^2 <= 1); below
// alpha ~ 1e-3 a lobe is a mirror. POV-Ray: exponent n = 1/roughness.
constexpr double kMinAlpha = 2e-3, kMaxAlpha = 1.0, kMinExponent = 1.0, kMaxExponent = 1e6;
// alpha(mu_v) = roughness mu_v^-slope (lobe_alpha): slope 1 follows the polished lobe's 1/cos(theta_d).
constexpr double kMaxRoughnessSlope = 2.0;

// One pixel of an orthographic sphere: the cosines the lobes need and the exact radiance per unit
// irradiance f_r cos(theta_i) per channel.
struct Pixel {
  double nl, nv, nh;
  std::array<double, 3> exact{};
  std::array<double, kColourTerms> basis{};  // B_k(nv)
  double floor = 0.0;                         // kFloorFraction x the scene's maximum
  bool selected = false;                      // counted in the quality (fit.h)
};

// Pixels of a unit sphere seen along V = +z (orthographic, grid x grid pixels over [-1, 1]^2), lit
// by a sun at `sun_deg` from V (in the x-z plane); only lit, visible pixels with both polar angles
// <= theta_limit_deg. Exact radiance from evaluate_batch, one batch per channel.
// window > 0 adds a second grid x grid block of pixels over the square of half-size `window`
// (projected coordinates) around the half vector's pixel, so that a narrow lobe gets enough samples.
std::vector<Pixel> sphere_scene(const std::vector<Model>& models, double sun_deg, int grid, double offset,
                                double theta_limit_deg, double window = 0.0) {
  const double s = std::sin(sun_deg * kPiD / 180.0), c = std::cos(sun_deg * kPiD / 180.0);
  const std::array<double, 3> L{s, 0.0, c};
  const double hl = std::sqrt(2.0 + 2.0 * c);
  const std::array<double, 3> H{s / hl, 0.0, (1.0 + c) / hl};
  const double limit = std::cos(theta_limit_deg * kPiD / 180.0);
  std::vector<Pixel> pixels;
  std::vector<ScatterAngles> angles;
  const int blocks = window > 0.0 ? 2 : 1;
  for (int block = 0; block < blocks; ++block)
  for (int iy = 0; iy < grid; ++iy)
    for (int ix = 0; ix < grid; ++ix) {
      const double half = block == 0 ? 1.0 : window;
      const double cx = block == 0 ? 0.0 : H[0], cy = 0.0;
      const double x = cx + half * (-1.0 + 2.0 * (ix + offset) / grid), y = cy + half * (-1.0 + 2.0 * (iy + offset) / grid);
      const double r2 = x * x + y * y;
      if (r2 >= 1.0) continue;
      const std::array<double, 3> N{x, y, std::sqrt(1.0 - r2)};
      const double nl = N[0] * L[0] + N[1] * L[1] + N[2] * L[2];
      const double nv = N[2];
      if (nl < limit || nv < limit) continue;
      const double nh = N[0] * H[0] + N[1] * H[1] + N[2] * H[2];
      // Azimuth between the tangential parts of L and V (conventions.md: back-scatter phi_s = 0).
      std::array<double, 3> lt{}, vt{};
      const std::array<double, 3> V{0.0, 0.0, 1.0};
      for (int k = 0; k < 3; ++k) {
        lt[k] = L[k] - nl * N[k];
        vt[k] = V[k] - nv * N[k];
      }
      const double ll = std::sqrt(lt[0] * lt[0] + lt[1] * lt[1] + lt[2] * lt[2]);
      const double vv = std::sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
      const double cos_phi = ll * vv > 1e-12 ? (lt[0] * vt[0] + lt[1] * vt[1] + lt[2] * vt[2]) / (ll * vv) : -1.0;
      Pixel p{nl, nv, nh, {}, {}, 0.0, false};
      for (int k = 0; k < kColourTerms; ++k) p.basis[static_cast<std::size_t>(k)] = bernstein(k, nv);
      pixels.push_back(p);
      angles.push_back({std::acos(std::min(nl, 1.0)), std::acos(std::min(nv, 1.0)),
                        std::acos(std::clamp(cos_phi, -1.0, 1.0))});
    }
  std::vector<double> values(angles.size());
  for (std::size_t ch = 0; ch < 3; ++ch) {
    const Model& model = models[std::min(ch, models.size() - 1)];
    if (ch > 0 && models.size() == 1) {
      for (Pixel& p : pixels) p.exact[ch] = p.exact[0];
      continue;
    }
    evaluate_batch(model, angles.data(), angles.size(), values.data());
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i].exact[ch] = values[i] * pixels[i].nl;
  }
  double peak = 0.0;
  for (const Pixel& p : pixels)
    for (double e : p.exact) peak = std::max(peak, std::isfinite(e) ? e : 0.0);
  const double select_cos = std::cos(kSelectThetaDeg * kPiD / 180.0);
  for (Pixel& p : pixels) {
    p.floor = kFloorFraction * peak;
    p.selected = peak > 0.0 && p.nl >= select_cos && p.nv >= select_cos &&
                 *std::min_element(p.exact.begin(), p.exact.end()) > p.floor;
  }
  return pixels;
}

std::vector<Pixel> scenes(const std::vector<Model>& models, const std::vector<double>& suns_deg, int grid,
                          double offset, double theta_limit_deg, double window = 0.0) {
  std::vector<Pixel> all;
  for (double sun : suns_deg) {
    std::vector<Pixel> one = sphere_scene(models, sun, grid, offset, theta_limit_deg, window);
    all.insert(all.end(), one.begin(), one.end());
  }
  return all;
}

double ggx_value(double alpha, double nl, double nv, double nh) {
  if (!(nl > 0.0) || !(nv > 0.0) || !(nh > 0.0)) return 0.0;
  const double a2 = alpha * alpha;
  const double t = nh * nh * (a2 - 1.0) + 1.0;
  const double d = a2 / (kPiD * t * t);
  auto g1 = [a2](double x) { return 2.0 * x / (x + std::sqrt(a2 + (1.0 - a2) * x * x)); };
  return d * g1(nl) * g1(nv) / (4.0 * nv);
}

// Cycles' Beckmann: D = exp(-tan^2 / a^2) / (pi a^2 cos^4), Smith G1 by Walter et al.'s rational
// approximation (as Cycles evaluates it).
double beckmann_value(double alpha, double nl, double nv, double nh) {
  if (!(nl > 0.0) || !(nv > 0.0) || !(nh > 0.0)) return 0.0;
  const double c2 = nh * nh, t2 = (1.0 - c2) / c2, a2 = alpha * alpha;
  const double d = std::exp(-t2 / a2) / (kPiD * a2 * c2 * c2);
  auto g1 = [alpha](double x) {
    const double tan_x = std::sqrt(std::max(1.0 - x * x, 0.0)) / x;
    if (!(tan_x > 0.0)) return 1.0;
    const double a = 1.0 / (alpha * tan_x);
    return a < 1.6 ? (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a) : 1.0;
  };
  return d * g1(nl) * g1(nv) / (4.0 * nv);
}

// POV-Ray's highlight of a blinn-shape lobe: Blinn (N.H)^n or Phong (R.L)^n, R = 2 (N.V) N - V, so
// R.L = 2 N.V N.L - V.L with V.L = (N.L + N.V)^2 / (2 (N.H)^2) - 1 (from H = (L + V) / |L + V|).
double highlight_at(const Lobe& lobe, double exponent, double nl, double nv, double nh) {
  if (!lobe.phong) return std::pow(nh, exponent);
  const double vl = (nl + nv) * (nl + nv) / (2.0 * nh * nh) - 1.0;
  const double rl = 2.0 * nv * nl - vl;
  return rl > 0.0 ? std::pow(std::min(rl, 1.0), exponent) : 0.0;
}

double highlight_value(const Lobe& lobe, double nl, double nv, double nh) {
  if (!(nl > 0.0) || !(nh > 0.0)) return 0.0;
  if (lobe.roughness_slope == 0.0) return highlight_at(lobe, lobe.roughness, nl, nv, nh);
  // An exponent following N.V: POV-Ray blends the lobe's textures at the view nodes linearly in
  // the slope value (blinn_exponent_at_node), as the include's texture_map does.
  const double s = 0.5 + std::asin(std::clamp(nv, 0.0, 1.0)) / kPiD;
  const double position = std::clamp((s - 0.5) * 2.0 * (kViewNodes - 1), 0.0, static_cast<double>(kViewNodes - 1));
  const int k = std::min(static_cast<int>(position), kViewNodes - 2);
  const double w = position - k;
  return (1.0 - w) * highlight_at(lobe, blinn_exponent_at_node(lobe, k), nl, nv, nh) +
         w * highlight_at(lobe, blinn_exponent_at_node(lobe, k + 1), nl, nv, nh);
}

// Non-negative least squares on normal equations (Lawson & Hanson's active-set method):
// minimize x' G x - 2 b' x over x >= 0, G symmetric positive semi-definite (n small).
class Nnls {
 public:
  static std::vector<double> solve(const std::vector<double>& G, const std::vector<double>& b, int n) {
    std::vector<double> x(static_cast<std::size_t>(n), 0.0);
    std::vector<char> passive(static_cast<std::size_t>(n), 0);
    double diag = 0.0;
    for (int i = 0; i < n; ++i) diag = std::max(diag, G[idx(i, i, n)]);
    if (!(diag > 0.0)) return x;
    const double ridge = 1e-11 * diag;  // keeps nearly collinear columns (similar lobes) solvable
    const double tol = 1e-13 * diag;
    for (int outer = 0; outer < 3 * n; ++outer) {
      std::vector<double> w = gradient(G, b, x, n);
      int t = -1;
      double best = tol;
      for (int i = 0; i < n; ++i)
        if (!passive[static_cast<std::size_t>(i)] && w[static_cast<std::size_t>(i)] > best) {
          best = w[static_cast<std::size_t>(i)];
          t = i;
        }
      if (t < 0) break;
      passive[static_cast<std::size_t>(t)] = 1;
      for (int inner = 0; inner < 3 * n; ++inner) {
        std::vector<double> z = solve_passive(G, b, passive, n, ridge);
        bool feasible = true;
        for (int i = 0; i < n; ++i)
          if (passive[static_cast<std::size_t>(i)] && z[static_cast<std::size_t>(i)] <= 0.0) feasible = false;
        if (feasible) {
          x = z;
          break;
        }
        double step = 1.0;
        for (int i = 0; i < n; ++i) {
          const auto u = static_cast<std::size_t>(i);
          if (passive[u] && z[u] <= 0.0) step = std::min(step, x[u] / std::max(x[u] - z[u], 1e-300));
        }
        for (int i = 0; i < n; ++i) {
          const auto u = static_cast<std::size_t>(i);
          x[u] += step * (z[u] - x[u]);
          if (passive[u] && x[u] <= 1e-15 * std::max(1.0, std::abs(z[u]))) {
            passive[u] = 0;
            x[u] = 0.0;
          }
        }
      }
    }
    return x;
  }

  static std::vector<double> unconstrained(const std::vector<double>& G, const std::vector<double>& b, int n) {
    double diag = 0.0;
    for (int i = 0; i < n; ++i) diag = std::max(diag, G[idx(i, i, n)]);
    if (!(diag > 0.0)) return std::vector<double>(static_cast<std::size_t>(n), 0.0);
    return solve_passive(G, b, std::vector<char>(static_cast<std::size_t>(n), 1), n, kSignedRidge * diag);
  }

 private:
  static std::size_t idx(int i, int j, int n) { return static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j); }
  static std::vector<double> gradient(const std::vector<double>& G, const std::vector<double>& b,
                                      const std::vector<double>& x, int n) {
    std::vector<double> w(b);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) w[static_cast<std::size_t>(i)] -= G[idx(i, j, n)] * x[static_cast<std::size_t>(j)];
    return w;
  }
  // Solves G_PP z_P = b_P (Cholesky, ridge on the diagonal); z = 0 off P.
  static std::vector<double> solve_passive(const std::vector<double>& G, const std::vector<double>& b,
                                           const std::vector<char>& passive, int n, double ridge) {
    std::vector<int> p;
    for (int i = 0; i < n; ++i)
      if (passive[static_cast<std::size_t>(i)]) p.push_back(i);
    const int m = static_cast<int>(p.size());
    std::vector<double> A(static_cast<std::size_t>(m * m)), y(static_cast<std::size_t>(m));
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < m; ++j) A[idx(i, j, m)] = G[idx(p[i], p[j], n)] + (i == j ? ridge : 0.0);
      y[static_cast<std::size_t>(i)] = b[static_cast<std::size_t>(p[i])];
    }
    for (int j = 0; j < m; ++j) {  // A = L L' in place (lower)
      double d = A[idx(j, j, m)];
      for (int k = 0; k < j; ++k) d -= A[idx(j, k, m)] * A[idx(j, k, m)];
      d = std::sqrt(std::max(d, 1e-300));
      A[idx(j, j, m)] = d;
      for (int i = j + 1; i < m; ++i) {
        double s = A[idx(i, j, m)];
        for (int k = 0; k < j; ++k) s -= A[idx(i, k, m)] * A[idx(j, k, m)];
        A[idx(i, j, m)] = s / d;
      }
    }
    for (int i = 0; i < m; ++i) {
      double s = y[static_cast<std::size_t>(i)];
      for (int k = 0; k < i; ++k) s -= A[idx(i, k, m)] * y[static_cast<std::size_t>(k)];
      y[static_cast<std::size_t>(i)] = s / A[idx(i, i, m)];
    }
    for (int i = m - 1; i >= 0; --i) {
      double s = y[static_cast<std::size_t>(i)];
      for (int k = i + 1; k < m; ++k) s -= A[idx(k, i, m)] * y[static_cast<std::size_t>(k)];
      y[static_cast<std::size_t>(i)] = s / A[idx(i, i, m)];
    }
    std::vector<double> z(static_cast<std::size_t>(n), 0.0);
    for (int i = 0; i < m; ++i) z[static_cast<std::size_t>(p[i])] = y[static_cast<std::size_t>(i)];
    return z;
  }
};

double weight_of(const Pixel& p, std::size_t ch) {
  const double scale = p.exact[ch] >= p.floor ? p.exact[ch] : kTailScale * p.floor;
  return scale > 0.0 ? 1.0 / (scale * scale) : 0.0;
}

// Colours (and POV-Ray's S) for fixed roughnesses; returns the weighted squared error (the
// objective: squared relative error above the floor, squared error / floor^2 below it).
// Per channel, radiance = sum_jk x_jk v_j(p) B_k(N.V): ggx/beckmann: v_j the lobe; blinn:
// v_j = h_j (1 - F_m) and x = S c, leaving out the white term sum_j S_j h_j F_m(N.L). POV-Ray's S is one
// number for the three channels and its F_m part is white: the colours are solved without it,
// then S_j = kWhiteFraction x the largest x_jk keeps the white part negligible (below 0.1% of the
// lobe; it is in lobe_radiance, so measured). Was S_j = the largest x_jk with a second pass for its
// F_m term: that white term alone cost POV-Ray renders several % (BK7 median 7.1%).
double solve_colours(LobeShape shape, bool signed_colours, std::vector<Lobe>& lobes, const std::vector<Pixel>& pixels) {
  const int J = static_cast<int>(lobes.size());
  constexpr int K = kColourTerms;
  const int n = J * K;
  const bool blinn = shape == LobeShape::blinn;
  std::vector<double> value(static_cast<std::size_t>(J)), phi(static_cast<std::size_t>(n));
  std::array<std::vector<double>, 3> G, b;
  std::array<double, 3> rr{};
  for (auto& g : G) g.assign(static_cast<std::size_t>(n * n), 0.0);
  for (auto& v : b) v.assign(static_cast<std::size_t>(n), 0.0);
  for (const Pixel& p : pixels) {
    double share = 1.0;
    if (blinn) {
      share = 1.0 - povray_metallic_weight(p.nl);
      for (int j = 0; j < J; ++j)
        value[static_cast<std::size_t>(j)] = highlight_value(lobes[static_cast<std::size_t>(j)], p.nl, p.nv, p.nh);
    } else {
      for (int j = 0; j < J; ++j) {
        const double r = lobe_alpha(lobes[static_cast<std::size_t>(j)], p.nv);
        value[static_cast<std::size_t>(j)] =
            shape == LobeShape::ggx ? ggx_value(r, p.nl, p.nv, p.nh) : beckmann_value(r, p.nl, p.nv, p.nh);
      }
    }
    for (int j = 0; j < J; ++j)
      for (int k = 0; k < K; ++k)
        phi[static_cast<std::size_t>(j * K + k)] = value[static_cast<std::size_t>(j)] * share * p.basis[static_cast<std::size_t>(k)];
    for (std::size_t ch = 0; ch < 3; ++ch) {
      const double w = weight_of(p, ch);
      if (w == 0.0) continue;
      const double target = p.exact[ch];
      rr[ch] += w * target * target;
      for (int i = 0; i < n; ++i) {
        const double wi = w * phi[static_cast<std::size_t>(i)];
        if (wi == 0.0) continue;
        b[ch][static_cast<std::size_t>(i)] += wi * target;
        for (int j = 0; j <= i; ++j) G[ch][static_cast<std::size_t>(i * n + j)] += wi * phi[static_cast<std::size_t>(j)];
      }
    }
  }
  double objective = 0.0;
  for (std::size_t ch = 0; ch < 3; ++ch) {
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < i; ++j) G[ch][static_cast<std::size_t>(j * n + i)] = G[ch][static_cast<std::size_t>(i * n + j)];
    const std::vector<double> x = signed_colours ? Nnls::unconstrained(G[ch], b[ch], n) : Nnls::solve(G[ch], b[ch], n);
    double e = rr[ch];
    for (int i = 0; i < n; ++i) {
      e -= 2.0 * b[ch][static_cast<std::size_t>(i)] * x[static_cast<std::size_t>(i)];
      for (int j = 0; j < n; ++j)
        e += x[static_cast<std::size_t>(i)] * G[ch][static_cast<std::size_t>(i * n + j)] * x[static_cast<std::size_t>(j)];
    }
    objective += std::max(e, 0.0);
    for (int j = 0; j < J; ++j)
      for (int k = 0; k < K; ++k)
        lobes[static_cast<std::size_t>(j)].colour[ch][static_cast<std::size_t>(k)] = x[static_cast<std::size_t>(j * K + k)];
  }
  for (Lobe& l : lobes) {
    double largest = 0.0;
    for (const auto& c : l.colour)
      for (double v : c) largest = std::max(largest, v);
    l.specular = !blinn ? 1.0 : largest > 0.0 ? kWhiteFraction * largest : 1e-6;  // POV-Ray needs S > 0
  }
  if (blinn)  // x = S c: the pigment coefficients
    for (Lobe& l : lobes)
      for (auto& c : l.colour)
        for (double& v : c) v /= l.specular;
  return objective;
}

FitQuality measure(const NativeFit& fit, const std::vector<Pixel>& pixels) {
  std::vector<double> rel;
  double lowest = 0.0;
  for (const Pixel& p : pixels) {
    for (int ch = 0; ch < 3 && p.floor > 0.0; ++ch)
      lowest = std::min(lowest, fit.radiance(ch, p.nl, p.nv, p.nh) * kFloorFraction / p.floor);
    if (!p.selected) continue;
    for (int ch = 0; ch < 3; ++ch) {
      const double e = p.exact[static_cast<std::size_t>(ch)];
      rel.push_back(std::abs(fit.radiance(ch, p.nl, p.nv, p.nh) - e) / e);
    }
  }
  FitQuality q;
  q.values = rel.size();
  q.lowest = lowest;
  if (rel.empty()) return q;
  std::sort(rel.begin(), rel.end());
  auto quantile = [&](double f) { return rel[std::min(rel.size() - 1, static_cast<std::size_t>(f * static_cast<double>(rel.size())))]; };
  q.median = quantile(0.5);
  q.p95 = quantile(0.95);
  q.max = rel.back();
  return q;
}

// Widths in eta_r of J groups of MBK terms of equal Poisson mass at theta_i = theta_s = 30 deg
// (fit.h); a surface without sigma_s/l_c (given sigma_g) starts from sigma_g.
std::vector<double> initial_widths(const Model& model, int J) {
  const ModelParameters& p = model.parameters();
  std::vector<double> widths;
  if (p.sigma_s_um && p.lc_um && *p.sigma_s_um > 0.0) {
    const double lambda = p.wavelength_um, lc = *p.lc_um;
    const double k = 2.0 * kPiD * *p.sigma_s_um / lambda;
    const double g = k * k * 3.0;  // (cos 30 + cos 30)^2 = 3
    // log of e^-g g^m / (m! m), m >= 1, over the window that carries the mass.
    const double spread = 10.0 * std::sqrt(g) + 10.0;
    const auto m_lo = static_cast<long long>(std::max(1.0, std::floor(g - spread)));
    const auto m_hi = static_cast<long long>(std::ceil(g + spread));
    std::vector<double> mass, ms;
    double total = 0.0;
    for (long long m = m_lo; m <= m_hi; ++m) {
      const double md = static_cast<double>(m);
      const double w = std::exp(-g + md * std::log(g) - std::lgamma(md + 1.0) - std::log(md));
      mass.push_back(w);
      ms.push_back(md);
      total += w;
    }
    double acc = 0.0;
    std::size_t i = 0;
    for (int j = 0; j < J; ++j) {
      const double end = total * (j + 1) / J;
      double wsum = 0.0, msum = 0.0;
      while (i < mass.size() && (acc < end || wsum == 0.0)) {
        acc += mass[i];
        wsum += mass[i];
        msum += mass[i] * std::sqrt(ms[i]);
        ++i;
      }
      const double root_m = wsum > 0.0 ? msum / wsum : std::sqrt(ms.back());
      widths.push_back(root_m * lambda / (kPiD * lc));
    }
  } else {
    const double sigma_g = model.sigma_g() > 0.0 ? model.sigma_g() : 0.2;
    for (int j = 0; j < J; ++j) widths.push_back(2.0 * std::sqrt(2.0) * sigma_g);
  }
  // Distinct starting lobes: consecutive widths at least 1.4x apart (a polished surface has all its
  // mass in m = 1, a narrow Gaussian whose GGX match still wants a narrower core and a wider skirt).
  std::sort(widths.begin(), widths.end());
  for (std::size_t j = 1; j < widths.size(); ++j) widths[j] = std::max(widths[j], 1.4 * widths[j - 1]);
  const double shift = std::pow(1.4, -0.5 * (J - 1));
  if (widths.size() > 1 && widths.front() == widths.back()) for (double& w : widths) w *= shift;
  return widths;
}

double roughness_from_width(LobeShape shape, double width) {
  // GGX near its peak ~ Beckmann exp(-tan^2 theta_h / alpha^2) with eta_r ~ 2 tan theta_h;
  // Blinn (N.H)^n ~ exp(-n theta_h^2 / 2). A Gaussian exp(-(eta_r/w)^2) gives alpha = w/2, n = 8/w^2.
  return shape != LobeShape::blinn ? std::clamp(0.5 * width, kMinAlpha, kMaxAlpha)
                                 : std::clamp(8.0 / (width * width), kMinExponent, kMaxExponent);
}

// The roughness bounds, and the request's excluded band of alpha (a trial inside it moves to the
// nearer edge, in log alpha).
double clamp_roughness(const FitRequest& request, double r) {
  if (request.shape == LobeShape::blinn) return std::clamp(r, kMinExponent, kMaxExponent);
  r = std::clamp(r, kMinAlpha, kMaxAlpha);
  const double low = request.excluded_alpha_low, high = request.excluded_alpha_high;
  if (r > low && r < high) r = r * r < low * high ? low : high;
  return r;
}

// Nelder-Mead on log roughness (J dimensions), and on each lobe's roughness_slope when the request
// asks for alphas following N.V (J more); the colours are solved exactly at every trial.
std::vector<Lobe> refine(const FitRequest& request, std::vector<Lobe> lobes, const std::vector<Pixel>& pixels, int evaluations) {
  const LobeShape shape = request.shape;
  const bool signed_colours = request.signed_colours;
  const int J = static_cast<int>(lobes.size());
  const bool slopes = request.view_dependent_roughness;
  const int dimensions = slopes ? 2 * J : J;
  auto at = [&](const std::vector<double>& logs, std::vector<Lobe>& out) {
    out = lobes;
    for (int j = 0; j < J; ++j) {
      Lobe& l = out[static_cast<std::size_t>(j)];
      l.roughness = clamp_roughness(request, std::exp(logs[static_cast<std::size_t>(j)]));
      if (slopes) l.roughness_slope = std::clamp(logs[static_cast<std::size_t>(J + j)], 0.0, kMaxRoughnessSlope);
    }
    return solve_colours(shape, signed_colours, out, pixels);
  };
  std::vector<std::vector<double>> simplex;
  std::vector<double> values;
  std::vector<Lobe> scratch;
  std::vector<double> start;
  for (const Lobe& l : lobes) start.push_back(std::log(l.roughness));
  if (slopes)
    for (const Lobe& l : lobes) start.push_back(l.roughness_slope);
  simplex.push_back(start);
  for (int j = 0; j < dimensions; ++j) {
    std::vector<double> v = start;
    v[static_cast<std::size_t>(j)] += j < J ? 0.4 : (v[static_cast<std::size_t>(j)] > 0.5 ? -0.4 : 0.4);  // 1.5x in roughness; slope +-0.4
    simplex.push_back(v);
  }
  for (const auto& v : simplex) values.push_back(at(v, scratch));
  int used = static_cast<int>(simplex.size());
  while (used < evaluations) {
    std::vector<std::size_t> order(simplex.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
    const std::size_t best = order.front(), worst = order.back(), second = order[order.size() - 2];
    if (values[worst] - values[best] <= 1e-7 * std::max(values[best], 1e-300)) break;
    std::vector<double> centroid(static_cast<std::size_t>(dimensions), 0.0);
    for (std::size_t i : order)
      if (i != worst)
        for (int j = 0; j < dimensions; ++j) centroid[static_cast<std::size_t>(j)] += simplex[i][static_cast<std::size_t>(j)] / dimensions;
    auto along = [&](double t) {
      std::vector<double> v(static_cast<std::size_t>(dimensions));
      for (int j = 0; j < dimensions; ++j) {
        const auto u = static_cast<std::size_t>(j);
        v[u] = centroid[u] + t * (simplex[worst][u] - centroid[u]);
      }
      return v;
    };
    const std::vector<double> reflected = along(-1.0);
    const double fr = at(reflected, scratch);
    ++used;
    if (fr < values[best]) {
      const std::vector<double> expanded = along(-2.0);
      const double fe = at(expanded, scratch);
      ++used;
      if (fe < fr) simplex[worst] = expanded, values[worst] = fe;
      else simplex[worst] = reflected, values[worst] = fr;
    } else if (fr < values[second]) {
      simplex[worst] = reflected, values[worst] = fr;
    } else {
      const std::vector<double> contracted = along(fr < values[worst] ? -0.5 : 0.5);
      const double fc = at(contracted, scratch);
      ++used;
      if (fc < std::min(fr, values[worst])) {
        simplex[worst] = contracted, values[worst] = fc;
      } else {
        for (std::size_t i = 0; i < simplex.size(); ++i) {
          if (i == best) continue;
          for (int j = 0; j < dimensions; ++j) {
            const auto u = static_cast<std::size_t>(j);
            simplex[i][u] = simplex[best][u] + 0.5 * (simplex[i][u] - simplex[best][u]);
          }
          values[i] = at(simplex[i], scratch);
          ++used;
        }
      }
    }
  }
  const std::size_t best = static_cast<std::size_t>(std::min_element(values.begin(), values.end()) - values.begin());
  std::vector<Lobe> out;
  at(simplex[best], out);
  // Sharpest lobe first (the order the exporters list them in).
  std::sort(out.begin(), out.end(), [shape](const Lobe& a, const Lobe& b) {
    return shape != LobeShape::blinn ? a.roughness < b.roughness : a.roughness > b.roughness;
  });
  return out;
}

// Blinn exponents 2..2e4 and Phong exponents 1..1e4 (log-spaced: (R.L)^p ~ (N.H)^(4p), fit.h),
// colours fitted together, sorted by S (heaviest first); lobes the NNLS left at 0 are dropped.
std::vector<Lobe> ranked_ladder(const FitRequest& request, const std::vector<Pixel>& train) {
  constexpr int kBlinn = 16, kPhong = 14;
  std::vector<Lobe> lobes;
  for (int i = 0; i < kBlinn + kPhong; ++i) {
    Lobe l;
    l.phong = i >= kBlinn;
    l.roughness = l.phong ? std::pow(10.0, 4.0 * (i - kBlinn) / (kPhong - 1)) : 2.0 * std::pow(10.0, 4.0 * i / (kBlinn - 1));
    lobes.push_back(l);
  }
  solve_colours(request.shape, request.signed_colours, lobes, train);
  std::vector<Lobe> used;
  for (const Lobe& l : lobes)
    if (std::any_of(l.colour.begin(), l.colour.end(), [](const auto& c) { return *std::max_element(c.begin(), c.end()) > 0.0; }))
      used.push_back(l);
  std::stable_sort(used.begin(), used.end(), [](const Lobe& a, const Lobe& b) { return a.specular > b.specular; });
  return used;
}

}  // namespace

double bernstein(int k, double mu) {
  static constexpr std::array<double, kColourTerms> binomial = [] {
    std::array<double, kColourTerms> c{};
    for (int i = 0; i < kColourTerms; ++i) {
      double v = 1.0;
      for (int j = 1; j <= i; ++j) v = v * (kColourDegree - j + 1) / j;
      c[static_cast<std::size_t>(i)] = v;
    }
    return c;
  }();
  const double x = std::clamp(mu, 0.0, 1.0);
  return binomial[static_cast<std::size_t>(k)] * std::pow(x, k) * std::pow(1.0 - x, kColourDegree - k);
}

double lobe_colour(const Lobe& lobe, int channel, double mu_v) {
  double c = 0.0;
  for (int k = 0; k < kColourTerms; ++k)
    c += lobe.colour[static_cast<std::size_t>(channel)][static_cast<std::size_t>(k)] * bernstein(k, mu_v);
  return c;
}

double lobe_alpha(const Lobe& lobe, double mu_v) {
  if (lobe.roughness_slope == 0.0) return lobe.roughness;
  return std::min(lobe.roughness * std::pow(std::max(mu_v, kMinViewCosine), -lobe.roughness_slope), kMaxAlpha);
}

double view_node_cosine(int k) { return std::sin(0.5 * kPiD * k / (kViewNodes - 1)); }

double blinn_exponent_at_node(const Lobe& lobe, int k) {
  if (lobe.roughness_slope == 0.0) return lobe.roughness;
  const double mu = std::max(view_node_cosine(k), kMinViewCosine);
  return std::clamp(lobe.roughness * std::pow(mu, 2.0 * lobe.roughness_slope), kMinExponent, kMaxExponent);
}

double povray_metallic_weight(double n_dot_l) {
  const double x = std::acos(std::clamp(n_dot_l, -1.0, 1.0)) / (0.5 * kPiD);
  return std::clamp(0.014567225 / ((x - 1.12) * (x - 1.12)) - 0.011612903, 0.0, 1.0);
}

double lobe_radiance(LobeShape shape, const Lobe& lobe, int channel, double n_dot_l, double n_dot_v, double n_dot_h) {
  if (!(n_dot_l > 0.0) || !(n_dot_v > 0.0)) return 0.0;
  const double c = lobe_colour(lobe, channel, n_dot_v);
  if (shape == LobeShape::ggx) return c * ggx_value(lobe_alpha(lobe, n_dot_v), n_dot_l, n_dot_v, n_dot_h);
  if (shape == LobeShape::beckmann) return c * beckmann_value(lobe_alpha(lobe, n_dot_v), n_dot_l, n_dot_v, n_dot_h);
  const double fm = povray_metallic_weight(n_dot_l);
  return lobe.specular * highlight_value(lobe, n_dot_l, n_dot_v, n_dot_h) * (fm + (1.0 - fm) * c);
}

double NativeFit::radiance(int channel, double n_dot_l, double n_dot_v, double n_dot_h) const {
  double sum = 0.0;
  for (const Lobe& l : lobes) sum += lobe_radiance(shape, l, channel, n_dot_l, n_dot_v, n_dot_h);
  return sum;
}

void validate_target_error(double target_error) {
  if (!std::isfinite(target_error) || !(target_error > 0.0) || target_error > 1.0)
    throw InvalidArgument("target-error", "must be a relative error in (0, 1] (got " + std::to_string(target_error) + ")");
}

NativeFit fit_native_lobes(const std::vector<Model>& models, const FitRequest& request) {
  validate_target_error(request.target_error);
  if (models.size() != 1 && models.size() != 3)
    throw InvalidArgument("wavelength", "the native-lobe fit takes 1 or 3 channels (got " + std::to_string(models.size()) + ")");
  if (request.max_lobes < 1 || request.max_lobes > 8)
    throw InvalidArgument("max-lobes", "must be in 1..8 (got " + std::to_string(request.max_lobes) + ")");
  NativeFit fit;
  fit.shape = request.shape;
  fit.target_error = request.target_error;
  fit.channels = static_cast<int>(models.size());
  fit.signed_colours = request.signed_colours;
  // Fitting and validation scenes (fit.h): different sun angles and pixel grids.
  // The narrowest channel's narrowest group of terms sets how finely the lobe is sampled: the
  // training scenes add a window of 4 widths around the half vector, the validation grid gives the
  // lobe at least ~12 pixels of radius (uniform pixels, as in a render).
  double narrowest = 1.0;
  for (const Model& m : models) narrowest = std::min(narrowest, initial_widths(m, 1).front());
  const double window = std::min(1.0, 2.0 * narrowest);  // eta_r ~ 2 x (projected normal offset)
  const int check_grid = std::clamp(static_cast<int>(std::ceil(24.0 / std::max(window, 1e-3))), 56, 320);
  const std::vector<Pixel> train = scenes(models, {5, 20, 35, 50, 65, 80, 95, 110, 125, 138}, 32, 0.5, kFitThetaDeg,
                                          window < 0.5 ? window : 0.0);
  // Validation: two suns inside each band of sun-camera angle (kSunAngleBands), pooled for the
  // lobe count and measured band by band for the chosen fit.
  std::vector<std::vector<Pixel>> check_bands;
  std::vector<Pixel> check;
  for (std::size_t b = 0; b + 1 < kSunAngleBands.size(); ++b) {
    const double low = kSunAngleBands[b], high = kSunAngleBands[b + 1];
    check_bands.push_back(scenes(models, {low + 0.3 * (high - low), low + 0.7 * (high - low)}, check_grid, 0.31, kFitThetaDeg));
    check.insert(check.end(), check_bands.back().begin(), check_bands.back().end());
  }
  double peak = 0.0;
  for (const Pixel& p : train) peak = std::max(peak, p.floor);
  if (!(peak > 0.0)) {  // no scattered light at all (e.g. sigma_s = 0: only the spike)
    fit.target_met = true;
    return fit;
  }
  const Model& reference = models[models.size() / 2];
  // POV-Ray: Blinn and Phong lobes, whose kinds the greedy growth below cannot choose well (a
  // lobe's kind is fixed once added): a ladder of both kinds, all fitted at once (NNLS) and ranked
  // by their weight S, offers each count J its J heaviest as one more start.
  const std::vector<Lobe> ladder = request.shape == LobeShape::blinn ? ranked_ladder(request, train) : std::vector<Lobe>{};
  NativeFit best;
  std::vector<Lobe> previous;
  int stalls = 0;
  for (int J = 1; J <= request.max_lobes; ++J) {
    // Start: the Poisson groups' widths (fit.h), or, when better, the previous count's optimum
    // plus one lobe (narrower or wider than its extremes, alternately).
    std::vector<Lobe> lobes(static_cast<std::size_t>(J));
    const std::vector<double> widths = initial_widths(reference, J);
    for (int j = 0; j < J; ++j) lobes[static_cast<std::size_t>(j)].roughness =
          clamp_roughness(request, roughness_from_width(request.shape, widths[static_cast<std::size_t>(j)]));
    std::vector<std::vector<Lobe>> candidates{lobes};
    if (request.view_dependent_roughness) {
      // The same widths (set at theta_i = theta_s = 30 deg, mu_v = cos 30) following 1/N.V
      // (blinn: exponent ~ 1/width^2 ~ N.V^2).
      const double cos30 = std::cos(30.0 * kPiD / 180.0);
      for (Lobe& l : lobes) {
        l.roughness = clamp_roughness(request, request.shape == LobeShape::blinn ? l.roughness / (cos30 * cos30) : l.roughness * cos30);
        l.roughness_slope = 1.0;
      }
      candidates.push_back(lobes);
    }
    if (!previous.empty()) {
      Lobe extra = J % 2 == 0 ? previous.back() : previous.front();  // sorted sharpest first
      const double factor = request.shape == LobeShape::blinn ? (J % 2 == 0 ? 0.5 : 2.0) : (J % 2 == 0 ? 1.5 : 0.7);
      extra.roughness = clamp_roughness(request, extra.roughness * factor);
      candidates.push_back(previous);
      candidates.back().push_back(extra);
      if (request.shape == LobeShape::blinn) {  // or the extra lobe as a Phong highlight (fit.h)
        extra.phong = !extra.phong;
        // (R.L)^p ~ (N.H)^(4p) near the peak (the angle from R to L is ~ 2 theta_h in the plane).
        extra.roughness = clamp_roughness(request, extra.phong ? 0.25 * extra.roughness : 4.0 * extra.roughness);
        candidates.push_back(previous);
        candidates.back().push_back(extra);
      }
    }
    if (static_cast<int>(ladder.size()) >= J) candidates.emplace_back(ladder.begin(), ladder.begin() + J);
    if (candidates.size() > 1) {
      double lowest = std::numeric_limits<double>::infinity();
      for (const std::vector<Lobe>& candidate : candidates) {
        std::vector<Lobe> trial = candidate;
        const double objective = solve_colours(request.shape, request.signed_colours, trial, train);
        if (objective < lowest) lowest = objective, lobes = candidate;
      }
    }
    NativeFit trial = fit;
    trial.lobes = refine(request, lobes, train, 40 + (request.view_dependent_roughness ? 50 : 25) * J);
    trial.quality = measure(trial, check);
    previous = trial.lobes;
    fit.tried.push_back(trial.quality);
    stalls = !best.lobes.empty() && trial.quality.p95 > 0.97 * best.quality.p95 ? stalls + 1 : 0;
    if (best.lobes.empty() || trial.quality.p95 < best.quality.p95) best = trial;
    if (trial.quality.p95 <= request.target_error) break;
    if (stalls >= 2) break;  // two more lobes gained < 3% each: more will not meet the target either
  }
  best.tried = fit.tried;
  best.target_met = best.quality.p95 <= request.target_error;
  for (std::size_t b = 0; b < check_bands.size(); ++b)
    best.by_sun_angle.push_back({kSunAngleBands[b], kSunAngleBands[b + 1], measure(best, check_bands[b])});
  return best;
}

}  // namespace libbrdf::fit
