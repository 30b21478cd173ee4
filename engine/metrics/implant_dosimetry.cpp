#include "engine/metrics/implant_dosimetry.h"

#include "engine/dosimetry/organ_mask.h"
#include "engine/tools/probe/probe.h"
#include "engine/util/error.h"

namespace ps {

namespace {

std::vector<Vec3> to_mm(const std::vector<Vec3>& m) {
  std::vector<Vec3> out;
  out.reserve(m.size());
  for (const Vec3& p : m) out.push_back(1e3 * p);
  return out;
}

const dosimetry::SourceModel& model_of(const std::string& isotope) {
  const dosimetry::SourceModel* s = dosimetry::find_source_model(isotope);
  if (!s) throw InputError("", 0, "isotope", "unknown seed model '" + isotope + "' (known: " + dosimetry::source_model_names() + ")");
  return *s;
}

}  // namespace

void organ_surface_mm(const Model& m, int c, const std::vector<Vec3>& x, std::vector<Vec3>& v,
                      std::vector<std::array<int, 3>>& f) {
  v.clear();
  f.clear();
  if (c < 0 || m.components[static_cast<size_t>(c)].surface < 0) return;
  const Surface& s = m.surfaces[static_cast<size_t>(m.components[static_cast<size_t>(c)].surface)];
  v.reserve(s.vertices.size());
  std::vector<int> local(x.size(), -1);
  for (int p : s.vertices) {
    local[static_cast<size_t>(p)] = static_cast<int>(v.size());
    v.push_back(1e3 * x[static_cast<size_t>(p)]);
  }
  for (const auto& t : s.faces) f.push_back({local[static_cast<size_t>(t[0])], local[static_cast<size_t>(t[1])], local[static_cast<size_t>(t[2])]});
}

std::vector<dosimetry::Seed> deposited_seeds(const NeedleTool& tool, double strength_u) {
  std::vector<dosimetry::Seed> out;
  for (const SeedReport& r : tool.seeds())
    if (r.deposited) out.push_back({1e3 * r.current, tool.spec(r.needle).direction.normalized(), strength_u});
  return out;
}

std::vector<dosimetry::Seed> planned_seeds(const NeedleTool& tool, double strength_u) {
  std::vector<dosimetry::Seed> out;
  for (const SeedReport& r : tool.seeds()) out.push_back({1e3 * r.planned, tool.spec(r.needle).direction.normalized(), strength_u});
  return out;
}

DosimetryReport implant_dosimetry(const Model& m, const std::vector<Vec3>& x, const NeedleTool& tool,
                                  const std::vector<Vec3>& urethra_rest, const std::vector<Vec3>& urethra_now,
                                  const DosimetryOptions& opt) {
  DosimetryReport rep;
  const std::vector<dosimetry::Seed> plan = planned_seeds(tool, opt.strength_u);
  const int gland = m.find_organ(opt.gland, Role::Prostate), rectum = m.find_organ(opt.rectum, Role::Rectum);
  if (plan.empty() || gland < 0) return rep;
  const dosimetry::SourceModel& src = model_of(opt.isotope);
  rep.computed = true;
  rep.isotope = src.name;
  rep.prescription_gy = opt.prescription_gy;
  rep.strength_u = opt.strength_u;
  const std::vector<dosimetry::Seed> now = deposited_seeds(tool, opt.strength_u);
  rep.seeds_planned = static_cast<int>(plan.size());
  rep.seeds_deposited = static_cast<int>(now.size());
  std::vector<Vec3> pv, rv;
  std::vector<std::array<int, 3>> pf, rf;
  // planned: organs at rest
  organ_surface_mm(m, gland, m.rest_pos, pv, pf);
  organ_surface_mm(m, rectum, m.rest_pos, rv, rf);
  const dosimetry::GridSpec g = dosimetry::gland_grid(pv);
  {
    const auto mask = dosimetry::structure_mask(g, pv, pf, rv, rf, to_mm(urethra_rest), opt.urethra_radius_mm);
    dosimetry::DoseAccumulator acc(src, g);
    acc.rebuild(plan);
    rep.planned = dosimetry::dosimetry_indices(g, acc.dose_gy(), mask, opt.prescription_gy, rep.seeds_planned);
    rep.dvh_planned = dosimetry::dvh_curve(acc.dose_gy(), mask, opt.prescription_gy);
  }
  // achieved: organs where they are now
  organ_surface_mm(m, gland, x, pv, pf);
  organ_surface_mm(m, rectum, x, rv, rf);
  const auto mask = dosimetry::structure_mask(g, pv, pf, rv, rf, to_mm(urethra_now), opt.urethra_radius_mm);
  dosimetry::DoseAccumulator acc(src, g);
  acc.rebuild(now);
  rep.achieved = dosimetry::dosimetry_indices(g, acc.dose_gy(), mask, opt.prescription_gy, rep.seeds_deposited);
  rep.dvh_achieved = dosimetry::dvh_curve(acc.dose_gy(), mask, opt.prescription_gy);
  return rep;
}

dosimetry::PlanInput plan_input(const Model& m, const ProbeTool& probe, const std::vector<Vec3>& urethra_rest,
                                const DosimetryOptions& opt) {
  dosimetry::PlanInput in;
  in.model = &model_of(opt.isotope);
  in.prescription_gy = opt.prescription_gy;
  in.strength_u = opt.strength_u;
  in.urethra_radius_mm = opt.urethra_radius_mm;
  organ_surface_mm(m, m.find_organ(opt.gland, Role::Prostate), m.rest_pos, in.prostate_mm, in.prostate_faces);
  if (in.prostate_mm.empty())
    throw InputError("", 0, "components",
                     opt.gland.empty() ? "no component with role prostate and a surface to plan on"
                                       : "no '" + opt.gland + "' component with a surface to plan on");
  organ_surface_mm(m, m.find_organ(opt.rectum, Role::Rectum), m.rest_pos, in.rectum_mm, in.rectum_faces);
  for (size_t c = 0; c < m.components.size(); ++c)
    if (m.components[c].kind == ComponentKind::Rigid) {
      std::vector<Vec3> v;
      std::vector<std::array<int, 3>> f;
      organ_surface_mm(m, static_cast<int>(c), m.rest_pos, v, f);
      const int base = static_cast<int>(in.bone_mm.size());
      for (const Vec3& p : v) in.bone_mm.push_back(p);
      for (const auto& t : f) in.bone_faces.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
  in.urethra_mm = to_mm(urethra_rest);
  const ProbeSpec& ps = probe.spec();
  if (!ps.has_template) throw InputError("", 0, "probe.template", "the probe has no template: nothing to plan the needles on");
  for (int col = 0; col < ps.template_cols; ++col)
    for (int row = 0; row < ps.template_rows; ++row) {
      const NeedlePath h = probe.template_hole(col, row);
      in.holes.push_back({col, row, 1e3 * h.entry, h.direction.normalized()});
    }
  return in;
}

}  // namespace ps
