// Seeded mutation fuzzing of the script, recording and saved-state readers
// (engine/realtime/script.h, recording.h, state_file.h): 10 000 mutated inputs each (4 shards of
// 2 500, fixed seeds so a failure replays), from config/scripts/*.yaml, from recordings written by
// format_command_line (versions 1 and 2) and from a state file written by write_state_file. Each must parse or throw InputError naming the file; never another
// exception, a crash or a hang. Compiled only where those readers exist (__has_include), so this
// file can land before them.
#if __has_include("engine/realtime/script.h") && __has_include("engine/realtime/recording.h")
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "engine/realtime/recording.h"
#include "engine/realtime/script.h"
#include "engine/realtime/state_file.h"
#include "engine/util/error.h"
#include "tests/time_budget.h"

namespace ps {
namespace {

std::string read_text(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string mutate(std::string s, std::mt19937_64& rng) {
  static const char* kTokens[] = {"1e308", "-0", "nan", ".nan", "-inf", "1e-320", "99999999999999999999", "-1",
                                  "[", "]", "{", "}", ":", "- ", "\n", " ", "c ", "end ", "probe_move", "\t", "#",
                                  "ffffffffffffffff", "9223372036854775807", "&a", "*a", "\xff"};
  const int n = 1 + static_cast<int>(rng() % 4);
  for (int k = 0; k < n && !s.empty(); ++k) {
    const size_t at = rng() % s.size();
    switch (rng() % 5) {
      case 0: s[at] ^= static_cast<char>(1 << (rng() % 8)); break;
      case 1: s.erase(at, 1 + rng() % 30); break;
      case 2: s.insert(at, s.substr(rng() % s.size(), 1 + rng() % 80)); break;
      case 3: s.insert(at, kTokens[rng() % (sizeof kTokens / sizeof *kTokens)]); break;
      case 4: s.resize(at); break;
    }
  }
  return s;
}

template <class Parse>
void shard(const std::vector<std::string>& seeds, uint64_t seed, int count, const char* file, Parse parse) {
  std::mt19937_64 rng(seed);
  int refused = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < count; ++i) {
    const std::string text = mutate(seeds[i % seeds.size()], rng);
    try {
      parse(text);
    } catch (const InputError& e) {
      ++refused;
      ASSERT_EQ(e.file(), file) << "seed " << seed << " input " << i;
    } catch (const std::exception& e) {
      FAIL() << "seed " << seed << " input " << i << ": " << typeid(e).name() << ": " << e.what() << "\n--- input ---\n" << text;
    }
  }
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(sec, ps::test::time_budget(60.0));
  EXPECT_GT(refused, count / 10);
}

std::vector<std::string> script_seeds() {
  const std::string d = std::string(PROSTATESIM_SOURCE_DIR) + "/config/scripts/";
  return {read_text(d + "biopsy.yaml"), read_text(d + "brachytherapy.yaml")};
}

std::vector<std::string> recording_seeds() {
  std::string text = std::string("prostatesim-recording 1\nprogram ") + kProgramVersion +
                     "\nscenario s\nscenario_hash 0123456789abcdef\ndt 0.001\nsubsteps 2\n";
  Command c;
  for (int k = 0; k < 6; ++k) {
    c.tick = 3 * k;
    c.probe.insertion = 0.01 * k;
    c.probe.duration = 1e-6 * k;
    text += format_command_line(c) + "\n";
  }
  // version 2: hash_every, periodic hashes, a fault line
  std::string v2 = std::string("prostatesim-recording 2\nprogram ") + kProgramVersion +
                   "\nscenario s\nscenario_hash 0123456789abcdef\ndt 0.001\nsubsteps 2\nhash_every 5\n";
  for (int k = 0; k < 6; ++k) {
    c.tick = 3 * k;
    v2 += format_command_line(c) + "\n";
    if (k % 2 == 1) v2 += "h " + std::to_string(5 * (k / 2 + 1)) + " 00000000000000a" + std::to_string(k) + "\n";
  }
  return {text, text + "end 20 0123456789abcdef\n", v2 + "fault 19\nend 19 0123456789abcdef\n"};
}

// saved states (engine/realtime/state_file.h): header and bytes
std::vector<std::string> state_seeds() {
  SavedState st;
  st.scenario = "s";
  st.scenario_hash = 0x0123456789abcdefull;
  st.tick = 42;
  st.time = 0.042;
  st.fault = "tick 42: t=0.042 s: particle 3 (component 'prostate') position or velocity is NaN/Inf";
  for (int i = 0; i < 200; ++i) st.bytes.push_back(static_cast<uint8_t>(i * 37));
  st.state_hash = saved_state_hash(st.bytes);
  const std::string path = (std::filesystem::temp_directory_path() / ("ps_fuzz_state_" + std::to_string(::getpid()))).string();
  write_state_file(path, st);
  const std::string text = read_text(path);
  std::filesystem::remove(path);
  return {text};
}

void script_shard(uint64_t seed) {
  shard(script_seeds(), seed, 2500, "fuzz.yaml", [](const std::string& t) { parse_script_text(t, "fuzz.yaml"); });
}
void recording_shard(uint64_t seed) {
  shard(recording_seeds(), seed, 2500, "fuzz.rec", [](const std::string& t) { parse_recording_text(t, "fuzz.rec"); });
}

void state_shard(uint64_t seed) {
  shard(state_seeds(), seed, 2500, "fuzz.state", [](const std::string& t) { parse_state_text(t, "fuzz.state"); });
}

TEST(StateFileReaderFuzz, Shard1) { state_shard(41); }
TEST(StateFileReaderFuzz, Shard2) { state_shard(42); }
TEST(StateFileReaderFuzz, Shard3) { state_shard(43); }
TEST(StateFileReaderFuzz, Shard4) { state_shard(44); }
TEST(ScriptReaderFuzz, Shard1) { script_shard(21); }
TEST(ScriptReaderFuzz, Shard2) { script_shard(22); }
TEST(ScriptReaderFuzz, Shard3) { script_shard(23); }
TEST(ScriptReaderFuzz, Shard4) { script_shard(24); }
TEST(RecordingReaderFuzz, Shard1) { recording_shard(31); }
TEST(RecordingReaderFuzz, Shard2) { recording_shard(32); }
TEST(RecordingReaderFuzz, Shard3) { recording_shard(33); }
TEST(RecordingReaderFuzz, Shard4) { recording_shard(34); }

}  // namespace
}  // namespace ps
#endif
