// Inputs of the ultrasound image generator (engine/ultrasound/imager.h), as plain data:
//  - UltrasoundAnatomy: what does not change while the scene deforms (built once from a Model:
//    each component's tissue, its closed surface, rest positions, and a rest-space echogenicity
//    volume of the prostate from its zone and lesion tags and the urethra);
//  - UltrasoundScene: what changes every frame (current particle positions, the probe frame,
//    needles and seeds as rods, overlay lines), filled by the adapters of
//    engine/ultrasound/from_simulation.h from a Simulation or a Snapshot.
// All lengths in metres, world frame (patient RAS, see config/*.yaml).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/util/vec.h"

namespace ps::us {

// Acoustic class of a component: sets echogenicity, attenuation and what its inside is.
enum class Tissue : uint8_t {
  Prostate,   // volumetric gland: echogenicity from the rest-space volume (zones, lesion, urethra)
  Fat,        // periprostatic fat: brighter than the gland and heterogeneous
  Bladder,    // membrane: its inside is urine (anechoic, no attenuation: posterior enhancement)
  Rectum,     // membrane: its inside is the lumen (water-filled balloon around the probe: anechoic)
  Bone,       // bright surface, total acoustic shadow
  Gas,        // bright surface with reverberation, total shadow (e.g. rectal gas)
  SeminalVesicle,  // fluid-filled convoluted sacs: hypoechoic, mottled, little attenuation
  Soft,       // any other soft tissue: isoechoic speckle
};

// Acoustic parameters of one tissue (tissue.cpp holds the table and its sources).
struct TissueAcoustics {
  float echo = 1.0f;          // backscatter amplitude relative to the peripheral zone [-]
  float hetero = 0.0f;        // relative amplitude of the low-frequency texture [-]
  float atten = 0.5f;         // attenuation [dB/(cm MHz)], one way
  float interface = 0.5f;     // coherent reflection at its surface (specular part) [-]
  float diffuse = 0.5f;       // reflection at its surface seen at any angle [-]
  float wall = 0.0f;          // wall band outside its surface [m] (rectal / bladder wall), 0: none
  float wall_echo = 0.4f;     // echogenicity of that band [-]
};
const TissueAcoustics& acoustics(Tissue t);

struct UsComponent {
  std::string name;
  Tissue tissue = Tissue::Soft;
  int first_particle = 0, particle_count = 0;        // none for a carried shape (seminal vesicle)
  double spacing = 0.0;                              // particle spacing h [m]
  // closed outward surface: particle indices, or rest.size() + v for carried vertex v
  std::vector<std::array<int, 3>> faces;
  int priority = 0;                                  // 0 = drawn over all others (smallest volume)
};

// Scalar field on a regular grid in rest space (trilinear look-up), e.g. the prostate's echo.
struct RestVolume {
  Vec3 origin = Vec3::Zero();      // centre of voxel (0,0,0) [m]
  double step = 1e-3;              // voxel size [m]
  int nx = 0, ny = 0, nz = 0;
  std::vector<float> value;        // [nx*ny*nz], x fastest
  bool empty() const { return value.empty(); }
};

// Prostate echo-volume values at or above this are calcifications: bright, and they stop the beam
// (acoustic shadow) like bone.
constexpr float kCalcificationEcho = 4.0f;

// A lesion (a tag whose role is lesion, engine/model/role.h) as MRI-TRUS fusion shows it: a
// sphere of its rest extent around the current centroid of its particles.
struct UsLesion {
  std::string name;
  std::vector<int> particles;
  double radius = 0.0;                   // [m] rest extent: farthest particle + half its spacing
};

struct UltrasoundAnatomy {
  std::vector<UsComponent> components;   // imaged components, in Model order (at most 32)
  std::vector<int> component_index;      // [model components] index into `components`, -1 if none
  std::vector<Vec3> rest;                // [particles] rest positions [m]
  int prostate = -1;                     // index into components of the gland, -1 if none
  RestVolume prostate_echo;              // rest-space echogenicity inside the gland [-]
  std::vector<Vec3> urethra;             // prostatic urethra centre line, rest space [m] (may be empty)
  double urethra_radius = 1.2e-3;        // hypoechoic (collapsed) lumen radius [m]
  std::vector<std::pair<Vec3, double>> calcifications;  // rest-space centre and radius [m] (in the echo volume)
  std::vector<UsLesion> lesions;         // fused MRI contours (overlays only, not echo)
  // Vertices of shapes that are imaged but not simulated (the seminal vesicles,
  // engine/anatomy/display_meshes.h), carried by the tissue: vertex v (index rest.size() + v in
  // a component's faces) lies at sum_k weights[v][k] x[particles[v][k]] + offsets[v].
  std::vector<std::array<int, 4>> carried_particles;
  std::vector<std::array<float, 4>> carried_weights;
  std::vector<Vec3> carried_offsets;     // [m]
};

// A thin rigid object the beam sees (needle shaft, seed): a segment with a radius.
struct Rod {
  Vec3 a = Vec3::Zero(), b = Vec3::Zero();  // ends [m] (a: needle tip)
  double radius = 0.6e-3;                    // [m]
  float reflect = 25.0f;                     // coherent reflection amplitude (PZ speckle rms = 1) [-]
  float reverb = 0.40f;                      // comet-tail ratio between successive echoes [-]
  float shadow = 0.4f;                       // fraction of the beam it stops [-]
};

// A line drawn over the image: the biopsy guide (sagittal, dotted) or a template hole (a dot where
// it crosses the transverse plane).
struct OverlayLine {
  enum Kind : uint8_t { Guide, TemplateHole } kind = Guide;
  Vec3 entry = Vec3::Zero();       // [m]
  Vec3 direction = Vec3::UnitZ();  // unit
};

// The probe as the imager needs it (engine/tools/probe/probe_geometry.h ProbeFrame).
struct ProbeView {
  Vec3 tip_centre = Vec3::Zero();  // tip-hemisphere centre B [m]
  Vec3 axis = Vec3::UnitZ();       // probe axis d (insertion direction), unit
  Vec3 anterior = Vec3::UnitY();   // body anterior (the side the arrays look to), unit, _|_ axis
  Vec3 lateral = -Vec3::UnitX();   // axis x anterior: the patient's left at roll 0, unit
  double radius = 0.010;           // probe radius [m]
};

struct UltrasoundScene {
  const float* x = nullptr;        // 3 * particles current positions [m] (Snapshot::x layout)
  int particle_count = 0;
  ProbeView probe;
  std::vector<Rod> rods;           // needles and deposited seeds
  std::vector<OverlayLine> overlays;
  std::vector<float> x_storage;    // owned positions when filled from a State (x points here)
};

}  // namespace ps::us
