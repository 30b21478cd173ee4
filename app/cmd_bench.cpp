// `prostatesim bench [--quick] [--out DIR] [--json FILE]`: run time against error.
//  1. Real-time figures of the default scenes with their instruments active: each scene driven by
//     its trainee script (config/scripts/<scene>.yaml: probe pushed onto the gland, needle advanced
//     and fired, or inserted), lock-step, unpaced: simulated seconds per wall second, the tick's
//     median and 99th percentile in wall and thread CPU time, preempted ticks, particles;
//     and the substep time of the 1331-particle cube (the paper's "1300 particles").
//  2. Run time against error: a locally loaded block (a 1 N force on a 12 x 12 mm patch of the
//     top of a 48 mm cube, bottom fixed) for each model, spacing and substep count, its displacement
//     field compared at fixed interior sample points with a converged reference run (finest
//     spacing, a quarter of the stable substep). Pareto front and the shipped default (the
//     default anatomy's model and prostate spacing) are marked in DIR/runtime_vs_error.png.
//  3. Without --quick, also each validation case's error against its reference (analytic, phantom,
//     FEM) with its run time.
// A new model plugs in by its scenario key: --models paper,strain,<new> (any `model:` value).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <sstream>

#include "app/commands.h"
#include "app/frames/snapshot_dose.h"
#include "app/output_paths.h"
#include "app/plot/chart.h"
#include "app/progress.h"
#include "app/checks/validation.h"
#include "engine/io/png_write.h"
#include "engine/model/role.h"
#include "engine/realtime/scripted_run.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/material_models.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/util/atomic_file.h"
#include "engine/util/error.h"
#include "engine/util/thread_cpu_time.h"

namespace ps::app {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct BenchArgs {
  bool quick = false;
  std::string out = "out/bench", json, root;
  std::string models = "paper,strain,tet";
  std::string reference_model = "strain";
};

std::string find_root(const std::string& given) {
  namespace fs = std::filesystem;
  if (!given.empty()) return given;
  for (fs::path p = fs::current_path(); !p.empty(); p = p.parent_path()) {
    if (fs::exists(p / "config/biopsy.yaml")) return p.string();
    if (p == p.parent_path()) break;
  }
  throw InputError("", 0, "bench", "config/biopsy.yaml not found above the working directory (use --root)");
}

// --- 1. real time --------------------------------------------------------------------------------
struct Realtime {
  double factor = 0, p99_us = 0, median_us = 0, sim_s = 0;
  // the same ticks in this thread's CPU time [us]: the physics' own cost, without the time the
  // host gave the core to someone else in the middle of a tick (the wall time's tail on a shared
  // machine); and how many ticks lost more than 10 % of the period that way
  double p99_cpu_us = 0, median_cpu_us = 0;
  int64_t ticks = 0, preempted_ticks = 0;
  double period_us = 0;   // the scene's tick, the p99's bound [us]
  double factor_cpu = 0;  // simulated s per CPU s of this process: steadier on a shared machine
  int particles = 0, substeps = 0;
  std::vector<std::string> pipeline;
  bool faulted = false;
  int dose_updates = 0;     // with_dose: dose updates the worker finished during the run
  double dose_ms_median = 0.0, dose_ms_max = 0.0;  // their median and largest wall time [ms]
};

// The trainee window's dose worker, as the benchmark runs it (app/gui/dose_worker.h does the
// same with the window's snapshots): every kDoseEveryTicks the physics side hands over a
// snapshot (a 60 Hz UI at a 500 Hz tick), and a thread of its own brings the dose up to date
// from the newest one, so the physics pays only the copy and a core shared with the worker.
class BenchDoseWorker {
 public:
  static constexpr int kDoseEveryTicks = 8;
  explicit BenchDoseWorker(const Scene& sc) : dose_(sc), thread_([this] { run(); }) {}
  ~BenchDoseWorker() {
    {
      std::lock_guard<std::mutex> g(mu_);
      stop_ = true;
    }
    cv_.notify_one();
    thread_.join();
  }
  void post(const Snapshot& snap) {
    {
      std::lock_guard<std::mutex> g(mu_);
      next_ = snap;
      fresh_ = true;
    }
    cv_.notify_one();
  }
  // finished updates and their wall times [ms]; call after the destructor's join or while idle
  std::vector<double> times_ms() {
    std::lock_guard<std::mutex> g(mu_);
    return ms_;
  }

 private:
  void run() {
    Snapshot mine;
    for (;;) {
      {
        std::unique_lock<std::mutex> lk(mu_);
        cv_.wait(lk, [this] { return fresh_ || stop_; });
        if (stop_) return;
        std::swap(mine, next_);
        fresh_ = false;
      }
      const auto t0 = Clock::now();
      dose_.update(mine);
      const double ms = since(t0) * 1e3;
      std::lock_guard<std::mutex> g(mu_);
      ms_.push_back(ms);
    }
  }
  frames::SnapshotDose dose_;
  std::mutex mu_;
  std::condition_variable cv_;
  Snapshot next_;
  bool fresh_ = false, stop_ = false;
  std::vector<double> ms_;
  std::thread thread_;
};

// The scene driven by its trainee script (config/scripts/<scene>.yaml: the probe pushed onto the
// gland, the needle advanced and fired or inserted) in lock-step, as fast as it goes, for the
// script's whole length or `seconds` when shorter: the tick time of each tick, wall clock around
// the tick (commands applied, physics, nothing else).
Realtime realtime_of(const std::string& file, const std::string& script_file, double seconds, bool with_dose = false) {
  ScriptedRun sr(parse_scenario_file(file), script_file);
  std::unique_ptr<BenchDoseWorker> dose;
  if (with_dose) dose = std::make_unique<BenchDoseWorker>(sr.sc);
  const Model& m = *sr.sc.model;
  Realtime r;
  r.particles = m.particle_count();
  r.substeps = m.substeps;
  r.period_us = m.dt * 1e6;
  for (Stage s : sr.sc.sim->pipeline()) r.pipeline.push_back(stage_name(s));
  const int64_t ticks = std::max<int64_t>(1, std::min<int64_t>(sr.ticks(), std::llround(seconds / m.dt)));
  std::vector<double> us, cpu_us;
  us.reserve(ticks);
  cpu_us.reserve(ticks);
  const auto t0 = Clock::now();
  const std::clock_t c0 = std::clock();
  for (int64_t k = 0; k < ticks; ++k) {
    const int64_t c = thread_cpu_ns();
    const auto a = Clock::now();
    if (!sr.run.step()) { r.faulted = true; break; }
    if (dose && k % BenchDoseWorker::kDoseEveryTicks == 0) dose->post(sr.run.snapshot());
    us.push_back(since(a) * 1e6);
    cpu_us.push_back((thread_cpu_ns() - c) * 1e-3);
    if (us.back() - cpu_us.back() > 0.1 * r.period_us) ++r.preempted_ticks;
  }
  r.ticks = static_cast<int64_t>(us.size());
  const double wall = since(t0);
  if (dose) {
    std::vector<double> ms = dose->times_ms();
    dose.reset();
    r.dose_updates = static_cast<int>(ms.size());
    if (!ms.empty()) {
      std::sort(ms.begin(), ms.end());
      r.dose_ms_median = ms[ms.size() / 2];
      r.dose_ms_max = ms.back();
    }
  }
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  r.sim_s = sr.sc.sim->state().time;
  r.factor = r.sim_s / wall;
  r.factor_cpu = cpu > 0 ? r.sim_s / cpu : 0.0;
  if (!us.empty()) {
    // p99 and median of a sample, sorted in place
    auto p99_median = [](std::vector<double>& v, double& p99, double& median) {
      std::sort(v.begin(), v.end());
      p99 = v[std::min(v.size() - 1, static_cast<size_t>(0.99 * v.size()))];
      median = v[v.size() / 2];
    };
    p99_median(us, r.p99_us, r.median_us);
    p99_median(cpu_us, r.p99_cpu_us, r.median_cpu_us);
  }
  return r;
}

double step_us_cube(int points_per_side, int steps) {
  const int side = 6 * (points_per_side - 1);
  std::ostringstream y;
  y << "name: cube" << points_per_side << "\ntime: {dt_ms: 1, substeps: 1, duration_s: 1}\ngravity_m_s2: [0, 0, -9.81]\n"
    << "materials:\n  soft: {young_kpa: 10, density_kg_m3: 1000, damping_1_s: 20}\n"
    << "components:\n  - name: cube\n    material: soft\n    spacing_mm: 6\n    box: {min_mm: [0, 0, 0], max_mm: [" << side
    << ", " << side << ", " << side << "]}\n"
    << "constraints:\n  - fix: {component: cube, region: {box: {min_mm: [-1, -1, -1], max_mm: [1000, 1000, 0.5]}}}\n";
  auto model = compile_scenario(parse_scenario_text(y.str(), "bench_cube.yaml"));
  Simulation sim(model);
  const double h = model->dt / model->substeps;
  for (int i = 0; i < 20; ++i) sim.step(h);  // warm caches
  std::vector<double> rounds;
  for (int r = 0; r < 5; ++r) {
    const auto t0 = Clock::now();
    for (int i = 0; i < steps; ++i) sim.step(h);
    rounds.push_back(since(t0) * 1e6 / steps);
  }
  std::sort(rounds.begin(), rounds.end());
  return rounds[rounds.size() / 2];  // median of 5 rounds
}

// --- 2. run time against error ------------------------------------------------------------------
constexpr double kSide = 48.0;  // [mm]

std::string block_yaml(const std::string& model, double spacing_mm) {
  std::ostringstream y;
  y << "name: local_load_block\ntime: {dt_ms: 1, substeps: 1, duration_s: 1}\ngravity_m_s2: [0, 0, 0]\n"
    << "materials:\n  gel: {young_kpa: 10, density_kg_m3: 1000, damping_1_s: 40, model: " << model << "}\n"
    << "components:\n  - name: block\n    material: gel\n    spacing_mm: " << spacing_mm
    << "\n    box: {min_mm: [0, 0, 0], max_mm: [" << kSide << ", " << kSide << ", " << kSide << "]}\n"
    << "constraints:\n  - fix: {component: block, region: {box: {min_mm: [-1, -1, -1], max_mm: [100, 100, 0.5]}}}\n"
    << "  - force: {component: block, region: {box: {min_mm: [17.5, 17.5, " << kSide - 0.5 << "], max_mm: [30.5, 30.5, "
    << kSide + 0.5 << "]}}, total_n: [0, 0, -1], ramp_s: [0, 0.1]}\n";
  return y.str();
}

struct Field {  // displacement [m] at the fixed sample points
  std::vector<Vec3> u;
};

std::vector<Vec3> sample_points() {
  std::vector<Vec3> p;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 6; ++k) p.push_back(Vec3(4 + 8 * i, 4 + 8 * j, 4 + 8 * k) * 1e-3);
  return p;
}

// Trilinear interpolation of the lattice displacement at the sample points (box lattices are
// exact grids: step = side / round(side / h)).
Field sample(const Model& m, const State& s) {
  // grid resolution from the particle count of a full lattice: (cells + 1)^3
  const int pts = static_cast<int>(std::lround(std::cbrt(m.particle_count())));
  const int cells = pts - 1;
  const double step = kSide * 1e-3 / cells;
  std::vector<Vec3> grid(static_cast<size_t>(pts) * pts * pts, Vec3::Zero());
  for (int p = 0; p < m.particle_count(); ++p) {
    const Vec3 g = m.rest_pos[p] / step;
    const int i = static_cast<int>(std::lround(g.x())), j = static_cast<int>(std::lround(g.y())), k = static_cast<int>(std::lround(g.z()));
    grid[(static_cast<size_t>(k) * pts + j) * pts + i] = s.x[p] - m.rest_pos[p];
  }
  Field f;
  for (const Vec3& q : sample_points()) {
    const Vec3 g = q / step;
    const int i = std::min(cells - 1, static_cast<int>(g.x())), j = std::min(cells - 1, static_cast<int>(g.y())),
              k = std::min(cells - 1, static_cast<int>(g.z()));
    const double fx = g.x() - i, fy = g.y() - j, fz = g.z() - k;
    Vec3 u = Vec3::Zero();
    for (int c = 0; c < 8; ++c) {
      const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
      const double w = (di ? fx : 1 - fx) * (dj ? fy : 1 - fy) * (dk ? fz : 1 - fz);
      u += w * grid[(static_cast<size_t>(k + dk) * pts + (j + dj)) * pts + (i + di)];
    }
    f.u.push_back(u);
  }
  return f;
}

struct Config {
  std::string scene = "local_load_block", model;
  double spacing_mm = 0, substep_ms = 0;
  int substeps = 0;
  std::string precision = "double";
  double wall_per_sim = 0, err_rms = NAN, err_max = NAN;
  bool pareto = false, shipped = false, faulted = false;
  std::string note;
};

constexpr double kBlockRun = 0.5;  // simulated time: load ramp 0.1 s, then settling [s]

Field run_block(Config& c, int substep_factor) {
  auto model = compile_scenario(parse_scenario_text(block_yaml(c.model, c.spacing_mm), "bench_block.yaml"));
  Simulation sim(model);
  c.substeps = model->substeps * substep_factor;
  c.substep_ms = model->dt / c.substeps * 1e3;
  const int ticks = static_cast<int>(std::lround(kBlockRun / model->dt));
  const auto t0 = Clock::now();
  for (int k = 0; k < ticks && !c.faulted; ++k)
    for (int i = 0; i < c.substeps; ++i)
      if (!sim.step(model->dt / c.substeps)) { c.faulted = true; break; }
  c.wall_per_sim = since(t0) / kBlockRun;
  return sample(*model, sim.state());
}

void mark_pareto(std::vector<Config>& cs) {
  for (auto& a : cs) {
    if (!std::isfinite(a.err_rms)) continue;
    a.pareto = true;
    for (const auto& b : cs)
      if (&a != &b && std::isfinite(b.err_rms) && b.wall_per_sim <= a.wall_per_sim && b.err_rms <= a.err_rms &&
          (b.wall_per_sim < a.wall_per_sim || b.err_rms < a.err_rms))
        a.pareto = false;
  }
}

void write_chart(const std::string& path, const std::vector<Config>& cs, const std::vector<std::string>& models) {
  plot::Chart ch;
  ch.title = "Run time against error: local load on a 48 mm block";
  ch.x = {"wall time per simulated second [s]", true};
  ch.y = {"displacement RMS error vs converged reference [% of max]", true};
  const plot::Marker marks[] = {plot::Marker::Circle, plot::Marker::Triangle, plot::Marker::Square, plot::Marker::Diamond};
  for (size_t mi = 0; mi < models.size(); ++mi)
    for (int fine = 0; fine < 2; ++fine) {
      plot::Series s;
      s.label = "model " + models[mi] + (fine ? ", substep / 2" : ", stable substep");
      s.color = plot::palette(static_cast<int>(mi));
      s.marker = marks[(mi * 2 + fine) % 4];
      s.dashed = fine;
      for (const auto& c : cs)
        if (c.model == models[mi] && (c.substeps > 0) && std::isfinite(c.err_rms) && ((c.note == "half") == (fine == 1))) {
          s.x.push_back(c.wall_per_sim);
          s.y.push_back(100 * c.err_rms);
        }
      if (!s.x.empty()) ch.series.push_back(s);
    }
  plot::Series front;
  front.label = "Pareto front";
  front.color = {40, 40, 40};
  front.line_width = 1.5;
  std::vector<const Config*> p;
  for (const auto& c : cs) if (c.pareto) p.push_back(&c);
  std::sort(p.begin(), p.end(), [](auto* a, auto* b) { return a->wall_per_sim < b->wall_per_sim; });
  for (auto* c : p) { front.x.push_back(c->wall_per_sim); front.y.push_back(100 * c->err_rms); }
  if (!front.x.empty()) ch.series.push_back(front);
  plot::Series ship;
  ship.label = "shipped default";
  ship.line = false;
  ship.marker = plot::Marker::Star;
  ship.marker_size = 22;
  ship.color = {230, 160, 0};
  for (const auto& c : cs)
    if (c.shipped && std::isfinite(c.err_rms)) { ship.x.push_back(c.wall_per_sim); ship.y.push_back(100 * c.err_rms); }
  if (!ship.x.empty()) ch.series.push_back(ship);
  const plot::Canvas cv = plot::render(ch, 1100, 720);
  write_png_atomic(path, cv.width(), cv.height(), 3, cv.pixels().data());
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string t; std::getline(ss, t, ',');) if (!t.empty()) out.push_back(t);
  return out;
}

}  // namespace

void add_bench_command(CLI::App& app, Runner& run) {
  auto a = std::make_shared<BenchArgs>();
  CLI::App* sub = app.add_subcommand("bench", "run time against error: real-time factors, runtime_vs_error.csv/.png");
  sub->add_flag("--quick", a->quick, "fewer configurations and shorter runs (under 2 minutes)");
  sub->add_option("--out", a->out, "folder for runtime_vs_error.csv and .png (created)")->capture_default_str();
  sub->add_option("--json", a->json, "also write the headline figures as JSON");
  sub->add_option("--root", a->root, "repository root holding config/ (default: found from the working directory)");
  sub->add_option("--models", a->models, "comma-separated `model:` values to compare")->capture_default_str();
  sub->add_option("--reference-model", a->reference_model, "model of the converged reference run")->capture_default_str();
  sub->callback([a, &run] {
    run = [a]() -> int {
      const std::string root = find_root(a->root);
      // the outputs before minutes of runs (app/output_paths.h)
      prepare_output_dir(a->out, "--out");
      prepare_output_file(a->json, "--json");
      const std::vector<std::string> models = split(a->models);
      if (models.empty()) throw InputError("", 0, "--models", "give at least one model");
      // Check every model name against the parser before running anything.
      for (const auto& m : models) parse_scenario_text(block_yaml(m, 12), "--models");
      const std::vector<double> spacings = a->quick ? std::vector<double>{12, 8, 6} : std::vector<double>{12, 8, 6, 4.8, 4};
      const double ref_spacing = a->quick ? 4.0 : 3.0;
      const std::vector<int> factors = a->quick ? std::vector<int>{1} : std::vector<int>{1, 2};
      // simulated time per scene for the real-time figures: the whole script (biopsy 3 s,
      // brachytherapy 6.5 s), at most 10 s. A p99 needs thousands of ticks: over 50 it would be the
      // slowest one, the first tick's setup included.
      const double rt_seconds = 10.0;
      const int work = 3 + 1 + static_cast<int>(models.size() * spacings.size() * factors.size());
      Progress progress("bench", work);
      int done = 0;
      nlohmann::json j;

      // 1. real time
      for (const char* scene : {"biopsy", "brachytherapy"}) {
        progress.update(done++, std::string(scene) + " real time");
        const Realtime r =
            realtime_of(root + "/config/" + scene + ".yaml", root + "/config/scripts/" + scene + ".yaml", rt_seconds);
        j[std::string("realtime_factor_") + scene] = r.factor;
        j[std::string("realtime_factor_cpu_") + scene] = r.factor_cpu;
        j[std::string("tick_p99_us_") + scene] = r.p99_us;
        j[std::string("tick_period_us_") + scene] = r.period_us;
        j[std::string("tick_median_us_") + scene] = r.median_us;
        j[std::string("tick_p99_cpu_us_") + scene] = r.p99_cpu_us;
        j[std::string("tick_median_cpu_us_") + scene] = r.median_cpu_us;
        j[std::string("ticks_") + scene] = r.ticks;
        j[std::string("ticks_preempted_") + scene] = r.preempted_ticks;
        j[std::string("particles_") + scene] = r.particles;
        j[std::string("substeps_") + scene] = r.substeps;
        j[std::string("pipeline_") + scene] = r.pipeline;
        j[std::string("simulated_s_") + scene] = r.sim_s;
        if (r.faulted) j[std::string("faulted_") + scene] = true;
      }
      {  // brachytherapy with the dose worker the window runs beside it (issue 46)
        progress.update(done, "brachytherapy real time, dose updates on");
        const Realtime r = realtime_of(root + "/config/brachytherapy.yaml", root + "/config/scripts/brachytherapy.yaml", rt_seconds, true);
        j["realtime_factor_brachytherapy_dose"] = r.factor;
        j["tick_median_us_brachytherapy_dose"] = r.median_us;
        j["tick_p99_us_brachytherapy_dose"] = r.p99_us;
        j["dose_updates_brachytherapy_dose"] = r.dose_updates;
        j["dose_update_ms_median_brachytherapy_dose"] = r.dose_ms_median;
        j["dose_update_ms_max_brachytherapy_dose"] = r.dose_ms_max;
        if (r.faulted) j["faulted_brachytherapy_dose"] = true;
      }
      progress.update(done++, "cube 1331 substep");
      j["step_us_1300"] = step_us_cube(11, a->quick ? 200 : 1000);

      // 2. run time against error
      progress.update(done++, "reference run");
      Config ref;
      ref.model = a->reference_model;
      ref.spacing_mm = ref_spacing;
      const Field fr = run_block(ref, 4);
      double umax = 0;
      for (const Vec3& u : fr.u) umax = std::max(umax, u.norm());
      // Shipped default: the default anatomy's prostate material and spacing.
      const ScenarioSpec biopsy = parse_scenario_file(root + "/config/biopsy.yaml");
      std::string ship_model = "paper";
      double ship_spacing = 6;
      for (const auto& c : biopsy.components)
        if (resolve_role(c.role, c.name, c.kind == "rigid") == Role::Prostate) {
          ship_spacing = c.spacing * 1e3;
          for (const auto& m : biopsy.materials)
            if (m.name == c.material) ship_model = material_model(m.model).name;
        }
      std::vector<Config> cs;
      for (const auto& m : models)
        for (double h : spacings)
          for (int f : factors) {
            progress.update(done++, m + " " + std::to_string(h).substr(0, 4) + " mm");
            Config c;
            c.model = m;
            c.spacing_mm = h;
            c.note = f == 1 ? "stable" : "half";
            const Field fc = run_block(c, f);
            double se = 0, mx = 0;
            for (size_t i = 0; i < fc.u.size(); ++i) {
              const double e = (fc.u[i] - fr.u[i]).norm();
              se += e * e;
              mx = std::max(mx, e);
            }
            if (!c.faulted && umax > 0) {
              c.err_rms = std::sqrt(se / fc.u.size()) / umax;
              c.err_max = mx / umax;
            }
            c.shipped = f == 1 && m == ship_model && std::abs(h - ship_spacing) < 1e-9;
            cs.push_back(c);
          }
      mark_pareto(cs);
      progress.clear();

      std::ostringstream csv;
      csv << "scene,model,spacing_mm,substeps_per_tick,substep_ms,precision,wall_s_per_sim_s,err_rms_rel,err_max_rel,pareto,shipped,"
             "reference\n";
      for (const auto& c : cs)
        csv << c.scene << ',' << c.model << ',' << c.spacing_mm << ',' << c.substeps << ',' << c.substep_ms << ',' << c.precision << ','
            << c.wall_per_sim << ',' << c.err_rms << ',' << c.err_max << ',' << c.pareto << ',' << c.shipped << ",converged run "
            << ref.model << ' ' << ref.spacing_mm << " mm substep " << ref.substep_ms << " ms\n";
      // 3. validation cases against their own references (full run only: minutes)
      if (!a->quick) {
        for (const auto& vc : validation_cases()) {
          const auto t0 = Clock::now();
          std::vector<ValidationRow> rows;
          try {
            rows = vc.run(root, root + "/../shared/data");
          } catch (const std::exception& e) {
            csv << "validation:" << vc.name << ",,,,,double,,,,,,failed: " << e.what() << "\n";
            continue;
          }
          const double wall = since(t0);
          for (const auto& r : rows)
            if (std::isfinite(r.reference) && r.reference != 0)
              csv << "validation:" << vc.name << ",shipped,,,,double," << wall << ',' << std::abs(r.value - r.reference) / std::abs(r.reference)
                  << ",," << 0 << ',' << 1 << ",\"" << r.metric << "\"\n";
        }
      }
      write_file_atomic(a->out + "/runtime_vs_error.csv", csv.str());
      write_chart(a->out + "/runtime_vs_error.png", cs, models);

      j["reference"] = {{"model", ref.model}, {"spacing_mm", ref.spacing_mm}, {"substep_ms", ref.substep_ms},
                        {"max_displacement_mm", umax * 1e3}};
      j["configs"] = nlohmann::json::array();
      for (const auto& c : cs)
        j["configs"].push_back({{"model", c.model}, {"spacing_mm", c.spacing_mm}, {"substeps", c.substeps},
                                {"wall_s_per_sim_s", c.wall_per_sim}, {"err_rms_rel", std::isfinite(c.err_rms) ? nlohmann::json(c.err_rms) : nlohmann::json()},
                                {"pareto", c.pareto}, {"shipped", c.shipped}});
      if (!a->json.empty()) write_file_atomic(a->json, j.dump(2) + "\n");
      for (const std::string scene : {"biopsy", "brachytherapy"})
        std::printf("%-14s realtime factor %.3g, tick median %.0f / p99 %.0f us wall, %.0f / %.0f us CPU (period %.0f us), "
                    "%lld of %lld ticks preempted\n",
                    scene.c_str(), j["realtime_factor_" + scene].get<double>(), j["tick_median_us_" + scene].get<double>(),
                    j["tick_p99_us_" + scene].get<double>(), j["tick_median_cpu_us_" + scene].get<double>(),
                    j["tick_p99_cpu_us_" + scene].get<double>(), j["tick_period_us_" + scene].get<double>(),
                    static_cast<long long>(j["ticks_preempted_" + scene].get<int64_t>()),
                    static_cast<long long>(j["ticks_" + scene].get<int64_t>()));
      std::printf("brachytherapy, dose updates on: realtime factor %.3g, tick median %.0f / p99 %.0f us wall; %d dose updates, "
                  "median %.1f ms, max %.1f ms (worker thread)\n",
                  j["realtime_factor_brachytherapy_dose"].get<double>(), j["tick_median_us_brachytherapy_dose"].get<double>(),
                  j["tick_p99_us_brachytherapy_dose"].get<double>(), j["dose_updates_brachytherapy_dose"].get<int>(),
                  j["dose_update_ms_median_brachytherapy_dose"].get<double>(), j["dose_update_ms_max_brachytherapy_dose"].get<double>());
      std::printf("step_us_1300 %.1f  particles_biopsy %d\n", j["step_us_1300"].get<double>(), j["particles_biopsy"].get<int>());
      std::printf("%-8s %8s %9s %14s %10s %s\n", "model", "h_mm", "substeps", "wall_s/sim_s", "err_rms_%", "");
      for (const auto& c : cs)
        std::printf("%-8s %8.3g %9d %14.4g %10.3g %s%s\n", c.model.c_str(), c.spacing_mm, c.substeps, c.wall_per_sim, 100 * c.err_rms,
                    c.pareto ? "pareto " : "", c.shipped ? "shipped" : "");
      std::printf("wrote %s/runtime_vs_error.{csv,png}\n", a->out.c_str());
      return kExitOk;
    };
  });
}

}  // namespace ps::app
