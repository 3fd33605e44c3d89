#pragma once
// SIGINT, SIGTERM and SIGHUP for the commands that write files (bake, export).
//
// The signals are blocked in the calling (main) thread, and so in every thread it starts later
// (oneTBB's workers), and taken synchronously by one thread of their own (sigwait). That thread
// takes libbrdf's publication lock (image_file.h) -- waiting, at most, for a rename in progress --
// removes every temporary file, prints one line and exits with 128 + the signal number (130
// SIGINT, 143 SIGTERM, 129 SIGHUP). So at any moment of a bake or an export -- model set-up, K
// table, node values, error measurement, writing -- a signal leaves every final file either
// untouched or completely written (published before the signal), and no temporary. The exit is
// immediate: it does not wait for a parallel loop to notice a flag.
namespace brdf_cli {

// Call before any thread is started: main.cpp does so first thing for `bake` and `export` (so a
// signal during option parsing is handled too); later calls do nothing. `command` names it in the
// message ("bake", "export blender").
void handle_interrupts(const char* command);

// Tells the signal thread that the outputs are in place (its message then says so).
void outputs_published();

}  // namespace brdf_cli
