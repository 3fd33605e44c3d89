// brdf: bake, evaluate, compare and benchmark the BRDF models of libbrdf.
#include <CLI/CLI.hpp>

#include <iostream>

#include "commands.h"
#include "libbrdf/error.h"
#include "libbrdf/version.h"

int main(int argc, char** argv) {
  CLI::App app{"brdf: physical-optics BRDFs (MBK, BK, microfacet) evaluated and baked into LUTs"};
  app.set_version_flag("--version", libbrdf::kVersion);
  app.require_subcommand(1);
  // One line per error (CLI11's default adds a help hint on a second line).
  app.failure_message([](const CLI::App*, const CLI::Error& e) { return std::string(e.what()) + "\n"; });

  brdf_cli::ActionTable actions;
  for (auto registrar : {&brdf_cli::register_eval, &brdf_cli::register_bake, &brdf_cli::register_bench, &brdf_cli::register_export_blender, &brdf_cli::register_export_povray}) registrar(app, actions);

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
