#pragma once
// Each subcommand registers itself on the root app and returns the action to run when chosen.
#include <CLI/CLI.hpp>

#include <functional>

namespace brdf_cli {

using Action = std::function<int()>;

Action register_eval(CLI::App& app);
Action register_bake(CLI::App& app);
Action register_bench(CLI::App& app);
Action register_export(CLI::App& app);

}  // namespace brdf_cli
