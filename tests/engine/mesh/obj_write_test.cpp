// OBJ output: exact text for a small mesh, and a round trip through import_mesh.
#include "engine/mesh/obj_write.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <unistd.h>

#include "engine/mesh/mesh_import.h"

namespace ps {
namespace {

TEST(MeshObjWrite, TextIsOneBasedAndScaled) {
  TriMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(0.001, 0, 0), Vec3(0, 0.0025, -0.1)};
  m.faces = {{0, 1, 2}};
  EXPECT_EQ(to_obj(m, 1000.0),
            "# ProstateSim surface: 3 vertices, 1 triangles\n"
            "v 0 0 0\nv 1 0 0\nv 0 2.5 -100\nf 1 2 3\n");
  EXPECT_EQ(to_obj(m), "# ProstateSim surface: 3 vertices, 1 triangles\n"
                       "v 0 0 0\nv 0.001 0 0\nv 0 0.0025 -0.1\nf 1 2 3\n");
}

TEST(MeshObjWrite, RoundTripThroughImport) {
  TriMesh c;
  for (int i = 0; i < 8; ++i) c.vertices.push_back(Vec3(i & 1 ? 0.03 : 0, i & 2 ? 0.02 : 0, i & 4 ? 0.01 : 0));
  c.faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
             {2, 6, 7}, {2, 7, 3}, {1, 3, 7}, {1, 7, 5}, {0, 4, 6}, {0, 6, 2}};
  const std::string path =
      (std::filesystem::temp_directory_path() / ("ps_obj_write_" + std::to_string(::getpid()) + ".obj")).string();
  write_obj(path, c, 1000.0);   // millimetres
  MeshImportOptions opt;
  opt.units = "mm";
  const TriMesh back = import_mesh(path, opt);
  std::filesystem::remove(path);
  // Assimp renumbers vertices: match them by position, then compare the faces.
  ASSERT_EQ(back.vertices.size(), c.vertices.size());
  std::vector<int> to_c(back.vertices.size(), -1);
  for (size_t i = 0; i < back.vertices.size(); ++i)
    for (size_t j = 0; j < c.vertices.size(); ++j)
      if ((back.vertices[i] - c.vertices[j]).norm() < 1e-9) to_c[i] = static_cast<int>(j);   // float precision
  std::vector<std::array<int, 3>> faces;
  for (auto f : back.faces) {
    for (int& i : f) {
      ASSERT_GE(to_c[i], 0);
      i = to_c[i];
    }
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    faces.push_back(f);
  }
  std::vector<std::array<int, 3>> expected;
  for (auto f : c.faces) {
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    expected.push_back(f);
  }
  std::sort(faces.begin(), faces.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(faces, expected);
  EXPECT_NEAR(signed_volume(back), 6e-6, 1e-12);
  EXPECT_THROW(write_obj("/nonexistent-dir/x.obj", c, 1.0), std::runtime_error);
}

}  // namespace
}  // namespace ps
