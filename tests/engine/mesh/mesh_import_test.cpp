// Import of real reference meshes and of small files written here, units and placement, and the
// error messages for bad input.
#include "engine/mesh/mesh_import.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "engine/mesh/mesh_check.h"
#include "engine/util/error.h"

namespace ps {
namespace {

const std::string kData = PROSTATESIM_SHARED_DATA;
const std::string kPhantom = kData + "/prostate_phantom/prostate.stl";
const std::string kPelvis = kData + "/pelvis_bone/pelvis_f.obj";

const double kCubeV[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                             {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
const int kCubeF[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                           {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};

class TempDir {
 public:
  TempDir() {
    path_ = std::filesystem::temp_directory_path() /
            ("ps_mesh_import_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name, const std::string& content) const {
    const std::string p = (path_ / name).string();
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }

 private:
  std::filesystem::path path_;
};

std::string cube_ascii_stl() {
  std::string s = "solid cube\n";
  for (const auto& f : kCubeF) {
    s += "  facet normal 0 0 0\n    outer loop\n";
    for (int i : f)
      s += "      vertex " + std::to_string(kCubeV[i][0]) + " " + std::to_string(kCubeV[i][1]) + " " +
           std::to_string(kCubeV[i][2]) + "\n";
    s += "    endloop\n  endfacet\n";
  }
  return s + "endsolid cube\n";
}

std::string cube_ascii_ply() {
  std::string s =
      "ply\nformat ascii 1.0\ncomment unit cube\nelement vertex 8\nproperty float x\nproperty float y\n"
      "property float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& v : kCubeV)
    s += std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
  for (const auto& f : kCubeF)
    s += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
  return s;
}

std::string cube_binary_ply() {
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
      "property float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n";
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

// The cube as OBJ with quads (exercises aiProcess_Triangulate).
std::string cube_quad_obj() {
  std::string s = "# unit cube, quads\n";
  for (const auto& v : kCubeV)
    s += "v " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
  s += "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n";
  return s;
}

void expect_unit_cube(const TriMesh& m) {
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(m.faces.size(), 12u);
  EXPECT_NEAR(signed_volume(m), 1.0, 1e-9);
  EXPECT_TRUE(check_mesh(m).valid_solid()) << check_mesh(m).summary();
}

// Runs f, expects an InputError naming `file` whose message contains `what`.
template <class F>
void expect_input_error(F f, const std::string& file, const std::string& what) {
  try {
    f();
    ADD_FAILURE() << "no InputError for " << file;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file);
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

TEST(MeshImport, PhantomStlIsClosedWithPublishedVolume) {
  MeshImportOptions opt;
  opt.units = "mm";
  const TriMesh m = import_mesh(kPhantom, opt);
  EXPECT_EQ(m.faces.size(), 8084u);
  EXPECT_EQ(m.vertices.size(), 4052u);
  const MeshReport r = check_mesh(m);
  EXPECT_TRUE(r.closed()) << r.summary();
  EXPECT_EQ(r.non_manifold_vertices, 0);
  EXPECT_EQ(r.inconsistent_edges, 0);
  EXPECT_EQ(r.degenerate_faces, 0);
  // Measured: besides the gland (8052 faces) the file holds four 8-face specks of ~20 um,
  // oriented inward; they carry ~1e-6 mm^3 and do not affect the volume.
  EXPECT_EQ(r.components, 5);
  EXPECT_NEAR(std::abs(r.signed_volume), 26.3e-6, 0.01 * 26.3e-6);   // 26.3 cm^3
  EXPECT_NEAR(signed_volume(m), 26.327e-6, 0.001e-6);
  Vec3 lo = m.vertices[0], hi = lo;
  for (const Vec3& v : m.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  EXPECT_NEAR(hi.x() - lo.x(), 0.0401, 0.0005);   // README: 40 x 32 x 38 mm
  EXPECT_NEAR(hi.y() - lo.y(), 0.0323, 0.0005);
  EXPECT_NEAR(hi.z() - lo.z(), 0.0384, 0.0005);

  RepairStats st;
  const TriMesh fixed = repair_closed_surface(m, kPhantom, &st);
  EXPECT_TRUE(check_mesh(fixed).valid_solid()) << check_mesh(fixed).summary();
  EXPECT_EQ(st.merged_vertices, 0);
  EXPECT_EQ(st.flipped_faces, 32);   // the four inward specks, 8 faces each
  EXPECT_NEAR(signed_volume(fixed), signed_volume(m), 1e-9 * signed_volume(m));
}

TEST(MeshImport, PelvisObjInDecimetresIsAClosedTorus) {
  MeshImportOptions opt;
  opt.units = "dm";
  const TriMesh m = import_mesh(kPelvis, opt);
  EXPECT_EQ(m.vertices.size(), 4884u);
  EXPECT_EQ(m.faces.size(), 9768u);
  const MeshReport r = check_mesh(m);
  // Measured: closed, manifold, outward, one component, Euler characteristic V - F/2 = 0,
  // i.e. genus 1 (the obturator foramen is a hole through the bone).
  EXPECT_TRUE(r.valid_solid()) << r.summary();
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(r.vertices - r.faces / 2, 0);
  EXPECT_NEAR(r.signed_volume, 230.77e-6, 0.01e-6);   // 231 cm^3 at decimetres
  Vec3 lo = m.vertices[0], hi = lo;
  for (const Vec3& v : m.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double diag = (hi - lo).norm();
  EXPECT_GT(diag, 0.15);   // a hip bone is ~0.2-0.3 m across
  EXPECT_LT(diag, 0.35);
}

TEST(MeshImport, AsciiStlCube) {
  TempDir dir;
  expect_unit_cube(import_mesh(dir.file("cube.stl", cube_ascii_stl())));
}

TEST(MeshImport, AsciiAndBinaryPlyCube) {
  TempDir dir;
  expect_unit_cube(import_mesh(dir.file("cube.ply", cube_ascii_ply())));
  expect_unit_cube(import_mesh(dir.file("cube_bin.PLY", cube_binary_ply())));
}

TEST(MeshImport, ObjQuadsAreTriangulated) {
  TempDir dir;
  expect_unit_cube(import_mesh(dir.file("cube.obj", cube_quad_obj())));
}

TEST(MeshImport, AllMeshesOfAFileAreMerged) {
  TempDir dir;
  std::string s = "o first\n" + cube_quad_obj() + "o second\n";
  for (const auto& v : kCubeV)
    s += "v " + std::to_string(v[0] + 3) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + "\n";
  s += "f 9 12 11 10\nf 13 14 15 16\nf 9 10 14 13\nf 11 12 16 15\nf 10 11 15 14\nf 9 13 16 12\n";
  const TriMesh m = import_mesh(dir.file("two.obj", s));
  EXPECT_EQ(m.faces.size(), 24u);
  EXPECT_EQ(check_mesh(m).components, 2);
  EXPECT_NEAR(signed_volume(m), 2.0, 1e-9);
}

TEST(MeshImport, UnitsScaleToMetres) {
  TempDir dir;
  const std::string path = dir.file("cube.stl", cube_ascii_stl());
  // Even 1 mm (a 1.7 mm diagonal) is still accepted.
  for (const auto& [units, metres] : {std::pair{"mm", 1e-3}, {"cm", 1e-2}, {"dm", 0.1}, {"m", 1.0}}) {
    MeshImportOptions opt;
    opt.units = units;
    const double expected = metres * metres * metres;   // [m^3]
    EXPECT_NEAR(signed_volume(import_mesh(path, opt)), expected, 1e-9 * expected) << units;
  }
}

TEST(MeshImport, TransformScalesRotatesThenTranslates) {
  TempDir dir;
  const std::string path = dir.file("cube.stl", cube_ascii_stl());
  MeshImportOptions opt;
  opt.units = "cm";
  opt.scale = Vec3(2, 1, 1);
  opt.rotate_deg = Vec3(90, 90, 0);   // about x first, then about y
  opt.translate_m = Vec3(1, 2, 3);
  const TriMesh m = import_mesh(path, opt);
  // File vertex (0, 1, 0) cm -> (0, 0.01, 0) m -> Rx(90): (0, 0, 0.01) -> Ry(90): (0.01, 0, 0).
  // File vertex (1, 0, 0) cm -> scaled (0.02, 0, 0) -> Rx: same -> Ry(90): (0, 0, -0.02).
  bool found_y = false, found_x = false;
  for (const Vec3& v : m.vertices) {
    found_y |= (v - Vec3(1.01, 2, 3)).norm() < 1e-9;
    found_x |= (v - Vec3(1, 2, 2.98)).norm() < 1e-9;
  }
  EXPECT_TRUE(found_y);
  EXPECT_TRUE(found_x);
  EXPECT_NEAR(signed_volume(m), 2e-6, 1e-12);
}

TEST(MeshImport, MirroringScaleKeepsFacesOutward) {
  TempDir dir;
  MeshImportOptions opt;
  opt.scale = Vec3(-1, 1, 1);
  const TriMesh m = import_mesh(dir.file("cube.stl", cube_ascii_stl()), opt);
  EXPECT_NEAR(signed_volume(m), 1.0, 1e-9);
  EXPECT_TRUE(check_mesh(m).valid_solid());
}

TEST(MeshImport, WrongUnitsAreRefused) {
  MeshImportOptions opt;
  opt.units = "m";   // the phantom in metres would be 64 m across
  expect_input_error([&] { import_mesh(kPhantom, opt); }, kPhantom, "wrong units?");
  const std::string cylinder = kData + "/truth_cylinder/cylinder_Surface.obj";
  opt.units = "mm";   // the cylinder (metres, 0.19 m across) in millimetres would be 0.19 mm
  expect_input_error([&] { import_mesh(cylinder, opt); }, cylinder, "wrong units?");
}

TEST(MeshImport, BadOptionsAndFilesAreInputErrors) {
  TempDir dir;
  const std::string cube = dir.file("cube.stl", cube_ascii_stl());
  MeshImportOptions opt;
  opt.units = "inch";
  expect_input_error([&] { import_mesh(cube, opt); }, cube, "unknown length unit 'inch'");
  opt = {};
  opt.scale = Vec3(1, 0, 1);
  expect_input_error([&] { import_mesh(cube, opt); }, cube, "scale");
  opt = {};
  opt.translate_m = Vec3(NAN, 0, 0);
  expect_input_error([&] { import_mesh(cube, opt); }, cube, "translation");

  const std::string missing = dir.file("x", "") + "_missing.stl";
  expect_input_error([&] { import_mesh(missing); }, missing, "does not exist");
  const std::string txt = dir.file("cube.txt", cube_ascii_stl());
  expect_input_error([&] { import_mesh(txt); }, txt, "unsupported mesh format '.txt'");
  const std::string empty = dir.file("empty.obj", "");
  expect_input_error([&] { import_mesh(empty); }, empty, "empty mesh file");
  const std::string no_faces = dir.file("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expect_input_error([&] { import_mesh(no_faces); }, no_faces, "");
  const std::string lines_only = dir.file("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
  expect_input_error([&] { import_mesh(lines_only); }, lines_only, "");
  const std::string dir_path = dir.file("sub.obj", "") + "_dir.obj";
  std::filesystem::create_directory(dir_path);
  expect_input_error([&] { import_mesh(dir_path); }, dir_path, "not a regular file");
}

TEST(MeshImport, NonFiniteCoordinatesNameTheVertex) {
  TempDir dir;
  std::string stl = cube_ascii_stl();
  stl.replace(stl.find("vertex 1.000000 1.000000 0.000000"), 33, "vertex nan 1.000000 0.000000");
  const std::string a = dir.file("nan.stl", stl);
  expect_input_error([&] { import_mesh(a); }, a, "vertex 1 (face 0) has a non-finite coordinate");
  const std::string b = dir.file("inf.obj", "v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_input_error([&] { import_mesh(b); }, b, "vertex 2 has a non-finite coordinate (inf, 0, 0)");
  // the OBJ's own vertex number and line (assimp numbers one vertex per face corner, so its own
  // number for the file's 4th vertex would read "vertex 5 (face 1)"); beyond float range is inf
  const std::string c = dir.file("nan.obj", "# tetrahedron\nv 0 0 0\nv 10 0 0\nv 0 10 0\nv nan 0 10\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n");
  try {
    import_mesh(c);
    ADD_FAILURE() << "accepted a NaN vertex";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 5);
    EXPECT_EQ(e.field(), "v");
    EXPECT_NE(std::string(e.what()).find("vertex 4 has a non-finite coordinate (nan, 0, 10)"), std::string::npos) << e.what();
  }
  const std::string d = dir.file("big.obj", "v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n");
  expect_input_error([&] { import_mesh(d); }, d, "vertex 3 has a non-finite coordinate (0, inf, 0)");
}

TEST(MeshImport, CorruptHeadersAreRefusedBeforeAllocating) {
  TempDir dir;
  std::string stl(80, '\0');
  const uint32_t n = 1u << 31;
  stl.append(reinterpret_cast<const char*>(&n), 4);
  stl.append(500, '\0');
  const std::string a = dir.file("huge.stl", stl);
  expect_input_error([&] { import_mesh(a); }, a, "header declares 2147483648 triangles");
  const std::string b = dir.file("huge.ply",
                                 "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                                 "property float x\nend_header\n");
  expect_input_error([&] { import_mesh(b); }, b, "more than the limit");
  std::string ply = cube_ascii_ply();
  ply.replace(ply.find("3 0 2 1"), 7, "4000000000 0 2 1");
  const std::string c = dir.file("longlist.ply", ply);
  expect_input_error([&] { import_mesh(c); }, c, "bad list length");
}

}  // namespace
}  // namespace ps
