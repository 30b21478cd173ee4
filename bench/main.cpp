// prostatesim_bench: Google Benchmark runner plus a few plain modes that need no timer.
//   prostatesim_bench [--benchmark_...]        the benchmarks (step_bench.cpp, stage_bench.cpp)
//   prostatesim_bench --info                   particles, neighbours, triplets, substeps per scene
//   prostatesim_bench --steps SCENE N          N substeps of SCENE after 20 warm-up substeps; under
//                                              valgrind --tool=callgrind --collect-atstart=no
//                                              only those N substeps are counted
//   prostatesim_bench --verify                 optimised shape memory vs the reference copy
//   prostatesim_bench --stable-dt [N]          largest stable substep vs the estimate (N substeps)
//   prostatesim_bench --dt-profile FILE        what sets FILE's stable substep (particles, terms)
//   prostatesim_bench --fast-error SCENE SUBSTEPS MASS_SCALING TRIPLETS DURATION_S [REF_SUBSTEPS
//                     [FAST_NU [FAST_PRESSURE [PRESSURE_ITERATIONS [FAST_SLEEP_WAKE [FAST_MULTIRATE
//                     [FAST_DT_MS [REF_FILE]]]]]]]]
//                                              fast configuration vs the converged reference
//   prostatesim_bench --ticks SCENARIO N       N ticks of a scenario file with its tools (callgrind)
//   prostatesim_bench --soak [N]               config/biopsy.yaml with its tools for N substeps
//                                              (default 100000): no fault, finite, volumes held
//   prostatesim_bench --speed-trace SCENARIO SCRIPT [SUBSTEPS [MASS_SCALING]]
//                                              largest particle speed per 10 ms of a scripted run
//   prostatesim_bench --tick-trace SCENARIO SCRIPT [WINDOW_MS]
//                                              CPU time per tick over a scripted run, per window
//   prostatesim_bench --realtime [WALL_S]      the real-time loop on each default scene with its
//                                              script, WALL_S s each: tick rate, jitter, slow motion
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "bench/bench_modes.h"

int main(int argc, char** argv) {
  if (argc >= 2 && std::strcmp(argv[1], "--info") == 0) return ps::bench::print_info();
  if (argc >= 2 && std::strcmp(argv[1], "--verify") == 0) return ps::bench::verify_shape_memory();
  if (argc >= 4 && std::strcmp(argv[1], "--steps") == 0)
    return ps::bench::run_steps(argv[2], std::atoi(argv[3]));
  if (argc >= 2 && std::strcmp(argv[1], "--stable-dt") == 0)
    return ps::bench::stable_dt_study(argc >= 3 ? std::atoi(argv[2]) : 20000);
  if (argc >= 3 && std::strcmp(argv[1], "--dt-profile") == 0) return ps::bench::stable_dt_profile(argv[2]);
  if (argc >= 7 && std::strcmp(argv[1], "--fast-error") == 0)
    return ps::bench::fast_error(argv[2], std::atoi(argv[3]), std::atoi(argv[4]), std::atoi(argv[5]),
                                 std::atof(argv[6]), argc >= 8 ? std::atoi(argv[7]) : 0,
                                 argc >= 9 ? std::atof(argv[8]) : 0.0, argc >= 10 ? std::atoi(argv[9]) : -1,
                                 argc >= 11 ? std::atoi(argv[10]) : 0, argc >= 12 ? std::atof(argv[11]) : -1.0,
                                 argc >= 13 ? std::atoi(argv[12]) : -1, argc >= 14 ? std::atof(argv[13]) : -1.0,
                                 argc >= 15 ? argv[14] : "");
  if (argc >= 2 && std::strcmp(argv[1], "--soak") == 0) return ps::bench::soak(argc >= 3 ? std::atoi(argv[2]) : 100000);
  if (argc >= 2 && std::strcmp(argv[1], "--realtime") == 0) return ps::bench::realtime_loop(argc >= 3 ? std::atof(argv[2]) : 20.0);
  if (argc >= 4 && std::strcmp(argv[1], "--speed-trace") == 0)
    return ps::bench::speed_trace(argv[2], argv[3], argc >= 5 ? std::atoi(argv[4]) : 0, argc >= 6 ? std::atoi(argv[5]) : -1);
  if (argc >= 4 && std::strcmp(argv[1], "--tick-trace") == 0)
    return ps::bench::tick_trace(argv[2], argv[3], argc >= 5 ? std::atof(argv[4]) : 250.0);
  if (argc >= 4 && std::strcmp(argv[1], "--ticks") == 0) return ps::bench::run_ticks(argv[2], std::atoi(argv[3]));
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
