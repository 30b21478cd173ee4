#include "engine/metrics/metrics_options.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/util/error.h"

namespace ps {

std::vector<Vec3> parse_urethra_csv(const std::string& text, const std::string& file) {
  std::vector<Vec3> out;
  std::istringstream in(text);
  std::string line;
  int n = 0;
  bool header = false;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      if (line.rfind("x_mm,y_mm,z_mm", 0) != 0) throw InputError(file, n, "header", "expected x_mm,y_mm,z_mm");
      header = true;
      continue;
    }
    double v[3];
    std::istringstream row(line);
    std::string cell;
    for (int k = 0; k < 3; ++k) {
      if (!std::getline(row, cell, ',')) throw InputError(file, n, "xyz"[k] + std::string("_mm"), "missing");
      try {
        size_t used = 0;
        v[k] = std::stod(cell, &used);
        if (used != cell.size() && cell.find_first_not_of(" \r", used) != std::string::npos) throw std::invalid_argument(cell);
      } catch (const std::exception&) {
        throw InputError(file, n, "xyz"[k] + std::string("_mm"), "not a number: '" + cell + "'");
      }
      if (!std::isfinite(v[k])) throw InputError(file, n, "xyz"[k] + std::string("_mm"), "not finite");
    }
    out.emplace_back(1e-3 * v[0], 1e-3 * v[1], 1e-3 * v[2]);
  }
  return out;
}

MetricsOptions metrics_options_for(const ScenarioSpec& spec) {
  MetricsOptions o;
  if (spec.prostate_zones) o.gland = spec.prostate_zones->component;
  for (const ComponentSpec& c : spec.components) {
    if (c.name != o.gland || c.shape.kind != ShapeSpec::Mesh) continue;
    const std::filesystem::path csv = std::filesystem::path(c.shape.mesh.file).parent_path() / "urethra.csv";
    std::ifstream in(csv);
    if (!in) break;
    std::stringstream ss;
    ss << in.rdbuf();
    o.urethra = parse_urethra_csv(ss.str(), csv.string());
  }
  return o;
}

}  // namespace ps
