#include "engine/metrics/metrics_options.h"

namespace ps {

MetricsOptions metrics_options_for(const ScenarioSpec& spec, const Model& model) {
  MetricsOptions o;
  if (spec.prostate_zones) o.gland = spec.prostate_zones->component;
  else if (const int c = model.find_role(Role::Prostate); c >= 0) o.gland = model.components[static_cast<size_t>(c)].name;
  o.urethra = model.urethra;
  return o;
}

}  // namespace ps
