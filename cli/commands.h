#pragma once
// Each subcommand registers itself (and its own subcommands) on a parent app and records the
// action to run when it is the command chosen. main.cpp lists the registrars.
#include <CLI/CLI.hpp>

#include <functional>
#include <utility>
#include <vector>

namespace brdf_cli {

using Action = std::function<int()>;
using ActionTable = std::vector<std::pair<CLI::App*, Action>>;

void register_eval(CLI::App& app, ActionTable& actions);    // eval_command.cpp
void register_bake(CLI::App& app, ActionTable& actions);    // bake_command.cpp
void register_bench(CLI::App& app, ActionTable& actions);   // bench_command.cpp
void register_albedo(CLI::App& app, ActionTable& actions);  // albedo_command.cpp
void register_export_blender(CLI::App& app, ActionTable& actions);  // export_blender_command.cpp (under `export`)
void register_export_povray(CLI::App& app, ActionTable& actions);   // export_povray_command.cpp (under `export`)

// The `export` parent command (created on first use); exporters add their subcommands to it.
CLI::App& export_parent(CLI::App& app);

}  // namespace brdf_cli
