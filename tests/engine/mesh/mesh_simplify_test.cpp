// Remeshing to a particle spacing keeps a valid solid, the volume and the requested edge length;
// subdivision only splits.
#include "engine/mesh/mesh_simplify.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/mesh/mesh_check.h"
#include "engine/mesh/mesh_import.h"
#include "tests/engine/mesh/test_meshes.h"

namespace ps {
namespace {

const std::string kData = PROSTATESIM_SHARED_DATA;

double max_edge(const TriMesh& m) {
  double e = 0;
  for (const auto& f : m.faces)
    for (int k = 0; k < 3; ++k) e = std::max(e, (m.vertices[f[k]] - m.vertices[f[(k + 1) % 3]]).norm());
  return e;
}

TriMesh phantom() {
  MeshImportOptions opt;
  opt.units = "mm";
  return repair_closed_surface(import_mesh(kData + "/prostate_phantom/prostate.stl", opt), "prostate.stl");
}

TEST(MeshSimplify, SubdivideSplitsLongEdgesOnly) {
  const TriMesh c = test::cube_mesh(0.05);   // 5 cm cube, 12 triangles
  const TriMesh s = subdivide_to_spacing(c, 0.012);
  EXPECT_LE(max_edge(s), 0.012);
  EXPECT_GT(s.faces.size(), 12u * 16);
  EXPECT_NEAR(signed_volume(s), signed_volume(c), 1e-15);
  EXPECT_TRUE(check_mesh(s).valid_solid()) << check_mesh(s).summary();
  // Nothing to split: unchanged.
  const TriMesh same = subdivide_to_spacing(c, 1.0);
  EXPECT_EQ(same.faces, c.faces);
  EXPECT_THROW(subdivide_to_spacing(c, 0.0), std::invalid_argument);
  EXPECT_THROW(subdivide_to_spacing(c, 1e-9), std::invalid_argument);   // > 20 M faces
}

TEST(MeshSimplify, PhantomAtThreeMillimetres) {
  const TriMesh in = phantom();
  RemeshStats st;
  const TriMesh out = remesh_to_spacing(in, 0.003, &st);
  const MeshReport r = check_mesh(out);
  EXPECT_TRUE(r.valid_solid()) << r.summary();
  EXPECT_EQ(r.components, 1);   // the four ~20 um specks vanish in their cells
  EXPECT_FALSE(st.fell_back);
  const double v_in = signed_volume(in), v_out = signed_volume(out);
  std::printf("[ remesh   ] phantom 3 mm: %zu -> %zu faces, volume %.4f -> %.4f cm^3, mean edge %.2f mm, %d attempt(s)\n",
              in.faces.size(), out.faces.size(), v_in * 1e6, v_out * 1e6, st.mean_edge_m * 1e3, st.attempts);
  EXPECT_NEAR(v_out, v_in, 0.02 * v_in);
  EXPECT_NEAR(st.mean_edge_m, 0.003, 0.0006);
  EXPECT_LT(out.faces.size(), 2000u);
  EXPECT_GT(out.faces.size(), 800u);
}

TEST(MeshSimplify, CoarseCubeIsRefinedThenResampled) {
  // 12 triangles with 10 cm edges at 2 cm spacing: needs the subdivision step first.
  const TriMesh c = test::cube_mesh(0.1);
  RemeshStats st;
  const TriMesh out = remesh_to_spacing(c, 0.02, &st);
  EXPECT_TRUE(check_mesh(out).valid_solid()) << check_mesh(out).summary();
  EXPECT_NEAR(signed_volume(out), 1e-3, 0.03e-3);
  EXPECT_NEAR(st.mean_edge_m, 0.02, 0.005);
  EXPECT_LT(max_edge(out), 0.05);
}

TEST(MeshSimplify, ThinPelvisIsCoarsenedByEdgeCollapse) {
  // The hip bone has walls thinner than the grid, so every clustering breaks its topology; the
  // edge-collapse fallback must still coarsen it to about the spacing (the rigid bones of the
  // scenarios use 7 mm) as a valid solid of the same genus (1) and volume.
  MeshImportOptions opt;
  opt.units = "dm";
  const TriMesh in = import_mesh(kData + "/pelvis_bone/pelvis_f.obj", opt);
  RemeshStats st;
  const TriMesh out = remesh_to_spacing(in, 0.007, &st);
  const MeshReport r = check_mesh(out);
  EXPECT_TRUE(r.valid_solid()) << r.summary();
  EXPECT_EQ(r.vertices - r.faces / 2, 0) << "genus 1 kept (Euler characteristic 0)";
  EXPECT_TRUE(st.collapsed);
  EXPECT_FALSE(st.fell_back);
  EXPECT_NEAR(signed_volume(out), signed_volume(in), 0.01 * signed_volume(in));
  EXPECT_LT(out.vertices.size(), in.vertices.size() / 2) << "coarser than the 4884-vertex input";
  EXPECT_GT(st.mean_edge_m, 0.7 * 0.007);
  EXPECT_LT(st.mean_edge_m, 1.3 * 0.007);
  std::printf("[ remesh   ] pelvis 7 mm: %zu vertices, mean edge %.2f mm\n", out.vertices.size(), st.mean_edge_m * 1e3);
}

TEST(MeshSimplify, RejectsOpenInput) {
  TriMesh c = test::cube_mesh(0.05);
  c.faces.pop_back();
  EXPECT_THROW(remesh_to_spacing(c, 0.01), std::invalid_argument);
  EXPECT_THROW(remesh_to_spacing(test::cube_mesh(0.05), -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace ps
