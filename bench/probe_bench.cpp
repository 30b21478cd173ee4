// Probe contact cost, FCL broad phase against the analytic box (engine/tools/probe/probe.h), in the
// probe test scene (config/validation/probe_pelvis_box.yaml) with the probe pushed 6 mm and
// tilted 4 degrees and the tissue settled against it (~60 particles on the probe):
//  - BM_ProbeCandidates: finding the substep's candidates and projecting them (the probe's
//    constraints hook on a scene state restored every iteration; the restore is a copy into
//    sized vectors, BM_ProbeRestoreOnly measures it alone);
//  - BM_ProbeStep: the whole Simulation::step with the probe (and its volume alternation);
//  - BM_ProbeCandidatesBiopsy: the hook in the default anatomy (below).
#include <benchmark/benchmark.h>

#include "tests/engine/tools/probe/probe_scene.h"

namespace ps::bench {

namespace test = ps::test;
namespace {

struct ProbeBench {
  test::ProbeScene scene;
  State snapshot;
};

test::ProbeScene& probe_scene(ProbeBroadPhase b, State*& snapshot) {
  static ProbeBench benches[2];
  ProbeBench& pb = benches[static_cast<int>(b)];
  test::ProbeScene& s = pb.scene;
  if (!s.sim) {
    s = test::build_probe_scene(false);
    ProbePose t = s.probe->pose();
    t.offset = Vec3(0, 0.006, 0);
    t.tilt = 0.0698;  // 4 deg
    s.probe->move_to(t, 0.0);
    for (int i = 0; i < 80; ++i) s.sim->tick();
  }
  s.probe->set_broad_phase(b);
  pb.snapshot = s.sim->state();
  snapshot = &pb.snapshot;
  return s;
}

void restore(State& s, const State& from) {
  s.x = from.x;  // same sizes: copies, no allocation
  s.contact = from.contact;
}

void BM_ProbeCandidates(benchmark::State& state, ProbeBroadPhase b) {
  State* snap = nullptr;
  test::ProbeScene& s = probe_scene(b, snap);
  State& st = s.sim->state();
  const double h = s.m->dt / s.m->substeps;
  for (auto _ : state) {
    restore(st, *snap);
    s.probe->constraints(*s.m, st, h);
    benchmark::DoNotOptimize(st.x.data());
  }
  state.counters["contacts"] = s.probe->contact_count();
  state.counters["tested"] = s.probe->near_count();
  state.counters["bvh_triangles"] = s.probe->fcl_triangle_count();
  restore(st, *snap);
}

void BM_ProbeRestoreOnly(benchmark::State& state) {
  State* snap = nullptr;
  test::ProbeScene& s = probe_scene(ProbeBroadPhase::Box, snap);
  State& st = s.sim->state();
  for (auto _ : state) {
    restore(st, *snap);
    benchmark::DoNotOptimize(st.x.data());
  }
}

void BM_ProbeStep(benchmark::State& state, ProbeBroadPhase b) {
  State* snap = nullptr;
  test::ProbeScene& s = probe_scene(b, snap);
  const double h = s.m->dt / s.m->substeps;
  int k = 0;
  for (auto _ : state) {
    if (++k == 200) { s.sim->state() = *snap; k = 0; }  // stay in the settled contact state
    if (!s.sim->step(h)) { state.SkipWithError("step faulted"); break; }
  }
  state.counters["particles"] = s.m->particle_count();
  s.sim->state() = *snap;
}

// The default biopsy anatomy (config/biopsy.yaml, 3664 particles; the probe pushes every soft
// component, so the BVH holds the prostate, bladder, rectum and fat surfaces and the pubic
// arch's), probe at its start pose 5 mm clear of the wall: the cost of finding that nothing
// touches, the common case.
void BM_ProbeCandidatesBiopsy(benchmark::State& state, ProbeBroadPhase b) {
  static test::ProbeScene s = test::build_probe_scene(parse_scenario_file(std::string(PROSTATESIM_SOURCE_DIR) + "/config/biopsy.yaml"), false);
  s.probe->set_broad_phase(b);
  State& st = s.sim->state();
  const double h = s.m->dt / s.m->substeps;
  for (auto _ : state) {
    s.probe->constraints(*s.m, st, h);
    benchmark::DoNotOptimize(st.x.data());
  }
  state.counters["particles"] = s.m->particle_count();
  state.counters["tested"] = s.probe->near_count();
  state.counters["bvh_triangles"] = s.probe->fcl_triangle_count();
}

BENCHMARK_CAPTURE(BM_ProbeCandidatesBiopsy, fcl, ProbeBroadPhase::Fcl);
BENCHMARK_CAPTURE(BM_ProbeCandidatesBiopsy, box, ProbeBroadPhase::Box);
BENCHMARK_CAPTURE(BM_ProbeCandidates, fcl, ProbeBroadPhase::Fcl);
BENCHMARK_CAPTURE(BM_ProbeCandidates, box, ProbeBroadPhase::Box);
BENCHMARK(BM_ProbeRestoreOnly);
BENCHMARK_CAPTURE(BM_ProbeStep, fcl, ProbeBroadPhase::Fcl);
BENCHMARK_CAPTURE(BM_ProbeStep, box, ProbeBroadPhase::Box);

}  // namespace
}  // namespace ps::bench
