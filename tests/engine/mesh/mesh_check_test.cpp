// check_mesh finds each kind of defect; repair_closed_surface fixes what is safe and refuses,
// with the documented messages, what is not.
#include "engine/mesh/mesh_check.h"

#include <gtest/gtest.h>

#include <string>

#include "engine/util/error.h"

namespace ps {
namespace {

// Unit cube, outward, 8 shared vertices.
TriMesh cube(const Vec3& at = Vec3::Zero()) {
  TriMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back(at + Vec3(i & 1 ? 1 : 0, i & 2 ? 1 : 0, i & 4 ? 1 : 0));
  // Vertex i = x + 2y + 4z.
  m.faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
             {2, 6, 7}, {2, 7, 3}, {1, 3, 7}, {1, 7, 5}, {0, 4, 6}, {0, 6, 2}};
  return m;
}

std::string refusal(const TriMesh& m) {
  try {
    repair_closed_surface(m, "organ.stl");
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "organ.stl");
    return e.what();
  }
  return "(accepted)";
}

TEST(MeshCheck, CubeIsAValidSolid) {
  const MeshReport r = check_mesh(cube());
  EXPECT_TRUE(r.valid_solid()) << r.summary();
  EXPECT_EQ(r.components, 1);
  EXPECT_NEAR(r.signed_volume, 1.0, 1e-12);
  EXPECT_NEAR(r.area, 6.0, 1e-12);
  EXPECT_NE(r.summary().find("closed 2-manifold"), std::string::npos);
}

TEST(MeshCheck, DetectsHole) {
  TriMesh m = cube();
  m.faces.erase(m.faces.begin());   // face {0, 2, 3}
  const MeshReport r = check_mesh(m);
  EXPECT_FALSE(r.closed());
  EXPECT_EQ(r.boundary_edges, 3);
  EXPECT_EQ(r.first_boundary_edge, (std::array<int, 2>{0, 2}));
  EXPECT_FALSE(r.inverted);
  EXPECT_NE(r.summary().find("open: 3 boundary edges"), std::string::npos) << r.summary();
}

TEST(MeshCheck, DetectsNonManifoldEdge) {
  TriMesh m = cube();
  m.vertices.push_back(Vec3(0.5, -1, 0.5));
  m.faces.push_back({0, 1, 8});   // a fin on edge 0-1, now shared by three faces
  const MeshReport r = check_mesh(m);
  EXPECT_EQ(r.non_manifold_edges, 1);
  EXPECT_EQ(r.first_non_manifold_edge, (std::array<int, 2>{0, 1}));
  EXPECT_EQ(r.boundary_edges, 2);   // the fin's free edges
  EXPECT_FALSE(r.valid_solid());
}

TEST(MeshCheck, DetectsBowTieVertex) {
  // Two cubes touching at one corner: every edge fine, the shared vertex is not.
  TriMesh m = cube();
  const TriMesh b = cube(Vec3(1, 1, 1));
  const int base = static_cast<int>(m.vertices.size());
  for (const Vec3& v : b.vertices) m.vertices.push_back(v);
  for (auto f : b.faces) {
    for (int& i : f) i = (i == 0) ? 7 : base + i;   // b's corner 0 is the cube's corner 7
    m.faces.push_back(f);
  }
  const MeshReport r = check_mesh(m);
  EXPECT_TRUE(r.closed());
  EXPECT_EQ(r.non_manifold_vertices, 1);
  EXPECT_EQ(r.first_non_manifold_vertex, 7);
  EXPECT_EQ(r.components, 1);
  EXPECT_FALSE(r.valid_solid());
}

TEST(MeshCheck, DetectsDegenerateFaces) {
  TriMesh m = cube();
  m.faces.push_back({1, 1, 2});   // repeated vertex
  MeshReport r = check_mesh(m);
  EXPECT_EQ(r.degenerate_faces, 1);
  EXPECT_EQ(r.first_degenerate_face, 12);

  TriMesh z = cube();
  z.vertices.push_back(Vec3(0.5, 0, 0));   // on edge 0-1
  z.faces.push_back({0, 8, 1});            // distinct indices, zero area
  r = check_mesh(z);
  EXPECT_EQ(r.degenerate_faces, 1);
  EXPECT_EQ(r.first_degenerate_face, 12);
}

TEST(MeshCheck, DetectsInvertedCube) {
  TriMesh m = cube();
  for (auto& f : m.faces) std::swap(f[1], f[2]);
  const MeshReport r = check_mesh(m);
  EXPECT_TRUE(r.closed());
  EXPECT_EQ(r.inconsistent_edges, 0);
  EXPECT_TRUE(r.inverted);
  EXPECT_NEAR(r.signed_volume, -1.0, 1e-12);
  EXPECT_NE(r.summary().find("inverted"), std::string::npos);
}

TEST(MeshCheck, DetectsInconsistentOrientation) {
  TriMesh m = cube();
  std::swap(m.faces[5][1], m.faces[5][2]);
  const MeshReport r = check_mesh(m);
  EXPECT_EQ(r.inconsistent_edges, 3);
  EXPECT_FALSE(r.inverted);
  EXPECT_FALSE(r.valid_solid());
}

TEST(MeshCheck, CountsComponentsAndBadIndices) {
  TriMesh m = cube();
  const TriMesh b = cube(Vec3(3, 0, 0));
  for (const Vec3& v : b.vertices) m.vertices.push_back(v);
  for (auto f : b.faces) m.faces.push_back({f[0] + 8, f[1] + 8, f[2] + 8});
  EXPECT_EQ(check_mesh(m).components, 2);
  EXPECT_NEAR(check_mesh(m).signed_volume, 2.0, 1e-12);
  m.faces.push_back({0, 1, 99});
  const MeshReport r = check_mesh(m);
  EXPECT_EQ(r.invalid_faces, 1);
  EXPECT_EQ(r.first_invalid_face, 24);
  EXPECT_FALSE(r.closed());
}

TEST(MeshCheck, RepairWeldsDuplicatesAndFixesAFlippedFace) {
  // STL-style soup: every face has its own three vertices (some off by 1e-9 m), one face flipped.
  const TriMesh c = cube();
  TriMesh soup;
  for (size_t f = 0; f < c.faces.size(); ++f) {
    std::array<int, 3> t{};
    for (int k = 0; k < 3; ++k) {
      t[k] = static_cast<int>(soup.vertices.size());
      soup.vertices.push_back(c.vertices[c.faces[f][k]] + Vec3::Constant(f % 2 ? 1e-9 : 0.0));
    }
    if (f == 7) std::swap(t[1], t[2]);
    soup.faces.push_back(t);
  }
  EXPECT_EQ(check_mesh(soup).boundary_edges, 36);
  RepairStats st;
  const TriMesh m = repair_closed_surface(soup, "soup.stl", &st);
  const MeshReport r = check_mesh(m);
  EXPECT_TRUE(r.valid_solid()) << r.summary();
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(m.faces.size(), 12u);
  EXPECT_EQ(st.merged_vertices, 28);
  EXPECT_EQ(st.flipped_faces, 1);
  EXPECT_NEAR(signed_volume(m), 1.0, 1e-6);
}

TEST(MeshCheck, RepairTurnsAnInvertedCubeOutward) {
  TriMesh m = cube();
  for (auto& f : m.faces) std::swap(f[1], f[2]);
  RepairStats st;
  const TriMesh fixed = repair_closed_surface(m, "x.obj", &st);
  EXPECT_EQ(st.flipped_faces, 12);
  EXPECT_NEAR(signed_volume(fixed), 1.0, 1e-12);
  EXPECT_TRUE(check_mesh(fixed).valid_solid());
}

TEST(MeshCheck, RepairDropsCollapsedAndDuplicateFaces) {
  TriMesh m = cube();
  m.faces.push_back(m.faces[3]);                                       // exact duplicate
  m.faces.push_back({m.faces[4][0], m.faces[4][2], m.faces[4][1]});   // reversed copy of a real face
  m.faces.push_back({2, 2, 6});                                        // collapsed
  EXPECT_EQ(check_mesh(m).non_manifold_edges, 6);
  RepairStats st;
  const TriMesh fixed = repair_closed_surface(m, "x.obj", &st);
  EXPECT_EQ(st.dropped_faces, 3);
  EXPECT_EQ(st.flipped_faces, 0);   // the kept copy is the one oriented like its neighbours
  EXPECT_EQ(fixed.faces.size(), 12u);
  EXPECT_TRUE(check_mesh(fixed).valid_solid()) << check_mesh(fixed).summary();
  EXPECT_NEAR(signed_volume(fixed), 1.0, 1e-12);

  // A detached two-triangle pillow (zero volume) goes; the cube stays.
  TriMesh p = cube();
  p.vertices.push_back(Vec3(5, 0, 0));
  p.vertices.push_back(Vec3(6, 0, 0));
  p.vertices.push_back(Vec3(5, 1, 0));
  p.faces.push_back({8, 9, 10});
  p.faces.push_back({8, 10, 9});
  const TriMesh q = repair_closed_surface(p, "x.obj", &st);
  EXPECT_EQ(q.faces.size(), 12u);
  EXPECT_EQ(q.vertices.size(), 8u);
}

TEST(MeshCheck, RepairRefusesWhatIsNotSafe) {
  TriMesh hole = cube();
  hole.faces.erase(hole.faces.begin());
  EXPECT_NE(refusal(hole).find("open surface: 3 boundary edges, first at vertices 0-2"), std::string::npos)
      << refusal(hole);

  TriMesh fin = cube();
  fin.vertices.push_back(Vec3(0.5, -1, 0.5));
  fin.faces.push_back({0, 1, 8});
  fin.faces.push_back({1, 0, 8});   // a two-sided fin: closed, but edge 0-1 has four faces
  EXPECT_NE(refusal(fin).find("non-manifold surface: 1 edges"), std::string::npos) << refusal(fin);

  // A closed cube where edge 0-1 is split by a vertex on it and closed by a zero-area face:
  // dropping that face would open a hole, so it must be refused and named.
  TriMesh sliver = cube();
  sliver.vertices.push_back(Vec3(0.5, 0, 0));   // vertex 8 on edge 0-1
  // Faces using edge 0-1: {0, 3, 1} (walks 1->0 ... ) and {0, 1, 5}; split {0, 1, 5}.
  sliver.faces[4] = {0, 8, 5};
  sliver.faces.push_back({8, 1, 5});
  sliver.faces.push_back({0, 1, 8});   // zero area, closes 0-8-1 against edge 0-1
  EXPECT_TRUE(check_mesh(sliver).closed()) << check_mesh(sliver).summary();
  EXPECT_NE(refusal(sliver).find("degenerate (zero-area) face 13"), std::string::npos) << refusal(sliver);

  TriMesh nan = cube();
  nan.vertices[3].x() = NAN;
  EXPECT_NE(refusal(nan).find("vertex 3 has a non-finite coordinate"), std::string::npos);
  TriMesh bad = cube();
  bad.faces[2][1] = 42;
  EXPECT_NE(refusal(bad).find("face 2 refers to a vertex out of range"), std::string::npos);
}

}  // namespace
}  // namespace ps
