// FCL is confined to this file (heavy headers); fcl_surface.h says why the query is FCL's own
// AABB tree traversal with an analytic leaf test instead of fcl::collide's GJK leaf test.
#include "engine/tools/fcl_surface.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/narrowphase/detail/gjk_solver_indep.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_shape_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>

#include <stdexcept>

#include "engine/tools/probe/probe_geometry.h"

namespace ps {

namespace {

using Solver = fcl::detail::GJKSolver_indep<double>;

using BV = fcl::AABBd;

// FCL's mesh-capsule traversal (AABB tree against the capsule's AABB, in place) whose leaf test
// is the exact capsule distance of the triangle's corners instead of GJK + EPA (EPA::initialize
// allocates its vertex and face stores on every triangle that intersects).
class CapsuleCornerNode final : public fcl::detail::MeshShapeCollisionTraversalNode<BV, fcl::Capsuled, Solver> {
 public:
  Capsule capsule;                 // the query's capsule, radius included [m]
  std::vector<int>* hits = nullptr;
  const std::array<int, 3>* local = nullptr;  // triangles by BVH vertex (FCL's Triangle::operator[] is out of line)
  void leafTesting(int b1, int) const override {
    const int tri = -(this->model1->getBV(b1).first_child + 1);  // primitiveId(), inline
    const std::array<int, 3>& t = local[tri];
    for (int k = 0; k < 3; ++k)
      if (capsule_signed_distance(capsule, this->vertices[t[k]]) < 0.0) {
        hits->push_back(tri);  // capacity: one per triangle, each visited once
        return;
      }
  }
};

}  // namespace

struct FclSurfaceContact::Impl {
  fcl::BVHModel<BV> mesh;
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
    local_faces_.push_back({v[0], v[1], v[2]});
  }
  Impl& I = *impl_;
  I.mesh.beginModel(static_cast<int>(tris.size()), static_cast<int>(pts.size()));
  I.mesh.addSubModel(pts, tris);
  I.mesh.endModel();
  for (int i = 0; i < I.mesh.getNumBVs(); ++i) {  // refit() relies on children after parents
    const fcl::BVNode<BV>& node = I.mesh.getBV(i);
    if (!node.isLeaf() && (node.leftChild() <= i || node.rightChild() <= i))
      throw std::logic_error("FclSurfaceContact: FCL BVH node numbering changed (child before parent)");
  }
  hits_.reserve(faces_.size());
}

FclSurfaceContact::~FclSurfaceContact() = default;

void FclSurfaceContact::refit(const std::vector<Vec3>& x) {
  // FCL's own refit (beginUpdateModel / updateVertex / endUpdateModel) boxes each triangle's
  // previous and current corners and merges through out-of-line AABB operators: 0.1 ms for the
  // 1228 triangles of the probe scene, 10x the probe's whole box broad phase. The same boxes over
  // the current corners only, children before parents (FCL numbers a node's children after it),
  // are exact for a query at the current positions and cost a few ns per node.
  fcl::BVHModel<BV>& mesh = impl_->mesh;
  const size_t nv = vertices_.size();
  for (size_t v = 0; v < nv; ++v) mesh.vertices[v] = x[vertices_[v]];
  // BVNodeBase's accessors are out of line in libfcl: read first_child directly (< 0: leaf
  // holding primitive -(first_child + 1); else children first_child, first_child + 1)
  for (int i = mesh.getNumBVs() - 1; i >= 0; --i) {
    fcl::BVNode<BV>& node = mesh.getBV(i);
    const int fc = node.first_child;
    Vec3 lo, hi;
    if (fc < 0) {
      const std::array<int, 3>& t = local_faces_[-(fc + 1)];
      const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
      lo = a.cwiseMin(b).cwiseMin(c);
      hi = a.cwiseMax(b).cwiseMax(c);
    } else {
      const BV& l = mesh.getBV(fc).bv;
      const BV& r = mesh.getBV(fc + 1).bv;
      lo = l.min_.cwiseMin(r.min_);
      hi = l.max_.cwiseMax(r.max_);
    }
    node.bv.min_ = lo;
    node.bv.max_ = hi;
  }
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
  node.local = local_faces_.data();
  hits_.clear();
  I.result.clear();
  fcl::Transform3d mesh_tf = fcl::Transform3d::Identity();  // world frame: FCL copies nothing
  fcl::detail::initialize(node, I.mesh, mesh_tf, I.capsule, tf, &I.solver, I.request, I.result);
  fcl::detail::collide(&node);
  return static_cast<int>(hits_.size());
}

}  // namespace ps
