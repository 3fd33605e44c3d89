// Issue 11 in the library: directional albedo (white furnace), the K integral at huge g, domain
// ranges, messages that quote untrusted text, tables that refuse negative values, publication
// of a file group whose paths spell one directory two ways.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <string>
#include <thread>

#include "libbrdf/albedo.h"
#include "libbrdf/error.h"
#include "libbrdf/image_file.h"
#include "libbrdf/lut.h"
#include "libbrdf/models.h"
#include "libbrdf/renormalization.h"

namespace {

using libbrdf::ModelKind;
using libbrdf::ModelParameters;

ModelParameters gold(double sigma_s_um, double lc_um) {
  ModelParameters p;
  p.sigma_s_um = sigma_s_um;
  p.lc_um = lc_um;
  p.wavelength_um = 0.55;
  p.index = libbrdf::ComplexIndex{0.43, 2.45};
  return p;
}

double deg(double d) { return d * libbrdf::kPi / 180.0; }

TEST(Albedo, WhiteLambertianIsOne) {
  ModelParameters p = gold(0.1, 2.0);
  p.rho_s = 0.0;
  p.rho_d = 1.0;
  const libbrdf::Model model(ModelKind::microfacet, p);
  for (double ti : {0.0, 45.0, 85.0}) {
    const double a = libbrdf::directional_albedo(model, deg(ti)).total;
    EXPECT_NEAR(a, 1.0, 1e-8) << "theta_i " << ti;
  }
}

TEST(Albedo, MirrorIsFresnelAtTheta_i) {
  const libbrdf::Model model(ModelKind::mbk, gold(0.0, 2.0));
  for (double ti : {0.0, 60.0, 85.0}) {
    const double ci = std::cos(deg(ti));
    const double f = libbrdf::fresnel_reflectance(libbrdf::ComplexIndex{0.43, 2.45}.permittivity(), ci);
    EXPECT_NEAR(libbrdf::directional_albedo(model, deg(ti)).total, f, 1e-12) << "theta_i " << ti;
  }
}

TEST(Albedo, PlaneKExceedsOneAtGrazingAndTisDoesNot) {
  // The case: Au (here n = 0.43 + 2.45i), sigma_s = 0.5 um, l_c = 2 um at 0.55 um,
  // theta_i = 80 deg: 1.09 with the tabulated gold (tests/cli), 1.082 with this index.
  const libbrdf::Model plane(ModelKind::mbk, gold(0.5, 2.0));
  const double a = libbrdf::directional_albedo(plane, deg(80.0)).total;
  EXPECT_NEAR(a, 1.082, 2e-3);
  // Moderately rough (sigma_s/lambda = 0.15): tis stays <= 1 at every angle, plane exceeds it at 89 deg.
  ModelParameters p = gold(0.15 * 0.55, 2.0);
  const libbrdf::Model moderate_plane(ModelKind::mbk, p);
  p.k_mode = libbrdf::KMode::tis;
  const libbrdf::Model moderate_tis(ModelKind::mbk, p);
  for (double ti : {0.0, 40.0, 80.0, 89.0})
    EXPECT_LE(libbrdf::directional_albedo(moderate_tis, deg(ti)).total, 1.0) << "theta_i " << ti;
  EXPECT_GT(libbrdf::directional_albedo(moderate_plane, deg(89.0)).total, 1.0);
}

TEST(Albedo, RefusesQuantitiesThatAreNotBrdfs) {
  const libbrdf::Model fresnel(ModelKind::fresnel, gold(0.1, 2.0));
  EXPECT_THROW(libbrdf::directional_albedo(fresnel, 0.3), libbrdf::InvalidArgument);
}

TEST(Renormalization, HugeRoughnessFinishesInBoundedTime) {
  // g1 = (2 pi sigma_s cos ti / lambda)^2 from 3e9 (an int term index overflowed there) to 3e31.
  for (double sigma_over_lambda : {1e4, 1e8, 1e12, 1e15}) {
    const libbrdf::Surface surface{sigma_over_lambda, 2.0, 1.0};
    const auto start = std::chrono::steady_clock::now();
    const auto parts = libbrdf::renormalization_direct(surface, deg(30.0), libbrdf::KMode::plane);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_TRUE(std::isfinite(parts.k) && parts.k >= 1.0) << sigma_over_lambda << ": K = " << parts.k;
    EXPECT_LT(seconds, 5.0) << sigma_over_lambda;
  }
}

TEST(Renormalization, StridedOutsideSumIsContinuousAcrossStrideChanges) {
  // The stride becomes 2 at g1 = 64 (sigma/lambda = 1.4701 at 30 deg): K is smooth across it.
  std::vector<double> k;
  for (double s = 1.455; s < 1.4851; s += 0.005)
    k.push_back(libbrdf::renormalization_direct(libbrdf::Surface{s, 2.0, 1.0}, deg(30.0), libbrdf::KMode::plane).k);
  // K is smooth (second differences ~1.3e-4 and nearly constant): a slip of the strided sum at the
  // stride change would show as a jump of the second difference there.
  for (std::size_t i = 2; i + 1 < k.size(); ++i) {
    const double before = k[i] - 2.0 * k[i - 1] + k[i - 2], after = k[i + 1] - 2.0 * k[i] + k[i - 1];
    EXPECT_LT(std::abs(after - before), 1e-6) << i;
  }
}

TEST(Domain, RatiosBeyondTheRangeAreErrorsNamingTheParameter) {
  auto message = [](const ModelParameters& p) {
    try {
      libbrdf::Model(ModelKind::mbk, p);
    } catch (const libbrdf::InvalidArgument& e) {
      return e.parameter();
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(gold(1e308, 2.0)), "sigma_s");
  EXPECT_EQ(message(gold(0.1, 1e308)), "lc");
  EXPECT_EQ(message(gold(0.1, 1e-9)), "lc");
  ModelParameters p = gold(0.1, 2.0);
  p.index = libbrdf::ComplexIndex{1.5, 1e308};
  EXPECT_EQ(message(p), "k");
  p.index = libbrdf::ComplexIndex{1001.0, 0.0};
  EXPECT_EQ(message(p), "n");
}

TEST(Messages, ExcerptEscapesControlBytesAndCutsLongText) {
  EXPECT_EQ(libbrdf::message_excerpt(std::string("a\nb\x1b", 3)), "a\\x0ab");
  const std::string cut = libbrdf::message_excerpt(std::string(50 << 20, '9'), 20);
  EXPECT_LT(cut.size(), 60u);
  EXPECT_NE(cut.find("52428800 bytes"), std::string::npos) << cut;
}

// A rejected value is quoted in the fewest digits that read back as the same double: 15 where
// they do (1e-07, not 9.9999999999999995e-08), 17 where 15 would name another number.
TEST(Messages, NumbersAreQuotedInTheirShortestExactDigits) {
  auto message = [](double value) {
    try {
      libbrdf::require_positive("sigma_s", value, "um");
    } catch (const libbrdf::InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(-1e-7), "sigma_s: must be a finite number > 0 um (got -1e-07)");
  const double not_0_3 = -(0.1 + 0.2);  // -0.30000000000000004: "%.15g" would print -0.3
  EXPECT_EQ(message(not_0_3), "sigma_s: must be a finite number > 0 um (got -0.30000000000000004)");
  EXPECT_EQ(std::strtod("-0.30000000000000004", nullptr), not_0_3);
}

TEST(LutFiles, WritersAndReadersRefuseNegativeValues) {
  libbrdf::Lut lut;
  lut.layout = libbrdf::LutLayout::rusinkiewicz;
  lut.wavelengths_um = {0.55};
  lut.shape = {2, 2, 2};
  lut.values.assign(8, 1.0f);
  lut.values[3] = -1.0f;
  lut.specular_reflectance = {std::vector<float>(libbrdf::kThetaINodes, 0.5f)};
  lut.renormalization = {std::vector<float>(libbrdf::kThetaINodes, 1.0f)};
  EXPECT_THROW(libbrdf::write_lut_exr(lut, testing::TempDir() + "/negative.exr"), libbrdf::LutFileError);
}

}  // namespace

// A group whose files spell one directory two ways ("D/a" and "D/./b") takes one lock on it:
// flock(2) locks of one process through two descriptors conflict, so two locks on the same
// directory made the publication wait for itself forever (found by the Blender exporter with a
// relative and an absolute output path).
TEST(PublicationGroup, OneDirectorySpelledTwoWaysIsLockedOnce) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("libbrdf_publication_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string first = (dir / "a.txt").string(), second = (dir / "." / "b.txt").string();
  std::promise<void> done;
  std::future<void> finished = done.get_future();
  std::thread publisher([&] {
    libbrdf::PublicationGroup group;
    libbrdf::write_text_file_atomically(first, "a");
    libbrdf::write_text_file_atomically(second, "b");
    group.publish();
    done.set_value();
  });
  if (finished.wait_for(std::chrono::seconds(30)) != std::future_status::ready) {
    ADD_FAILURE() << "publish() did not return within 30 s (directory locked twice)";
    std::_Exit(1);  // the publisher thread cannot be joined
  }
  publisher.join();
  EXPECT_TRUE(fs::exists(dir / "a.txt"));
  EXPECT_TRUE(fs::exists(dir / "b.txt"));
  fs::remove_all(dir);
}
