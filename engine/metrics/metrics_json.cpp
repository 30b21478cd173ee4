#include "engine/metrics/metrics_json.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "engine/util/error.h"

namespace ps {

namespace {

using nlohmann::ordered_json;

ordered_json mm(double v) { return std::isfinite(v) ? ordered_json(1e3 * v) : ordered_json(nullptr); }
ordered_json num(double v) { return std::isfinite(v) ? ordered_json(v) : ordered_json(nullptr); }
ordered_json mm3(const Vec3& p) { return ordered_json::array({1e3 * p.x(), 1e3 * p.y(), 1e3 * p.z()}); }

ordered_json indices_json(const dosimetry::DosimetryIndices& x) {
  return {{"seeds", x.seeds},
          {"prostate_cc", x.prostate_cc},
          {"prostate_d90_gy", x.prostate_d90_gy},
          {"prostate_v100", x.prostate_v100},
          {"prostate_v150", x.prostate_v150},
          {"prostate_v200", x.prostate_v200},
          {"urethra_d10_gy", x.urethra_d10_gy},
          {"urethra_d30_gy", x.urethra_d30_gy},
          {"rectum_d2cc_gy", x.rectum_d2cc_gy},
          {"rectum_v100_cc", x.rectum_v100_cc}};
}

ordered_json dosimetry_json(const DosimetryReport& d) {
  if (!d.computed) return nullptr;
  return {{"isotope", d.isotope},
          {"prescription_gy", d.prescription_gy},
          {"strength_u", d.strength_u},
          {"grid_mm", 1.0},
          {"planned", indices_json(d.planned)},
          {"achieved", indices_json(d.achieved)}};
}

}  // namespace

std::string metrics_json(const SessionReport& r, const Score& score, const SessionInfo& info) {
  ordered_json j;
  j["format"] = "prostatesim-metrics";
  j["version"] = kMetricsFormatVersion;
  j["trainee"] = info.trainee;
  j["session"] = info.session;
  j["scenario"] = r.scenario;
  j["score"] = score.value;
  ordered_json terms = ordered_json::array();
  for (const ScoreTerm& t : score.terms) terms.push_back({{"term", t.name}, {"points", t.points}, {"detail", t.detail}});
  j["score_terms"] = terms;
  j["faulted"] = r.faulted;
  j["duration_s"] = r.duration;
  j["procedure_time_s"] = num(r.procedure_time);
  j["targeting"] = {{"mean_error_mm", mm(r.mean_error)}, {"max_error_mm", mm(r.max_error)},
                    {"scale_position", num(han_scale_position(r.mean_error))}, {"scale", han_scale_text(r.mean_error)},
                    {"reference", {{"source", "Han et al., J Urol 2012, pelvic mock-ups"},
                                   {"freehand_mm", 1e3 * kHanFreehandError}, {"robot_mm", 1e3 * kHanRobotError}}}};
  j["probe"] = {{"peak_force_n", num(r.probe_peak_force)}, {"time_above_threshold_s", num(r.probe_time_above)},
                {"threshold_n", kProbeForceThreshold}, {"threshold_note", "provisional: no published TRUS probe force found"}};
  j["totals"] = {{"needles", r.needles.size()}, {"punctures", r.punctures}, {"reinsertions", r.reinsertions},
                 {"structures_hit", r.structures_hit}, {"capsule_exits", r.capsule_exits}};
  ordered_json needles = ordered_json::array();
  for (const NeedleMetrics& n : r.needles)
    needles.push_back({{"name", n.name}, {"scored", n.scored}, {"measured_at", n.measured_at},
                       {"target_rest_mm", mm3(n.target_rest)}, {"target_mm", n.scored ? mm3(n.target_now) : ordered_json(nullptr)},
                       {"sample_mm", n.scored ? mm3(n.sample) : ordered_json(nullptr)}, {"error_mm", mm(n.error)},
                       {"lateral_error_mm", mm(n.lateral_error)}, {"depth_error_mm", mm(n.depth_error)},
                       {"punctures", n.punctures}, {"reinsertions", n.reinsertions}, {"peak_force_n", n.peak_force},
                       {"mean_force_n", n.mean_force}, {"insertion_time_s", num(n.insertion_time)},
                       {"structures_hit", n.structures_hit}, {"capsule_exits", n.capsule_exits},
                       {"target_in_lesion", n.target_in_lesion}});
  j["needles"] = needles;
  ordered_json cores = ordered_json::array();
  for (const CoreMetrics& c : r.cores)
    cores.push_back({{"needle", c.needle}, {"taken", c.taken}, {"time_s", c.time}, {"site", c.site},
                     {"planned_site", c.planned_site}, {"lesion_hit", c.lesion_hit}, {"lesion_length_mm", 1e3 * c.lesion_length},
                     {"notch_length_mm", 1e3 * c.notch_length},
                     {"notch_centre_mm", c.taken ? mm3(c.notch_centre) : ordered_json(nullptr)},
                     {"site_error_mm", mm(c.site_error)}});
  ordered_json per_zone = ordered_json::object();
  for (const auto& [z, n] : r.cores_per_zone) per_zone[z] = n;
  ordered_json centres = ordered_json::object();
  for (const PlannedSite& ps : r.planned_site_centres) centres[ps.label] = mm3(ps.centre);
  j["biopsy"] = {{"cores", cores}, {"cores_per_zone", per_zone}, {"planned_sites", r.planned_sites}, {"planned_site_centres_mm", centres},
                 {"coverage", num(r.coverage)}, {"cores_outside_gland", r.cores_outside_gland},
                 {"lesions_targeted", r.lesions_targeted}, {"lesions_missed", r.lesions_missed}};
  ordered_json seeds = ordered_json::array();
  for (const SeedMetrics& s : r.seeds)
    seeds.push_back({{"needle", s.needle}, {"index", s.index}, {"deposited", s.deposited}, {"error_mm", mm(s.error)},
                     {"outside_gland", s.outside_gland}});
  j["brachytherapy"] = {{"seeds", seeds}, {"seed_error_mean_mm", mm(r.seed_error_mean)}, {"seed_error_max_mm", mm(r.seed_error_max)},
                        {"seeds_outside_gland", r.gland_known ? ordered_json(r.seeds_outside_gland) : ordered_json(nullptr)},
                        {"dosimetry", dosimetry_json(r.dosimetry)}};
  return j.dump(2) + "\n";
}

MetricsRow parse_metrics_json(const std::string& text, const std::string& file) {
  ordered_json j;
  try {
    j = ordered_json::parse(text);
  } catch (const std::exception& e) {
    throw InputError(file, 0, "", std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object()) throw InputError(file, 0, "", "expected a JSON object");
  auto at = [&](const std::string& path) -> const ordered_json& {
    const ordered_json* cur = &j;
    size_t b = 0;
    while (true) {
      const size_t e = path.find('.', b);
      const std::string key = path.substr(b, e == std::string::npos ? std::string::npos : e - b);
      if (!cur->is_object() || !cur->contains(key)) throw InputError(file, 0, path, "missing");
      cur = &(*cur)[key];
      if (e == std::string::npos) return *cur;
      b = e + 1;
    }
  };
  auto str = [&](const std::string& p) {
    const ordered_json& v = at(p);
    if (!v.is_string()) throw InputError(file, 0, p, "expected a string");
    return v.get<std::string>();
  };
  auto number = [&](const std::string& p, bool nullable) {
    const ordered_json& v = at(p);
    if (v.is_null() && nullable) return static_cast<double>(NAN);
    if (!v.is_number()) throw InputError(file, 0, p, nullable ? "expected a number or null" : "expected a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) throw InputError(file, 0, p, "not finite");
    return d;
  };
  auto integer = [&](const std::string& p) {
    const ordered_json& v = at(p);
    if (!v.is_number_integer() || v.get<long long>() < 0) throw InputError(file, 0, p, "expected a non-negative integer");
    return static_cast<int>(v.get<long long>());
  };
  if (str("format") != "prostatesim-metrics") throw InputError(file, 0, "format", "expected \"prostatesim-metrics\"");
  if (integer("version") != kMetricsFormatVersion)
    throw InputError(file, 0, "version", "unsupported version (expected " + std::to_string(kMetricsFormatVersion) + ")");
  MetricsRow r;
  r.file = file;
  r.trainee = str("trainee");
  r.session = str("session");
  r.scenario = str("scenario");
  r.score = number("score", false);
  if (r.score < 0 || r.score > 100) throw InputError(file, 0, "score", "outside [0, 100]");
  r.mean_error_mm = number("targeting.mean_error_mm", true);
  r.max_error_mm = number("targeting.max_error_mm", true);
  r.procedure_time_s = number("procedure_time_s", true);
  r.needles = integer("totals.needles");
  r.punctures = integer("totals.punctures");
  r.reinsertions = integer("totals.reinsertions");
  r.structures_hit = integer("totals.structures_hit");
  r.coverage = number("biopsy.coverage", true);
  const ordered_json& cores = at("biopsy.cores");
  if (!cores.is_array()) throw InputError(file, 0, "biopsy.cores", "expected a list");
  r.cores = static_cast<int>(cores.size());
  r.lesions_targeted = integer("biopsy.lesions_targeted");
  r.lesions_missed = integer("biopsy.lesions_missed");
  r.seed_error_mean_mm = number("brachytherapy.seed_error_mean_mm", true);
  const ordered_json& so = at("brachytherapy.seeds_outside_gland");
  r.seeds_outside_gland = so.is_null() ? 0 : integer("brachytherapy.seeds_outside_gland");
  return r;
}

}  // namespace ps
