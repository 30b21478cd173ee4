// FCL is confined to this file (heavy headers); fcl_surface.h says why the query is FCL's own
// OBB tree traversal with an analytic leaf test instead of fcl::collide's GJK leaf test.
#include "engine/tools/fcl_surface.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/narrowphase/detail/gjk_solver_indep.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_shape_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>

#include <stdexcept>

#include "engine/tools/probe_geometry.h"

namespace ps {

namespace {

using Solver = fcl::detail::GJKSolver_indep<double>;

// FCL's mesh-capsule traversal (OBB tree against the capsule's OBB, in place) whose leaf test is
// the exact capsule distance of the triangle's corners instead of GJK + EPA (EPA::initialize
// allocates its vertex and face stores on every triangle that intersects).
class CapsuleCornerNode final : public fcl::detail::MeshShapeCollisionTraversalNodeOBB<fcl::Capsuled, Solver> {
 public:
  Capsule capsule;                 // the query's capsule, radius included [m]
  std::vector<int>* hits = nullptr;
  void leafTesting(int b1, int) const override {
    const int tri = this->model1->getBV(b1).primitiveId();
    const fcl::Triangle& t = this->tri_indices[tri];
    for (int k = 0; k < 3; ++k)
      if (capsule_signed_distance(capsule, this->vertices[t[k]]) < 0.0) {
        hits->push_back(tri);  // capacity: one per triangle, each visited once
        return;
      }
  }
};

}  // namespace

struct FclSurfaceContact::Impl {
  fcl::BVHModel<fcl::OBBd> mesh;
  fcl::Capsuled capsule{1.0, 1.0};   // radius and length set per query [m]
  Solver solver;
  fcl::CollisionRequestd request{1, false, 1, false, true, fcl::GST_INDEP};
  fcl::CollisionResultd result;      // stays empty: hits are recorded by the leaf test
};

FclSurfaceContact::FclSurfaceContact(const std::vector<std::array<int, 3>>& faces, const std::vector<Vec3>& x)
    : impl_(std::make_unique<Impl>()), faces_(faces) {
  if (faces_.empty()) throw std::invalid_argument("FclSurfaceContact: no triangles");
  std::vector<int> local(x.size(), -1);
  std::vector<fcl::Vector3d> pts;
  std::vector<fcl::Triangle> tris;
  tris.reserve(faces_.size());
  for (const auto& f : faces_) {
    int v[3];
    for (int k = 0; k < 3; ++k) {
      const int p = f[k];
      if (local[p] < 0) {
        local[p] = static_cast<int>(vertices_.size());
        vertices_.push_back(p);
        pts.push_back(x[p]);
      }
      v[k] = local[p];
    }
    tris.emplace_back(v[0], v[1], v[2]);
  }
  Impl& I = *impl_;
  I.mesh.beginModel(static_cast<int>(tris.size()), static_cast<int>(pts.size()));
  I.mesh.addSubModel(pts, tris);
  I.mesh.endModel();
  hits_.reserve(faces_.size());
  refit(x);  // the first update allocates FCL's previous-frame vertex array; later ones swap
}

FclSurfaceContact::~FclSurfaceContact() = default;

void FclSurfaceContact::refit(const std::vector<Vec3>& x) {
  fcl::BVHModel<fcl::OBBd>& mesh = impl_->mesh;
  mesh.beginUpdateModel();
  for (int p : vertices_) mesh.updateVertex(x[p]);
  mesh.endUpdateModel(true, true);  // refit bottom-up, keep the tree
}

int FclSurfaceContact::collide_capsule(const Vec3& a, const Vec3& b, double radius) {
  Impl& I = *impl_;
  const Vec3 d = b - a;
  const double len = d.norm();
  I.capsule.radius = radius;
  I.capsule.lz = len;
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.translation() = 0.5 * (a + b);
  if (len > 0.0) tf.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), d / len).toRotationMatrix();
  CapsuleCornerNode node;
  node.capsule.back = a;
  node.capsule.tip = b;
  node.capsule.length = len;
  node.capsule.dir = len > 0.0 ? Vec3(d / len) : Vec3::UnitZ();
  node.capsule.radius = radius;
  node.hits = &hits_;
  hits_.clear();
  I.result.clear();
  fcl::detail::initialize(node, I.mesh, fcl::Transform3d::Identity(), I.capsule, tf, &I.solver, I.request, I.result);
  fcl::detail::collide(&node);
  return static_cast<int>(hits_.size());
}

}  // namespace ps
