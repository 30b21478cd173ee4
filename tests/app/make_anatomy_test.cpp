// `prostatesim make-anatomy` reproduces the committed assets byte for byte, `check` compiles
// the default scenario within its time budget, and bad organ meshes (issue 3, "Bad input") stop
// `simulate` with exit code 2, one error line naming the file and the problem, nothing written.
#include <gtest/gtest.h>

#include "tests/app/run_cli.h"
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

namespace fs = std::filesystem;

using Result = ps::test::CliResult;
using ps::test::run_cli;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(MakeAnatomy, ReproducesTheCommittedAssets) {
  const fs::path out = ps::test::cli_temp_dir("anatomy");
  fs::remove_all(out);   // make-anatomy creates it
  const Result r = run_cli("make-anatomy --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("prostate"), std::string::npos);
  EXPECT_NE(r.out.find("29.43"), std::string::npos) << r.out;   // prostate volume [cm^3]
  const fs::path assets = fs::path(PROSTATESIM_SOURCE_DIR) / "assets" / "anatomy";
  int files = 0;
  for (const auto& e : fs::directory_iterator(out)) {
    ++files;
    EXPECT_TRUE(slurp(e.path()) == slurp(assets / e.path().filename())) << e.path().filename() << " differs from the committed asset";
  }
  EXPECT_EQ(files, 10);  // five organ meshes, the seminal vesicles and the pubic bone as drawn, landmarks, the urethra line and the calcifications
  fs::remove_all(out);
}

TEST(MakeAnatomy, CheckCompilesTheDefaultScenario) {
  const Result r = run_cli("check " + (fs::path(PROSTATESIM_SOURCE_DIR) / "config" / "biopsy.yaml").string());
  ASSERT_EQ(r.code, 0) << r.out;
  double seconds = -1, cpu = -1;
  const size_t at = r.out.find("compiled in ");
  ASSERT_NE(at, std::string::npos) << r.out;
  std::sscanf(r.out.c_str() + at, "compiled in %lf s, %lf s CPU", &seconds, &cpu);
  EXPECT_GT(seconds, 0.0);
  EXPECT_GT(cpu, 0.0) << r.out;  // how long is a benchmark: BM_CompileScenario (bench/compile_bench.cpp)
  EXPECT_EQ(r.out.find("warning"), std::string::npos) << r.out;
}

// One scene with one volumetric organ mesh written into a fresh folder; returns the output of
// `simulate` (exit code and text) and whether it wrote its --out folder.
struct BadMeshRun {
  Result r;
  bool wrote = false;
};

BadMeshRun simulate_mesh(const std::string& name, const std::string& mesh_bytes, const std::string& mesh_keys) {
  const fs::path dir = ps::test::cli_temp_dir("badmesh_" + name);
  const std::string file = name.substr(0, name.find('.')) == name ? name + ".obj" : name;
  std::ofstream(dir / file, std::ios::binary) << mesh_bytes;
  std::ofstream(dir / "scene.yaml") << "name: bad_mesh\n"
                                       "materials:\n  m: {young_kpa: 10, density_kg_m3: 1000}\n"
                                       "components:\n"
                                       "  - {name: organ, material: m, spacing_mm: 3, mesh: {file: " + file + ", " + mesh_keys + "}}\n";
  BadMeshRun b;
  b.r = run_cli("simulate " + (dir / "scene.yaml").string() + " --out " + (dir / "out").string());
  b.wrote = fs::exists(dir / "out");
  fs::remove_all(dir);
  return b;
}

void expect_one_error(const BadMeshRun& b, const std::string& file, const std::string& what) {
  EXPECT_EQ(b.r.code, 2) << b.r.out;
  EXPECT_NE(b.r.out.find(file), std::string::npos) << b.r.out;
  EXPECT_NE(b.r.out.find(what), std::string::npos) << b.r.out;
  EXPECT_EQ(std::count(b.r.out.begin(), b.r.out.end(), '\n'), 1) << "one error line: " << b.r.out;
  EXPECT_FALSE(b.wrote);
}

// a 10 mm tetrahedron, outward
const char* kTetra = "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";

// config/biopsy.yaml with its bladder moved by translate_mm (a wrong placement or unit).
BadMeshRun simulate_moved_bladder(const std::string& name, const std::string& translate_mm) {
  const fs::path dir = ps::test::cli_temp_dir("badmesh_" + name);
  std::string y = slurp(fs::path(PROSTATESIM_SOURCE_DIR) / "config" / "biopsy.yaml");
  const std::string assets = (fs::path(PROSTATESIM_SOURCE_DIR) / "assets" / "anatomy").string() + "/";
  for (size_t at; (at = y.find("../assets/anatomy/")) != std::string::npos;) y.replace(at, 18, assets);
  const std::string bladder = "bladder.obj, units: mm}";
  y.replace(y.find(bladder), bladder.size(), "bladder.obj, units: mm, translate_mm: " + translate_mm + "}");
  std::ofstream(dir / (name + ".yaml")) << y;
  BadMeshRun b;
  b.r = run_cli("simulate " + (dir / (name + ".yaml")).string() + " --out " + (dir / "out").string());
  b.wrote = fs::exists(dir / "out");
  fs::remove_all(dir);
  return b;
}

TEST(AnatomyBadInput, MisplacedOrgansInTheDefaultSceneExit2) {
  // 2 m up (e.g. a CT's scanner coordinates, or cm read as mm): outside the fat that holds it
  expect_one_error(simulate_moved_bladder("far", "[0, 0, 2000]"), "far.yaml", "'bladder' is not inside 'fat'");
  // 25 mm down: into the prostate
  expect_one_error(simulate_moved_bladder("overlap", "[0, 0, -25]"), "overlap.yaml", "overlap");
}

TEST(AnatomyBadInput, BadOrganMeshesExit2NamingTheFileAndWriteNothing) {
  // open surface given for a volumetric fill
  expect_one_error(simulate_mesh("open", "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nf 1 3 2\nf 1 2 4\nf 2 3 4\n", "units: mm"),
                   "open.obj", "open surface");
  // zero-area face (M on edge AB closes the surface with a flat triangle A-B-M)
  expect_one_error(simulate_mesh("flat", "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nv 5 0 0\n"
                                         "f 1 3 2\nf 1 5 4\nf 5 2 4\nf 1 2 5\nf 2 3 4\nf 1 4 3\n", "units: mm"),
                   "flat.obj", "zero-area");
  // truncated binary STL: header promises more triangles than the file holds
  std::string stl(80, ' ');
  const uint32_t n = 1000;
  stl.append(reinterpret_cast<const char*>(&n), 4);
  stl.append(150, '\0');
  expect_one_error(simulate_mesh("cut.stl", stl, "units: mm"), "cut.stl", "corrupt binary STL");
  // not a mesh at all
  expect_one_error(simulate_mesh("text.ply", "hello\n", "units: mm"), "text.ply", "not a PLY file");
  // wrong units: a 10 mm organ declared in metres is 17 m across
  expect_one_error(simulate_mesh("big", kTetra, "units: m"), "big.obj", "wrong units?");
}

}  // namespace
