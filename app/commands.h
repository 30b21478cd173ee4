// Subcommands of the `prostatesim` executable. Each registers its options on the CLI11 app and
// returns a function run after parsing. Exit codes: 0 ok, 1 validation out of tolerance,
// 2 bad input (scenario, mesh, command line), 3 simulation fault (NaN / blow-up), 4 internal
// fault (a bug in ProstateSim: a broken invariant, not the user's input; main asks for a report).
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace ps::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitOutOfTolerance = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitFault = 3;
inline constexpr int kExitInternal = 4;
inline constexpr const char* kVersion = "0.1";

// The message for an internal fault: what broke, and what to send with a report.
std::string internal_fault_message(const std::string& what, int argc, char** argv);

using Runner = std::function<int()>;

void add_simulate_command(CLI::App& app, Runner& run);
void add_check_command(CLI::App& app, Runner& run);
void add_validate_command(CLI::App& app, Runner& run);
void add_make_anatomy_command(CLI::App& app, Runner& run);
void add_insert_command(CLI::App& app, Runner& run);        // cmd_insert.cpp (needles)
void add_ultrasound_command(CLI::App& app, Runner& run);    // cmd_ultrasound.cpp (simulated TRUS)
void add_report_command(CLI::App& app, Runner& run);        // cmd_report.cpp (class metrics)
void add_run_command(CLI::App& app, Runner& run);           // cmd_run.cpp (real-time loop)
void add_replay_command(CLI::App& app, Runner& run);        // cmd_replay.cpp (record/replay)
void add_stress_command(CLI::App& app, Runner& run);        // cmd_stress.cpp (app/checks/stress.h)
void add_bench_command(CLI::App& app, Runner& run);         // cmd_bench.cpp
void add_edit_command(CLI::App& app, Runner& run);          // cmd_edit.cpp (app/editor/)
void add_dose_command(CLI::App& app, Runner& run);          // cmd_dose.cpp (TG-43U1 dose at points)
void add_plan_command(CLI::App& app, Runner& run);          // cmd_dose.cpp (seed implant plan)

}  // namespace ps::app
