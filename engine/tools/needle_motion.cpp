// computeNeedleMovement and adjustIntensityNeedleVelocity (paper Algorithm 2). The needle is
// one rigid body of mass m whose tip follows the commanded pose through a spring-damper:
//   m dV/dt = k (T_cmd - T) + c (V_cmd - V) + F_tissue
// The coupling is integrated implicitly (backward Euler, exact for this linear part, so a stiff
// coupling never limits the step); the tissue reaction is explicit. Then the safety clamps:
// coupling force at max_force, speed at max_speed. Then the bone stop: the tip may not move
// closer to a bone surface than it is (conservative advancement with FCL distances).
#include <algorithm>

#include "engine/tools/bone_contact.h"
#include "engine/tools/needle_internal.h"

namespace ps {

namespace {

// depth and its rate along the script at time t (linear between points, held outside)
void script_depth(const NeedleSpec& s, double t, double& depth, double& rate) {
  rate = 0.0;
  if (s.script.empty()) { depth = 0.0; return; }
  if (t <= s.script.front().t) { depth = s.script.front().depth; return; }
  if (t >= s.script.back().t) { depth = s.script.back().depth; return; }
  const auto it = std::upper_bound(s.script.begin(), s.script.end(), t,
                                   [](double v, const NeedleScriptPoint& p) { return v < p.t; });
  const NeedleScriptPoint& b = *it;
  const NeedleScriptPoint& a = *(it - 1);
  rate = (b.depth - a.depth) / (b.t - a.t);
  depth = a.depth + rate * (t - a.t);
}

}  // namespace

void needle_command(const NeedleTool::Needle& nd, double t, Vec3& tip, Vec3& dir, Vec3& vel) {
  if (nd.interactive) {
    // the device holds the gun body; a fired gun extends the needle by the stroke
    // a live advance/retract moves the commanded tip along the commanded direction
    dir = nd.cmd_d;
    tip = nd.cmd_T + (nd.cmd_speed * (t - nd.cmd_t0) + gun_stroke(nd, t)) * dir;
    vel = nd.cmd_V + (nd.cmd_speed + gun_stroke_rate(nd, t)) * dir;
    return;
  }
  double depth = 0.0, rate = 0.0;
  script_depth(nd.spec, t, depth, rate);
  depth += gun_stroke(nd, t);
  rate += gun_stroke_rate(nd, t);
  dir = nd.spec.direction;
  tip = nd.spec.start + depth * dir;
  vel = rate * dir;
}

void move_needle(NeedleTool::Needle& nd, const Model& m, State& s, const Vec3& f_tissue, double dt, const BoneContact* bone,
                 NeedleEventRing& events) {
  const NeedleSpec& sp = nd.spec;
  Vec3 T_cmd, d_cmd, V_cmd;
  needle_command(nd, s.time + dt, T_cmd, d_cmd, V_cmd);
  const double mass = sp.mass, k = sp.coupling_stiffness, c = sp.coupling_damping;
  // implicit coupling: (m + dt c + dt^2 k) V' = m V + dt (F_tissue + k (T_cmd - T) + c V_cmd)
  Vec3 V_new = (mass * nd.V + dt * (f_tissue + k * (T_cmd - nd.T) + c * V_cmd)) / (mass + dt * c + dt * dt * k);
  Vec3 F_c = k * (T_cmd - (nd.T + dt * V_new)) + c * (V_cmd - V_new);
  bool clamped = false;
  double requested = F_c.norm();
  if (requested > sp.max_force) {
    // an absurd command (teleported target, runaway device): push with the limit instead
    F_c *= sp.max_force / requested;
    V_new = nd.V + (dt / mass) * (f_tissue + F_c);
    clamped = true;
  }
  const double speed = V_new.norm();
  if (speed > sp.max_speed) {
    V_new *= sp.max_speed / speed;
    requested = std::max(requested, mass * speed / dt);
    clamped = true;
  }
  Vec3 step = dt * V_new;

  // bone: conservative advancement towards the nearest bone point
  if (bone && !bone->empty()) {
    Vec3 nearest;
    int comp = -1;
    const double reach = step.norm() + nd.radius + 2e-3;
    const double dist = bone->distance(s, nd.T, nd.radius, reach, &nearest, &comp);
    if (std::isfinite(dist)) {
      const Vec3 to_bone = nearest - nd.T;
      const double toward = to_bone.norm() > 0.0 ? step.dot(to_bone.normalized()) : 0.0;
      const double allowed = std::max(0.0, dist - 1e-5);
      if (toward > allowed) {
        // remove the part of the step (and velocity) that goes into the bone beyond the gap
        const Vec3 nrm = to_bone.normalized();
        step -= (toward - allowed) * nrm;
        const double vn = V_new.dot(nrm);
        if (vn > 0.0) V_new -= vn * nrm;
        nd.phase_blocked = 2;
        if (!nd.bone_touch) {
          nd.bone_touch = true;
          push_event(events, nd, NeedleEventKind::BoneHit, s.time + dt, nearest, comp, -1, dist);
        }
      } else if (dist > 1e-3) {
        nd.bone_touch = false;  // re-armed once the tip is 1 mm away
      }
    } else {
      nd.bone_touch = false;
    }
  }

  if (clamped) {
    ++s.clamp_count;
    if (!nd.clamping) push_event(events, nd, NeedleEventKind::ForceClamped, s.time + dt, nd.T, -1, -1, requested);
  }
  nd.clamping = clamped;
  nd.T += step;
  nd.V = V_new;
  const double a = std::min(1.0, dt / kCutFilterTime);
  nd.v_cut += a * (V_new.dot(d_cmd) - nd.v_cut);
  nd.d = d_cmd;
  nd.ro.coupling_force = F_c;
  nd.ro.command_tip = T_cmd;
}

}  // namespace ps
