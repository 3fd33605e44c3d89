#pragma once
// Command-line options shared by every subcommand that names a model and a surface
// (eval, bake, export): --model, --sigma-s, --lc, --wavelength, --n, --k, --material, ...
#include <CLI/CLI.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "libbrdf/lut.h"
#include "libbrdf/models.h"

namespace brdf_cli {

struct ModelOptions {
  std::string model;
  std::optional<double> sigma_s_um, lc_um, n, kappa, sigma_g, rho_s;
  double rho_d = 0.0;
  std::vector<double> wavelengths_um;  // one per channel
  std::string material;
  std::string g_term = "smith";
  std::string k_mode = "plane";
  std::string sigma_g_mapping = "auto";
  double tolerance = 1e-6;
};

// Registers the options on a subcommand. `default_wavelengths` is what an absent --wavelength means.
void add_model_options(CLI::App& command, ModelOptions& options, bool require_model = true);

// The kind named by --model (throws libbrdf::InvalidArgument naming "model").
libbrdf::ModelKind parse_model_kind(const ModelOptions& options);

// ModelParameters for one wavelength (complex index from --n/--k or --material at that wavelength).
libbrdf::ModelParameters model_parameters(const ModelOptions& options, double wavelength_um);

// The channels' wavelengths: --wavelength values, or the given default.
std::vector<double> channel_wavelengths(const ModelOptions& options, std::vector<double> default_wavelengths);

// Parses "a,b,c" into exactly `count` finite numbers; throws InvalidArgument naming `parameter`.
std::vector<double> parse_number_list(const std::string& text, std::size_t count, const char* parameter);

// A world direction "X,Y,Z" (nonzero; normalized by its users); throws InvalidArgument naming `parameter`.
libbrdf::Direction parse_direction(const std::string& text, const char* parameter);

// Table nodes per axis "N0,N1[,N2]": `count` whole numbers in [2, 4096]; unused axes are 1.
// Throws InvalidArgument naming "resolution".
std::array<int, 3> parse_node_counts(const std::string& text, std::size_t count);

}  // namespace brdf_cli
