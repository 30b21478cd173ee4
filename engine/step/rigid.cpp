// Rigid components (paper §3.1, skeleton). A rigid body is made of rigid particles; elastic
// border particles attached to it are "doubled" particles held coincident with a body point
// whatever forces act on them, so the elastic forces on them are transmitted to the body.
// Kinematic bodies (bones held still, plates, instruments) move only by command.
#include "engine/step/stages.h"

namespace ps {

void gather_rigid_forces(const Model& m, State& s) {
  for (size_t b = 0; b < m.rigid_bodies.size(); ++b) {
    const RigidBody& rb = m.rigid_bodies[b];
    if (rb.kinematic) continue;
    RigidBodyState& bs = s.bodies[b];
    for (int p : rb.particles) {
      bs.force += s.f[p];
      bs.torque += (s.x[p] - bs.com).cross(s.f[p]);
    }
  }
  for (const RigidAttachment& at : m.attachments) {
    const RigidBody& rb = m.rigid_bodies[at.body];
    if (rb.kinematic) continue;
    RigidBodyState& bs = s.bodies[at.body];
    bs.force += s.f[at.particle];
    bs.torque += (s.x[at.particle] - bs.com).cross(s.f[at.particle]);
  }
}

void integrate_rigid_bodies(const Model& m, State& s, double dt) {
  for (size_t b = 0; b < m.rigid_bodies.size(); ++b) {
    const RigidBody& rb = m.rigid_bodies[b];
    RigidBodyState& bs = s.bodies[b];
    if (!rb.kinematic) {
      bs.lin_vel += (dt / rb.mass) * bs.force;
      const Mat3 R = bs.rot.toRotationMatrix();
      const Mat3 I_world = R * rb.inertia_body * R.transpose();
      const Vec3 gyro = bs.ang_vel.cross(I_world * bs.ang_vel);
      bs.ang_vel += dt * I_world.ldlt().solve(bs.torque - gyro);
      bs.com += dt * bs.lin_vel;
      const Quat w(0.0, bs.ang_vel.x(), bs.ang_vel.y(), bs.ang_vel.z());
      Quat dq = w * bs.rot;
      bs.rot.coeffs() += 0.5 * dt * dq.coeffs();
      bs.rot.normalize();
    }
    const Mat3 R = bs.rot.toRotationMatrix();
    for (size_t i = 0; i < rb.particles.size(); ++i) {
      const int p = rb.particles[i];
      const Vec3 r = R * rb.local[i];
      s.x[p] = bs.com + r;
      s.v[p] = bs.lin_vel + bs.ang_vel.cross(r);
    }
  }
  for (const RigidAttachment& at : m.attachments) {
    const RigidBodyState& bs = s.bodies[at.body];
    const Vec3 r = bs.rot * at.local;
    s.x[at.particle] = bs.com + r;
    s.v[at.particle] = bs.lin_vel + bs.ang_vel.cross(r);
  }
}

}  // namespace ps
