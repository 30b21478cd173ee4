#include "engine/dosimetry/dose_csv.h"

#include <charconv>
#include <cmath>
#include <sstream>

#include "engine/util/error.h"

namespace ps::dosimetry {

namespace {

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream ss(line);
  while (std::getline(ss, cell, ',')) out.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

// column index of `name`; InputError naming the header line when it is missing
size_t column(const CsvTable& t, const std::string& name, const std::string& file, int header_line) {
  for (size_t i = 0; i < t.header.size(); ++i)
    if (t.header[i] == name) return i;
  throw InputError(file, header_line, name, "missing column (the header must name it)");
}

double number(const CsvTable& t, size_t row, size_t col, const std::string& file) {
  const std::string& field = t.header[col];
  if (col >= t.rows[row].size() || t.rows[row][col].empty())
    throw InputError(file, t.lines[row], field, "missing value");
  const std::string& s = t.rows[row][col];
  double v = 0.0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v))
    throw InputError(file, t.lines[row], field, "'" + s + "' is not a finite number");
  return v;
}

}  // namespace

CsvTable parse_csv(const std::string& text, const std::string& file) {
  CsvTable t;
  std::istringstream in(text);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    const std::string s = trim(line);
    if (s.empty() || s[0] == '#') continue;
    if (t.header.empty()) {
      t.header = split(s);
      t.lines.push_back(n);  // header line kept first, removed below
      continue;
    }
    t.rows.push_back(split(s));
    t.lines.push_back(n);
  }
  if (t.header.empty()) throw InputError(file, 0, "header", "no header line (the file is empty)");
  return t;
}

std::vector<Seed> parse_seeds_csv(const std::string& text, const std::string& file) {
  CsvTable t = parse_csv(text, file);
  const int hl = t.lines.front();
  t.lines.erase(t.lines.begin());
  const size_t cx = column(t, "x_mm", file, hl), cy = column(t, "y_mm", file, hl), cz = column(t, "z_mm", file, hl);
  const size_t ax = column(t, "axis_x", file, hl), ay = column(t, "axis_y", file, hl), az = column(t, "axis_z", file, hl);
  const size_t cs = column(t, "air_kerma_strength_U", file, hl);
  std::vector<Seed> seeds;
  for (size_t r = 0; r < t.rows.size(); ++r) {
    Seed s;
    s.centre_mm = Vec3(number(t, r, cx, file), number(t, r, cy, file), number(t, r, cz, file));
    const Vec3 a(number(t, r, ax, file), number(t, r, ay, file), number(t, r, az, file));
    if (a.norm() < 1e-9) throw InputError(file, t.lines[r], "axis_x", "the seed axis is zero (give its needle's direction)");
    s.axis = a.normalized();
    s.strength_u = number(t, r, cs, file);
    if (!(s.strength_u > 0.0))
      throw InputError(file, t.lines[r], "air_kerma_strength_U", "must be positive (got " + t.rows[r][cs] + ")");
    seeds.push_back(s);
  }
  if (seeds.empty()) throw InputError(file, hl, "x_mm", "no seeds (the file has a header and no rows)");
  return seeds;
}

std::vector<Vec3> parse_points_csv(const std::string& text, const std::string& file) {
  CsvTable t = parse_csv(text, file);
  const int hl = t.lines.front();
  t.lines.erase(t.lines.begin());
  const size_t cx = column(t, "x_mm", file, hl), cy = column(t, "y_mm", file, hl), cz = column(t, "z_mm", file, hl);
  std::vector<Vec3> p;
  for (size_t r = 0; r < t.rows.size(); ++r)
    p.emplace_back(number(t, r, cx, file), number(t, r, cy, file), number(t, r, cz, file));
  return p;
}

}  // namespace ps::dosimetry
