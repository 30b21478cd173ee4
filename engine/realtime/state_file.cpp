#include "engine/realtime/state_file.h"

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "engine/realtime/recording.h"
#include "engine/util/atomic_file.h"
#include "engine/util/error.h"
#include "engine/util/state_io.h"

namespace ps {

uint64_t saved_state_hash(const std::vector<uint8_t>& bytes) { return fnv1a(bytes.data(), bytes.size()); }

std::string state_file_text(const SavedState& s) {
  std::string fault = s.fault;
  for (char& c : fault)
    if (c == '\n' || c == '\r') c = ' ';
  char head[160];
  std::string out = "prostatesim-state 1\nprogram " + std::string(kProgramVersion) + "\nscenario " + s.scenario + "\nscenario_hash " +
                    hex16(s.scenario_hash) + "\n";
  std::snprintf(head, sizeof head, "tick %" PRId64 "\ntime %.17g\nstate_hash %s\n", s.tick, s.time, hex16(s.state_hash).c_str());
  out += head;
  out += "fault " + fault + "\nbytes " + std::to_string(s.bytes.size()) + "\n";
  out.append(reinterpret_cast<const char*>(s.bytes.data()), s.bytes.size());
  return out;
}

void write_state_file(const std::string& path, const SavedState& s) { write_file_atomic(path, state_file_text(s)); }

SavedState read_state_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, "", "cannot read saved state");
  std::ostringstream ss;
  ss << f.rdbuf();
  return parse_state_text(ss.str(), path);
}

SavedState parse_state_text(const std::string& text, const std::string& path) {
  SavedState s;
  s.file = path;
  size_t pos = 0;
  auto next_line = [&](int ln, const char* key) {
    const size_t e = text.find('\n', pos);
    if (e == std::string::npos) throw InputError(path, ln, key, "file ends inside the header");
    std::string line = text.substr(pos, e - pos);
    pos = e + 1;
    const std::string k = std::string(key) + " ";
    if (line.compare(0, k.size(), k) != 0) throw InputError(path, ln, key, "expected '" + std::string(key) + " ...', got '" + line + "'");
    return line.substr(k.size());
  };
  auto hex = [&](const std::string& v, int ln, const char* key) {
    char* end = nullptr;
    const unsigned long long h = std::strtoull(v.c_str(), &end, 16);
    if (v.size() != 16 || *end != 0) throw InputError(path, ln, key, "expected 16 hex digits, got '" + v + "'");
    return static_cast<uint64_t>(h);
  };
  if (next_line(1, "prostatesim-state") != "1") throw InputError(path, 1, "prostatesim-state", "not a version 1 saved state");
  const std::string prog = next_line(2, "program");
  if (prog != kProgramVersion)
    throw InputError(path, 2, "program", "saved by prostatesim " + prog + ", this is " + kProgramVersion);
  s.scenario = next_line(3, "scenario");
  s.scenario_hash = hex(next_line(4, "scenario_hash"), 4, "scenario_hash");
  {
    const std::string v = next_line(5, "tick");
    char* end = nullptr;
    s.tick = std::strtoll(v.c_str(), &end, 10);
    if (v.empty() || *end != 0 || s.tick < 0) throw InputError(path, 5, "tick", "expected a tick count, got '" + v + "'");
  }
  {
    const std::string v = next_line(6, "time");
    char* end = nullptr;
    s.time = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != 0) throw InputError(path, 6, "time", "expected a number, got '" + v + "'");
  }
  s.state_hash = hex(next_line(7, "state_hash"), 7, "state_hash");
  s.fault = next_line(8, "fault");
  const std::string nb = next_line(9, "bytes");
  char* end = nullptr;
  const unsigned long long n = std::strtoull(nb.c_str(), &end, 10);
  if (nb.empty() || *end != 0 || n != text.size() - pos)
    throw InputError(path, 9, "bytes", "the file holds " + std::to_string(text.size() - pos) + " bytes of state, the header says " + nb);
  s.bytes.assign(text.begin() + static_cast<std::ptrdiff_t>(pos), text.end());
  if (saved_state_hash(s.bytes) != s.state_hash)
    throw InputError(path, 7, "state_hash", "the saved bytes do not match their hash (the file is damaged)");
  return s;
}

void check_state_matches(const SavedState& s, const std::string& name, uint64_t scenario_hash) {
  if (s.scenario != name)
    throw InputError(s.file, 3, "scenario", "a saved state of scenario '" + s.scenario + "', not of '" + name + "'");
  if (s.scenario_hash != scenario_hash)
    throw InputError(s.file, 4, "scenario_hash",
                     "saved from scenario file content " + hex16(s.scenario_hash) + ", this file is " + hex16(scenario_hash) +
                         ": the scenario file differs");
}

}  // namespace ps
