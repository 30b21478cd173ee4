// Seeded mutation fuzzing of the script and recording readers (engine/realtime/script.h and
// recording.h, from the real-time work): 10 000 mutated inputs each (4 shards of 2 500, fixed
// seeds so a failure replays), from config/scripts/*.yaml and from recordings written by
// format_command_line. Each must parse or throw InputError naming the file; never another
// exception, a crash or a hang. Compiled only where those readers exist (__has_include), so this
// file can land before them.
#if __has_include("engine/realtime/script.h") && __has_include("engine/realtime/recording.h")
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <random>
#include <sstream>

#include "engine/realtime/recording.h"
#include "engine/realtime/script.h"
#include "engine/util/error.h"

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
  EXPECT_LT(sec, 60.0);
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
    c.insertion = 0.01 * k;
    c.value = 1e-6 * k;
    text += format_command_line(c) + "\n";
  }
  return {text, text + "end 20 0123456789abcdef\n"};
}

void script_shard(uint64_t seed) {
  shard(script_seeds(), seed, 2500, "fuzz.yaml", [](const std::string& t) { parse_script_text(t, "fuzz.yaml"); });
}
void recording_shard(uint64_t seed) {
  shard(recording_seeds(), seed, 2500, "fuzz.rec", [](const std::string& t) { parse_recording_text(t, "fuzz.rec"); });
}

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
