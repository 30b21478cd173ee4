// FCL is confined to this file (heavy headers). The tip is a point probe (a BVHModel holding one
// triangle a nanometre wide, built once) placed by the query's transform; its distance to the
// bone's BVHModel<OBBRSS> minus the tip radius is the sphere's distance. Measured: a Sphere
// shape costs two heap allocations per fcl::distance call (Sphere::getBoundVertices fills a
// std::vector to fit the shape's bounding volume), mesh-mesh distance none, so the query can
// run inside a step.
#include "engine/tools/bone_contact.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/narrowphase/distance.h>

#include <cmath>

namespace ps {

struct BoneContact::Impl {
  struct Bone {
    int component = -1;
    int body = -1;                       // RigidBody index
    std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> mesh;
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // body-frame box [m]
  };
  std::vector<Bone> bones;
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> probe;
};

BoneContact::BoneContact(const Model& m) : impl_(std::make_unique<Impl>()) {
  impl_->probe = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  const std::vector<fcl::Vector3d> pp = {{0, 0, 0}, {1e-9, 0, 0}, {0, 1e-9, 0}};
  const std::vector<fcl::Triangle> pt = {{0, 1, 2}};
  impl_->probe->beginModel(1, 3);
  impl_->probe->addSubModel(pp, pt);
  impl_->probe->endModel();
  for (size_t b = 0; b < m.rigid_bodies.size(); ++b) {
    const RigidBody& rb = m.rigid_bodies[b];
    const Component& comp = m.components[rb.component];
    if (comp.surface < 0) continue;
    const Surface& surf = m.surfaces[comp.surface];
    if (surf.faces.empty()) continue;
    Impl::Bone bone;
    bone.component = rb.component;
    bone.body = static_cast<int>(b);
    std::vector<fcl::Vector3d> pts;
    std::vector<fcl::Triangle> tris;
    std::vector<int> local(m.particle_count(), -1);
    bone.lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    bone.hi = -bone.lo;
    for (int p : surf.vertices) {
      local[p] = static_cast<int>(pts.size());
      const Vec3 q = m.rest_pos[p] - rb.com_rest;  // body frame (rest rotation is identity)
      pts.push_back(q);
      bone.lo = bone.lo.cwiseMin(q);
      bone.hi = bone.hi.cwiseMax(q);
    }
    for (const auto& f : surf.faces) tris.emplace_back(local[f[0]], local[f[1]], local[f[2]]);
    bone.mesh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    bone.mesh->beginModel(static_cast<int>(tris.size()), static_cast<int>(pts.size()));
    bone.mesh->addSubModel(pts, tris);
    bone.mesh->endModel();
    impl_->bones.push_back(std::move(bone));
  }
}

BoneContact::~BoneContact() = default;

bool BoneContact::empty() const { return impl_->bones.empty(); }
int BoneContact::bone_count() const { return static_cast<int>(impl_->bones.size()); }

double BoneContact::distance(const State& s, const Vec3& c, double r, double reach, Vec3* nearest, int* component) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Impl::Bone& bone : impl_->bones) {
    const RigidBodyState& bs = s.bodies[bone.body];
    // centre in the body frame; box test with the reach
    const Vec3 cl = bs.rot.conjugate() * (c - bs.com);
    const Vec3 out = (bone.lo - cl).cwiseMax(cl - bone.hi).cwiseMax(Vec3::Zero());
    if (out.norm() > reach + r) continue;
    fcl::Transform3d tf_probe = fcl::Transform3d::Identity();
    tf_probe.translation() = cl;
    fcl::DistanceRequestd req;
    req.enable_nearest_points = true;
    req.enable_signed_distance = false;
    req.gjk_solver_type = fcl::GST_LIBCCD;
    fcl::DistanceResultd res;
    fcl::distance(bone.mesh.get(), fcl::Transform3d::Identity(), impl_->probe.get(), tf_probe, req, res);
    const double d = std::max(0.0, res.min_distance - r);
    if (d < best) {
      best = d;
      if (nearest) *nearest = bs.com + bs.rot * Vec3(res.nearest_points[0]);
      if (component) *component = bone.component;
    }
  }
  return best;
}

}  // namespace ps
