// Builds the static part of the ultrasound input (UltrasoundAnatomy, scene.h) from a compiled
// Model, once: each component's acoustic class (from its role, overridable), its closed surface,
// its drawing priority (smaller enclosed rest volume first, so an organ inside the fat block is
// drawn as the organ), and the prostate's rest-space echogenicity volume from the particles' zone
// and lesion tags (engine/anatomy/zones.h, scenario `tags:`) and the Model's urethra line.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "engine/anatomy/display_meshes.h"
#include "engine/model/model.h"
#include "engine/ultrasound/scene.h"

namespace ps::us {

struct AnatomyOptions {
  // component name -> tissue, applied over the role rule of tissue_for_component()
  std::vector<std::pair<std::string, Tissue>> tissue_overrides;
  // The urethra without a catheter is collapsed: a subtle hypoechoic line (lumen echo 0.5 of the
  // peripheral zone, 1.2 mm radius) with a faintly brighter periurethral rim, not a black band.
  double urethra_radius = 1.2e-3;  // [m]
  // prostatic calcifications in rest space: centre [m] and radius [m] (optional, per case)
  std::vector<std::pair<Vec3, double>> calcifications;
  double voxel = 1.0e-3;           // prostate echo volume voxel [m]
  // The bladder and the bones are imaged through smooth surfaces: their particle triangles (7-8 mm in
  // the scenes) Loop-subdivided this many times at rest (2: ~2 mm edges), each new vertex carried by
  // its 4 nearest particles of the component. A cut through the coarse triangles is a polygon with
  // straight walls (the pubic arch's 7 mm tube a V); 0: image the particle triangles themselves.
  int smooth_subdivisions = 2;
  // shapes imaged but not simulated (engine/anatomy/display_meshes.h): each seminal vesicle becomes
  // a component of tissue SeminalVesicle over carried vertices; the pubic bone as drawn is not
  // imaged (its parts overlap; the physics' pubic arch is)
  std::vector<anatomy::DisplayMesh> display_meshes;
};

// By role (Component::role): prostate -> Prostate, bladder -> Bladder, rectum -> Rectum,
// gas -> Gas, bone -> Bone, fat -> Fat; urethra, lesion, skin and other -> Soft.
Tissue tissue_for_component(const Component& c);

// Echogenicity of one prostate particle from its tags: a tag whose role is lesion -> 0.3
// (hypoechoic: ~60 % of peripheral-zone cancers on TRUS), peripheral 1.0 (the isoechoic
// reference), transition 0.75, anterior fibromuscular stroma 0.55, untagged 0.9.
float prostate_particle_echo(const Model& m, int particle);

UltrasoundAnatomy build_anatomy(const Model& m, const AnatomyOptions& opt = {});

// Reads prostatic calcifications (assets/anatomy/calcifications.csv: `x_mm,y_mm,z_mm,radius_mm`
// rows, '#' comments), scaled by unit_scale [m per file unit] and translated by `translate` [m]. InputError (file:line) on a
// malformed row or a radius outside (0, 10] mm.
std::vector<std::pair<Vec3, double>> read_calcifications_csv(const std::string& path, double unit_scale, const Vec3& translate);

}  // namespace ps::us
