// Built-in optical constants: the published samples are returned at their wavelengths, values in
// between are linear interpolations, and bad names / wavelengths are errors naming the parameter.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "libbrdf/error.h"
#include "libbrdf/materials.h"

namespace {

using namespace libbrdf;

std::string parameter_of(const char* name, double wavelength) {
  try {
    material_index(name, wavelength);
  } catch (const InvalidArgument& e) {
    return e.parameter();
  }
  return "accepted";
}

// Johnson & Christy, Phys. Rev. B 6, 4370 (1972), gold at 2.38 eV (0.5209 um) and 2.26 eV (0.5486 um).
TEST(Materials, GoldReturnsJohnsonChristySamplesAtTheirWavelengths) {
  const ComplexIndex a = material_index("Au", 0.5209), b = material_index("Au", 0.5486);
  EXPECT_DOUBLE_EQ(a.n, 0.62);
  EXPECT_DOUBLE_EQ(a.kappa, 2.081);
  EXPECT_DOUBLE_EQ(b.n, 0.43);
  EXPECT_DOUBLE_EQ(b.kappa, 2.455);
}

TEST(Materials, InterpolatesLinearlyBetweenSamples) {
  const ComplexIndex mid = material_index("Au", 0.5 * (0.5209 + 0.5486));
  EXPECT_NEAR(mid.n, 0.5 * (0.62 + 0.43), 1e-12);
  EXPECT_NEAR(mid.kappa, 0.5 * (2.081 + 2.455), 1e-12);
  const ComplexIndex quarter = material_index("Au", 0.5209 + 0.25 * (0.5486 - 0.5209));
  EXPECT_NEAR(quarter.n, 0.62 + 0.25 * (0.43 - 0.62), 1e-12);
}

TEST(Materials, EveryBuiltinIsPhysicalOverItsRange) {
  for (const MaterialInfo& info : builtin_materials()) {
    EXPECT_LT(info.min_wavelength_um, 0.4) << info.name;  // the visible range is covered
    EXPECT_GT(info.max_wavelength_um, 0.7) << info.name;
    EXPECT_FALSE(info.source.empty()) << info.name;
    for (int i = 0; i <= 200; ++i) {
      const double w = i == 200 ? info.max_wavelength_um
                                : info.min_wavelength_um + (info.max_wavelength_um - info.min_wavelength_um) * i / 200.0;
      const ComplexIndex index = material_index(info.name, w);
      ASSERT_TRUE(std::isfinite(index.n) && index.n > 0 && std::isfinite(index.kappa) && index.kappa >= 0)
          << info.name << " at " << w << " um";
    }
  }
}

TEST(Materials, UnknownNameThrowsNamingMaterial) {
  EXPECT_EQ(parameter_of("Unobtainium", 0.55), "material");
  EXPECT_EQ(parameter_of("", 0.55), "material");
  try {
    material_index("Xx", 0.55);
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("Au"), std::string::npos) << "list of known names expected: " << e.what();
  }
}

TEST(Materials, OutOfRangeOrNaNWavelengthThrowsNamingWavelength) {
  EXPECT_EQ(parameter_of("Au", 0.1), "wavelength");
  EXPECT_EQ(parameter_of("Au", 5.0), "wavelength");
  EXPECT_EQ(parameter_of("Au", std::nan("")), "wavelength");
  EXPECT_EQ(parameter_of("Au", -0.5), "wavelength");
  EXPECT_EQ(parameter_of("Au", 0.55), "accepted");
}

}  // namespace
