// `brdf export`: the parent of the renderer exporters (`brdf export povray`, `brdf export blender`).
#include "commands.h"

namespace brdf_cli {

CLI::App& export_parent(CLI::App& app) {
  for (CLI::App* sub : app.get_subcommands({}))
    if (sub->get_name() == "export") return *sub;
  CLI::App* parent = app.add_subcommand("export", "Write a baked material for a renderer (povray, blender)");
  parent->require_subcommand(1);
  return *parent;
}

}  // namespace brdf_cli
