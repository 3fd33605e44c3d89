#pragma once
// Command-line options shared by every subcommand that names a model and a surface
// (eval, bake, export): --model, --sigma-s, --lc, --wavelength, --n, --k, --material, ...
#include <CLI/CLI.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "libbrdf/lut.h"
#include "libbrdf/model_settings.h"
#include "libbrdf/models.h"

namespace brdf_cli {

// The model settings (libbrdf/model_settings.h: libbrdf::model_parameters maps them, also for the
// Python module) and the --wavelength text.
struct ModelOptions : libbrdf::ModelSettings {
  std::string wavelengths;  // --wavelength text "A[,B,...]" (parsed by channel_wavelengths)
};

// Registers the options on a subcommand. `default_wavelengths` is what an absent --wavelength means.
void add_model_options(CLI::App& command, ModelOptions& options, bool require_model = true);

// The kind named by --model (throws libbrdf::InvalidArgument naming "model").
libbrdf::ModelKind parse_model_kind(const ModelOptions& options);

// The channels' wavelengths: --wavelength values, or the given default.
std::vector<double> channel_wavelengths(const ModelOptions& options, std::vector<double> default_wavelengths);

// Parses "a,b,c" into exactly `count` finite numbers (count 0: one or more); throws
// InvalidArgument naming `parameter`. One rule for every list: an empty item, a leading or
// trailing comma, or an item that is not entirely a finite number is an error.
std::vector<double> parse_number_list(const std::string& text, std::size_t count, const char* parameter);

// A whole number in [lo, hi] written in decimal digits only (no sign, no exponent, no spaces);
// throws InvalidArgument naming `parameter` and the range.
std::uint64_t parse_whole_number(const std::string& text, std::uint64_t lo, std::uint64_t hi, const char* parameter);

// Every option value of `app` and its subcommands gets two checks: not empty (an empty value is
// an error, not "not given") and free of control characters (a newline in a path would reach a
// file header or an OSL string literal). Call once after every option is registered.
void add_value_checks(CLI::App& app);


// A world direction "X,Y,Z" (nonzero; normalized by its users); throws InvalidArgument naming `parameter`.
libbrdf::Direction parse_direction(const std::string& text, const char* parameter);

// Table nodes per axis "N0,N1[,N2]": `count` whole numbers in [2, 4096]; unused axes are 1.
// Throws InvalidArgument naming "resolution".
std::array<int, 3> parse_node_counts(const std::string& text, std::size_t count);

}  // namespace brdf_cli
