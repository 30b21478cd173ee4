// computeNeedleMovement and adjustIntensityNeedleVelocity (paper Algorithm 2). The needle is
// one rigid body of mass m whose tip follows the commanded pose through a spring-damper:
//   m dV/dt = k (T_cmd - T) + c (V_cmd - V) + F_tissue
// The coupling is integrated implicitly (backward Euler, exact for this linear part, so a stiff
// coupling never limits the step); the tissue reaction is explicit, but for the cutting gate's
// ramp, solved with the new velocity (implicit_cutting_force). Then the safety clamps:
// coupling force at max_force, speed at max_speed. Then the bone stop: the tip may not move
// closer to a bone surface than it is (conservative advancement with FCL distances).
#include <algorithm>

#include "engine/tools/bone_contact.h"
#include "engine/tools/needle/needle_internal.h"

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

double guide_depth(const NeedleTool::Needle& nd, double t) {
  if (!nd.interactive) {  // on its scenario script until a live command takes it over
    double depth = 0.0, rate = 0.0;
    script_depth(nd.spec, t, depth, rate);
    return depth + gun_stroke(nd, t);
  }
  return nd.cmd_depth + nd.cmd_speed * (t - nd.cmd_t0) + gun_stroke(nd, t);
}

namespace {

double guide_depth_rate(const NeedleTool::Needle& nd, double t) {
  if (!nd.interactive) {
    double depth = 0.0, rate = 0.0;
    script_depth(nd.spec, t, depth, rate);
    return rate + gun_stroke_rate(nd, t);
  }
  return nd.cmd_speed + gun_stroke_rate(nd, t);
}

}  // namespace

double implicit_cutting_force(double c_full, double u0, double beta, double v_cut, double a, double v_ramp) {
  if (c_full <= 0.0 || a <= 0.0) return 0.0;
  const double held = (1.0 - a) * v_cut;  // the filtered speed's part that does not depend on u
  // C(u) = c_full clamp((held + a u) / v_ramp, 0, 1): zero for u <= u_lo, full for u >= u_hi
  const double u_lo = -held / a, u_hi = (v_ramp - held) / a;
  if (u0 <= u_lo) return 0.0;
  if (u0 - beta * c_full >= u_hi) return c_full;
  // on the ramp: u + beta c_full (held + a u) / v_ramp = u0
  const double g = beta * c_full / v_ramp;
  const double u = (u0 - g * held) / (1.0 + g * a);
  return std::clamp(c_full * (held + a * u) / v_ramp, 0.0, c_full);
}

void needle_command(const NeedleTool::Needle& nd, double t, Vec3& tip, Vec3& dir, Vec3& vel) {
  if (nd.guided) {
    // the guide carries the needle: its entry and direction at the probe's pose now, and their
    // motion since the previous substep at the same depth (the probe turning or pushing it)
    const NeedlePath& g = nd.guide_now;
    const NeedlePath& g0 = nd.guide_prev;
    const double depth = guide_depth(nd, t);
    dir = g.direction;
    tip = g.entry + depth * dir;
    vel = guide_depth_rate(nd, t) * dir;
    if (nd.h_sub > 0.0) vel += ((g.entry + depth * g.direction) - (g0.entry + depth * g0.direction)) / nd.h_sub;
    return;
  }
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
  // implicit coupling: (m + dt c + dt^2 k) V' = m V + dt (F_tissue - C d + k (T_cmd - T) + c V_cmd),
  // with the cutting force C implicit too: it depends on V' through the gate's filtered speed
  const double m_eff = mass + dt * c + dt * dt * k;
  const Vec3 rhs = mass * nd.V + dt * (f_tissue + k * (T_cmd - nd.T) + c * V_cmd);
  const double a = std::min(1.0, dt / kCutFilterTime);
  const double cut = implicit_cutting_force(nd.cut_full, rhs.dot(d_cmd) / m_eff,
                                            dt * std::max(0.0, nd.d.dot(d_cmd)) / m_eff, nd.v_cut, a, sp.cut_velocity);
  apply_needle_cutting(nd, s, f_tissue, cut, events);
  const Vec3 f_all = f_tissue - cut * nd.d;  // every tissue force on the needle [N]
  Vec3 V_new = (rhs - (dt * cut) * nd.d) / m_eff;
  Vec3 F_c = k * (T_cmd - (nd.T + dt * V_new)) + c * (V_cmd - V_new);
  bool clamped = false;
  double requested = F_c.norm();
  if (requested > sp.max_force) {
    // an absurd command (teleported target, runaway device): push with the limit instead
    F_c *= sp.max_force / requested;
    V_new = nd.V + (dt / mass) * (f_all + F_c);
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
  nd.v_cut += a * (V_new.dot(d_cmd) - nd.v_cut);
  nd.d = d_cmd;
  nd.ro.coupling_force = F_c;
  nd.ro.command_tip = T_cmd;
}

}  // namespace ps
