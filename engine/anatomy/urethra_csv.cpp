#include "engine/anatomy/urethra_csv.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

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

}  // namespace ps
