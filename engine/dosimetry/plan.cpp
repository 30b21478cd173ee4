#include "engine/dosimetry/plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "engine/dosimetry/dose_grid.h"
#include "engine/dosimetry/organ_mask.h"
#include "engine/dosimetry/plan_annealing.h"
#include "engine/dosimetry/template_grid.h"
#include "engine/util/error.h"

namespace ps::dosimetry {

namespace {

constexpr uint8_t kBone = 8;
constexpr int kAnnealRounds = 8;            // annealing rounds at most (weights raised between them)
constexpr uint64_t kAnnealSeed = 46;        // the random stream of the first round (round r: 46 + r)

Vec3 lo_of(const std::vector<Vec3>& v) {
  Vec3 lo = v.front();
  for (const Vec3& p : v) lo = lo.cwiseMin(p);
  return lo;
}
Vec3 hi_of(const std::vector<Vec3>& v) {
  Vec3 hi = v.front();
  for (const Vec3& p : v) hi = hi.cwiseMax(p);
  return hi;
}

// voxel holding p, -1 outside the grid
long voxel_of(const GridSpec& g, const Vec3& p) {
  const Vec3 q = (p - g.origin_mm) / g.spacing_mm;
  const long i = std::lround(q.x()), j = std::lround(q.y()), k = std::lround(q.z());
  if (i < 0 || j < 0 || k < 0 || i >= g.nx || j >= g.ny || k >= g.nz) return -1;
  return static_cast<long>(g.index(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k)));
}

double distance_to_line(const std::vector<Vec3>& line, const Vec3& p) {
  double best = INFINITY;
  for (size_t s = 0; s + 1 < line.size(); ++s) {
    const Vec3 ab = line[s + 1] - line[s];
    const double t = std::clamp((p - line[s]).dot(ab) / std::max(ab.squaredNorm(), 1e-12), 0.0, 1.0);
    best = std::min(best, (p - (line[s] + t * ab)).norm());
  }
  if (line.size() == 1) best = (p - line[0]).norm();
  return best;
}

struct Candidate {
  size_t hole;
  double depth_mm;
  Vec3 at_mm;
};

DosimetryIndices evaluate(const PlanInput& in, const GridSpec& g, const std::vector<uint8_t>& mask,
                          const std::vector<Seed>& seeds) {
  DoseAccumulator acc(*in.model, g);
  acc.rebuild(seeds);
  return dosimetry_indices(g, acc.dose_gy(), mask, in.prescription_gy, static_cast<int>(seeds.size()));
}

}  // namespace

bool Plan::feasible() const {
  for (const ConstraintCheck& c : checks)
    if (!c.pass) return false;
  return !checks.empty();
}

std::vector<Seed> Plan::seed_list(double strength_u) const {
  std::vector<Seed> s;
  for (const PlannedNeedle& n : needles)
    for (double d : n.seed_depths_mm) s.push_back(Seed{n.entry_mm + d * n.direction, n.direction, strength_u});
  return s;
}

std::vector<ConstraintCheck> check_constraints(const DosimetryIndices& x) {
  const double rx = x.prescription_gy;
  const char* abs = "ABS consensus (Davis et al., Brachytherapy 11:6, 2012); AAPM TG-137 (Nath et al., Med Phys 36:5310, 2009)";
  const char* d90hi = "TG-137: D90 kept near 100-120 % of the prescription (higher D90 raises urethral and rectal toxicity)";
  const char* ure = "GEC/ESTRO-EAU (Salembier et al., Radiother Oncol 83:3, 2007); TG-137";
  const char* rect = "GEC/ESTRO-EAU (Salembier et al., Radiother Oncol 83:3, 2007): rectum D2cc < prescription";
  return {
      {"prostate V100 >= 95 %", 100.0 * x.prostate_v100, 95.0, "%", x.prostate_v100 >= 0.95, abs},
      {"prostate D90 >= 100 % of prescription", 100.0 * x.prostate_d90_gy / rx, 100.0, "%", x.prostate_d90_gy >= rx, abs},
      {"prostate D90 <= 120 % of prescription", 100.0 * x.prostate_d90_gy / rx, 120.0, "%", x.prostate_d90_gy <= 1.2 * rx, d90hi},
      {"urethra D10 < 150 % of prescription", 100.0 * x.urethra_d10_gy / rx, 150.0, "%", x.urethra_d10_gy < 1.5 * rx, ure},
      {"rectum D2cc < prescription", x.rectum_d2cc_gy, rx, "Gy", x.rectum_d2cc_gy < rx, rect},
  };
}

GridSpec gland_grid(const std::vector<Vec3>& prostate_mm, double margin_mm, double spacing_mm) {
  return grid_around(lo_of(prostate_mm), hi_of(prostate_mm), margin_mm, spacing_mm);
}

std::vector<uint8_t> structure_mask(const GridSpec& g, const std::vector<Vec3>& pv, const std::vector<std::array<int, 3>>& pf,
                                    const std::vector<Vec3>& rv, const std::vector<std::array<int, 3>>& rf,
                                    const std::vector<Vec3>& urethra, double urethra_radius_mm) {
  std::vector<uint8_t> m(g.size(), 0);
  fill_closed_surface(g, pv, pf, kProstate, m);
  if (!rv.empty()) {
    fill_closed_surface(g, rv, rf, kRectum, m);
    clear_where(m, kRectum, kProstate);
  }
  if (urethra.size() >= 2) fill_tube(g, urethra, urethra_radius_mm, kUrethra, m);
  return m;
}

Plan optimise_plan(const PlanInput& in) {
  if (!in.model) throw InputError("", 0, "isotope", "no seed model");
  if (in.prostate_mm.empty()) throw InputError("", 0, "prostate", "the scenario has no prostate surface to plan on");
  const double rx = in.prescription_gy;
  // planning grid (2 mm) and final grid (1 mm)
  const GridSpec pg = gland_grid(in.prostate_mm, 10.0, 2.0);
  const GridSpec fg = gland_grid(in.prostate_mm, 10.0, 1.0);
  const std::vector<uint8_t> pm = structure_mask(pg, in.prostate_mm, in.prostate_faces, in.rectum_mm, in.rectum_faces,
                                           in.urethra_mm, in.urethra_radius_mm);
  const std::vector<uint8_t> fm = structure_mask(fg, in.prostate_mm, in.prostate_faces, in.rectum_mm, in.rectum_faces,
                                                 in.urethra_mm, in.urethra_radius_mm);
  // a 1 mm mask with the bone for the line checks
  std::vector<uint8_t> lm = fm;
  if (!in.bone_mm.empty()) fill_closed_surface(fg, in.bone_mm, in.bone_faces, kBone, lm);

  // candidates
  std::vector<Candidate> cands;
  for (size_t h = 0; h < in.holes.size(); ++h) {
    const PlanHole& hole = in.holes[h];
    bool blocked = false;
    for (double d = 0.0; d < 200.0 && !blocked; d += 0.5) {
      const Vec3 p = hole.entry_mm + d * hole.direction;
      const long v = voxel_of(fg, p);
      if (v < 0) continue;
      if (lm[static_cast<size_t>(v)] & (kRectum | kBone)) { blocked = true; break; }
      if (std::fmod(d + 1e-9, in.step_mm) > 1e-6) continue;
      if (!(lm[static_cast<size_t>(v)] & kProstate)) continue;
      if (!in.urethra_mm.empty() && distance_to_line(in.urethra_mm, p) < in.min_urethra_mm) continue;
      cands.push_back(Candidate{h, d, p});
    }
  }
  if (cands.empty())
    throw InputError("", 0, "holes", "no template line reaches the gland (is the template in front of the prostate?)");

  // structure voxels of the planning grid and each candidate's dose to them
  PlanningMatrix M;
  std::vector<size_t> vox;
  for (size_t i = 0; i < pm.size(); ++i)
    if (pm[i]) {
      vox.push_back(i);
      M.kind.push_back(pm[i]);
    }
  const DoseKernel kernel(*in.model);
  M.candidates = cands.size();
  M.voxels = vox.size();
  M.dose_gy.resize(M.candidates * M.voxels);
  for (size_t c = 0; c < M.candidates; ++c) {
    const PlanHole& hole = in.holes[cands[c].hole];
    M.hole.push_back(static_cast<int>(cands[c].hole));
    M.col.push_back(hole.col);
    M.row.push_back(hole.row);
    M.step.push_back(static_cast<int>(std::lround(cands[c].depth_mm / in.step_mm)));
    const Vec3 a = hole.direction;
    for (size_t q = 0; q < M.voxels; ++q) {
      const size_t i = vox[q];
      const int x = static_cast<int>(i % pg.nx), y = static_cast<int>((i / pg.nx) % pg.ny), z = static_cast<int>(i / (pg.nx * pg.ny));
      const Vec3 d = pg.centre_mm(x, y, z) - cands[c].at_mm;
      const double along = d.dot(a);
      const double away = std::sqrt(std::max(0.0, d.squaredNorm() - along * along));
      M.dose_gy[c * M.voxels + q] = static_cast<float>(in.strength_u * kernel.gy_per_u(std::abs(along), away));
    }
  }

  auto plan_of = [&](const std::vector<char>& loaded) {
    Plan p;
    // needles from the loaded candidates, in hole order, seeds deepest first
    std::map<size_t, std::vector<double>> by_hole;
    for (size_t c = 0; c < cands.size(); ++c)
      if (loaded[c]) by_hole[cands[c].hole].push_back(cands[c].depth_mm);
    for (auto& [h, depths] : by_hole) {
      std::sort(depths.begin(), depths.end(), std::greater<double>());
      const PlanHole& hole = in.holes[h];
      p.needles.push_back({hole.col, hole.row, template_hole_label(hole.col, hole.row), hole.entry_mm, hole.direction, depths});
      p.seeds += static_cast<int>(depths.size());
    }
    p.predicted = evaluate(in, fg, fm, p.seed_list(in.strength_u));
    p.checks = check_constraints(p.predicted);
    return p;
  };
  // how far a plan is from its constraints (0: feasible)
  auto shortfall = [](const Plan& p) {
    double s = 0.0;
    for (const ConstraintCheck& c : p.checks)
      if (!c.pass) s += std::abs(c.value - c.limit) / std::max(1e-9, std::abs(c.limit)) + 1e-3;
    return s;
  };

  // annealing rounds: each starts from the last loading; the weight of each constraint the last
  // plan missed (on the 1 mm grid) is raised before the next
  AnnealWeights w;
  std::vector<char> loaded;
  Plan best;
  double best_short = INFINITY;
  const long iterations = std::max<long>(20000, 150 * static_cast<long>(M.candidates));
  for (int round = 0; round < kAnnealRounds; ++round) {
    const AnnealResult a = anneal_loading(M, rx, w, loaded, kAnnealSeed + static_cast<uint64_t>(round), iterations);
    loaded = a.loaded;
    Plan p = plan_of(loaded);
    p.rounds = round + 1;
    p.cost = a.cost;
    const double sf = shortfall(p);
    if (sf < best_short) {
      best_short = sf;
      best = p;
    }
    if (p.feasible()) break;
    const DosimetryIndices& x = p.predicted;
    if (x.prostate_v100 < 0.95 || x.prostate_d90_gy < rx) w.under *= 1.6;
    if (x.prostate_d90_gy > 1.2 * rx) w.over *= 2.0;
    if (x.urethra_d10_gy >= 1.5 * rx) w.urethra *= 2.0;
    if (x.rectum_d2cc_gy >= rx) w.rectum *= 2.0;
  }
  return best;
}

std::string plan_yaml(const Plan& p, const PlanInput& in, const std::string& scenario) {
  auto f = [](double v, int digits = 2) {
    char b[64];
    std::snprintf(b, sizeof b, "%.*f", digits, v);
    return std::string(b);
  };
  const DosimetryIndices& x = p.predicted;
  std::string s;
  s += "# Permanent seed implant plan (prostatesim plan): template holes, needle depths and seed\n";
  s += "# positions along each needle from where it leaves the template [mm], deepest first.\n";
  s += "# Loading: loose seeds with spacers in a preloaded 18 G needle, deposited one at a time as\n";
  s += "# the needle is withdrawn with the stylet held (docs/dosimetry.md).\n";
  s += "plan:\n";
  s += "  scenario: " + scenario + "\n";
  s += "  isotope: " + in.model->name + "\n";
  s += "  prescription_gy: " + f(in.prescription_gy, 1) + "\n";
  s += "  strength_u: " + f(in.strength_u, 3) + "\n";
  s += "  seed_step_mm: " + f(in.step_mm, 1) + "\n";
  s += "  seeds: " + std::to_string(p.seeds) + "\n";
  s += "  optimiser: simulated annealing (engine/dosimetry/plan_annealing.h), " + std::to_string(p.rounds) + " round(s)\n";
  s += "  needles:\n";
  for (const PlannedNeedle& n : p.needles) {
    std::string seeds;
    for (double d : n.seed_depths_mm) seeds += (seeds.empty() ? "" : ", ") + f(d, 1);
    s += "    - {hole: " + n.hole + ", col: " + std::to_string(n.col) + ", row: " + std::to_string(n.row) +
         ", entry_mm: [" + f(n.entry_mm.x()) + ", " + f(n.entry_mm.y()) + ", " + f(n.entry_mm.z()) + "], direction: [" +
         f(n.direction.x(), 4) + ", " + f(n.direction.y(), 4) + ", " + f(n.direction.z(), 4) + "], depth_mm: " +
         f(n.seed_depths_mm.front(), 1) + ", seeds_mm: [" + seeds + "]}\n";
  }
  s += "  predicted:\n";
  s += "    prostate_cc: " + f(x.prostate_cc, 1) + "\n";
  s += "    prostate_d90_gy: " + f(x.prostate_d90_gy, 1) + "\n";
  s += "    prostate_v100: " + f(x.prostate_v100, 4) + "\n";
  s += "    prostate_v150: " + f(x.prostate_v150, 4) + "\n";
  s += "    prostate_v200: " + f(x.prostate_v200, 4) + "\n";
  s += "    urethra_d10_gy: " + f(x.urethra_d10_gy, 1) + "\n";
  s += "    urethra_d30_gy: " + f(x.urethra_d30_gy, 1) + "\n";
  s += "    rectum_d2cc_gy: " + f(x.rectum_d2cc_gy, 1) + "\n";
  s += "    rectum_v100_cc: " + f(x.rectum_v100_cc, 3) + "\n";
  s += "  constraints:\n";
  for (const ConstraintCheck& c : p.checks)
    s += "    - {name: \"" + c.name + "\", value: " + f(c.value, 1) + ", limit: " + f(c.limit, 1) + ", unit: \"" + c.unit +
         "\", pass: " + (c.pass ? "true" : "false") + ", source: \"" + c.source + "\"}\n";
  return s;
}

}  // namespace ps::dosimetry
