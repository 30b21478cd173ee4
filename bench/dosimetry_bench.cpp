// Live implant dosimetry cost (engine/dosimetry/live_dosimetry.h), what the trainee window's dose
// worker does after a seed drops: 100 I-125 seeds (0.5 U) in a 36 cc ellipsoidal gland
// (46 x 36 x 42 mm) with a urethra and a rectum below it, on a 1 mm grid over the gland with a
// 10 mm margin (66 x 56 x 62 = 229 k voxels):
//  - BM_LiveDoseSeedDrop: the 100th seed drops (one seed pass), the masks are rebuilt on the
//    organs and the indices and DVH recomputed (issue 46: <= 20 ms per update, off the physics
//    thread);
//  - BM_LiveDoseAllMoved: every seed has moved more than the 0.25 mm tolerance (200 passes): the
//    worst case, a gland pushed as a whole;
//  - BM_DoseGridRebuild100: the grid alone from zero, 100 seed passes;
//  - BM_IsodoseSurface: what the worker adds after each update for the views: the grid's copy and
//    the prescription isodose surface at the views' 2 mm stride (marching tetrahedra,
//    engine/dosimetry/isodose.h);
//  - BM_IsodosePlanes: the 50/100/150/200 % lines of two 384 x 384 px TRUS planes through the
//    gland (the window's TRUS panel traces them on its UI thread from that copy).
#include <benchmark/benchmark.h>

#include <cmath>

#include "engine/dosimetry/isodose.h"
#include "engine/dosimetry/live_dosimetry.h"
#include "engine/dosimetry/plan.h"

namespace ps::bench {

namespace {

// latitude-longitude ellipsoid, outward faces
void ellipsoid(const Vec3& c, const Vec3& r, std::vector<Vec3>& v, std::vector<std::array<int, 3>>& f) {
  const int nu = 24, nv = 16;
  v.clear();
  f.clear();
  v.push_back(c + Vec3(0, 0, -r.z()));
  for (int j = 1; j < nv; ++j) {
    const double t = M_PI * j / nv;
    for (int i = 0; i < nu; ++i) {
      const double p = 2 * M_PI * i / nu;
      v.push_back(c + Vec3(r.x() * std::sin(t) * std::cos(p), r.y() * std::sin(t) * std::sin(p), -r.z() * std::cos(t)));
    }
  }
  v.push_back(c + Vec3(0, 0, r.z()));
  const int top = static_cast<int>(v.size()) - 1;
  auto id = [&](int j, int i) { return 1 + (j - 1) * nu + (i % nu); };
  for (int i = 0; i < nu; ++i) f.push_back({0, id(1, i + 1), id(1, i)});
  for (int j = 1; j < nv - 1; ++j)
    for (int i = 0; i < nu; ++i) {
      f.push_back({id(j, i), id(j, i + 1), id(j + 1, i + 1)});
      f.push_back({id(j, i), id(j + 1, i + 1), id(j + 1, i)});
    }
  for (int i = 0; i < nu; ++i) f.push_back({top, id(nv - 1, i), id(nv - 1, i + 1)});
}

struct Implant {
  std::vector<Vec3> pv, rv, urethra;
  std::vector<std::array<int, 3>> pf, rf;
  std::vector<dosimetry::Seed> seeds;
  dosimetry::GridSpec grid;
};

const Implant& implant() {
  static const Implant im = [] {
    Implant m;
    ellipsoid(Vec3(0, 0, 0), Vec3(23, 18, 21), m.pv, m.pf);
    ellipsoid(Vec3(0, -30, 0), Vec3(14, 10, 30), m.rv, m.rf);
    for (int k = -20; k <= 20; k += 2) m.urethra.emplace_back(0, 3, k);
    for (int x = -20; x <= 20 && m.seeds.size() < 100; x += 5)
      for (int y = -15; y <= 15 && m.seeds.size() < 100; y += 5)
        for (int z = -18; z <= 18 && m.seeds.size() < 100; z += 5) {
          const Vec3 p(x, y, z);
          if ((p.cwiseQuotient(Vec3(23, 18, 21))).norm() < 0.85 && std::hypot(p.x(), p.y() - 3) > 5)
            m.seeds.push_back({p, Vec3::UnitZ(), 0.5});
        }
    m.grid = dosimetry::gland_grid(m.pv);
    return m;
  }();
  return im;
}

const dosimetry::SourceModel& i125() { return *dosimetry::find_source_model("I125_6711"); }

void BM_LiveDoseSeedDrop(benchmark::State& st) {
  const Implant& m = implant();
  dosimetry::LiveDosimetry live(i125(), m.grid, m.pf, m.rf, 145.0);
  std::vector<dosimetry::Seed> before(m.seeds.begin(), m.seeds.end() - 1);
  live.update(before, m.pv, m.rv, m.urethra);
  for (auto _ : st) {
    live.update(m.seeds, m.pv, m.rv, m.urethra);  // the 100th drops
    st.PauseTiming();
    live.update(before, m.pv, m.rv, m.urethra);   // and is taken back, untimed
    st.ResumeTiming();
  }
  st.counters["seeds"] = static_cast<double>(m.seeds.size());
  st.counters["voxels"] = static_cast<double>(m.grid.size());
  st.counters["v100"] = live.update(m.seeds, m.pv, m.rv, m.urethra).indices.prostate_v100;
}
BENCHMARK(BM_LiveDoseSeedDrop)->Unit(benchmark::kMillisecond);

void BM_LiveDoseAllMoved(benchmark::State& st) {
  const Implant& m = implant();
  dosimetry::LiveDosimetry live(i125(), m.grid, m.pf, m.rf, 145.0);
  std::vector<dosimetry::Seed> moved = m.seeds;
  for (auto& s : moved) s.centre_mm += Vec3(0.5, 0, 0);
  live.update(m.seeds, m.pv, m.rv, m.urethra);
  bool flip = false;
  for (auto _ : st) {
    live.update(flip ? m.seeds : moved, m.pv, m.rv, m.urethra);
    flip = !flip;
  }
}
BENCHMARK(BM_LiveDoseAllMoved)->Unit(benchmark::kMillisecond);

void BM_DoseGridRebuild100(benchmark::State& st) {
  const Implant& m = implant();
  dosimetry::DoseAccumulator acc(i125(), m.grid);
  for (auto _ : st) acc.rebuild(m.seeds);
}
BENCHMARK(BM_DoseGridRebuild100)->Unit(benchmark::kMillisecond);

void BM_IsodoseSurface(benchmark::State& st) {
  const Implant& m = implant();
  dosimetry::LiveDosimetry live(i125(), m.grid, m.pf, m.rf, 145.0);
  live.update(m.seeds, m.pv, m.rv, m.urethra);
  size_t faces = 0;
  for (auto _ : st) {
    const auto field = live.field();
    const dosimetry::IsoSurface iso = dosimetry::isodose_surface(*field, 145.0, dosimetry::kViewSurfaceStride);
    faces = iso.faces.size();
    benchmark::DoNotOptimize(faces);
  }
  st.counters["triangles"] = static_cast<double>(faces);
}
BENCHMARK(BM_IsodoseSurface)->Unit(benchmark::kMillisecond);

void BM_IsodosePlanes(benchmark::State& st) {
  const Implant& m = implant();
  dosimetry::LiveDosimetry live(i125(), m.grid, m.pf, m.rf, 145.0);
  live.update(m.seeds, m.pv, m.rv, m.urethra);
  const auto field = live.field();
  // 60 x 60 mm planes of 384 px: transverse (z = 0) and sagittal (x = 0) through the gland
  dosimetry::PixelPlane tr, sg;
  tr.width = tr.height = sg.width = sg.height = 384;
  const double px = 60.0 / 384;
  tr.p00_mm = Vec3(-30, 30, 0);
  tr.dcol_mm = Vec3(px, 0, 0);
  tr.drow_mm = Vec3(0, -px, 0);
  sg.p00_mm = Vec3(0, 30, 30);
  sg.dcol_mm = Vec3(0, 0, -px);
  sg.drow_mm = Vec3(0, -px, 0);
  const std::vector<double> levels = {72.5, 145.0, 217.5, 290.0};
  std::vector<dosimetry::IsoSegment> a, b;
  for (auto _ : st) {
    dosimetry::plane_isodose(*field, tr, levels, 2, a);
    dosimetry::plane_isodose(*field, sg, levels, 2, b);
    benchmark::DoNotOptimize(a.data());
  }
  st.counters["segments"] = static_cast<double>(a.size() + b.size());
}
BENCHMARK(BM_IsodosePlanes)->Unit(benchmark::kMillisecond);

}  // namespace

}  // namespace ps::bench
