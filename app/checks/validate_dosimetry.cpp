// `validate tg43`: the TG-43U1 implementation (engine/dosimetry/tg43.h: geometry function,
// interpolation, extrapolation) against published single-seed numbers it does not read
// (engine/dosimetry/tg43_check.h): the I-125 model 6711 along-away dose rates at 0.5-7 cm, 0-90
// degrees (one row per point, tolerance 2 %), and the consensus 1-D anisotropy factor
// phi_an(r) at 0.5-5 cm (2 %). Values are reported as ratios to the reference (1 = exact).
#include "app/checks/validate_dosimetry.h"

#include "engine/dosimetry/tg43_check.h"

namespace ps::app {

std::vector<ValidationCase> dosimetry_validation_cases() {
  ValidationCase c;
  c.name = "tg43";
  c.description = "TG-43U1 seed dose rates (I-125 6711) against along-away tables and the consensus phi_an";
  c.run = [](const std::string&, const std::string&) {
    std::vector<ValidationRow> rows;
    for (const auto& v : dosimetry::check_6711_along_away())
      rows.push_back({"tg43", "I125_6711 " + v.metric + " / table", v.value / v.reference, 1.0, "ratio", v.tolerance_rel});
    for (const auto& v : dosimetry::check_6711_phi_an())
      rows.push_back({"tg43", "I125_6711 " + v.metric + " / consensus", v.value / v.reference, 1.0, "ratio", v.tolerance_rel});
    return rows;
  };
  return {c};
}

}  // namespace ps::app
