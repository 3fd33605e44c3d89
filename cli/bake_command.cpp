// `brdf bake`: a model baked into a table (OpenEXR or MERL binary), error measured and printed.
//   brdf bake --model NAME [surface params as in eval] [--wavelength a,b,c]
//             [--layout rusinkiewicz|merl|slice|kernel] [--resolution A,B,C | --target-error REL]
//             [--light-dir X,Y,Z --view-dir X,Y,Z] [--scene scene.json] -o OUT.exr|OUT.binary
// Progress goes to stderr only when stderr is a terminal. SIGINT, SIGTERM or SIGHUP at any moment
// exits 130/143/129 with no final file changed and no temporary left (interrupt.h); files are
// written to temporaries and renamed (a MERL binary and its sidecar as one unit, lut.h).
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <memory>

#include "commands.h"
#include "interrupt.h"
#include "libbrdf/error.h"
#include "libbrdf/lut.h"
#include "libbrdf/image_file.h"
#include "model_options.h"

namespace brdf_cli {

namespace {

struct BakeOptions {
  ModelOptions model;
  std::string layout;
  std::string kernel_angular;  // closed-form (default) | table
  std::string resolution;
  std::optional<double> target_error;
  std::string light_dir, view_dir;
  std::string scene;
  std::string output;
  std::string error_samples;  // whole number in [1, kMaxErrorSamples]; default 20000
  double error_floor = 1e-3;
  double error_theta_limit = libbrdf::kErrorThetaLimitDeg;
  std::string seed;  // whole number in [0, 2^64 - 1]; default 1
};

// Largest --error-samples: the measurement holds a batch of samples/channels geometries and their
// errors (~60 MB at this cap) and takes ~10 s for mbk; 2147483647 asked for 9 GB and never ended.
constexpr std::uint64_t kMaxErrorSamples = 1000000;

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}



class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled) {}
  void update(double fraction) {
    if (!enabled_) return;
    const int width = 40, filled = static_cast<int>(fraction * width + 0.5);
    std::fprintf(stderr, "\rbake [%s%s] %3d%%", std::string(filled, '#').c_str(), std::string(width - filled, ' ').c_str(),
                 static_cast<int>(fraction * 100 + 0.5));
    std::fflush(stderr);
    dirty_ = true;
  }
  void clear() {
    if (enabled_ && dirty_) std::fprintf(stderr, "\r%60s\r", "");
    dirty_ = false;
  }

 private:
  bool enabled_;
  bool dirty_ = false;
};

int run_bake(const BakeOptions& o) {
  using libbrdf::InvalidArgument;
  using libbrdf::LutLayout;
  handle_interrupts("bake");
  const bool merl_output = ends_with(o.output, ".binary");
  if (!merl_output && !ends_with(o.output, ".exr"))
    throw InvalidArgument("output", "must end in .exr (OpenEXR) or .binary (MERL) (got '" + libbrdf::message_excerpt(o.output) + "')");
  libbrdf::require_writable_output(o.output, "output");  // before any work, not after the bake

  libbrdf::BakeRequest request;
  request.model = parse_model_kind(o.model);
  std::vector<double> default_wavelengths{0.65, 0.55, 0.45};
  if (!o.scene.empty()) {
    for (const auto& [given, name] : {std::pair{!o.layout.empty(), "layout"}, std::pair{!o.light_dir.empty(), "light-dir"},
                                      std::pair{!o.view_dir.empty(), "view-dir"}})
      if (given) throw InvalidArgument(name, "the scene (--scene) decides it; give one or the other");
    const libbrdf::ScenePlan plan = libbrdf::plan_scene_bake(o.scene);
    if (!plan.wavelengths_um.empty() && !o.model.wavelengths.empty())
      throw InvalidArgument("wavelength", "the scene lists wavelengths_um; give them in one place");
    if (!plan.wavelengths_um.empty()) default_wavelengths = plan.wavelengths_um;
    request.layout = plan.layout;
    request.light = plan.light;
    request.view = plan.view;
    std::cerr << "scene: " << libbrdf::layout_name(plan.layout) << " (" << plan.reason << ")\n";
  } else if (!o.layout.empty()) {
    request.layout = libbrdf::layout_from_name(o.layout);
  } else {
    request.layout = merl_output ? LutLayout::merl : LutLayout::rusinkiewicz;
  }
  if (merl_output && request.layout != LutLayout::merl)
    throw InvalidArgument("output", "a .binary (MERL) file needs --layout merl");
  if (request.layout == LutLayout::slice && o.scene.empty()) {
    if (o.light_dir.empty()) throw InvalidArgument("light-dir", "required by layout slice (world direction towards the sun)");
    if (o.view_dir.empty()) throw InvalidArgument("view-dir", "required by layout slice (world direction towards the camera)");
    request.light = parse_direction(o.light_dir, "light-dir");
    request.view = parse_direction(o.view_dir, "view-dir");
  } else if (request.layout != LutLayout::slice && (!o.light_dir.empty() || !o.view_dir.empty())) {
    throw InvalidArgument(o.light_dir.empty() ? "view-dir" : "light-dir", "only used by layout slice");
  }
  if (!o.kernel_angular.empty()) {
    if (request.layout != LutLayout::kernel) throw InvalidArgument("kernel-angular", "only used by layout kernel");
    if (o.kernel_angular == "table") request.kernel_angular = libbrdf::KernelAngular::table;
    else if (o.kernel_angular != "closed-form")
      throw InvalidArgument("kernel-angular", "must be closed-form or table (got '" + o.kernel_angular + "')");
  }
  if (!o.resolution.empty()) request.resolution = parse_node_counts(o.resolution, request.layout == libbrdf::LutLayout::slice ? 2 : 3);
  request.target_error = o.target_error;
  request.error_samples = o.error_samples.empty() ? 20000 : static_cast<int>(parse_whole_number(o.error_samples, 1, kMaxErrorSamples, "error-samples"));
  request.error_floor_fraction = o.error_floor;
  request.error_theta_limit_deg = o.error_theta_limit;
  request.seed = o.seed.empty() ? 1 : parse_whole_number(o.seed, 0, UINT64_MAX, "seed");

  const std::vector<double> wavelengths = channel_wavelengths(o.model, default_wavelengths);
  if (merl_output && wavelengths.size() != 3)
    throw InvalidArgument("wavelength", "a MERL binary holds exactly 3 channels (red, green, blue)");
  for (double w : wavelengths) request.channels.push_back(model_parameters(o.model, w));

  ProgressBar bar(isatty(STDERR_FILENO) != 0);
  request.progress = [&bar](double fraction) { bar.update(fraction); };
  request.trial_done = [&bar, &request](const std::array<int, 3>& shape, const libbrdf::LutError& error) {
    bar.clear();
    std::fprintf(stderr, "target-error: %s max relative error %.3g (rms %.3g)\n", libbrdf::shape_text(shape, request.layout).c_str(),
                 error.max_relative, error.rms_relative);
  };
  const libbrdf::Lut lut = libbrdf::bake(request);
  bar.clear();
  if (merl_output) {
    libbrdf::write_merl_binary(lut, o.output);
  } else {
    libbrdf::write_lut_exr(lut, o.output);
  }
  outputs_published();
  std::printf("wrote %s: %s %s, %d channel(s), model %s\n", o.output.c_str(), std::string(libbrdf::layout_name(lut.layout)).c_str(),
              libbrdf::shape_text(lut.shape, lut.layout).c_str(), lut.channels(), o.model.model.c_str());
  std::printf("measured error at %d off-grid values (theta_i, theta_s <= %g deg): max relative %.3g, rms relative %.3g; "
              "up to the horizon: max relative %.3g (values below the floor %.3g 1/sr = %g x the table max ignored)\n",
              lut.error.samples, lut.error.theta_limit_deg, lut.error.max_relative, lut.error.rms_relative,
              lut.error.max_relative_all, lut.error.floor, o.error_floor);
  if (merl_output) std::printf("metadata and R_spec/K tables: %s.json\n", o.output.c_str());
  return 0;
}

}  // namespace

void register_bake(CLI::App& app, ActionTable& actions) {
  auto options = std::make_shared<BakeOptions>();
  CLI::App* command = app.add_subcommand("bake", "Bake a BRDF model into a table (OpenEXR or MERL binary) and measure its error");
  add_model_options(*command, options->model);
  command->add_option("--layout", options->layout, "Table layout: rusinkiewicz (default) | merl | slice | kernel (factored ASF models: K F P x Sigma(g, c))");
  command->add_option("--kernel-angular", options->kernel_angular,
                      "Layout kernel: closed-form (default; the angular factor P evaluated at lookup) | "
                      "table (P / F on the grid, what the Blender atlas holds)");
  command->add_option("--resolution", options->resolution, "Nodes per axis A,B,C (slice: A,B)");
  command->add_option("--target-error", options->target_error,
                      "Smallest table whose measured max relative error is <= REL (grid grows by 1.25 per axis)");
  command->add_option("--light-dir", options->light_dir, "Slice: world direction X,Y,Z towards the sun");
  command->add_option("--view-dir", options->view_dir, "Slice: world direction X,Y,Z towards the (orthographic) camera");
  command->add_option("--scene", options->scene, "Scene JSON (docs/scene.md): picks the layout, directions and wavelengths");
  command->add_option("--error-samples", options->error_samples, "Values compared (off-grid points x channels above the floor) in the error measurement, 1..1000000 (default 20000)");
  command->add_option("--error-floor", options->error_floor, "Ignore model values below this fraction of the table max (default 1e-3)");
  command->add_option("--error-theta-limit", options->error_theta_limit,
                      "Measure the claimed error where both polar angles are <= this (deg, default 85; see lut.h)");
  command->add_option("--seed", options->seed, "Seed of the error sampling, 0..18446744073709551615 (default 1)");
  command->add_option("-o,--output", options->output, "Output file: .exr (OpenEXR) or .binary (MERL)")->required();
  actions.emplace_back(command, [options]() { return run_bake(*options); });
}

}  // namespace brdf_cli
