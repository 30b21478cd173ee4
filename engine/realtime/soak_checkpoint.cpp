#include "engine/realtime/soak_checkpoint.h"

#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "engine/util/atomic_file.h"
#include "engine/util/error.h"

namespace ps {

namespace {

std::string line(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string line(const char* fmt, ...) {
  char b[256];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(b, sizeof b, fmt, ap);
  va_end(ap);
  return std::string(b) + "\n";
}

}  // namespace

void write_soak_checkpoint(const std::string& path, const SoakCheckpoint& c, const std::string& script) {
  const SoakReport& r = c.report;
  const WatchPeaks& p = r.peaks;
  std::string out = "prostatesim-soak 2\nscript " + (script.empty() ? std::string("-") : script) + "\n";
  out += line("period_ticks %" PRId64, r.period_ticks);
  out += line("cycles %" PRId64, r.cycles);
  out += line("commands %" PRId64 " %" PRId64, r.applied, r.refused);
  out += line("spent %.17g %.17g", r.wall_s, r.cpu_s);
  out += line("peak_speed %.17g %d %.17g", p.max_speed, p.fastest, p.max_speed_time);
  out += line("peak_kinetic %.17g %.17g", p.max_kinetic, p.max_kinetic_time);
  out += line("peak_volume_drift %.17g %d %.17g", p.max_volume_drift, p.worst_surface, p.max_volume_drift_time);
  out += line("peak_displacement %.17g %d", p.max_displacement, p.farthest);
  out += line("min_margin %.17g", p.min_margin);
  out += line("checks %" PRId64, p.checks);
  out += line("cycle_drift %.17g %.17g %d", r.cycle_drift_max, r.cycle_drift_rms, r.cycle_drift_particle);
  out += line("cycle_end_kinetic %.17g %.17g %" PRId64 " %.17g", r.cycle_end_kinetic_first, r.cycle_end_kinetic_last,
              r.ring_base_cycle, r.ring_base_kinetic);
  out += line("first_cycle_end %zu", c.first_cycle_end.size());
  for (const Vec3& x : c.first_cycle_end) out.append(reinterpret_cast<const char*>(x.data()), 3 * sizeof(double));
  const std::string state = state_file_text(c.state);
  out += line("state %zu", state.size());
  out += state;
  write_file_atomic(path, out);
}

SoakCheckpoint read_soak_checkpoint(const std::string& path, std::string& script) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, "", "cannot read soak checkpoint");
  std::ostringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  size_t pos = 0;
  int ln = 0;
  // the next line, which must start with `key `; returns the rest
  auto next = [&](const char* key) {
    ++ln;
    const size_t e = text.find('\n', pos);
    if (e == std::string::npos) throw InputError(path, ln, key, "file ends inside the header");
    const std::string l = text.substr(pos, e - pos);
    pos = e + 1;
    const std::string k = std::string(key) + " ";
    if (l.compare(0, k.size(), k) != 0) throw InputError(path, ln, key, "expected '" + std::string(key) + " ...', got '" + l + "'");
    return l.substr(k.size());
  };
  // scanf of the line's values: all `n` must be read and nothing may follow
  auto scan = [&](const char* key, const char* fmt, int n, auto*... out) {
    const std::string v = next(key);
    int used = 0;
    const std::string f2 = std::string(fmt) + "%n";
    if (std::sscanf(v.c_str(), f2.c_str(), out..., &used) != n || used != static_cast<int>(v.size()))
      throw InputError(path, ln, key, "expected " + std::to_string(n) + " number(s), got '" + v + "'");
  };
  // version 2: `cycle_end_kinetic` carries the self-excitation check's reference cycle
  if (next("prostatesim-soak") != "2")
    throw InputError(path, 1, "prostatesim-soak", "not a version 2 soak checkpoint (version 1 lacks the self-excitation check's reference cycle; start the soak again)");
  script = next("script");
  if (script == "-") script.clear();
  SoakCheckpoint c;
  SoakReport& r = c.report;
  WatchPeaks& p = r.peaks;
  int64_t period = 0, cycles = 0, applied = 0, refused = 0, checks = 0;
  scan("period_ticks", "%" SCNd64, 1, &period);
  scan("cycles", "%" SCNd64, 1, &cycles);
  scan("commands", "%" SCNd64 " %" SCNd64, 2, &applied, &refused);
  r.period_ticks = period;
  r.cycles = cycles;
  r.applied = applied;
  r.refused = refused;
  scan("spent", "%lf %lf", 2, &r.wall_s, &r.cpu_s);
  scan("peak_speed", "%lf %d %lf", 3, &p.max_speed, &p.fastest, &p.max_speed_time);
  scan("peak_kinetic", "%lf %lf", 2, &p.max_kinetic, &p.max_kinetic_time);
  scan("peak_volume_drift", "%lf %d %lf", 3, &p.max_volume_drift, &p.worst_surface, &p.max_volume_drift_time);
  scan("peak_displacement", "%lf %d", 2, &p.max_displacement, &p.farthest);
  scan("min_margin", "%lf", 1, &p.min_margin);
  scan("checks", "%" SCNd64, 1, &checks);
  p.checks = checks;
  scan("cycle_drift", "%lf %lf %d", 3, &r.cycle_drift_max, &r.cycle_drift_rms, &r.cycle_drift_particle);
  int64_t ring_cycle = 0;
  scan("cycle_end_kinetic", "%lf %lf %" SCNd64 " %lf", 4, &r.cycle_end_kinetic_first, &r.cycle_end_kinetic_last, &ring_cycle,
       &r.ring_base_kinetic);
  r.ring_base_cycle = ring_cycle;
  if (period < 1 || cycles < 0 || applied < 0 || refused < 0 || checks < 0 || ring_cycle < 0 || ring_cycle > cycles)
    throw InputError(path, 3, "period_ticks", "counts must not be negative (period at least 1, reference cycle at most cycles)");
  size_t n = 0;
  scan("first_cycle_end", "%zu", 1, &n);
  if (n > (text.size() - pos) / (3 * sizeof(double))) throw InputError(path, ln, "first_cycle_end", "more positions than the file holds");
  c.first_cycle_end.resize(n);
  for (size_t i = 0; i < n; ++i) {
    std::memcpy(c.first_cycle_end[i].data(), text.data() + pos, 3 * sizeof(double));
    pos += 3 * sizeof(double);
  }
  size_t bytes = 0;
  scan("state", "%zu", 1, &bytes);
  if (bytes != text.size() - pos)
    throw InputError(path, ln, "state", std::to_string(bytes) + " bytes announced, " + std::to_string(text.size() - pos) + " follow");
  c.state = parse_state_text(text.substr(pos), path + " (its saved state)");
  return c;
}

}  // namespace ps
