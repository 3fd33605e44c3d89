// Baked tables: axis mappings, bake + measured error, --target-error, files, cancellation.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <hwy/targets.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <fstream>
#include <random>
#include <string>
#include <utility>

#include "libbrdf/batch.h"
#include "libbrdf/error.h"
#include "libbrdf/lut.h"
#include "libbrdf/materials.h"
#include "lut_internal.h"
#include "test_support.h"

namespace {

using namespace libbrdf;
namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    static int counter = 0;
    path_ = fs::temp_directory_path() / ("libbrdf_lut_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::size_t entries() const { return static_cast<std::size_t>(std::distance(fs::directory_iterator(path_), fs::directory_iterator())); }

 private:
  fs::path path_;
};

struct SurfaceCase {
  const char* name;
  ModelKind model;
  double sigma_s_um, lc_um;
};

ModelParameters gold(double sigma_s_um, double lc_um, double wavelength_um) {
  ModelParameters p;
  p.sigma_s_um = sigma_s_um;
  p.lc_um = lc_um;
  p.wavelength_um = wavelength_um;
  p.index = material_index("Au", wavelength_um);
  return p;
}

BakeRequest request_for(ModelKind model, double sigma_s_um, double lc_um, std::vector<double> wavelengths = {0.55}) {
  BakeRequest r;
  r.model = model;
  for (double w : wavelengths) r.channels.push_back(gold(sigma_s_um, lc_um, w));
  r.error_samples = 6000;
  return r;
}

std::vector<Model> models_of(const BakeRequest& r) { return channel_models(r.model, r.channels); }

// Geometries drawn uniformly in (sqrt(theta_h), theta_d, phi_d) -- the test's own mapping, written
// from the paper's half/difference definitions -- with both polar angles <= limit_deg.
std::vector<ScatterAngles> random_geometries(int count, double limit_deg, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double limit = limit_deg * kPi / 180.0;
  std::vector<ScatterAngles> out;
  while (static_cast<int>(out.size()) < count) {
    const double u = uniform(rng);
    const double th = 0.5 * kPi * u * u, td = 0.5 * kPi * uniform(rng), pd = kPi * uniform(rng);
    // h = (sin th, 0, cos th); incident = R_y(th) (sin td cos pd, sin td sin pd, cos td); scattered = mirror about h.
    const double dx = std::sin(td) * std::cos(pd), dy = std::sin(td) * std::sin(pd), dz = std::cos(td);
    const double ix = dx * std::cos(th) + dz * std::sin(th), iy = dy, iz = -dx * std::sin(th) + dz * std::cos(th);
    const double hx = std::sin(th), hz = std::cos(th), dot = ix * hx + iz * hz;
    const double sx = 2 * dot * hx - ix, sy = -iy, sz = 2 * dot * hz - iz;
    if (iz <= std::cos(limit) || sz <= std::cos(limit)) continue;
    out.push_back({std::acos(iz), std::acos(sz), std::atan2(sy, sx) - std::atan2(iy, ix)});
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Axis mappings

TEST(HalfDifferenceAngles, AgreeWithEq5AndEq6AndRoundTrip) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> polar(0.0, 1.5), azimuth(-kPi, kPi);
  for (int k = 0; k < 2000; ++k) {
    const ScatterAngles a{polar(rng), polar(rng), azimuth(rng)};
    const ScatterGeometry geo = make_scatter_geometry(a);
    const HalfDifferenceAngles hd = half_difference_angles(geo);
    EXPECT_NEAR(std::cos(hd.theta_d), geo.cos_theta_d, 1e-12) << "eq. 5 at k = " << k;
    EXPECT_NEAR(std::cos(hd.theta_h), geo.cos_theta_h, 1e-12) << "eq. 6 at k = " << k;
    ASSERT_GE(hd.phi_d, 0.0);
    ASSERT_LE(hd.phi_d, kPi);
    const ScatterGeometry back = make_scatter_geometry(scatter_angles_from_half_difference(hd));
    EXPECT_NEAR(back.cos_theta_i, geo.cos_theta_i, 1e-12);
    EXPECT_NEAR(back.cos_theta_s, geo.cos_theta_s, 1e-12);
    // phi_d is folded by the mirror symmetry, so only cos phi_s comes back.
    EXPECT_NEAR(back.cos_phi_s, geo.cos_phi_s, 1e-9) << "k = " << k;
  }
}

TEST(HalfDifferenceAngles, SliceFormulasFromNormalDotLightAndView) {
  // lut.h: for fixed L, V: cos theta_h = (N.L + N.V) / (2 cos theta_d),
  // cos phi_d = (N.V - N.L) / (2 sin theta_h sin theta_d), cos 2 theta_d = L.V.
  const Direction light{0.3, 0.0, 1.0}, view{-0.5, 0.2, 1.0};
  const double theta_d = slice_theta_d(light, view);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const double ln = std::sqrt(1.09), vn = std::sqrt(1.29);
  const double lx = 0.3 / ln, lz = 1.0 / ln, vx = -0.5 / vn, vy = 0.2 / vn, vz = 1.0 / vn;
  int checked = 0;
  while (checked < 500) {
    double nx = uniform(rng), ny = uniform(rng), nz = uniform(rng);
    const double norm = std::sqrt(nx * nx + ny * ny + nz * nz);
    if (norm > 1.0 || norm < 0.1) continue;
    nx /= norm, ny /= norm, nz /= norm;
    const double u = nx * lx + nz * lz, v = nx * vx + ny * vy + nz * vz;
    if (u < 0.05 || v < 0.05) continue;
    // phi_s between the projections of L and V on the plane normal to N (eq. 5 solved for it).
    const double cos_phi = (lx * vx + lz * vz - u * v) / std::sqrt((1 - u * u) * (1 - v * v));
    const ScatterGeometry geo = make_scatter_geometry({std::acos(u), std::acos(v), std::acos(std::clamp(cos_phi, -1.0, 1.0))});
    const HalfDifferenceAngles hd = half_difference_angles(geo);
    EXPECT_NEAR(hd.theta_d, theta_d, 1e-9);
    EXPECT_NEAR(std::cos(hd.theta_h), (u + v) / (2 * std::cos(theta_d)), 1e-9);
    if (hd.theta_h > 1e-3) {
      EXPECT_NEAR(std::cos(hd.phi_d), (v - u) / (2 * std::sin(hd.theta_h) * std::sin(theta_d)), 1e-7);
    }
    ++checked;
  }
}

TEST(HalfDifferenceAngles, AsfIsConstantAlongPhiD) {
  // The bake computes the ASF once per (theta_h, theta_d) row: g and c depend on
  // cos ti + cos ts = 2 cos td cos th and eta_r = 2 cos td sin th only.
  for (ModelKind kind : {ModelKind::mbk, ModelKind::mbk_fg, ModelKind::bk, ModelKind::bk_modified}) {
    const Model model(kind, gold(0.3, 3.0, 0.55));
    ASSERT_TRUE(model.uses_asf());
    for (double th : {0.01, 0.3, 0.7}) {
      for (double td : {0.05, 0.5, 1.0}) {
        double asf = -1.0;
        for (double pd : {0.0, 0.4, 1.3, 2.2, 3.0}) {
          const ScatterAngles a = scatter_angles_from_half_difference({th, td, pd});
          if (a.theta_i >= 0.5 * kPi || a.theta_s >= 0.5 * kPi) continue;
          const ScatterGeometry geo = make_scatter_geometry(a);
          if (asf < 0.0) asf = model.asf_at(geo);
          ASSERT_GT(asf, 0.0);
          EXPECT_NEAR(model.asf_at(geo), asf, 1e-12 * asf);
          EXPECT_NEAR(model.evaluate(geo, asf), model.evaluate(geo), 1e-12 * model.evaluate(geo));
        }
      }
    }
  }
  EXPECT_FALSE(Model(ModelKind::microfacet, gold(0.3, 3.0, 0.55)).uses_asf());
}

TEST(LutLayout, NamesRoundTripAndUnknownNameIsInvalidArgument) {
  for (LutLayout layout : {LutLayout::rusinkiewicz, LutLayout::merl, LutLayout::slice})
    EXPECT_EQ(layout_from_name(layout_name(layout)), layout);
  try {
    layout_from_name("octahedral");
    FAIL() << "no throw";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.parameter(), "layout");
  }
}

TEST(Lut, LookupAtAFeasibleNodeReturnsTheNodeValue) {
  BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0);
  r.resolution = std::array<int, 3>{12, 10, 9};
  const Lut lut = bake(r);
  int checked = 0;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 9; ++k) {
        const ScatterAngles a = lut_node_angles(lut.layout, lut.shape, i, j, k);
        if (a.theta_i >= degrees_to_radians(kHorizonThetaLimitDeg) || a.theta_s >= degrees_to_radians(kHorizonThetaLimitDeg)) continue;
        const double node = lut.values[(static_cast<std::size_t>(i) * 10 + j) * 9 + k];
        EXPECT_NEAR(lut.lookup(0, make_scatter_geometry(a)), node, 1e-7 * std::abs(node) + 1e-30) << i << "," << j << "," << k;
        ++checked;
      }
  EXPECT_GT(checked, 500);
}

// The batch lookup (SIMD lanes, trilinear_simd.cpp) against the trilinear formula of the mapping
// lut.h documents, written here from the table's values: every channel, a count that leaves a
// partial vector, both trilinear layouts, queries up to the horizon and past the MERL grid's last
// nodes (whose values it holds).
TEST(Lut, BatchLookupIsTheDocumentedTrilinearFormula) {
  for (const LutLayout layout : {LutLayout::rusinkiewicz, LutLayout::merl}) {
    SCOPED_TRACE(layout_name(layout));
    BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0, {0.65, 0.55, 0.45});
    r.layout = layout;
    if (layout == LutLayout::rusinkiewicz) r.resolution = std::array<int, 3>{13, 11, 9};
    r.error_samples = 300;
    const Lut lut = bake(r);
    const int n0 = lut.shape[0], n1 = lut.shape[1], n2 = lut.shape[2];
    // Index-space length of each axis: N - 1 nodes' spacings (rusinkiewicz), N (MERL: no node on
    // the upper ends).
    const int last = layout == LutLayout::merl ? 0 : 1;
    auto axis = [](double x, int nodes, int& i, double& t) {
      x = std::min(std::max(x, 0.0), double(nodes - 1));
      i = std::min(static_cast<int>(std::floor(x)), nodes - 2);
      t = x - i;
    };
    std::vector<ScatterGeometry> geos;
    for (const ScatterAngles& a : random_geometries(1001, 89.9, 5)) geos.push_back(make_scatter_geometry(a));
    std::vector<double> batch(3 * geos.size());
    lookup_all_batch(lut, geos.data(), geos.size(), batch.data());
    double worst = 0.0;
    for (std::size_t k = 0; k < geos.size(); ++k) {
      const HalfDifferenceAngles hd = half_difference_angles(geos[k]);
      int i0, i1, i2;
      double t0, t1, t2;
      axis(std::sqrt(hd.theta_h / (0.5 * kPi)) * (n0 - last), n0, i0, t0);  // square map
      axis(hd.theta_d / (0.5 * kPi) * (n1 - last), n1, i1, t1);
      axis(hd.phi_d / kPi * (n2 - last), n2, i2, t2);
      for (int c = 0; c < 3; ++c) {
        auto node = [&](int a, int b, int e) {
          return double(lut.values[static_cast<std::size_t>(c) * lut.nodes_per_channel() + (static_cast<std::size_t>(i0 + a) * n1 + i1 + b) * n2 + i2 + e]);
        };
        // The weighted sum of the 8 corners. Allowed: the rounding of any order of evaluation
        // (1e-14 of the terms' magnitudes) and of the index positions, which this test computes
        // with other roundings than the library (x / (pi/2) against x (2/pi)): a few ulps of a
        // position move the value by that much times the corners' differences (corner values
        // span decades at the specular peak).
        double expected = 0.0, magnitude = 0.0, corners = 0.0;
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b)
            for (int e = 0; e < 2; ++e) {
              const double term = (a ? t0 : 1 - t0) * (b ? t1 : 1 - t1) * (e ? t2 : 1 - t2) * node(a, b, e);
              expected += term, magnitude += std::abs(term), corners += std::abs(node(a, b, e));
            }
        const double position_ulps = 8.0 * DBL_EPSILON * std::max({i0 + t0, i1 + t1, i2 + t2, 1.0});
        const double allowed = 1e-14 * magnitude + position_ulps * corners + 1e-300;
        const double got = batch[3 * k + c];
        ASSERT_TRUE(std::isfinite(got)) << k;
        worst = std::max(worst, std::abs(got - expected) / allowed);
        EXPECT_NEAR(got, expected, allowed) << "query " << k << " channel " << c;
        double single[3];
        lut.lookup_all(geos[k], single);  // one query: the same lanes, padded
        EXPECT_EQ(single[c], got) << "query " << k;
      }
    }
    std::cout << "[ measured ] batch lookup against the trilinear formula: largest difference / allowed " << worst << "\n";
  }
}

// LutSampler (channel-interleaved nodes for the trilinear layouts and the kernel layout's P~ table)
// against lookup_all_batch (planar nodes), on every Highway target this CPU runs: the same values
// to the bit, for 1-4 channels, rusinkiewicz, MERL and kernel (the kernel layout's closed form and
// 1 channel take lookup_all_batch's path), a count that leaves partial vectors and chunks, and
// grazing geometries.
// The P~ table's span interpolation (kernel_angular_span: stencils moved inside the phi_d rows,
// weights in SIMD lanes) against the definition, written out here: Catmull-Rom on each axis over
// nodes i - 1 .. i + 2 with every index clamped to the table (end nodes repeated), summed in long
// double. Random node values in [0.5, 1.5]; shapes with fewer than 4 nodes on an axis (the padded
// short rows), exactly 4, and larger; planar (one channel at a time and several) and
// channel-interleaved (2-4 channels); angles at both ends of every axis and beyond them (clamped),
// and inside; every Highway target. Allowed: 2e-6 relative (sums of 64 float products).
TEST(Lut, PTildeSpanMatchesTheCatmullRomDefinition) {
  const std::array<int, 3> shapes[] = {{2, 3, 2}, {3, 2, 3}, {4, 4, 4}, {5, 7, 4}, {12, 11, 10}, {6, 5, 31}};
  constexpr double kHalfPi = 0.5 * kPi;
  std::mt19937_64 rng(27);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<detail::TableAngles> angles;
  for (double h : {0.0, kHalfPi, 1.7, -0.1})
    for (double d : {0.0, kHalfPi, 0.3})
      for (double p : {0.0, kPi, 3.3, 1.0}) angles.push_back({h, d, p, 0.0});
  for (int k = 0; k < 301; ++k) angles.push_back({unit(rng) * kHalfPi, unit(rng) * kHalfPi, unit(rng) * kPi, 0.0});
  double worst = 0.0;
  int targets = 0;
  libbrdf_test::for_each_simd_target([&](std::int64_t) {
    ++targets;
    for (const auto& shape : shapes) {
      for (int channels = 1; channels <= 4; ++channels) {
        SCOPED_TRACE(std::to_string(shape[0]) + "x" + std::to_string(shape[1]) + "x" + std::to_string(shape[2]) + ", " +
                     std::to_string(channels) + " channels");
        const std::size_t nodes = static_cast<std::size_t>(shape[0]) * shape[1] * shape[2];
        std::vector<float> planar(nodes * channels), interleaved(nodes * channels + detail::kKernelInterleavedPadding, 0.0f);
        for (float& v : planar) v = static_cast<float>(0.5 + unit(rng));
        for (int c = 0; c < channels; ++c)
          for (std::size_t i = 0; i < nodes; ++i) interleaved[i * channels + c] = planar[c * nodes + i];
        auto definition = [&](const detail::TableAngles& a, int c) {
          const double x[3] = {a.theta_h / kHalfPi * (shape[0] - 1), a.theta_d / kHalfPi * (shape[1] - 1), a.phi_d / kPi * (shape[2] - 1)};
          int first[3];
          long double w[3][4];
          for (int axis = 0; axis < 3; ++axis) {
            const long double u = std::clamp(x[axis], 0.0, shape[axis] - 1.0);
            const int i = std::min(static_cast<int>(u), shape[axis] - 2);
            const long double t = u - i;
            first[axis] = i - 1;
            w[axis][0] = 0.5L * (-t * t * t + 2 * t * t - t), w[axis][1] = 0.5L * (3 * t * t * t - 5 * t * t + 2);
            w[axis][2] = 0.5L * (-3 * t * t * t + 4 * t * t + t), w[axis][3] = 0.5L * (t * t * t - t * t);
          }
          auto node = [&](int axis, int j) { return std::clamp(first[axis] + j, 0, shape[axis] - 1); };
          long double sum = 0.0L;
          for (int a0 = 0; a0 < 4; ++a0)
            for (int a1 = 0; a1 < 4; ++a1)
              for (int a2 = 0; a2 < 4; ++a2)
                sum += w[0][a0] * w[1][a1] * w[2][a2] *
                       planar[c * nodes + (static_cast<std::size_t>(node(0, a0)) * shape[1] + node(1, a1)) * shape[2] + node(2, a2)];
          return static_cast<double>(sum);
        };
        const detail::KernelAngularView planar_view{planar.data(), nodes, 1, {shape[0], shape[1], shape[2]},
                                                    {(shape[0] - 1) / kHalfPi, (shape[1] - 1) / kHalfPi, (shape[2] - 1) / kPi}};
        detail::KernelAngularView interleaved_view = planar_view;
        interleaved_view.values = interleaved.data(), interleaved_view.channel_stride = 1, interleaved_view.node_floats = channels;
        std::vector<double> all(angles.size() * channels), one(angles.size()), mixed(angles.size() * channels);
        detail::kernel_angular_span(planar_view, angles.data(), angles.size(), 0, channels, all.data());
        detail::kernel_angular_span(planar_view, angles.data(), angles.size(), channels - 1, 1, one.data());
        if (channels >= 2) detail::kernel_angular_span(interleaved_view, angles.data(), angles.size(), 0, channels, mixed.data());
        for (std::size_t k = 0; k < angles.size(); ++k) {
          for (int c = 0; c < channels; ++c) {
            const double expected = definition(angles[k], c), got = all[k * channels + c];
            ASSERT_TRUE(std::isfinite(got)) << "query " << k << " channel " << c;
            worst = std::max(worst, std::abs(got / expected - 1.0));
            ASSERT_NEAR(got / expected, 1.0, 2e-6) << "query " << k << " channel " << c;
            if (channels >= 2) {
              ASSERT_EQ(mixed[k * channels + c], got) << "interleaved, query " << k << " channel " << c;
            }
          }
          ASSERT_EQ(one[k], all[k * channels + channels - 1]) << "one channel alone, query " << k;
        }
      }
    }
  });
  EXPECT_GE(targets, 1);
  std::cout << "[ measured ] P~ span against the Catmull-Rom definition: largest relative difference " << worst << " on " << targets
            << " Highway targets\n";
}

TEST(Lut, SamplerGivesTheBatchLookupsBitForBit) {
  struct Case {
    LutLayout layout;
    std::vector<double> wavelengths;
    KernelAngular angular = KernelAngular::closed_form;  // kernel layout
  };
  const Case cases[] = {{LutLayout::rusinkiewicz, {0.65, 0.55, 0.45}}, {LutLayout::rusinkiewicz, {0.55}},
                        {LutLayout::rusinkiewicz, {0.65, 0.45}},       {LutLayout::rusinkiewicz, {0.7, 0.6, 0.5, 0.4}},
                        {LutLayout::merl, {0.65, 0.55, 0.45}},         {LutLayout::kernel, {0.65, 0.55, 0.45}},
                        {LutLayout::kernel, {0.65, 0.55, 0.45}, KernelAngular::table},
                        {LutLayout::kernel, {0.65, 0.45}, KernelAngular::table},
                        {LutLayout::kernel, {0.7, 0.6, 0.5, 0.4}, KernelAngular::table}};
  std::vector<ScatterGeometry> geos;
  for (const ScatterAngles& a : random_geometries(1001, 89.9, 9)) geos.push_back(make_scatter_geometry(a));
  geos.push_back(make_scatter_geometry_degrees(0.0, 0.0, 0.0));
  geos.push_back(make_scatter_geometry_degrees(89.99, 89.99, 180.0));
  geos.push_back(make_scatter_geometry_degrees(85.0, 30.0, 0.0));
  struct RestoreTargets {  // also when an assertion leaves the loop
    ~RestoreTargets() { hwy::SetSupportedTargetsForTest(0); }
  } restore;
  int targets_run = 0;
  for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
    SCOPED_TRACE(hwy::TargetName(target));
    hwy::SetSupportedTargetsForTest(target);
    ++targets_run;
    for (const Case& c : cases) {
      const bool angular_table = c.layout == LutLayout::kernel && c.angular == KernelAngular::table;
      SCOPED_TRACE(std::string(layout_name(c.layout)) + (angular_table ? " (P~ table)" : "") + " x" + std::to_string(c.wavelengths.size()));
      BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0, c.wavelengths);
      r.layout = c.layout;
      r.kernel_angular = c.angular;
      if (c.layout == LutLayout::rusinkiewicz) r.resolution = std::array<int, 3>{13, 11, 9};
      if (angular_table) r.resolution = std::array<int, 3>{12, 11, 10};  // stencils at both phi_d ends and inside
      r.error_samples = 100;
      const Lut lut = bake(r);
      const LutSampler sampler(lut);
      const std::size_t channels = c.wavelengths.size();
      std::vector<double> planar(channels * geos.size()), interleaved(channels * geos.size(), -1.0);
      lookup_all_batch(lut, geos.data(), geos.size(), planar.data());
      sampler.lookup_all(geos.data(), geos.size(), interleaved.data());
      for (std::size_t k = 0; k < planar.size(); ++k) {
        ASSERT_TRUE(std::isfinite(interleaved[k])) << k;
        ASSERT_EQ(interleaved[k], planar[k]) << "query " << k / channels << " channel " << k % channels;
      }
      sampler.lookup_all(geos.data() + 7, 1, interleaved.data());  // one query: a partial chunk and vector
      for (std::size_t ch = 0; ch < channels; ++ch) EXPECT_EQ(interleaved[ch], planar[7 * channels + ch]);
    }
  }
  EXPECT_GE(targets_run, 1);
  std::cout << "[ measured ] LutSampler = lookup_all_batch bit for bit on " << targets_run << " Highway targets\n";
}

// lookup_batch on a slice table: geometries of the slice (cos 2theta_d = L.V, eq. 5: here the
// in-plane pair whose half vector is the normal's bisector of L and V) answer as lut.lookup; the
// first geometry off the slice is rejected with its index, before anything is looked up.
TEST(Lut, BatchLookupOfASliceRejectsGeometriesOffTheSlice) {
  BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0);
  r.layout = LutLayout::slice;
  r.light = {0.3, 0.0, 1.0};
  r.view = {-0.3, 0.0, 1.0};  // L.V = (1 - 0.09) / 1.09: theta_i = theta_s = atan(0.3), phi_s = 180 deg
  r.resolution = std::array<int, 3>{32, 16, 1};
  r.error_samples = 100;
  const Lut lut = bake(r);
  const double t = std::atan(0.3);
  const ScatterAngles on{t, t, kPi}, off{0.2, 0.7, kPi};
  double value = 0.0;
  lookup_batch(lut, 0, &on, 1, &value);
  EXPECT_EQ(value, lut.lookup(0, make_scatter_geometry(on)));
  const ScatterAngles queries[3] = {on, off, off};
  double values[3] = {-1.0, -1.0, -1.0};
  try {
    lookup_batch(lut, 0, queries, 3, values);
    FAIL() << "an off-slice geometry was looked up";
  } catch (const InvalidQuery& e) {
    EXPECT_EQ(e.index(), 1u);
    EXPECT_EQ(e.parameter(), "phi_s");
    EXPECT_NE(std::string(e.what()).find("eq. 5"), std::string::npos) << e.what();
  }
  EXPECT_EQ(values[0], -1.0);  // nothing written
}

// The kernel layout's K(theta_i) is tabulated over [0, 90] deg: a hand-made geometry with the light
// below the horizon (theta_i = 100 deg) is refused by name, in the second block of 256 by the
// batch and the sampler, and alone (a partial vector) by Lut::lookup: K's position in lanes hands
// it to the scalar formula, which names it, instead of reading K at 90 deg.
TEST(Lut, KernelLookupsRefuseIncidenceBelowTheHorizon) {
  std::vector<ScatterGeometry> geos;
  for (const ScatterAngles& a : random_geometries(300, 80.0, 17)) geos.push_back(make_scatter_geometry(a));
  geos[261] = make_scatter_geometry(ScatterAngles{80.0 * kPi / 180.0, 0.3, 1.0});  // the second block
  geos[261].cos_theta_i = -geos[261].cos_theta_i;  // theta_i = 100 deg (make_scatter_geometry refuses it)
  for (KernelAngular angular : {KernelAngular::closed_form, KernelAngular::table}) {
    BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0, {0.65, 0.55, 0.45});
    r.layout = LutLayout::kernel;
    r.kernel_angular = angular;
    if (angular == KernelAngular::table) r.resolution = std::array<int, 3>{12, 12, 12};
    r.error_samples = 100;
    const Lut lut = bake(r);
    const LutSampler sampler(lut);
    std::vector<double> values(3 * geos.size());
    for (const auto& lookup : std::vector<std::function<void()>>{
             [&] { lookup_all_batch(lut, geos.data(), geos.size(), values.data()); },
             [&] { sampler.lookup_all(geos.data(), geos.size(), values.data()); },
             [&] { lut.lookup(2, geos[261]); }}) {
      try {
        lookup();
        ADD_FAILURE() << "theta_i = 100 deg accepted";
      } catch (const InvalidArgument& e) {
        EXPECT_EQ(e.parameter(), "theta_i");
      }
    }
    EXPECT_NO_THROW(lookup_all_batch(lut, geos.data(), 261, values.data()));
  }
}

// A hand-filled ScatterGeometry with a non-finite field is refused with its index, by every
// lookup of every layout, instead of being washed into some node (a finite, wrong value: what the
// lookups returned before). The trilinear layouts read the sines and cosines; the kernel layout
// reads every field.
TEST(Lut, LookupsRefuseNonFiniteGeometries) {
  struct Case {
    LutLayout layout;
    KernelAngular angular;
  };
  const Case cases[] = {{LutLayout::rusinkiewicz, KernelAngular::table},
                        {LutLayout::merl, KernelAngular::table},
                        {LutLayout::kernel, KernelAngular::closed_form},
                        {LutLayout::kernel, KernelAngular::table}};
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN(), kInf = std::numeric_limits<double>::infinity();
  std::vector<ScatterGeometry> geos;
  for (const ScatterAngles& a : random_geometries(600, 80.0, 13)) geos.push_back(make_scatter_geometry(a));
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(layout_name(c.layout)) + (c.angular == KernelAngular::table ? " table" : " closed form"));
    BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0, {0.65, 0.55, 0.45});
    r.layout = c.layout;
    r.kernel_angular = c.angular;
    if (c.layout == LutLayout::rusinkiewicz) r.resolution = std::array<int, 3>{13, 11, 9};
    if (c.layout == LutLayout::kernel && c.angular == KernelAngular::table) r.resolution = std::array<int, 3>{12, 12, 12};
    r.error_samples = 100;
    const Lut lut = bake(r);
    const LutSampler sampler(lut);
    std::vector<std::pair<double ScatterGeometry::*, double>> bad_fields = {{&ScatterGeometry::cos_theta_i, kNaN},
                                                                            {&ScatterGeometry::sin_phi_s, kInf},
                                                                            {&ScatterGeometry::cos_theta_s, -kInf}};
    if (c.layout == LutLayout::kernel) bad_fields.push_back({&ScatterGeometry::eta_r2, kNaN});
    for (const auto& [field, bad] : bad_fields) {
      std::vector<ScatterGeometry> with_bad = geos;
      with_bad[300].*field = bad;  // past the first block of 256
      with_bad[450].*field = bad;
      std::vector<double> values(3 * geos.size());
      auto refused_at = [&](const std::function<void()>& lookup) {
        try {
          lookup();
        } catch (const InvalidQuery& e) {
          EXPECT_EQ(e.parameter(), "geometry");
          return static_cast<long>(e.index());
        }
        return -1L;
      };
      EXPECT_EQ(refused_at([&] { lookup_all_batch(lut, with_bad.data(), with_bad.size(), values.data()); }), 300);
      EXPECT_EQ(refused_at([&] { sampler.lookup_all(with_bad.data(), with_bad.size(), values.data()); }), 300);
      EXPECT_EQ(refused_at([&] { lut.lookup(1, with_bad[300]); }), 0);
      EXPECT_NO_THROW(lut.lookup(1, with_bad[299]));
    }
  }
}

TEST(Lut, SamplerRejectsAnInconsistentTable) {
  BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0, {0.65, 0.55, 0.45});
  r.resolution = std::array<int, 3>{9, 9, 9};
  r.error_samples = 100;
  Lut lut = bake(r);
  lut.values.pop_back();
  EXPECT_THROW(LutSampler{lut}, LutFileError);
}

// ---------------------------------------------------------------------------------------------
// Bake, error, files

// bake -> write -> read -> lookup agrees with direct evaluation within the error the file claims
// (x 1.25: the claim is the largest of a finite sample, fresh points may exceed it slightly).
void check_round_trip(const SurfaceCase& c, const std::array<int, 3>& resolution, double expected_bound,
                      const std::vector<double>& wavelengths = {0.55}) {
  SCOPED_TRACE(c.name);
  TempDir dir;
  BakeRequest r = request_for(c.model, c.sigma_s_um, c.lc_um, wavelengths);
  const int channels = static_cast<int>(wavelengths.size());
  r.resolution = resolution;
  const Lut baked = bake(r);
  ASSERT_GT(baked.error.samples, 1000);
  EXPECT_LT(baked.error.max_relative, expected_bound) << "the table is far less accurate than this resolution gives";
  EXPECT_GT(baked.error.max_relative, 0.0);
  const std::string path = dir.file("table.exr");
  write_lut_exr(baked, path);
  const Lut lut = read_lut_exr(path);
  ASSERT_EQ(lut.values, baked.values);
  ASSERT_EQ(lut.specular_reflectance, baked.specular_reflectance);
  ASSERT_EQ(lut.renormalization, baked.renormalization);
  EXPECT_EQ(lut.layout, baked.layout);
  EXPECT_EQ(lut.shape, baked.shape);
  EXPECT_EQ(lut.wavelengths_um, baked.wavelengths_um);
  EXPECT_EQ(lut.error.max_relative, baked.error.max_relative);
  EXPECT_EQ(lut.attributes.at("model"), std::string(model_name(c.model)));

  const std::vector<Model> models = models_of(r);
  int compared = 0;
  double worst = 0.0;
  for (const ScatterAngles& a : random_geometries(4000, lut.error.theta_limit_deg, 99)) {
    const ScatterGeometry geo = make_scatter_geometry(a);
    for (int ch = 0; ch < channels; ++ch) {
      const double model = models[ch].evaluate(geo);
      if (model < lut.error.floor || model <= 0.0) continue;
      worst = std::max(worst, std::abs(lut.lookup(ch, geo) - model) / model);
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
  EXPECT_LE(worst, 1.25 * lut.error.max_relative) << "claimed " << lut.error.max_relative;
  // Side tables: R_spec and K at random theta_i within the claimed side-table error.
  const double side_error = std::stod(lut.attributes.at("side_tables_max_relative_error"));
  EXPECT_LT(side_error, 1e-3);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> theta(0.0, 0.5 * kPi);
  for (int k = 0; k < 200; ++k) {
    const double ti = theta(rng);
    const double k_model = models[channels - 1].renormalization(ti);
    EXPECT_NEAR(lut.renormalization_at(channels - 1, ti), k_model, 1.25 * side_error * k_model + 1e-7);
    const double spec = models[channels - 1].specular_reflectance(ti);
    if (spec > 1e-3) {
      EXPECT_NEAR(lut.specular_at(channels - 1, ti), spec, 1.25 * side_error * spec + 1e-7);
    }
  }
}

TEST(BakeRoundTrip, MbkPolishedSurface) { check_round_trip({"mbk polished", ModelKind::mbk, 0.01, 2.0}, {64, 40, 24}, 0.5); }
TEST(BakeRoundTrip, MbkIntermediateSurface) { check_round_trip({"mbk intermediate", ModelKind::mbk, 0.1, 2.0}, {48, 48, 32}, 0.3, {0.65, 0.55, 0.45}); }
TEST(BakeRoundTrip, MbkRoughSurface) { check_round_trip({"mbk rough", ModelKind::mbk, 0.5, 5.0}, {48, 48, 32}, 0.3); }
TEST(BakeRoundTrip, BkModified) { check_round_trip({"bk-modified", ModelKind::bk_modified, 0.1, 2.0}, {48, 48, 32}, 0.3); }
TEST(BakeRoundTrip, Microfacet) { check_round_trip({"microfacet", ModelKind::microfacet, 0.1, 2.0}, {48, 48, 32}, 0.3); }

TEST(BakeError, ConvergesQuadraticallyWithResolution) {
  // Linear interpolation: doubling every axis divides the error by ~4 (allow >= 2.5).
  BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0);
  r.layout = LutLayout::slice;
  r.light = {0.3, 0.0, 1.0};
  r.view = {-0.5, 0.2, 1.0};
  r.resolution = std::array<int, 3>{64, 32, 1};
  const double coarse = bake(r).error.max_relative;
  r.resolution = std::array<int, 3>{128, 64, 1};
  const double fine = bake(r).error.max_relative;
  EXPECT_GT(coarse / fine, 2.5) << coarse << " -> " << fine;
}

TEST(BakeError, MeasurementSeesAPerturbedTable) {
  BakeRequest r = request_for(ModelKind::mbk, 0.5, 5.0);
  r.layout = LutLayout::slice;
  r.light = {0.0, 0.4, 1.0};
  r.view = {0.2, -0.3, 1.0};
  r.resolution = std::array<int, 3>{200, 100, 1};
  Lut lut = bake(r);
  ASSERT_LT(lut.error.max_relative, 0.02);
  for (float& v : lut.values) v *= 1.05f;  // every node 5% high
  const LutError e = measure_lut_error(lut, models_of(r), 5000, 1e-3, 11);
  EXPECT_GT(e.max_relative, 0.045);
  EXPECT_GT(e.rms_relative, 0.04);
}

TEST(BakeTargetError, MeetsTheTargetAndATighterTargetGivesALargerTable) {
  BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0);
  r.layout = LutLayout::slice;
  r.light = {0.3, 0.0, 1.0};
  r.view = {-0.5, 0.2, 1.0};
  r.target_error = 1e-2;
  std::vector<double> trials;
  r.trial_done = [&trials](const std::array<int, 3>&, const LutError& e) { trials.push_back(e.max_relative); };
  const Lut loose = bake(r);
  EXPECT_LE(loose.error.max_relative, 1e-2);
  // Every smaller table of the search missed the target: this is the smallest that meets it.
  ASSERT_GT(trials.size(), 1u);
  for (std::size_t k = 0; k + 1 < trials.size(); ++k) EXPECT_GT(trials[k], 1e-2) << "trial " << k;
  r.target_error = 1e-3;
  const Lut tight = bake(r);
  EXPECT_LE(tight.error.max_relative, 1e-3);
  EXPECT_GT(tight.nodes_per_channel(), loose.nodes_per_channel());
  // Independent check with fresh points: within the claim x 1.25.
  const LutError fresh = measure_lut_error(tight, models_of(r), 6000, 1e-3, 12345);
  EXPECT_LE(fresh.max_relative, 1.25e-3);
}

TEST(BakeTargetError, MerlLayoutIsFixedAndTargetOutOfRangeIsInvalid) {
  BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0);
  r.layout = LutLayout::merl;
  r.target_error = 1e-2;
  EXPECT_THROW(bake(r), InvalidArgument);
  r.layout = LutLayout::rusinkiewicz;
  r.target_error = 0.0;
  EXPECT_THROW(bake(r), InvalidArgument);
  r.target_error = std::nullopt;
  r.resolution = std::array<int, 3>{1, 8, 8};
  try {
    bake(r);
    FAIL() << "no throw";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.parameter(), "resolution");
  }
}

TEST(Bake, RejectsAQuantityThatIsNotABrdf) {
  BakeRequest r = request_for(ModelKind::fresnel, 0.1, 2.0);
  try {
    bake(r);
    FAIL() << "no throw";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.parameter(), "model");
  }
}

TEST(Bake, PerfectMirrorBakesToZerosWithItsSpikeInRspec) {
  BakeRequest r = request_for(ModelKind::mbk, 0.0, 2.0);
  r.resolution = std::array<int, 3>{8, 8, 8};
  const Lut lut = bake(r);
  for (float v : lut.values) ASSERT_EQ(v, 0.0f);
  const Model model(ModelKind::mbk, r.channels[0]);
  EXPECT_NEAR(lut.specular_at(0, 0.3), model.specular_reflectance(0.3), 1e-4);
  EXPECT_GT(lut.specular_at(0, 0.3), 0.5);  // gold at 550 nm reflects most of the light
}

TEST(BakeCancel, CancelFlagStopsTheBakeAndNothingIsWritten) {
  TempDir dir;
  std::atomic<bool> cancel{false};
  BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0);
  r.resolution = std::array<int, 3>{64, 64, 64};
  int calls = 0;
  r.progress = [&](double fraction) {
    ++calls;
    if (fraction > 0.1) cancel.store(true);
  };
  r.cancel = &cancel;
  const std::string path = dir.file("cancelled.exr");
  EXPECT_THROW(write_lut_exr(bake(r), path), BakeCancelled);
  EXPECT_LT(calls, 100);  // it stopped early
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(dir.entries(), 0u);
}

TEST(LutFiles, SliceRoundTripKeepsDirections) {
  TempDir dir;
  BakeRequest r = request_for(ModelKind::microfacet, 0.2, 2.0);
  r.layout = LutLayout::slice;
  r.light = {0.2, 0.1, 1.0};
  r.view = {-0.4, 0.0, 0.9};
  r.resolution = std::array<int, 3>{64, 32, 1};
  const Lut baked = bake(r);
  write_lut_exr(baked, dir.file("slice.exr"));
  const Lut lut = read_lut_exr(dir.file("slice.exr"));
  EXPECT_EQ(lut.layout, LutLayout::slice);
  EXPECT_EQ(lut.values, baked.values);
  EXPECT_DOUBLE_EQ(lut.light.x, 0.2);
  EXPECT_DOUBLE_EQ(lut.view.z, 0.9);
}

TEST(LutFiles, MerlRoundTripThroughTheLibraryAndItsSidecar) {
  TempDir dir;
  BakeRequest r = request_for(ModelKind::bk_modified, 0.3, 3.0, {0.65, 0.55, 0.45});
  r.layout = LutLayout::merl;
  r.error_samples = 2000;
  const Lut baked = bake(r);
  const std::string path = dir.file("t.binary");
  write_merl_binary(baked, path);
  EXPECT_EQ(fs::file_size(path), 12u + 3u * 90u * 90u * 180u * 8u);
  const Lut lut = read_merl_binary(path);
  ASSERT_EQ(lut.values.size(), baked.values.size());
  for (std::size_t i = 0; i < lut.values.size(); i += 97)
    ASSERT_NEAR(lut.values[i], baked.values[i], 1e-6f * std::abs(baked.values[i])) << i;
  EXPECT_EQ(lut.wavelengths_um, baked.wavelengths_um);
  EXPECT_EQ(lut.renormalization, baked.renormalization);
  EXPECT_EQ(lut.attributes.at("model"), "bk-modified");
  // Without the sidecar: the table still reads, with the defaults stated in its attributes.
  fs::remove(path + ".json");
  const Lut bare = read_merl_binary(path);
  EXPECT_EQ(bare.attributes.count("side_tables"), 1u);
  EXPECT_EQ(bare.channels(), 3);
  // A MERL file needs 3 channels and the merl layout.
  BakeRequest one = request_for(ModelKind::mbk, 0.1, 2.0);
  one.resolution = std::array<int, 3>{8, 8, 8};
  EXPECT_THROW(write_merl_binary(bake(one), dir.file("x.binary")), LutFileError);
  EXPECT_FALSE(fs::exists(dir.file("x.binary")));
}

// Kernel layout, mbk-fg: the closed form evaluates F(theta_d) G/S at lookup (lut.h) with the
// channel's sigma_g and G term from the file; checked against the model at random geometries (a
// wrong or missing G, S or sigma_g shows as a large error: G/S varies by orders of magnitude).
TEST(KernelLayout, MbkFgClosedFormAgreesWithTheModelForEveryGTerm) {
  TempDir dir;
  for (GeometricTerm term : {GeometricTerm::smith, GeometricTerm::vgroove, GeometricTerm::none}) {
    BakeRequest r = request_for(ModelKind::mbk_fg, 0.02, 2.0, {0.65, 0.45});
    for (ModelParameters& p : r.channels) p.g_term = term;
    r.layout = LutLayout::kernel;
    r.error_samples = 2000;
    const Lut baked = bake(r);
    EXPECT_EQ(baked.kernel_angular, KernelAngular::closed_form);
    EXPECT_EQ(baked.shape, (std::array<int, 3>{2, 2, 2}));
    const std::string path = dir.file("fg.exr");
    write_lut_exr(baked, path);
    const Lut lut = read_lut_exr(path);
    const std::vector<Model> models = models_of(r);
    ASSERT_EQ(lut.kernel_sigma_g.size(), 2u);
    ASSERT_EQ(lut.kernel_g_term.size(), 2u);
    for (int c = 0; c < 2; ++c) {
      EXPECT_EQ(lut.kernel_sigma_g[c], models[c].sigma_g());
      EXPECT_EQ(lut.kernel_g_term[c], term);
    }
    for (const ScatterAngles& a : random_geometries(300, 85.0, 3)) {
      const ScatterGeometry geo = make_scatter_geometry(a);
      for (int c = 0; c < 2; ++c) {
        const double direct = models[c].evaluate(geo);
        EXPECT_NEAR(lut.lookup(c, geo), direct, 1e-4 * direct) << "g_term " << int(term);
        EXPECT_EQ(lut.lookup(c, geo), baked.lookup(c, geo));
      }
    }
  }
}

TEST(KernelLayout, MbkFgClosedFormHeaderNeedsSigmaGAndAGTermPerChannel) {
  BakeRequest r = request_for(ModelKind::mbk_fg, 0.3, 3.0, {0.65, 0.55, 0.45});
  r.layout = LutLayout::kernel;
  r.error_samples = 1000;
  const std::map<std::string, std::string> good = detail::lut_metadata(bake(r));
  Lut lut;
  detail::restore_from_metadata(lut, good, "good.exr");
  EXPECT_EQ(lut.kernel_g_term, std::vector<GeometricTerm>(3, GeometricTerm::smith));
  for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
           {"kernel_g_term", "smith,smith,ggx"}, {"kernel_g_term", "smith,smith"}, {"kernel_sigma_g", "0.1,0.1"},
           {"kernel_sigma_g", "0.1,-1,0.1"}, {"kernel_sigma_g", "0.1,1e-9,0.1"}, {"kernel_angular", "closed"}}) {
    std::map<std::string, std::string> bad = good;
    bad[key] = value;
    EXPECT_THROW(detail::restore_from_metadata(lut, bad, "bad.exr"), LutFileError) << key << " = " << value;
  }
  for (const char* key : {"kernel_sigma_g", "kernel_g_term"}) {
    std::map<std::string, std::string> missing = good;
    missing.erase(key);
    EXPECT_THROW(detail::restore_from_metadata(lut, missing, "bad.exr"), LutFileError) << key;
  }
  // The table form (G/S on the grid, and files without kernel_angular) needs neither.
  r.kernel_angular = KernelAngular::table;
  r.resolution = std::array<int, 3>{8, 8, 8};
  std::map<std::string, std::string> table = detail::lut_metadata(bake(r));
  EXPECT_EQ(table.count("kernel_sigma_g"), 0u);
  table.erase("kernel_angular");
  detail::restore_from_metadata(lut, table, "old.exr");
  EXPECT_EQ(lut.kernel_angular, KernelAngular::table);
  EXPECT_TRUE(lut.kernel_sigma_g.empty());
}

// The closed form's table holds P~ = 1 at every node and lookups do not read it (lut.h): a table
// that holds anything else is refused when written (and read), not silently ignored.
TEST(KernelLayout, ClosedFormTableMustHoldOnes) {
  TempDir dir;
  BakeRequest r = request_for(ModelKind::mbk, 0.2, 2.0, {0.65});
  r.layout = LutLayout::kernel;
  r.error_samples = 1000;
  Lut lut = bake(r);
  ASSERT_EQ(lut.kernel_angular, KernelAngular::closed_form);
  for (float v : lut.values) ASSERT_EQ(v, 1.0f);
  write_lut_exr(lut, dir.file("ones.exr"));
  lut.values[3] = 0.5f;
  EXPECT_THROW(write_lut_exr(lut, dir.file("bad.exr")), LutFileError);
  EXPECT_FALSE(fs::exists(dir.file("bad.exr")));
}

// Every failure is a LutFileError with a one-line message that names the file.
void expect_file_error(const std::function<void()>& read, const std::string& path) {
  try {
    read();
    ADD_FAILURE() << "no error for " << path;
  } catch (const LutFileError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_EQ(what.rfind(path, 0), 0u) << what;
  }
}

TEST(LutFiles, CorruptTruncatedAndForeignFilesGiveOneLineErrors) {
  TempDir dir;
  BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0, {0.65, 0.55, 0.45});
  r.resolution = std::array<int, 3>{24, 24, 16};
  const std::string good = dir.file("good.exr");
  write_lut_exr(bake(r), good);
  std::ifstream in(good, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto write = [&](const std::string& name, const std::string& content) {
    const std::string path = dir.file(name);
    std::ofstream(path, std::ios::binary) << content;
    return path;
  };
  // Missing, empty, text, truncated at several points.
  const std::string missing = dir.file("missing.exr");
  expect_file_error([&] { read_lut_exr(missing); }, missing);
  expect_file_error([&] { read_lut_file(missing); }, missing);
  for (const std::string& name : {std::string("empty.exr"), std::string("text.exr")}) {
    const std::string path = write(name, name == "empty.exr" ? "" : "hello, not an image\n");
    expect_file_error([&] { read_lut_exr(path); }, path);
    expect_file_error([&] { read_lut_file(path); }, path);
  }
  for (double fraction : {0.01, 0.1, 0.5, 0.9, 0.999}) {
    const std::string path = write("cut.exr", bytes.substr(0, static_cast<std::size_t>(fraction * double(bytes.size()))));
    expect_file_error([&] { read_lut_exr(path); }, path);
  }
  // Random byte corruption: either an error or a table that passes the consistency checks
  // (finite values of the right size), never a crash.
  std::mt19937_64 rng(5);
  int errors = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::string damaged = bytes;
    for (int k = 0; k < 8; ++k) damaged[std::uniform_int_distribution<std::size_t>(0, damaged.size() - 1)(rng)] ^= 0x5a;
    const std::string path = write("damaged.exr", damaged);
    try {
      const Lut lut = read_lut_exr(path);
      for (float v : lut.values) ASSERT_TRUE(std::isfinite(v));
    } catch (const LutFileError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
      ++errors;
    }
  }
  EXPECT_GT(errors, 0);
  // A foreign OpenEXR (a plain image, no libbrdf header).
  const std::string foreign = dir.file("foreign.exr");
  {
    auto out = OIIO::ImageOutput::create(foreign);
    OIIO::ImageSpec spec(8, 4, 3, OIIO::TypeDesc::FLOAT);
    std::vector<float> pixels(8 * 4 * 3, 0.5f);
    ASSERT_TRUE(out->open(foreign, spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close());
  }
  expect_file_error([&] { read_lut_exr(foreign); }, foreign);
  expect_file_error([&] { read_lut_file(foreign); }, foreign);
  expect_file_error([&] { read_merl_binary(good); }, good);
  // MERL: wrong dimensions, truncated, non-finite values.
  std::string merl(12 + 3 * 90 * 90 * 180 * 8, '\0');
  const std::int32_t dims[3] = {90, 90, 180};
  std::memcpy(merl.data(), dims, 12);
  const std::string ok_merl = write("zero.binary", merl);
  EXPECT_NO_THROW(read_merl_binary(ok_merl));
  const std::string cut = write("cut.binary", merl.substr(0, merl.size() - 8));
  expect_file_error([&] { read_merl_binary(cut); }, cut);
  std::string bad_dims = merl;
  const std::int32_t wrong[3] = {90, 90, 360};
  std::memcpy(bad_dims.data(), wrong, 12);
  const std::string dims_path = write("dims.binary", bad_dims);
  expect_file_error([&] { read_merl_binary(dims_path); }, dims_path);
  std::string nan_merl = merl;
  const double nan = std::nan("");
  std::memcpy(nan_merl.data() + 12 + 8 * 1000, &nan, 8);
  const std::string nan_path = write("nan.binary", nan_merl);
  expect_file_error([&] { read_merl_binary(nan_path); }, nan_path);
  const std::string sidecar = write("zero.binary.json", "{ not json");
  expect_file_error([&] { read_merl_binary(ok_merl); }, sidecar);
}

TEST(LutFiles, FailedWriteLeavesNoFile) {
  TempDir dir;
  BakeRequest r = request_for(ModelKind::mbk, 0.1, 2.0);
  r.resolution = std::array<int, 3>{8, 8, 8};
  const Lut lut = bake(r);
  const std::string path = dir.file("no/such/dir/t.exr");
  EXPECT_THROW(write_lut_exr(lut, path), LutFileError);
  Lut broken = lut;
  broken.values[3] = std::nanf("");
  EXPECT_THROW(write_lut_exr(broken, dir.file("nan.exr")), LutFileError);
  EXPECT_EQ(dir.entries(), 0u);
}

// ---------------------------------------------------------------------------------------------
// Scenes

TEST(ScenePlan, SunAndOrthographicCameraGiveASliceOtherwiseRusinkiewicz) {
  TempDir dir;
  auto plan = [&](const std::string& json) {
    const std::string path = dir.file("scene.json");
    std::ofstream(path) << json;
    return plan_scene_bake(path);
  };
  const ScenePlan sun_ortho = plan(R"({"lights": [{"type": "sun", "direction": [0.3, 0, 1]}],
      "camera": {"type": "orthographic", "direction": [0, -0.2, 1]}, "wavelengths_um": [0.6, 0.5]})");
  EXPECT_EQ(sun_ortho.layout, LutLayout::slice);
  EXPECT_DOUBLE_EQ(sun_ortho.light.x, 0.3);
  EXPECT_DOUBLE_EQ(sun_ortho.view.y, -0.2);
  EXPECT_EQ(sun_ortho.wavelengths_um, (std::vector<double>{0.6, 0.5}));
  EXPECT_EQ(plan(R"({"lights": [{"type": "sun", "direction": [0.3, 0, 1]}],
      "camera": {"type": "perspective", "position": [0, -2, 3]}})").layout, LutLayout::rusinkiewicz);
  EXPECT_EQ(plan(R"({"lights": [{"type": "point", "position": [0, 0, 3]}],
      "camera": {"type": "orthographic", "direction": [0, 0, 1]}})").layout, LutLayout::rusinkiewicz);
  for (const char* bad : {"{", R"({"lights": []})", R"({"lights": [{"type": "sun", "direction": [0, 0]}], "camera": {"type": "orthographic", "direction": [0, 0, 1]}})",
                          R"({"lights": [{"type": "sun", "direction": [0, 0, 1]}], "camera": {"type": "fisheye"}})",
                          R"({"lights": [{"type": "sun", "direction": [0, 0, 1]}], "camera": {"type": "orthographic", "direction": [0, 0, 1]}, "colour": 1})"}) {
    try {
      plan(bad);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.parameter(), "scene");
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
}

}  // namespace
