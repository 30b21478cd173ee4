#include "engine/realtime/recording.h"

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "engine/util/error.h"

namespace ps {

std::string hex16(uint64_t h) {
  char b[20];
  std::snprintf(b, sizeof b, "%016" PRIx64, h);
  return b;
}

namespace {

// A recording's command line keeps one column per field of the flat layout it has always had
// (component col row insertion offset[3] roll tilt yaw duration value pos[3] dir[3]), so files
// written before the per-kind payloads read the same; each kind fills and reads its own columns.
struct CommandColumns {
  int component = -1, col = 0, row = 0;
  double insertion = 0, offset[3] = {0, 0, 0}, roll = 0, tilt = 0, yaw = 0, duration = 0, value = 0;
  double pos[3] = {0, 0, 0}, dir[3] = {0, 0, 1};
};

bool is_fill(CommandKind k) { return k == CommandKind::FillRate || k == CommandKind::FillTo; }

CommandColumns columns_of(const Command& c) {
  CommandColumns w;
  w.component = c.fill.component;
  w.col = c.needle.col;
  w.row = c.needle.row;
  if (c.kind == CommandKind::ProbeMove) {
    w.insertion = c.probe.insertion;
    for (int i = 0; i < 3; ++i) w.offset[i] = c.probe.offset[i];
    w.roll = c.probe.roll;
    w.tilt = c.probe.tilt;
    w.yaw = c.probe.yaw;
    w.duration = c.probe.duration;
  } else if (is_fill(c.kind)) {
    w.duration = c.fill.duration;
    w.value = c.fill.value;
  } else {
    if (c.kind == CommandKind::NeedleDepth) w.insertion = c.needle.depth;
    w.value = c.kind == CommandKind::NeedleRotate ? c.needle.angle : c.needle.speed;
    for (int i = 0; i < 3; ++i) {
      w.pos[i] = c.needle.pos[i];
      w.dir[i] = c.needle.dir[i];
    }
  }
  return w;
}

void set_columns(Command& c, const CommandColumns& w) {
  c.fill.component = w.component;
  c.needle.col = w.col;
  c.needle.row = w.row;
  if (c.kind == CommandKind::ProbeMove) {
    c.probe.insertion = w.insertion;
    for (int i = 0; i < 3; ++i) c.probe.offset[i] = w.offset[i];
    c.probe.roll = w.roll;
    c.probe.tilt = w.tilt;
    c.probe.yaw = w.yaw;
    c.probe.duration = w.duration;
  } else if (is_fill(c.kind)) {
    c.fill.duration = w.duration;
    c.fill.value = w.value;
  } else {
    if (c.kind == CommandKind::NeedleDepth) c.needle.depth = w.insertion;
    if (c.kind == CommandKind::NeedleRotate) c.needle.angle = w.value;
    else c.needle.speed = w.value;
    for (int i = 0; i < 3; ++i) {
      c.needle.pos[i] = w.pos[i];
      c.needle.dir[i] = w.dir[i];
    }
  }
}

}  // namespace

std::string format_command_line(const Command& c) {
  const CommandColumns w = columns_of(c);
  char b[640];
  std::snprintf(b, sizeof b,
                "c %" PRId64 " %s %d %d %d %d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g",
                c.tick, command_kind_name(c.kind), c.tool, c.item, w.component, w.col, w.row, w.insertion, w.offset[0],
                w.offset[1], w.offset[2], w.roll, w.tilt, w.yaw, w.duration, w.value, w.pos[0], w.pos[1], w.pos[2], w.dir[0],
                w.dir[1], w.dir[2]);
  return b;
}

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream is(line);
  std::string w;
  while (is >> w) out.push_back(w);
  return out;
}

double to_double(const std::string& s, const std::string& file, int line, const char* field) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != 0 || !std::isfinite(v)) throw InputError(file, line, field, "expected a finite number, got '" + s + "'");
  return v;
}
int64_t to_int(const std::string& s, const std::string& file, int line, const char* field) {
  char* end = nullptr;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (s.empty() || *end != 0) throw InputError(file, line, field, "expected an integer, got '" + s + "'");
  return v;
}
uint64_t to_hex(const std::string& s, const std::string& file, int line, const char* field) {
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 16);
  if (s.size() != 16 || *end != 0) throw InputError(file, line, field, "expected 16 hex digits, got '" + s + "'");
  return v;
}

}  // namespace

Recording parse_recording_text(const std::string& text, const std::string& file) {
  Recording r;
  r.file = file;
  std::istringstream is(text);
  std::string line;
  int ln = 0;
  bool have[6] = {false, false, false, false, false, false};
  int64_t last_tick = 0, last_hash_tick = 0;
  int version = 0;
  r.header.hash_every = 0;
  while (std::getline(is, line)) {
    ++ln;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> w = split(line);
    if (w.empty() || w[0][0] == '#') continue;
    if (ln == 1 || !have[0]) {
      if (w.size() != 2 || w[0] != "prostatesim-recording")
        throw InputError(file, ln, "", "not a ProstateSim recording (first line must be 'prostatesim-recording 1')");
      version = static_cast<int>(to_int(w[1], file, ln, "version"));
      if (version < 1 || version > kRecordingVersion)
        throw InputError(file, ln, "version", "recording format version " + w[1] + ", this program reads versions 1 to " +
                                                  std::to_string(kRecordingVersion));
      have[0] = true;
      continue;
    }
    if (r.complete) throw InputError(file, ln, "", "text after the 'end' line");
    const std::string& k = w[0];
    auto need = [&](size_t n) {
      if (w.size() != n)
        throw InputError(file, ln, k, "expected " + std::to_string(n - 1) + " fields, got " + std::to_string(w.size() - 1));
    };
    if (k == "program") {
      need(2);
      if (w[1] != kProgramVersion)
        throw InputError(file, ln, "program", "recorded by prostatesim " + w[1] + ", this is " + kProgramVersion +
                                                  " (results are only bit-exact with the same program)");
      have[1] = true;
    } else if (k == "scenario") {
      if (w.size() < 2) need(2);
      r.header.scenario = line.substr(line.find("scenario") + 9);
      have[2] = true;
    } else if (k == "scenario_hash") {
      need(2);
      r.header.scenario_hash = to_hex(w[1], file, ln, "scenario_hash");
      r.header_line_hash = ln;
      have[3] = true;
    } else if (k == "dt") {
      need(2);
      r.header.dt = to_double(w[1], file, ln, "dt");
      have[4] = true;
    } else if (k == "substeps") {
      need(2);
      r.header.substeps = static_cast<int>(to_int(w[1], file, ln, "substeps"));
      have[5] = true;
    } else if (k == "hash_every" && version >= 2) {
      need(2);
      const int64_t n = to_int(w[1], file, ln, "hash_every");
      if (n < 0 || n > 1000000000) throw InputError(file, ln, "hash_every", "out of range 0..1e9");
      r.header.hash_every = static_cast<int>(n);
    } else if (k == "h" && version >= 2) {
      need(3);
      RecordedHash h;
      h.tick = to_int(w[1], file, ln, "h");
      if (h.tick <= last_hash_tick)
        throw InputError(file, ln, "h", "hash ticks must increase (" + w[1] + " after " + std::to_string(last_hash_tick) + ")");
      if (r.header.hash_every <= 0 || h.tick % r.header.hash_every != 0)
        throw InputError(file, ln, "h", "hash at tick " + w[1] + " is not a multiple of hash_every " + std::to_string(r.header.hash_every));
      last_hash_tick = h.tick;
      h.hash = to_hex(w[2], file, ln, "h");
      h.line = ln;
      r.hashes.push_back(h);
    } else if (k == "c") {
      for (int i = 1; i < 6; ++i)
        if (!have[i]) throw InputError(file, ln, "", "command before the header is complete (program, scenario, scenario_hash, dt, substeps)");
      need(23);
      Command c;
      c.tick = to_int(w[1], file, ln, "tick");
      if (c.tick < 0) throw InputError(file, ln, "tick", "negative tick");
      if (c.tick < last_tick)
        throw InputError(file, ln, "tick", "ticks go backwards (" + w[1] + " after " + std::to_string(last_tick) + ")");
      last_tick = c.tick;
      const int kind = command_kind_from_name(w[2].c_str());
      if (kind < 0) throw InputError(file, ln, "kind", "unknown command '" + w[2] + "'");
      c.kind = static_cast<CommandKind>(kind);
      c.tool = static_cast<int16_t>(to_int(w[3], file, ln, "tool"));
      c.item = static_cast<int16_t>(to_int(w[4], file, ln, "item"));
      CommandColumns col;
      col.component = static_cast<int>(to_int(w[5], file, ln, "component"));
      col.col = static_cast<int>(to_int(w[6], file, ln, "col"));
      col.row = static_cast<int>(to_int(w[7], file, ln, "row"));
      double* d[] = {&col.insertion, &col.offset[0], &col.offset[1], &col.offset[2], &col.roll, &col.tilt, &col.yaw, &col.duration,
                     &col.value, &col.pos[0], &col.pos[1], &col.pos[2], &col.dir[0], &col.dir[1], &col.dir[2]};
      for (int i = 0; i < 15; ++i) *d[i] = to_double(w[8 + i], file, ln, "value");
      set_columns(c, col);
      r.commands.push_back(c);
    } else if (k == "fault" && version >= 2) {
      need(2);
      r.fault_tick = to_int(w[1], file, ln, "fault");
      if (r.fault_tick < last_tick) throw InputError(file, ln, "fault", "fault before the last command");
    } else if (k == "end") {
      need(3);
      r.end_tick = to_int(w[1], file, ln, "end");
      if (r.end_tick < last_tick || r.end_tick < last_hash_tick) throw InputError(file, ln, "end", "ends before its last command or hash");
      r.end_hash = to_hex(w[2], file, ln, "end");
      r.end_line = ln;
      r.complete = true;
    } else {
      throw InputError(file, ln, k, "unknown record '" + k + "' (expected c, end or a header line)");
    }
  }
  if (!have[0]) throw InputError(file, 1, "", "empty file: not a ProstateSim recording");
  for (int i = 1; i < 6; ++i)
    if (!have[i]) throw InputError(file, ln, "", "recording header incomplete (program, scenario, scenario_hash, dt, substeps)");
  return r;
}

Recording parse_recording_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, "", "cannot read recording");
  std::ostringstream ss;
  ss << f.rdbuf();
  return parse_recording_text(ss.str(), path);
}

void HashVerifier::state_hash(int64_t ticks, uint64_t hash) {
  while (next_ < rec_.hashes.size() && rec_.hashes[next_].tick < ticks) ++next_;
  if (next_ >= rec_.hashes.size() || rec_.hashes[next_].tick != ticks) return;
  ++checked_;
  if (first_bad_ < 0 && hash != rec_.hashes[next_].hash) {
    first_bad_ = static_cast<int>(next_);
    got_ = hash;
  }
  ++next_;
}

std::string HashVerifier::describe() const {
  if (first_bad_ < 0) return "";
  const RecordedHash& h = rec_.hashes[first_bad_];
  return rec_.file + ":" + std::to_string(h.line) + ": tick " + std::to_string(h.tick) + ": the replay's state hash is " + hex16(got_) +
         ", the recording has " + hex16(h.hash) + " (the replay diverged between tick " +
         std::to_string(first_bad_ > 0 ? rec_.hashes[first_bad_ - 1].tick : 0) + " and this one)";
}

void check_recording_matches(const Recording& r, const RecordingHeader& scene) {
  if (r.header.scenario_hash != scene.scenario_hash || r.header.scenario != scene.scenario)
    throw InputError(r.file, r.header_line_hash, "scenario_hash",
                     "recording of scenario '" + r.header.scenario + "' (" + hex16(r.header.scenario_hash) + "), not of '" +
                         scene.scenario + "' (" + hex16(scene.scenario_hash) + "): the scenario file differs");
  if (r.header.dt != scene.dt || r.header.substeps != scene.substeps)
    throw InputError(r.file, r.header_line_hash, "dt", "recorded with another tick or substep count");
}

RecordingWriter::RecordingWriter(const std::string& path, const RecordingHeader& h) : path_(path), hash_every_(std::max(0, h.hash_every)) {
  // written as FILE.part while the run goes on (flushed, so a crash leaves a readable .part that
  // loses at most the last second), renamed to FILE when the run ends
  f_ = std::fopen((path + ".part").c_str(), "w");
  if (!f_) throw InputError(path, 0, "--record", "cannot create the recording file");
  std::fprintf(f_, "prostatesim-recording %d\nprogram %s\nscenario %s\nscenario_hash %s\ndt %.17g\nsubsteps %d\nhash_every %d\n",
               kRecordingVersion, kProgramVersion, h.scenario.c_str(), hex16(h.scenario_hash).c_str(), h.dt, h.substeps, hash_every_);
  std::fflush(f_);
  thread_ = std::thread([this] { writer_main(); });
}

RecordingWriter::~RecordingWriter() {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
  if (f_) {
    drain();
    std::fclose(f_);
  }
}

void RecordingWriter::applied(const Command& c) {
  Entry e;
  e.c = c;
  if (!ring_.push(e)) dropped_.fetch_add(1);
}

void RecordingWriter::state_hash(int64_t ticks, uint64_t hash) {
  Entry e;
  e.c.tick = ticks;
  e.hash = hash;
  e.is_hash = true;
  if (!ring_.push(e)) dropped_.fetch_add(1);
}

void RecordingWriter::drain() {
  Entry e;
  bool any = false;
  while (ring_.pop(e)) {
    if (e.is_hash) std::fprintf(f_, "h %" PRId64 " %s\n", e.c.tick, hex16(e.hash).c_str());
    else std::fprintf(f_, "%s\n", format_command_line(e.c).c_str());
    any = true;
  }
  if (any) std::fflush(f_);
}

void RecordingWriter::writer_main() {
  while (!stop_.load()) {
    drain();
    for (int i = 0; i < 10 && !stop_.load(); ++i) std::this_thread::sleep_for(std::chrono::duration<double>(kFlushSeconds / 10));
  }
}

void RecordingWriter::finish(int64_t ticks, uint64_t state_hash, int64_t fault_tick) {
  stop_.store(true);
  if (thread_.joinable()) thread_.join();
  if (!f_) return;
  drain();
  if (fault_tick >= 0) std::fprintf(f_, "fault %" PRId64 "\n", fault_tick);
  std::fprintf(f_, "end %" PRId64 " %s\n", ticks, hex16(state_hash).c_str());
  std::fclose(f_);
  f_ = nullptr;
  if (std::rename((path_ + ".part").c_str(), path_.c_str()) != 0)
    throw InputError(path_, 0, "--record", "cannot rename the finished recording into place");
}

}  // namespace ps
