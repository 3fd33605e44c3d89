// libbrdf_batch_timer: the C++ side of tools/time_python_binding.py. Times evaluate_batch
// (batch.h) on queries from a raw file, so that the Python binding's overhead per call and per
// point can be told apart from the batch API's own cost. Not a test; built on request only:
//   cmake --build build --target libbrdf_batch_timer
//   libbrdf_batch_timer --queries Q.f64 --values-out V.f64 [--repeat N] --model NAME [surface options of brdf eval]
// Q.f64: native doubles theta_i, theta_s, phi_s (degrees) per query; V.f64: the values, same order.
// Prints one line: points, best seconds of N runs, nanoseconds per point.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <vector>

#include "libbrdf/batch.h"
#include "libbrdf/error.h"
#include "model_options.h"

int main(int argc, char** argv) {
  CLI::App app{"Times libbrdf::evaluate_batch on raw query files"};
  brdf_cli::ModelOptions options;
  brdf_cli::add_model_options(app, options);
  std::string queries_path, values_path;
  int repeat = 3;
  app.add_option("--queries", queries_path, "Raw doubles theta_i,theta_s,phi_s (deg) per query")->required();
  app.add_option("--values-out", values_path, "Where to write the values (raw doubles)");
  app.add_option("--repeat", repeat, "Timed runs (the best is reported)");
  CLI11_PARSE(app, argc, argv);
  try {
    std::ifstream in(queries_path, std::ios::binary | std::ios::ate);
    if (!in) throw libbrdf::InvalidArgument("queries", "cannot open '" + queries_path + "'");
    std::vector<double> degrees;
    const auto bytes = static_cast<std::size_t>(in.tellg());
    in.seekg(0);
    degrees.resize(bytes / sizeof(double));
    in.read(reinterpret_cast<char*>(degrees.data()), static_cast<std::streamsize>(degrees.size() * sizeof(double)));
    const std::size_t count = degrees.size() / 3;
    const std::vector<double> wavelengths = brdf_cli::channel_wavelengths(options, {0.55});
    const libbrdf::Model model(brdf_cli::parse_model_kind(options), libbrdf::model_parameters(options, wavelengths[0]));
    std::vector<double> values(count);
    double best = 1e300;
    for (int r = 0; r < std::max(1, repeat); ++r) {
      // Degrees -> radians inside the timed region: the binding does the same per call.
      const auto start = std::chrono::steady_clock::now();
      std::vector<libbrdf::ScatterAngles> angles(count);
      for (std::size_t k = 0; k < count; ++k)
        angles[k] = libbrdf::scatter_angles_from_degrees(degrees[3 * k], degrees[3 * k + 1], degrees[3 * k + 2]);
      libbrdf::evaluate_batch(model, angles.data(), count, values.data());
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    if (!values_path.empty()) {
      std::ofstream out(values_path, std::ios::binary);
      out.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(count * sizeof(double)));
    }
    std::printf("%zu,%.6f,%.1f\n", count, best, 1e9 * best / static_cast<double>(count));
  } catch (const libbrdf::InvalidArgument& e) {
    std::cerr << "libbrdf_batch_timer: error: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
