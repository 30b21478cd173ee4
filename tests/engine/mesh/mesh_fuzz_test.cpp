// Corrupt-input robustness of import_mesh: hundreds of mutated files (random bytes, truncated
// real files, flipped bytes, NaN coordinates, lying headers) must each give an InputError or,
// when the mutation happens to be a valid file, a well-formed mesh. Never a crash, another
// exception type, or a hang (the whole test is timed).
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <typeinfo>
#include <unistd.h>
#include <vector>

#include "engine/mesh/mesh_import.h"
#include "engine/util/error.h"
#include "tests/time_budget.h"

namespace ps {
namespace {

const std::string kData = PROSTATESIM_SHARED_DATA;

struct Case {
  std::string name;
  std::string ext;   // "stl", "obj", "ply"
  std::string data;
  bool must_fail;    // true: only an InputError is acceptable
};

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const double kCubeV[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                             {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
const int kCubeF[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                           {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string ascii_stl() {
  std::string s = "solid cube\n";
  for (const auto& f : kCubeF) {
    s += "facet normal 0 0 0\nouter loop\n";
    for (int i : f) s += "vertex " + num(kCubeV[i][0]) + " " + num(kCubeV[i][1]) + " " + num(kCubeV[i][2]) + "\n";
    s += "endloop\nendfacet\n";
  }
  return s + "endsolid cube\n";
}

std::string binary_stl() {
  std::string s(80, 'x');
  const uint32_t n = 12;
  s.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& f : kCubeF) {
    const float zero[3] = {0, 0, 0};
    s.append(reinterpret_cast<const char*>(zero), 12);
    for (int i : f)
      for (int k = 0; k < 3; ++k) {
        const float c = static_cast<float>(kCubeV[i][k]);
        s.append(reinterpret_cast<const char*>(&c), 4);
      }
    s.append(2, '\0');
  }
  return s;
}

std::string obj() {
  std::string s;
  for (const auto& v : kCubeV) s += "v " + num(v[0]) + " " + num(v[1]) + " " + num(v[2]) + "\n";
  for (const auto& f : kCubeF)
    s += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + "\n";
  return s;
}

const char* kPlyHeader =
    "element vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 12\nproperty list uchar int vertex_indices\nend_header\n";

std::string ascii_ply() {
  std::string s = std::string("ply\nformat ascii 1.0\n") + kPlyHeader;
  for (const auto& v : kCubeV) s += num(v[0]) + " " + num(v[1]) + " " + num(v[2]) + "\n";
  for (const auto& f : kCubeF)
    s += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
  return s;
}

std::string binary_ply() {
  std::string s = std::string("ply\nformat binary_little_endian 1.0\n") + kPlyHeader;
  for (const auto& v : kCubeV)
    for (double c : v) {
      const float f = static_cast<float>(c);
      s.append(reinterpret_cast<const char*>(&f), 4);
    }
  for (const auto& f : kCubeF) {
    s += '\3';
    for (int i : f) s.append(reinterpret_cast<const char*>(&i), 4);
  }
  return s;
}

std::string replace_first(std::string s, const std::string& from, const std::string& to) {
  const size_t p = s.find(from);
  if (p != std::string::npos) s.replace(p, from.size(), to);
  return s;
}

std::vector<Case> make_cases() {
  std::mt19937 rng(20240611);   // fixed: the same cases every run
  auto uniform = [&](size_t lo, size_t hi) { return std::uniform_int_distribution<size_t>(lo, hi)(rng); };
  std::vector<Case> cases;

  struct Seed {
    std::string name, ext, data;
  };
  const std::vector<Seed> seeds = {
      {"phantom", "stl", read_file(kData + "/prostate_phantom/prostate.stl")},
      {"inner0", "stl", read_file(kData + "/prostate_phantom/inner_0.stl")},
      {"pelvis", "obj", read_file(kData + "/pelvis_bone/pelvis_f.obj")},
      {"cylinder", "obj", read_file(kData + "/truth_cylinder/cylinder_Surface.obj")},
      {"ascii_stl", "stl", ascii_stl()},
      {"binary_stl", "stl", binary_stl()},
      {"obj", "obj", obj()},
      {"ascii_ply", "ply", ascii_ply()},
      {"binary_ply", "ply", binary_ply()},
  };
  for (const auto& s : seeds) EXPECT_GT(s.data.size(), 100u) << s.name << " seed is missing";

  // Empty files.
  for (const char* ext : {"stl", "obj", "ply"}) cases.push_back({"empty", ext, "", true});

  // Random bytes of random length.
  for (int i = 0; i < 60; ++i) {
    std::string d(uniform(1, 4000), '\0');
    for (char& c : d) c = static_cast<char>(uniform(0, 255));
    cases.push_back({"random" + std::to_string(i), i % 3 == 0 ? "stl" : i % 3 == 1 ? "obj" : "ply", d, false});
  }

  // Truncated copies at many cut points (the big files at fewer points: each parse costs more).
  for (const auto& s : seeds) {
    const int cuts = s.data.size() > 100000 ? 25 : 30;
    std::vector<size_t> at = {0, 1, 5, 80, 83, 84, 85, 134, s.data.size() / 2, s.data.size() - 1};
    while (static_cast<int>(at.size()) < cuts) at.push_back(uniform(0, s.data.size() - 1));
    for (size_t cut : at) {
      if (cut >= s.data.size()) continue;
      cases.push_back({s.name + "_cut" + std::to_string(cut), s.ext, s.data.substr(0, cut), cut == 0});
    }
  }

  // Random byte flips and text-like substitutions on the small seeds.
  for (int i = 0; i < 80; ++i) {
    const Seed& s = seeds[4 + i % 5];
    std::string d = s.data;
    const int n = static_cast<int>(uniform(1, 12));
    for (int k = 0; k < n; ++k) {
      const size_t p = uniform(0, d.size() - 1);
      d[p] = i % 2 ? static_cast<char>(uniform(0, 255)) : "0123456789 -.+eE\n/#fvnai"[uniform(0, 24)];
    }
    cases.push_back({s.name + "_flip" + std::to_string(i), s.ext, d, false});
  }

  // Spliced pieces of the same file.
  for (int i = 0; i < 20; ++i) {
    const Seed& s = seeds[4 + i % 5];
    const size_t a = uniform(0, s.data.size()), b = uniform(0, s.data.size());
    cases.push_back({s.name + "_splice" + std::to_string(i), s.ext, s.data.substr(0, a) + s.data.substr(b), false});
  }

  // Non-finite coordinates: always an error.
  for (const char* bad : {"nan", "NaN", "inf", "-inf", "1e999", "-1e400"}) {
    cases.push_back({std::string("stl_") + bad, "stl", replace_first(ascii_stl(), "vertex 1 0 0", std::string("vertex ") + bad + " 0 0"), true});
    cases.push_back({std::string("obj_") + bad, "obj", replace_first(obj(), "v 1 1 0", std::string("v 1 ") + bad + " 0"), true});
    cases.push_back({std::string("ply_") + bad, "ply", replace_first(ascii_ply(), "\n1 1 0\n", std::string("\n1 1 ") + bad + "\n"), true});
  }
  {
    std::string d = binary_stl();
    const float nan = NAN;
    std::memcpy(&d[84 + 12 + 4], &nan, 4);
    cases.push_back({"binary_stl_nan", "stl", d, true});
  }

  // Lying headers and structural nonsense: always an error.
  {
    std::string h(80, '\0');
    for (uint32_t n : {1u << 31, 0xffffffffu, 2147483660u /* 84 + 50n wraps to the file size */, 13u, 0u}) {
      std::string d = h;
      d.append(reinterpret_cast<const char*>(&n), 4);
      d += binary_stl().substr(84);
      cases.push_back({"stl_count" + std::to_string(n), "stl", d, true});
    }
    cases.push_back({"solid_binary", "stl", "solid " + std::string(200, '\x01'), true});
  }
  const std::string ply_tail = "property float x\nproperty float y\nproperty float z\n";
  cases.push_back({"ply_huge_vertices", "ply", "ply\nformat ascii 1.0\nelement vertex 4000000000\n" + ply_tail + "end_header\n", true});
  cases.push_back({"ply_huge_faces", "ply", replace_first(ascii_ply(), "element face 12", "element face 2000000000"), true});
  cases.push_back({"ply_long_list", "ply", replace_first(ascii_ply(), "\n3 0 2 1\n", "\n2147483647 0 2 1\n"), true});
  cases.push_back({"ply_empty_face", "ply", replace_first(ascii_ply(), "\n3 0 2 1\n", "\n0\n"), true});
  cases.push_back({"ply_two_index_face", "ply", replace_first(ascii_ply(), "\n3 0 2 1\n", "\n2 0 2\n"), true});
  cases.push_back({"ply_index_range", "ply", replace_first(ascii_ply(), "\n3 0 2 1\n", "\n3 0 2 99\n"), true});
  cases.push_back({"ply_negative_index", "ply", replace_first(ascii_ply(), "\n3 0 2 1\n", "\n3 0 2 -1\n"), true});
  cases.push_back({"ply_one_line", "ply", std::string("ply\nformat ascii 1.0\n") + kPlyHeader + "0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1\n", true});
  cases.push_back({"ply_no_end_header", "ply", replace_first(ascii_ply(), "end_header", "end_headr"), true});
  // A property named end_header is legal: the header ends only at a line of its own.
  cases.push_back({"ply_end_header_in_property", "ply", replace_first(ascii_ply(), "property float z\n", "property float end_header\n"), false});
  cases.push_back({"ply_bad_type", "ply", replace_first(ascii_ply(), "property float z", "property quad z"), true});
  cases.push_back({"ply_no_format", "ply", replace_first(ascii_ply(), "format ascii 1.0\n", ""), true});
  {
    std::string d = binary_ply();
    const size_t body = d.find("end_header\n") + 11;
    const int32_t huge = 0x7fffffff;
    d[body + 8 * 12] = '\xff';   // first face: 255 indices declared, 12 bytes present
    cases.push_back({"ply_binary_list_overrun", "ply", d, true});
    std::string e = replace_first(binary_ply(), "property list uchar int", "property list int int");
    const size_t eb = e.find("end_header\n") + 11;
    e = e.substr(0, eb + 96) + std::string(reinterpret_cast<const char*>(&huge), 4) + e.substr(eb + 97);
    cases.push_back({"ply_binary_int_count", "ply", e, true});
  }
  cases.push_back({"obj_index_range", "obj", obj() + "f 1 2 99\n", true});
  cases.push_back({"obj_index_zero", "obj", obj() + "f 1 2 0\n", true});
  cases.push_back({"obj_negative_range", "obj", obj() + "f 1 2 -99\n", true});
  {
    std::string big = obj() + "f";
    for (int i = 0; i < 5000; ++i) big += " " + std::to_string(1 + i % 8);
    cases.push_back({"obj_giant_polygon", "obj", big + "\n", true});
  }
  cases.push_back({"obj_no_faces", "obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", true});
  cases.push_back({"obj_lines_only", "obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n", true});
  cases.push_back({"obj_binary", "obj", std::string("v 0 0 0\n\0\0\0f 1 2 3\n", 20), true});
  cases.push_back({"obj_mtllib_elsewhere", "obj", "mtllib /dev/zero\nmtllib ../../../../etc/passwd\n" + obj(), false});
  return cases;
}

TEST(MeshFuzz, CorruptInputGivesInputErrorOrValidMesh) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto dir = std::filesystem::temp_directory_path() / ("ps_mesh_fuzz_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::vector<Case> cases = make_cases();
  int errors = 0, valid = 0;
  for (size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const std::string path = (dir / (std::to_string(i) + "_" + c.name + "." + c.ext)).string();
    std::ofstream(path, std::ios::binary) << c.data;
    try {
      const TriMesh m = import_mesh(path);
      ++valid;
      EXPECT_FALSE(c.must_fail) << c.name << ": imported, expected an InputError";
      EXPECT_FALSE(m.faces.empty()) << c.name;
      for (const Vec3& v : m.vertices) EXPECT_TRUE(v.allFinite()) << c.name;
      for (const auto& f : m.faces)
        for (int k : f) ASSERT_TRUE(k >= 0 && size_t(k) < m.vertices.size()) << c.name;
    } catch (const InputError& e) {
      ++errors;
      EXPECT_EQ(e.file(), path) << c.name;
      EXPECT_GT(std::strlen(e.what()), path.size() + 5) << c.name << ": no reason given";
    } catch (const std::exception& e) {
      ADD_FAILURE() << c.name << ": " << typeid(e).name() << " instead of InputError: " << e.what();
    }
    std::filesystem::remove(path);
  }
  std::filesystem::remove_all(dir);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("[ fuzz     ] %zu inputs: %d InputError, %d valid, %.2f s\n", cases.size(), errors, valid, seconds);
  EXPECT_GE(cases.size(), 200u);
  EXPECT_GT(errors, 150);
  EXPECT_LT(seconds, ps::test::time_budget(20.0));
}

}  // namespace
}  // namespace ps
