// The default anatomy of ProstateSim (GitHub issue 3): prostate, bladder, rectum, pelvic fat,
// pubic arch, urethra path and perineal skin plane, generated from a handful of documented
// dimensions (docs/anatomy.md gives the values and their sources). Pure geometry and
// deterministic: the same parameters give bit-identical meshes.
//
// Frame: patient RAS, metres. x towards the patient's right, y posterior -> anterior,
// z inferior -> superior (head). Origin at the centre of the prostate's bounding ellipsoid.
// Every organ surface is closed, outward-oriented and 2-manifold; organs do not touch (gaps of
// a few millimetres where they are neighbours: scenarios link them with `links:`).
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "engine/mesh/tri_mesh.h"
#include "engine/util/vec.h"

namespace ps::anatomy {

struct ProstateParams {
  // Chestnut: an ellipsoid with different semi-axes on each side, widened towards the base and
  // narrowed towards the apex, flattened posteriorly with a shallow median sulcus.
  double half_width = 23.5e-3;       // lateral semi-axis at mid-height [m]
  double half_depth_anterior = 16.5e-3;   // antero-posterior semi-axis, anterior side [m]
  double half_depth_posterior = 14.5e-3;  // ... posterior side (flatter, faces the rectum) [m]
  double half_length_base = 18.5e-3; // centre -> base (superior) [m]
  double half_length_apex = 21.5e-3; // centre -> apex (inferior; the apex is the pointed end) [m]
  double taper = 0.20;               // relative widening per unit of z/half_length (base > apex) [-]
  double sulcus_depth = 2.0e-3;      // posterior median sulcus [m]
  double sulcus_width = 8.0e-3;      // its lateral half-width (Gaussian) [m]
  int sphere_levels = 3;             // icosphere subdivisions: 642 vertices, ~3 mm edges
};

struct BladderParams {
  double volume = 200.0e-6;          // resting volume [m^3] (200 ml)
  double half_width = 45.0e-3;       // lateral semi-axis [m]
  double half_depth = 30.0e-3;       // antero-posterior semi-axis [m]
  double half_height_below = 26.0e-3;  // centre -> neck (flatter base resting on the prostate) [m]
  double neck_offset_y = 10.0e-3;     // bladder neck anterior of the prostate centre [m]
  double gap_to_prostate = 2.0e-3;   // bladder neck above the prostate base [m]
  int sphere_levels = 3;
};

struct RectumParams {
  double radius = 15.0e-3;           // lumen + wall, distended by a TRUS probe (30 mm diameter) [m]
  double gap_to_prostate = 3.0e-3;   // Denonvilliers' fascia between rectum and prostate [m]
  double bottom_above_perineum = 10.0e-3;  // lower end (anal canal) above the skin plane [m]
  double straight_top_z = 10.0e-3;   // straight along z up to here, then bends posteriorly [m]
  double bend_radius = 60.0e-3;      // sacral curve radius of the axis [m]
  double bend_angle_deg = 35.0;      // posterior bend of the upper rectum [deg]
  int ring = 24;                     // vertices per cross-section (~3.9 mm edges)
  double step = 4.0e-3;              // cross-section spacing along the axis [m]
};

struct PubicArchParams {
  // The inferior border of the symphysis and the inferior pubic rami, as a tube along the arch
  // x = w s, y = y_top - drop_y s^2, z = z_top - drop_z s^2, s in [-1, 1] (template view: an
  // inverted U over the anterior prostate). Placed so that perineal needles aimed within a few
  // millimetres of the anterior prostate edge strike it (pubic arch interference).
  double radius = 7.0e-3;            // bone half-thickness [m]
  double half_span = 38.0e-3;        // lateral reach of the rami w [m]
  double y_top = 20.0e-3;            // arch top (symphysis) antero-posterior position [m]
  double z_top = -24.0e-3;           // arch top height (below the prostate mid-plane) [m]
  double drop_y = 30.0e-3;           // rami run posteriorly... [m]
  double drop_z = 14.0e-3;           // ... and inferiorly [m]
  int ring = 12;
  double step = 3.5e-3;
};

// Seminal vesicles (paired): flattened sacs on the posterior bladder wall, posterior-superior to
// the prostate's base, diverging superolaterally from the base (a "V" seen from behind). Each is
// an ellipsoid along the line medial end -> lateral end (x of the right one; the left one is its
// mirror), flattened antero-posteriorly, bent slightly posteriorly around the bladder. Not physical
// (no particles): the ultrasound images them and the 3D view draws them, both carried by the tissue
// around them (engine/anatomy/display_meshes.h).
struct SeminalVesicleParams {
  Vec3 medial_end = Vec3(2.5e-3, -12.0e-3, 19.5e-3);   // right vesicle, near the base midline [m]
  Vec3 lateral_end = Vec3(30.0e-3, -18.5e-3, 36.0e-3); // right vesicle, superolateral tip [m]
  double half_width = 7.0e-3;        // across the long axis, in the coronal plane [m]
  double half_thickness = 3.5e-3;    // antero-posterior [m]
  double bend = 2.0e-3;              // posterior sag of the middle [m]
  int sphere_levels = 2;             // 162 vertices each
};

// The pubic bone as the 3D view draws it (not physical: the physics keeps the pubic arch tube, the
// part needles strike): the symphysis with both pubic bodies above the arch's top, the superior
// rami running laterally and posteriorly towards the acetabula, and the ischial rami closing each
// obturator foramen down to the arch's ends.
struct PubicBoneParams {
  Vec3 symphysis_centre = Vec3(0.0, 29.0e-3, -6.0e-3);  // [m]
  Vec3 symphysis_half = Vec3(20.0e-3, 7.0e-3, 19.0e-3); // pubic bodies: lateral, AP, height [m]
  double symphysis_tilt_deg = 20.0;  // its upper end anterior [deg]
  Vec3 superior_ramus_end = Vec3(52.0e-3, 4.0e-3, 22.0e-3);  // right side, at the acetabulum [m]
  double ramus_radius = 6.0e-3;      // [m]
  int ring = 12;
  double step = 4.0e-3;
};

struct AnatomyParams {
  ProstateParams prostate;
  SeminalVesicleParams seminal_vesicles;
  PubicBoneParams pubic_bone;
  BladderParams bladder;
  RectumParams rectum;
  PubicArchParams pubic_arch;
  // Pelvic fat / connective tissue: a block around the organs. Its inferior face is the perineal
  // skin plane (z = fat_min.z); the other faces stand for the pelvic walls. The part above the
  // bladder dome (91.4 mm) stands for the lower abdominal contents the filling dome rises into:
  // 32.6 mm of it (three 10 mm fat lattice layers), more than the dome's ~20 mm rise when the
  // bladder doubles (bladder_filling.yaml). With 14.6 mm (fat_max.z = 106 mm: one lattice layer
  // under the surface layer) the doubled dome made those particles vibrate at 0.1-0.5 m/s
  // without settling (docs/anatomy.md).
  Vec3 fat_min = Vec3(-60e-3, -70e-3, -62e-3);  // [m]
  Vec3 fat_max = Vec3(60e-3, 56e-3, 124e-3);    // [m]
  double fat_edge = 12.0e-3;                     // edge length of the block mesh [m]
  double urethra_step = 1.0e-3;                  // urethra polyline sampling [m]
  // Calcifications on the surgical capsule (present in most men of biopsy age), as directions
  // from the prostate centre (scaled to the surface), the fraction of the way to the surface and
  // the radius; empty: none.
  struct CalcificationSpec {
    Vec3 direction;
    double fraction;
    double radius;                               // [m]
  };
  std::vector<CalcificationSpec> calcifications = {
      {Vec3(0.55, -0.45, 0.35), 0.62, 1.2e-3},
      {Vec3(-0.5, -0.5, 0.2), 0.60, 1.0e-3},
      {Vec3(-0.6, -0.35, -0.25), 0.58, 1.4e-3},
  };
};

// Prostatic calcification (corpora amylacea): a small stone, usually along the surgical capsule
// between the transition and peripheral zones; on TRUS a bright focus with an acoustic shadow.
struct Calcification {
  Vec3 centre = Vec3::Zero();        // [m]
  double radius = 1.0e-3;            // [m]
};

struct Landmark {
  std::string name;
  Vec3 position;                     // [m]
};

struct Anatomy {
  TriMesh prostate, bladder, rectum, fat, pubic_arch;   // closed outward surfaces [m]
  // not physical (drawn and imaged only): both vesicles (two closed surfaces) and the pubic bone
  // (closed parts that overlap: drawn, not filled)
  TriMesh seminal_vesicles, pubic_bone;
  std::vector<Vec3> urethra;         // prostatic urethra, bladder neck -> apex, inside the prostate [m]
  std::vector<Vec3> rectum_axis;     // centre line of the rectum tube, inferior -> superior [m]
  std::vector<Calcification> calcifications;  // in the prostate, on the surgical capsule [m]
  double perineum_z = 0.0;           // perineal skin plane z = perineum_z, outward normal -z [m]
  std::vector<Landmark> landmarks;
};

Anatomy generate_anatomy(const AnatomyParams& params = {});

// The chestnut prostate as a map from a unit direction to its surface point [m].
Vec3 prostate_surface_point(const ProstateParams& p, const Vec3& unit_dir);

}  // namespace ps::anatomy
