#include "model_options.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "libbrdf/error.h"

namespace brdf_cli {

using libbrdf::InvalidArgument;

void add_model_options(CLI::App& command, ModelOptions& o, bool require_model) {
  std::string names;
  for (const libbrdf::ModelKind kind : libbrdf::all_models()) names += (names.empty() ? "" : ", ") + std::string(libbrdf::model_name(kind));
  auto* model = command.add_option("--model", o.model, "Model name: " + names + " (README: what each is)");
  if (require_model) model->required();
  command.add_option("--sigma-s", o.sigma_s_um, "RMS surface height sigma_s [um], >= 0");
  command.add_option("--lc", o.lc_um, "Surface correlation length l_c [um], > 0");
  command.add_option("--wavelength", o.wavelengths,
                     "Wavelength [um]; bake and the exporters take one per channel: A[,B,...] (eval and albedo: one)");
  command.add_option("--n", o.n, "Real part n of the complex index n + i k, in [0.001, 1000]");
  command.add_option("--k", o.kappa, "Imaginary part kappa of the complex index, in [0, 1000] (default 0)");
  command.add_option("--material", o.material, "Built-in material (n, k tabulated per wavelength): Au, Ag, Al, Cu, Cr, Ni, Ti, Si, BK7");
  command.add_option("--sigma-g", o.sigma_g, "Microfacet slope parameter sigma_g (eq. 7), in [1e-7, 1000]; default: mapped from sigma_s, l_c");
  command.add_option("--rho-s", o.rho_s, "Microfacet amplitude rho_s (eq. 2), in [0, 1000]; default: K(theta_i)");
  command.add_option("--rho-d", o.rho_d, "Lambertian albedo rho_d (eq. 2), in [0, 1], default 0");
  command.add_option("--g-term", o.g_term, "Shadowing/masking G: none|smith|vgroove (default smith)");
  command.add_option("--k-mode", o.k_mode, "Renormalization K: plane (eq. 13, default) | tis");
  command.add_option("--sigma-g-mapping", o.sigma_g_mapping, "sigma_g from sigma_s, l_c: auto|rough (eq. 20)|polished (eq. 25)");
  command.add_option("--tolerance", o.tolerance, "Relative error allowed for a closed form inside mbk (0 = always the series; default 1e-6)");
  command.add_option("--asf-method", o.asf_method,
                     "How the ASF (eq. 11) meets --tolerance: auto (the fastest certified: kernel table, closed forms, "
                     "series; default) | series (no kernel table)");
}

libbrdf::ModelKind parse_model_kind(const ModelOptions& o) { return libbrdf::model_from_name(o.model); }

std::vector<double> channel_wavelengths(const ModelOptions& o, std::vector<double> default_wavelengths) {
  std::vector<double> out = o.wavelengths.empty() ? std::move(default_wavelengths) : parse_number_list(o.wavelengths, 0, "wavelength");
  for (double w : out) libbrdf::require_positive("wavelength", w, "um");
  return out;
}

std::vector<double> parse_number_list(const std::string& text, std::size_t count, const char* parameter) {
  const std::string expected = (count ? "expected " + std::to_string(count) : std::string("expected one or more")) +
                               " comma-separated finite numbers (got '" + libbrdf::message_excerpt(text) + "')";
  std::vector<double> values;
  std::size_t begin = 0;
  for (;;) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    // Surrounding blanks are allowed ("30, 40, 180"); an item with nothing else is an error.
    const std::string item = text.substr(begin, end - begin);
    const std::size_t first = item.find_first_not_of(" \t\r"), last = item.find_last_not_of(" \t\r");
    if (first == std::string::npos) throw InvalidArgument(parameter, "empty item in the list; " + expected);
    const std::string number = item.substr(first, last - first + 1);
    char* stop = nullptr;
    errno = 0;
    const double v = std::strtod(number.c_str(), &stop);
    if (stop != number.c_str() + number.size() || !std::isfinite(v))
      throw InvalidArgument(parameter, expected);
    values.push_back(v);
    if (end == text.size()) break;
    begin = end + 1;
  }
  if (count && values.size() != count) throw InvalidArgument(parameter, expected);
  return values;
}

std::uint64_t parse_whole_number(const std::string& text, std::uint64_t lo, std::uint64_t hi, const char* parameter) {
  const std::string range = "must be a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got '" +
                            libbrdf::message_excerpt(text) + "')";
  if (text.empty() || text.size() > 20 || text.find_first_not_of("0123456789") != std::string::npos)
    throw InvalidArgument(parameter, range);
  errno = 0;
  const unsigned long long value = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE || value < lo || value > hi) throw InvalidArgument(parameter, range);
  return value;
}

void add_value_checks(CLI::App& app) {
  const CLI::Validator checked(
      [](std::string& value) -> std::string {
        if (value.empty()) return "empty value (give a value or leave the option out)";
        for (const char c : value)
          if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
            return "control character in the value '" + libbrdf::message_excerpt(value) + "'";
        return "";
      },
      "", "value");
  for (CLI::Option* option : app.get_options())
    if (option->get_type_size() != 0) option->check(checked);
  for (CLI::App* sub : app.get_subcommands({})) add_value_checks(*sub);
}

libbrdf::Direction parse_direction(const std::string& text, const char* parameter) {
  const std::vector<double> v = parse_number_list(text, 3, parameter);
  if (!(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 0.0)) throw InvalidArgument(parameter, "must be a nonzero vector X,Y,Z");
  return {v[0], v[1], v[2]};
}

std::array<int, 3> parse_node_counts(const std::string& text, std::size_t count) {
  const std::vector<double> v = parse_number_list(text, count, "resolution");
  std::array<int, 3> nodes{1, 1, 1};
  for (std::size_t k = 0; k < count; ++k) {
    if (v[k] != std::floor(v[k]) || v[k] < 2 || v[k] > 4096)
      throw InvalidArgument("resolution", "expected " + std::to_string(count) +
                                              " whole numbers of nodes per axis in [2, 4096] (got '" + libbrdf::message_excerpt(text) + "')");
    nodes[k] = static_cast<int>(v[k]);
  }
  return nodes;
}

}  // namespace brdf_cli
