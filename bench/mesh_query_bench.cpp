// MeshQuery speed (engine/mesh/mesh_query.h): inside() and distance() at 100k points spread
// uniformly over 1.5x the mesh's bounding box, on a round sphere of 20 480 triangles (the worst
// case for distance: deep inside, every patch is nearly equidistant) and on the measured prostate
// phantom (8084 triangles, ../shared/data/prostate_phantom/prostate.stl; skipped when absent).
// One iteration is 100k queries.
//   prostatesim_bench --benchmark_filter=BM_MeshQuery --benchmark_repetitions=3
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <vector>

#include "engine/anatomy/shapes.h"
#include "engine/mesh/mesh_import.h"
#include "engine/mesh/mesh_query.h"
#include "tests/engine/mesh/query_points.h"

namespace ps {
namespace {

TriMesh query_mesh(int which) {
  if (which == 0) {
    TriMesh m = anatomy::icosphere(5);
    for (Vec3& v : m.vertices) v *= 0.025;  // [m]
    return m;
  }
  MeshImportOptions opt;
  opt.units = "mm";
  return import_mesh(std::string(PROSTATESIM_SOURCE_DIR) + "/../shared/data/prostate_phantom/prostate.stl", opt);
}

// range(0): 0 the sphere, 1 the phantom; range(1): 0 inside(), 1 distance()
void BM_MeshQuery(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  if (which == 1 && !std::filesystem::exists(std::string(PROSTATESIM_SOURCE_DIR) + "/../shared/data/prostate_phantom/prostate.stl")) {
    state.SkipWithError("../shared/data/prostate_phantom/prostate.stl not found");
    return;
  }
  const TriMesh m = query_mesh(which);
  const MeshQuery q(m);
  const std::vector<Vec3> pts = test::query_points(m);
  const bool distance = state.range(1) != 0;
  for (auto _ : state) {
    double sum = 0.0;
    for (const Vec3& p : pts) sum += distance ? q.distance(p) : static_cast<double>(q.inside(p));
    benchmark::DoNotOptimize(sum);
  }
  state.SetLabel(std::string(which == 0 ? "sphere" : "phantom") + (distance ? " distance" : " inside"));
  state.counters["triangles"] = static_cast<double>(q.num_faces());
}
BENCHMARK(BM_MeshQuery)->Args({0, 0})->Args({0, 1})->Args({1, 0})->Args({1, 1})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ps
