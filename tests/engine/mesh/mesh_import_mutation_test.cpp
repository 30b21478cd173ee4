// Seeded mutation loop over the mesh reader (engine/mesh/mesh_import.cpp), complementing the
// hand-picked corruptions of mesh_fuzz_test.cpp with volume: 10 000 mutated files (4 shards of
// 2 500, fixed seeds so a failure replays) from a unit cube in OBJ, ASCII/binary STL and
// ASCII/binary PLY. Each must import to a well-formed mesh or throw InputError naming the file;
// never another exception, a crash, a hang, or a huge allocation from a lying header.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "engine/mesh/mesh_import.h"
#include "engine/util/error.h"
#include "tests/time_budget.h"

namespace ps {
namespace {

const float kV[8][3] = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}, {0, 0, 10}, {10, 0, 10}, {10, 10, 10}, {0, 10, 10}};
const int kF[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                       {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};

struct Seed {
  std::string ext, data;
};

std::vector<Seed> seeds() {
  std::string obj, stl = "solid c\n", ply, bstl(80, ' '), bply;
  for (auto& v : kV) obj += "v " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
  for (auto& f : kF) obj += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + "\n";
  const uint32_t nf = 12;
  bstl.append(reinterpret_cast<const char*>(&nf), 4);
  for (auto& f : kF) {
    stl += "facet normal 0 0 0\nouter loop\n";
    const float n[3] = {0, 0, 0};
    bstl.append(reinterpret_cast<const char*>(n), 12);
    for (int i : f) {
      stl += "vertex " + std::to_string(kV[i][0]) + " " + std::to_string(kV[i][1]) + " " + std::to_string(kV[i][2]) + "\n";
      bstl.append(reinterpret_cast<const char*>(kV[i]), 12);
    }
    bstl.append(2, '\0');
    stl += "endloop\nendfacet\n";
  }
  stl += "endsolid c\n";
  const std::string head = "ply\nformat %s 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 12\nproperty list uchar int vertex_indices\nend_header\n";
  auto header = [&](const char* f) {
    std::string h = head;
    h.replace(h.find("%s"), 2, f);
    return h;
  };
  ply = header("ascii");
  for (auto& v : kV) ply += std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
  for (auto& f : kF) ply += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
  bply = header("binary_little_endian");
  for (auto& v : kV) bply.append(reinterpret_cast<const char*>(v), 12);
  for (auto& f : kF) {
    bply.push_back(3);
    bply.append(reinterpret_cast<const char*>(f), 12);
  }
  return {{"obj", obj}, {"stl", stl}, {"stl", bstl}, {"ply", ply}, {"ply", bply}};
}

std::string mutate(std::string s, std::mt19937_64& rng) {
  static const char* kTokens[] = {"nan", "1e999", "-inf", "4294967295", "2147483647", "-1", "0", "\n", " ", "/", "#",
                                  "element vertex 99999999999\n", "element face 4000000000\n", "f 1 2\n", "v 1\n"};
  const int n = 1 + static_cast<int>(rng() % 5);
  for (int k = 0; k < n && !s.empty(); ++k) {
    const size_t at = rng() % s.size();
    switch (rng() % 6) {
      case 0: s[at] = static_cast<char>(rng()); break;
      case 1: s.erase(at, 1 + rng() % 30); break;
      case 2: s.insert(at, s.substr(rng() % s.size(), 1 + rng() % 60)); break;
      case 3: s.insert(at, kTokens[rng() % (sizeof kTokens / sizeof *kTokens)]); break;
      case 4: s.resize(at); break;
      case 5: {  // a lying 32-bit count at a random aligned offset (binary headers, face lists)
        const uint32_t big = static_cast<uint32_t>(rng());
        if (at + 4 <= s.size()) std::memcpy(&s[at & ~size_t{3}], &big, 4);
        break;
      }
    }
  }
  return s;
}

void shard(uint64_t seed, int count) {
  const auto in = seeds();
  const auto dir = std::filesystem::temp_directory_path() / ("ps_mesh_mut_" + std::to_string(::getpid()) + "_" + std::to_string(seed));
  std::filesystem::create_directories(dir);
  std::mt19937_64 rng(seed);
  int errors = 0, valid = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < count; ++i) {
    const Seed& s = in[i % in.size()];
    const std::string data = mutate(s.data, rng);
    const std::string path = (dir / ("m." + s.ext)).string();
    { std::ofstream(path, std::ios::binary | std::ios::trunc) << data; }
    try {
      const TriMesh m = import_mesh(path, MeshImportOptions{"mm"});
      ++valid;
      for (const Vec3& v : m.vertices) ASSERT_TRUE(v.allFinite()) << "seed " << seed << " input " << i;
      for (const auto& f : m.faces)
        for (int k : f) ASSERT_TRUE(k >= 0 && static_cast<size_t>(k) < m.vertices.size()) << "seed " << seed << " input " << i;
    } catch (const InputError& e) {
      ++errors;
      ASSERT_EQ(e.file(), path);
    } catch (const std::exception& e) {
      FAIL() << "seed " << seed << " input " << i << " (" << s.ext << "): " << typeid(e).name() << ": " << e.what();
    }
  }
  std::filesystem::remove_all(dir);
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ mutate   ] seed %llu: %d inputs, %d InputError, %d valid, %.2f s\n", static_cast<unsigned long long>(seed), count,
              errors, valid, sec);
  EXPECT_GT(errors, count / 10);
  EXPECT_LT(sec, ps::test::time_budget(60.0));
}

TEST(MeshImportMutation, Shard1) { shard(11, 2500); }
TEST(MeshImportMutation, Shard2) { shard(12, 2500); }
TEST(MeshImportMutation, Shard3) { shard(13, 2500); }
TEST(MeshImportMutation, Shard4) { shard(14, 2500); }

}  // namespace
}  // namespace ps
