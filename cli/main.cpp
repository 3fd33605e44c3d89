// brdf: bake, evaluate, compare and benchmark the BRDF models of libbrdf.
#include <CLI/CLI.hpp>

#include <iostream>

#include "commands.h"
#include "interrupt.h"
#include "model_options.h"
#include "libbrdf/error.h"
#include "libbrdf/version.h"

int main(int argc, char** argv) {
  // Commands that write files take SIGINT/SIGTERM/SIGHUP from the very start (interrupt.h).
  if (argc > 1 && (std::string(argv[1]) == "bake" || std::string(argv[1]) == "export"))
    brdf_cli::handle_interrupts(std::string(argv[1]) == "bake" ? "bake" : argc > 2 && std::string(argv[2]) == "povray" ? "export povray" : "export blender");
  CLI::App app{"brdf: physical-optics BRDFs (MBK, BK, microfacet) evaluated and baked into LUTs"};
  app.set_version_flag("--version", libbrdf::kVersion);
  app.require_subcommand(1);
  // One line per error (CLI11's default adds a help hint on a second line).
  app.failure_message([](const CLI::App*, const CLI::Error& e) { return std::string(e.what()) + "\n"; });

  brdf_cli::ActionTable actions;
  for (auto registrar : {&brdf_cli::register_eval, &brdf_cli::register_bake, &brdf_cli::register_bench, &brdf_cli::register_albedo, &brdf_cli::register_export_blender, &brdf_cli::register_export_povray}) registrar(app, actions);
  // One rule for every value: empty or with control characters is an error (model_options.h).
  brdf_cli::add_value_checks(app);

  // An unknown command word is named (CLI11 would only say that a subcommand is required).
  for (int depth = 1, at = 1; at < argc && depth <= 2; ++depth, ++at) {
    const std::string word = argv[at];
    if (word.empty() || word[0] == '-') break;
    const CLI::App* parent = depth == 1 ? &app : nullptr;
    if (depth == 2) {
      if (std::string(argv[1]) != "export") break;
      parent = &brdf_cli::export_parent(app);
    }
    std::string names;
    bool known = false;
    for (const CLI::App* sub : const_cast<CLI::App*>(parent)->get_subcommands({})) {
      names += (names.empty() ? "" : ", ") + sub->get_name();
      known = known || sub->get_name() == word;
    }
    if (!known) {
      std::cerr << "brdf: error: unknown command '" << libbrdf::message_excerpt(word) << "' (one of: " << names << ")\n";
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "brdf: error: " << e.what() << "\n";
    return 2;
  }
  try {
    // The chosen command is the last parsed one (nested commands register after their parent).
    for (auto it = actions.rbegin(); it != actions.rend(); ++it)
      if (it->first->parsed()) return it->second();
  } catch (const libbrdf::InvalidArgument& e) {
    std::cerr << "brdf: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "brdf: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
