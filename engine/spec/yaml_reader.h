// Small typed reader over yaml-cpp nodes that knows the file name and reports file:line:key.
// Internal to engine/scenario (kept out of public headers so yaml-cpp stays private).
#pragma once
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <set>
#include <string>
#include <vector>

#include "engine/util/error.h"
#include "engine/util/vec.h"

namespace ps {

class YamlReader {
 public:
  explicit YamlReader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  static int line_of(const YAML::Node& n) { return n.IsDefined() ? static_cast<int>(n.Mark().line) + 1 : 0; }

  [[noreturn]] void fail(const YAML::Node& at, const std::string& key, const std::string& msg) const {
    throw InputError(file_, line_of(at), key, msg);
  }

  // Rejects any key of map `n` not in `allowed` (typos must not be silently ignored).
  void only_keys(const YAML::Node& n, const std::string& where, std::initializer_list<const char*> allowed) const {
    only_keys(n, where, std::vector<std::string>(allowed.begin(), allowed.end()));
  }
  void only_keys(const YAML::Node& n, const std::string& where, const std::vector<std::string>& allowed) const {
    if (!n.IsMap()) fail(n, where, "expected a mapping");
    std::set<std::string> ok(allowed.begin(), allowed.end());
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string k = it->first.as<std::string>();
      if (!ok.count(k)) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        throw InputError(file_, line_of(it->first), where.empty() ? k : where + "." + k,
                         "unknown key (allowed: " + list + ")");
      }
    }
  }

  YAML::Node require(const YAML::Node& map, const std::string& where, const char* key) const {
    const YAML::Node v = map[key];
    if (!v.IsDefined() || v.IsNull()) fail(map, join(where, key), "missing required key");
    return v;
  }

  // Every number in a scenario is in the file's units (mm, kPa, ms, N, ...); none of them has a
  // physical meaning beyond 1e9 in magnitude, and values like 1e30 or inf only overflow what is
  // computed from them (substep counts, particle counts), so they are refused here, for every key.
  static constexpr double kMaxMagnitude = 1e9;
  double number(const YAML::Node& v, const std::string& key) const {
    if (!v.IsScalar()) fail(v, key, "expected a number");
    double x = 0.0;
    try {
      x = v.as<double>();
    } catch (const YAML::Exception&) {
      fail(v, key, "expected a number, got '" + v.Scalar() + "'");
    }
    if (!std::isfinite(x)) fail(v, key, "not a finite number: " + v.Scalar());
    if (std::abs(x) > kMaxMagnitude)
      fail(v, key, "out of physical range: " + v.Scalar() + " (no scenario value exceeds 1e9 in the file's units)");
    return x;
  }
  // A number in [lo, hi] (file units; `unit` is shown in the message, e.g. "kPa").
  double ranged(const YAML::Node& v, const std::string& key, double lo, double hi, const char* unit) const {
    const double x = number(v, key);
    if (!(x >= lo && x <= hi))
      fail(v, key, "out of physical range: " + v.Scalar() + " " + unit + " (allowed " + fmt(lo) + " .. " + fmt(hi) +
                       " " + unit + ")");
    return x;
  }
  static std::string fmt(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", x);
    return b;
  }
  double positive(const YAML::Node& v, const std::string& key) const {
    const double x = number(v, key);
    if (!(x > 0.0) || !std::isfinite(x)) fail(v, key, "must be a positive number, got " + v.Scalar());
    return x;
  }
  double non_negative(const YAML::Node& v, const std::string& key) const {
    const double x = number(v, key);
    if (!(x >= 0.0) || !std::isfinite(x)) fail(v, key, "must be >= 0, got " + v.Scalar());
    return x;
  }
  int integer(const YAML::Node& v, const std::string& key) const {
    if (!v.IsScalar()) fail(v, key, "expected an integer");
    try {
      return v.as<int>();  // yaml-cpp refuses values that do not fit an int
    } catch (const YAML::Exception&) {
      fail(v, key, "expected an integer, got '" + v.Scalar() + "'");
    }
  }
  bool boolean(const YAML::Node& v, const std::string& key) const {
    if (!v.IsScalar()) fail(v, key, "expected true or false");
    try {
      return v.as<bool>();
    } catch (const YAML::Exception&) {
      fail(v, key, "expected true or false, got '" + v.Scalar() + "'");
    }
  }
  std::string string(const YAML::Node& v, const std::string& key) const {
    if (!v.IsScalar() || v.Scalar().empty()) fail(v, key, "expected a non-empty string");
    return v.Scalar();
  }
  Vec3 vec3(const YAML::Node& v, const std::string& key, double scale = 1.0) const {
    if (!v.IsSequence() || v.size() != 3) fail(v, key, "expected a list of 3 numbers [x, y, z]");
    Vec3 r;
    for (int i = 0; i < 3; ++i) {
      r[i] = number(v[i], key) * scale;
      if (!std::isfinite(r[i])) fail(v, key, "not a finite number");
    }
    return r;
  }
  Vec3 unit_vec3(const YAML::Node& v, const std::string& key) const {
    const Vec3 d = vec3(v, key);
    if (!(d.norm() > 0.0)) fail(v, key, "direction must be non-zero");
    return d.normalized();
  }

  static std::string join(const std::string& a, const std::string& b) { return a.empty() ? b : a + "." + b; }

 private:
  std::string file_;
};

}  // namespace ps
