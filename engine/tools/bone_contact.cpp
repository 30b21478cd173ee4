// FCL is confined to this file (heavy headers). Queries use the sphere-triangle distance of
// FCL's libccd solver, which is analytic for spheres, on a BVHModel<OBBRSS> built once.
#include "engine/tools/bone_contact.h"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/sphere.h>
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
};

BoneContact::BoneContact(const Model& m) : impl_(std::make_unique<Impl>()) {
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
    const fcl::Sphered sphere(r);
    fcl::Transform3d tf_sphere = fcl::Transform3d::Identity();
    tf_sphere.translation() = cl;
    fcl::DistanceRequestd req;
    req.enable_nearest_points = true;
    req.enable_signed_distance = false;
    req.gjk_solver_type = fcl::GST_LIBCCD;
    fcl::DistanceResultd res;
    fcl::distance(bone.mesh.get(), fcl::Transform3d::Identity(), &sphere, tf_sphere, req, res);
    const double d = std::max(0.0, res.min_distance);
    if (d < best) {
      best = d;
      if (nearest) *nearest = bs.com + bs.rot * Vec3(res.nearest_points[0]);
      if (component) *component = bone.component;
    }
  }
  return best;
}

}  // namespace ps
