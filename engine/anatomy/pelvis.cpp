#include "engine/anatomy/pelvis.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/anatomy/shapes.h"
#include "engine/mesh/mesh_query.h"

namespace ps::anatomy {

namespace {

double max_z(const TriMesh& m) {
  double z = -1e300;
  for (const Vec3& v : m.vertices) z = std::max(z, v.z());
  return z;
}
double min_z(const TriMesh& m) {
  double z = 1e300;
  for (const Vec3& v : m.vertices) z = std::min(z, v.z());
  return z;
}

// Bladder: ellipsoid with a flatter lower half (the base resting on the prostate), scaled about
// its lowest point (the neck) so that the polyhedron holds exactly the requested volume.
TriMesh make_bladder(const BladderParams& b, const Vec3& neck) {
  const double a = b.half_width, d = b.half_depth, lo = b.half_height_below;
  // half-ellipsoids: V = 2/3 pi a d (c_up + c_down)
  const double hi = 3.0 * b.volume / (2.0 * std::numbers::pi * a * d) - lo;
  TriMesh m = map_sphere(icosphere(b.sphere_levels), [&](const Vec3& u) {
    return Vec3(a * u.x(), d * u.y(), (u.z() >= 0.0 ? hi : lo) * u.z());
  });
  const double zlow = min_z(m);
  const Vec3 bottom(0.0, 0.0, zlow);
  const double s = std::cbrt(b.volume / signed_volume(m));
  for (Vec3& v : m.vertices) v = neck + s * (v - bottom);
  return m;
}

// Largest y of a z-parallel axis at (0, y) whose tube of radius r keeps `gap` from every vertex
// of `m` below z_max (the rectum placed behind the prostate).
double tube_axis_y_behind(const TriMesh& m, double r, double gap, double z_max) {
  double y = 1e300;
  const double rr = r + gap;
  for (const Vec3& v : m.vertices) {
    if (v.z() > z_max || std::abs(v.x()) >= rr) continue;
    y = std::min(y, v.y() - std::sqrt(rr * rr - v.x() * v.x()));
  }
  return y;
}

void append(TriMesh& to, const TriMesh& part) {
  const int off = static_cast<int>(to.vertices.size());
  to.vertices.insert(to.vertices.end(), part.vertices.begin(), part.vertices.end());
  for (const auto& f : part.faces) to.faces.push_back({f[0] + off, f[1] + off, f[2] + off});
}

// One seminal vesicle: an ellipsoid from `m` to `l` (long axis), flattened antero-posteriorly,
// its middle sagging posteriorly by `bend`. The frame (long, anterior, width) is right-handed, so
// the sphere's outward faces stay outward.
TriMesh seminal_vesicle(const SeminalVesicleParams& p, const Vec3& m, const Vec3& l) {
  const Vec3 c = 0.5 * (m + l), A = (l - m).normalized();
  const Vec3 T = (Vec3::UnitY() - Vec3::UnitY().dot(A) * A).normalized();
  const Vec3 W = A.cross(T);
  const double a = 0.5 * (l - m).norm();
  return map_sphere(icosphere(p.sphere_levels), [&](const Vec3& u) {
    return Vec3(c + a * u.x() * A + (p.half_thickness * u.y() - p.bend * (1.0 - u.x() * u.x())) * T + p.half_width * u.z() * W);
  });
}

TriMesh make_seminal_vesicles(const SeminalVesicleParams& p) {
  const Vec3 mirror(-1.0, 1.0, 1.0);
  TriMesh m = seminal_vesicle(p, p.medial_end, p.lateral_end);
  append(m, seminal_vesicle(p, p.medial_end.cwiseProduct(mirror), p.lateral_end.cwiseProduct(mirror)));
  return m;
}

// Pubic bone for the 3D view: the symphysis (both pubic bodies, a rounded block tilted with its
// upper end anterior), superior rami to the acetabula, ischial rami from the arch's ends up to them.
TriMesh make_pubic_bone(const PubicBoneParams& p, const PubicArchParams& arch) {
  const double th = -p.symphysis_tilt_deg * std::numbers::pi / 180.0;
  const double c = std::cos(th), s = std::sin(th);
  auto boxy = [](double v) { return std::copysign(std::pow(std::abs(v), 0.75), v); };
  TriMesh m = map_sphere(icosphere(2), [&](const Vec3& u) {
    const Vec3 q(p.symphysis_half.x() * boxy(u.x()), p.symphysis_half.y() * boxy(u.y()), p.symphysis_half.z() * boxy(u.z()));
    return Vec3(p.symphysis_centre + Vec3(q.x(), c * q.y() - s * q.z(), s * q.y() + c * q.z()));
  });
  const int cap = std::max(2, static_cast<int>(std::lround(0.5 * std::numbers::pi * p.ramus_radius / p.step)));
  for (const double side : {1.0, -1.0}) {
    const Vec3 k(side, 1.0, 1.0);
    const Vec3 top = (p.symphysis_centre + Vec3(0.7 * p.symphysis_half.x(), 0.0, 0.6 * p.symphysis_half.z())).cwiseProduct(k);
    const Vec3 acetabulum = p.superior_ramus_end.cwiseProduct(k);
    const Vec3 mid = 0.5 * (top + acetabulum) + Vec3(0.0, 4.0e-3, -4.0e-3);
    append(m, swept_tube(resample_polyline({top, mid, acetabulum}, p.step), p.ramus_radius, p.ring, cap));
    // the arch's end (s = +-1) up along the ischium to the acetabulum
    const Vec3 arch_end = Vec3(arch.half_span, arch.y_top - arch.drop_y, arch.z_top - arch.drop_z).cwiseProduct(k);
    const Vec3 ischium = Vec3(p.superior_ramus_end.x() + 2.0e-3, arch.y_top - arch.drop_y - 4.0e-3, 0.5 * (arch.z_top - arch.drop_z + p.superior_ramus_end.z())).cwiseProduct(k);
    append(m, swept_tube(resample_polyline({arch_end, ischium, acetabulum}, p.step), p.ramus_radius, p.ring, cap));
  }
  return m;
}

}  // namespace

Vec3 prostate_surface_point(const ProstateParams& p, const Vec3& u) {
  const double a = p.half_width * (1.0 + p.taper * u.z());
  const double b = (u.y() >= 0.0 ? p.half_depth_anterior : p.half_depth_posterior) * (1.0 + 0.5 * p.taper * u.z());
  const double c = u.z() >= 0.0 ? p.half_length_base : p.half_length_apex;
  Vec3 x(a * u.x(), b * u.y(), c * u.z());
  if (u.y() < 0.0) {
    // median sulcus: the posterior surface pushed in along the midline
    const double w = x.x() / p.sulcus_width;
    x.y() += p.sulcus_depth * u.y() * u.y() * std::exp(-w * w);
  }
  return x;
}

Anatomy generate_anatomy(const AnatomyParams& P) {
  Anatomy A;
  A.perineum_z = P.fat_min.z();

  // prostate, centred at the origin
  A.prostate = map_sphere(icosphere(P.prostate.sphere_levels),
                          [&](const Vec3& u) { return prostate_surface_point(P.prostate, u); });
  const double base_z = max_z(A.prostate), apex_z = min_z(A.prostate);

  // bladder: neck just above the prostate base, slightly anterior
  const Vec3 neck(0.0, P.bladder.neck_offset_y, base_z + P.bladder.gap_to_prostate);
  A.bladder = make_bladder(P.bladder, neck);

  // rectum: straight behind the prostate, then curving posteriorly along the sacrum
  const RectumParams& R = P.rectum;
  const double axis_y = tube_axis_y_behind(A.prostate, R.radius, R.gap_to_prostate, R.straight_top_z);
  const double z0 = A.perineum_z + R.bottom_above_perineum + R.radius;
  std::vector<Vec3> axis = resample_polyline({Vec3(0, axis_y, z0), Vec3(0, axis_y, R.straight_top_z)}, R.step);
  const double th_end = R.bend_angle_deg * std::numbers::pi / 180.0;
  const int n_arc = std::max(1, static_cast<int>(std::lround(R.bend_radius * th_end / R.step)));
  for (int k = 1; k <= n_arc; ++k) {
    const double th = th_end * k / n_arc;
    axis.emplace_back(0.0, axis_y - R.bend_radius * (1.0 - std::cos(th)), R.straight_top_z + R.bend_radius * std::sin(th));
  }
  A.rectum_axis = axis;
  A.rectum = swept_tube(axis, R.radius, R.ring, std::max(2, static_cast<int>(std::lround(0.5 * std::numbers::pi * R.radius / R.step))));

  // pubic arch
  const PubicArchParams& B = P.pubic_arch;
  std::vector<Vec3> arch;
  const int n_fine = 400;
  for (int k = 0; k <= n_fine; ++k) {
    const double s = -1.0 + 2.0 * k / n_fine;
    arch.emplace_back(B.half_span * s, B.y_top - B.drop_y * s * s, B.z_top - B.drop_z * s * s);
  }
  A.pubic_arch = swept_tube(resample_polyline(arch, B.step), B.radius, B.ring,
                            std::max(2, static_cast<int>(std::lround(0.5 * std::numbers::pi * B.radius / B.step))));

  // not physical: seminal vesicles and the pubic bone as drawn
  A.seminal_vesicles = make_seminal_vesicles(P.seminal_vesicles);
  A.pubic_bone = make_pubic_bone(P.pubic_bone, B);

  // fat block
  A.fat = grid_box(P.fat_min, P.fat_max, P.fat_edge);

  // prostatic urethra: bladder neck -> verumontanum (mid-gland, bent ~35 deg anteriorly) -> apex,
  // the part inside the prostate
  const ProstateParams& Q = P.prostate;
  const std::vector<Vec3> guide = {Vec3(0, 0.35 * Q.half_depth_anterior, base_z + 1e-3),
                                   Vec3(0, -0.1 * Q.half_depth_posterior, -1.0e-3),
                                   Vec3(0, 0.25 * Q.half_depth_anterior, apex_z - 1e-3)};
  const MeshQuery prostate_q(A.prostate);
  for (const Vec3& p : resample_polyline(guide, P.urethra_step))
    if (prostate_q.inside(p)) A.urethra.push_back(p);

  // calcifications: on the surgical capsule, a fixed fraction of the way from the centre to the
  // surface along each direction
  for (const AnatomyParams::CalcificationSpec& c : P.calcifications)
    A.calcifications.push_back({c.fraction * prostate_surface_point(Q, c.direction.normalized()), c.radius});

  // landmarks
  const Vec3 arch_top(0.0, B.y_top, B.z_top);
  A.landmarks = {
      {"prostate_centre", Vec3::Zero()},
      {"prostate_base", Vec3(0, 0, base_z)},
      {"prostate_apex", Vec3(0, 0, apex_z)},
      {"bladder_neck", neck},
      {"verumontanum", guide[1]},
      {"urethra_base_end", A.urethra.front()},
      {"urethra_apex_end", A.urethra.back()},
      {"rectum_axis_bottom", axis.front()},
      {"rectum_axis_at_prostate", Vec3(0, axis_y, 0)},
      {"rectum_axis_top", axis.back()},
      {"pubic_arch_top", arch_top},
      {"perineum_centre", Vec3(0, 0, A.perineum_z)},
      {"fat_min", P.fat_min},
      {"fat_max", P.fat_max},
  };
  return A;
}

}  // namespace ps::anatomy
