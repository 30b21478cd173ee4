// Geometry of the endorectal ultrasound probe: a capsule (cylinder of radius r with a
// hemispherical tip, and a rounded back end that stands for the shaft leaving the modelled
// region), its pose in the rectal frame, and the needle paths fixed to it (biopsy guide on the
// probe, brachytherapy template on the stepper). Pure functions, no state: the probe tool and
// the needle tool both use them, and tests check them without a simulation.
//
// Rectal frame: entry point E (anal entry, the pivot of tilt and yaw), axial a (insertion
// direction), anterior n (toward the prostate, orthogonalised against a), lateral l = a x n.
// Pose (ScenarioSpec ProbePose): pivot P = E + offset (offset's axial part removed),
//   R = Rot(l, tilt) * Rot(-n, yaw) * Rot(a, roll),   probe axis d = R a,
//   tip-hemisphere centre B = P + insertion * d,  back end A = B - length * d.
// Positive tilt swings the tip toward the prostate (anterior), positive yaw toward +l.
#pragma once
#include "engine/spec/scenario_spec.h"
#include "engine/util/vec.h"

namespace ps {

struct RectalFrame {
  Vec3 entry = Vec3::Zero();       // [m]
  Vec3 axial = Vec3::UnitZ();      // unit
  Vec3 anterior = Vec3::UnitY();   // unit, perpendicular to axial
  Vec3 lateral = Vec3::UnitX();    // axial x anterior
};

// Orthonormal rectal frame from the spec (anterior made perpendicular to the axis). Throws
// std::invalid_argument if anterior is parallel to the axis (the parser rejects that first).
RectalFrame rectal_frame(const ProbeSpec& spec);

// Segment [back, tip] swept by a sphere of the probe radius.
struct Capsule {
  Vec3 back = Vec3::Zero();        // back end centre A [m]
  Vec3 tip = Vec3::Zero();         // tip-hemisphere centre B [m]
  Vec3 dir = Vec3::UnitZ();        // (B - A)/|B - A|
  double length = 0.0;             // |B - A| [m]
  double radius = 0.0;             // [m]
};

struct ProbeFrame {
  Vec3 pivot = Vec3::Zero();       // [m]
  Mat3 rot = Mat3::Identity();     // columns: probe axis d, body anterior R n, body lateral R l
  Capsule capsule;
  Vec3 axis() const { return rot.col(0); }
  Vec3 anterior() const { return rot.col(1); }
};

ProbeFrame probe_frame(const ProbeSpec& spec, const RectalFrame& rf, const ProbePose& pose);

// Closest point of the capsule's axis segment to x, and the signed distance from x to the
// capsule surface (negative inside) [m].
inline double capsule_signed_distance(const Capsule& c, const Vec3& x, Vec3* axis_point = nullptr) {
  double t = (x - c.back).dot(c.dir);
  t = t < 0.0 ? 0.0 : (t > c.length ? c.length : t);
  const Vec3 q = c.back + t * c.dir;
  if (axis_point) *axis_point = q;
  return (x - q).norm() - c.radius;
}

// A straight needle path: where the needle enters (leaves its guide) and its unit direction.
struct NeedlePath {
  Vec3 entry = Vec3::Zero();       // [m]
  Vec3 direction = Vec3::UnitZ();  // unit
};

// Biopsy guide clamped on the probe (turns with roll): exits on the probe surface on the body
// anterior side, guide_back behind the tip centre, angled guide_angle from the probe axis toward
// the body anterior.
NeedlePath biopsy_guide_path(const ProbeSpec& spec, const ProbeFrame& f);

// Brachytherapy template hole (col, row), 0-based: the template is fixed to the stepper, so it
// follows the probe's offset, tilt and yaw but neither its insertion (the stepper moves the
// probe through it) nor its roll. Plane perpendicular to the probe axis, template_distance
// behind the pivot; column c sits at lateral (c - (cols-1)/2) * pitch, row r at anterior
// template_first_row + r * pitch from the probe axis. Needles run parallel to the probe axis.
// Throws InputError (field "template hole") for a hole outside the grid.
NeedlePath template_hole_path(const ProbeSpec& spec, const RectalFrame& rf, const ProbePose& pose, int col, int row);

}  // namespace ps
