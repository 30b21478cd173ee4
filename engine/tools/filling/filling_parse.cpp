#include "engine/tools/filling/filling_parse.h"

#include <cmath>

namespace ps {

namespace {
void check_component(const YamlReader& r, const ScenarioSpec& s, const YAML::Node& v, const std::string& key,
                     const std::string& name) {
  for (const auto& c : s.components)
    if (c.name == name) return;
  r.fail(v, key, "unknown component '" + name + "'");
}
SourceLoc loc_of(const YamlReader& r, const YAML::Node& n) { return SourceLoc{r.file(), YamlReader::line_of(n)}; }
}  // namespace

void parse_filling_section(const YamlReader& r, const YAML::Node& n, ScenarioSpec& s) {
  r.only_keys(n, "filling", {"max_rate_ml_s", "schedule"});
  FillingSpec f;
  f.loc = loc_of(r, n);
  if (n["max_rate_ml_s"]) f.max_rate = r.positive(n["max_rate_ml_s"], "filling.max_rate_ml_s") * 1e-6;
  const YAML::Node sch = r.require(n, "filling", "schedule");
  if (!sch.IsSequence() || sch.size() == 0) r.fail(sch, "filling.schedule", "expected a non-empty list");
  for (size_t i = 0; i < sch.size(); ++i) {
    const YAML::Node e = sch[i];
    const std::string k = "filling.schedule[" + std::to_string(i) + "]";
    r.only_keys(e, k, {"component", "rate_ml_s", "target_ml", "target_factor", "ramp_s"});
    FillSpec fs;
    fs.loc = loc_of(r, e);
    fs.component = r.string(r.require(e, k, "component"), k + ".component");
    check_component(r, s, e["component"], k + ".component", fs.component);
    const int kinds = (e["rate_ml_s"] ? 1 : 0) + (e["target_ml"] ? 1 : 0) + (e["target_factor"] ? 1 : 0);
    if (kinds != 1) r.fail(e, k, "give exactly one of rate_ml_s, target_ml, target_factor");
    if (e["rate_ml_s"]) {
      fs.kind = FillSpec::Rate;
      fs.value = r.number(e["rate_ml_s"], k + ".rate_ml_s") * 1e-6;
      if (!std::isfinite(fs.value)) r.fail(e["rate_ml_s"], k + ".rate_ml_s", "not a finite number");
    } else if (e["target_ml"]) {
      fs.kind = FillSpec::Target;
      const double v = r.number(e["target_ml"], k + ".target_ml");
      if (!(v > 0.0) || !std::isfinite(v)) r.fail(e["target_ml"], k + ".target_ml", "a target volume must be > 0, got " + e["target_ml"].Scalar());
      fs.value = v * 1e-6;
    } else {
      fs.kind = FillSpec::Factor;
      const double v = r.number(e["target_factor"], k + ".target_factor");
      if (!(v > 0.0) || !std::isfinite(v)) r.fail(e["target_factor"], k + ".target_factor", "a target volume must be > 0, got " + e["target_factor"].Scalar());
      fs.value = v;
    }
    const YAML::Node ramp = r.require(e, k, "ramp_s");
    if (!ramp.IsSequence() || ramp.size() != 2) r.fail(ramp, k + ".ramp_s", "expected [start_s, end_s]");
    fs.t0 = r.non_negative(ramp[0], k + ".ramp_s");
    fs.t1 = r.non_negative(ramp[1], k + ".ramp_s");
    if (fs.t1 < fs.t0) r.fail(ramp, k + ".ramp_s", "ramp end is before its start");
    f.schedule.push_back(fs);
  }
  s.filling = f;
}

}  // namespace ps
