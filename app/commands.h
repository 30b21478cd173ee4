// Subcommands of the `prostatesim` executable. Each registers its options on the CLI11 app and
// returns a function run after parsing. Exit codes: 0 ok, 1 validation out of tolerance,
// 2 bad input (scenario, mesh, command line), 3 simulation fault (NaN / blow-up).
#pragma once
#include <CLI/CLI.hpp>
#include <functional>

namespace ps::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitOutOfTolerance = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitFault = 3;

using Runner = std::function<int()>;

void add_simulate_command(CLI::App& app, Runner& run);
void add_check_command(CLI::App& app, Runner& run);
void add_validate_command(CLI::App& app, Runner& run);
void add_make_anatomy_command(CLI::App& app, Runner& run);
void add_insert_command(CLI::App& app, Runner& run);        // cmd_insert.cpp (needles)
void add_run_command(CLI::App& app, Runner& run);           // cmd_run.cpp (real-time loop)
void add_replay_command(CLI::App& app, Runner& run);        // cmd_replay.cpp (record/replay)

}  // namespace ps::app
