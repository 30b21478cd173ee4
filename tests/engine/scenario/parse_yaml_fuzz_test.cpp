// Seeded mutation fuzzing of the scenario reader (engine/scenario/parse_yaml.cpp): 10 000 mutated
// scenario texts (4 shards of 2 500, seeds fixed so a failure replays) built from the test cube
// and the shipped scenes. Each must parse or throw InputError naming the file; never another
// exception, a crash or a hang. Mutations: byte flips, deleted and duplicated ranges, inserted
// YAML punctuation, numbers replaced by extreme values (1e308, -0, nan, 1e-320, huge integers).
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <random>
#include <sstream>

#include "engine/scenario/parse_yaml.h"
#include "engine/util/error.h"
#include "tests/engine/test_scenes.h"
#include "tests/time_budget.h"

namespace ps {
namespace {

std::string read_text(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> seeds() {
  const std::string dir = std::string(PROSTATESIM_SOURCE_DIR) + "/config/";
  return {test::cube_yaml(40, 10, true), read_text(dir + "biopsy.yaml"), read_text(dir + "brachytherapy.yaml"),
          read_text(dir + "bladder_filling.yaml"), read_text(dir + "validation/cube_bonded.yaml")};
}

std::string mutate(std::string s, std::mt19937_64& rng) {
  static const char* kTokens[] = {"1e308", "-0", ".nan", "-.inf", "1e-320", "99999999999999999999", "[", "]", "{", "}",
                                  ":", "- ", "\n", "  ", "&a", "*a", "!!binary", "\"", "'", "#", "0x7fffffff", "~", ",",
                                  "<<: *a", "? ", "|", ">", "%YAML 1.2\n---\n", "\t", "\xff\xfe", std::string(1, '\0').c_str()};
  std::uniform_int_distribution<int> op(0, 5);
  const int n = 1 + static_cast<int>(rng() % 4);
  for (int k = 0; k < n && !s.empty(); ++k) {
    std::uniform_int_distribution<size_t> at(0, s.size() - 1);
    switch (op(rng)) {
      case 0: s[at(rng)] ^= static_cast<char>(1 << (rng() % 8)); break;
      case 1: { const size_t a = at(rng); s.erase(a, 1 + rng() % 40); break; }
      case 2: { const size_t a = at(rng), b = at(rng); s.insert(a, s.substr(std::min(a, b), 1 + rng() % 80)); break; }
      case 3: s.insert(at(rng), kTokens[rng() % (sizeof kTokens / sizeof *kTokens)]); break;
      case 4: {  // replace a number by an extreme one
        const size_t a = s.find_first_of("0123456789", at(rng));
        if (a == std::string::npos) break;
        const size_t e = s.find_first_not_of("0123456789.e-", a);
        s.replace(a, (e == std::string::npos ? s.size() : e) - a, kTokens[rng() % 6]);
        break;
      }
      case 5: s.resize(at(rng)); break;  // truncated file
    }
  }
  return s;
}

void fuzz_shard(uint64_t seed, int count) {
  const auto inputs = seeds();
  std::mt19937_64 rng(seed);
  int parsed = 0, refused = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < count; ++i) {
    const std::string text = mutate(inputs[i % inputs.size()], rng);
    try {
      parse_scenario_text(text, "fuzz.yaml");
      ++parsed;
    } catch (const InputError& e) {
      ++refused;
      ASSERT_EQ(e.file(), "fuzz.yaml") << "seed " << seed << " input " << i;
    } catch (const std::exception& e) {
      FAIL() << "seed " << seed << " input " << i << ": " << typeid(e).name() << ": " << e.what() << "\n--- input ---\n" << text;
    }
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(s, ps::test::time_budget(60.0)) << "parsing " << count << " inputs took " << s << " s (a hang?)";
  EXPECT_GT(refused, count / 10);  // the mutations do reach the error paths
  ::testing::Test::RecordProperty("parsed", parsed);
}

TEST(ParseYamlFuzz, Shard1) { fuzz_shard(1, 2500); }
TEST(ParseYamlFuzz, Shard2) { fuzz_shard(2, 2500); }
TEST(ParseYamlFuzz, Shard3) { fuzz_shard(3, 2500); }
TEST(ParseYamlFuzz, Shard4) { fuzz_shard(4, 2500); }

}  // namespace
}  // namespace ps
