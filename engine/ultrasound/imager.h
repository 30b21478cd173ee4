// Simulated B-mode image of one plane of a biplane TRUS probe (issue 12), pure CPU, generated
// from the current deformed surfaces of the particle model (no pre-acquired volume):
//
//  1. plane: transverse = convex sector perpendicular to the probe axis, apex on the axis,
//     centred on the probe's anterior side; sagittal = linear array on the anterior side,
//     beams along the anterior direction, in the plane of the probe axis. Display (clinical
//     convention): the probe at the bottom, depth upwards; transverse: the patient's right on the
//     screen's left (screen right = probe lateral = axis x anterior); sagittal: the probe tip
//     (cranial, base) on the screen's left.
//  2. regions: every component surface triangle that crosses the plane gives a segment; an
//     even-odd fill (XOR parity per pixel, one bit per component) labels each pixel with the
//     smallest enclosing component; walls (rectal, bladder) are bands outside their membranes.
//  3. material coordinates: the displacement of the particles near the plane is splatted
//     (per component, Wendland-like weights, radius 1.6 h) on a 2 mm grid; a pixel's rest
//     point X = x - u(x). Speckle (speckle.h) and the prostate's echo volume (zones, lesion,
//     urethra) are read at X, so they move and deform with the tissue and do not flicker.
//  4. scattering: backscatter amplitude x complex speckle, plus coherent reflections: surfaces
//     (specular ~ cos^4 of the angle of incidence + a diffuse part; the capsule is a bright line),
//     needles and seeds as rods weighted by the elevation beam profile (visibility falls with the
//     distance from the plane relative to the slice thickness), with comet-tail reverberation
//     along the beam behind them; then a separable Gaussian point-spread function (axial and
//     lateral widths from the wavelength, at least ~1 pixel) and the envelope |.|.
//  5. propagation, on a beam grid (rays from the sector apex / parallel beams): attenuation per
//     tissue and frequency, total shadow behind bone and gas (their attenuation), partial shadow
//     behind rods; time-gain compensation; gain; log compression over the dynamic range.
//  6. overlays: biopsy guide (dotted, sagittal) and template holes (dots, transverse).
// Buffers are sized in the constructor; render() does not allocate once the scene's vectors
// have reached their size (the segment list grows to the largest cut seen, then stays).
#pragma once
#include <cstdint>
#include <vector>

#include "engine/ultrasound/scene.h"
#include "engine/ultrasound/settings.h"

namespace ps::us {

enum class PlaneKind : uint8_t { Transverse, Sagittal };

// Orthonormal frame of the image plane in the world for one probe pose.
struct PlaneFrame {
  Vec3 origin = Vec3::Zero();   // transverse: sector apex on the probe axis; sagittal: on the axis under the array centre [m]
  Vec3 right = Vec3::UnitX();   // screen right (unit)
  Vec3 up = Vec3::UnitY();      // screen up = away from the probe (unit)
  Vec3 normal = Vec3::UnitZ();  // elevation: right x up
};

struct UsImage {
  int width = 0, height = 0;
  double pixel = 0.0;                 // pixel size [m] (square pixels)
  std::vector<uint8_t> pixels;        // grayscale, rows top-down
  std::vector<float> envelope;        // echo amplitude before log compression (PZ speckle rms ~ 1)
  std::vector<uint8_t> label;         // component index per pixel (walls: 64 + component), 255: none
  std::vector<uint8_t> in_view;       // 1 inside the sector / linear field of view
};

class PlaneImager {
 public:
  // Validates the settings (InputError naming the field) and sizes every buffer.
  PlaneImager(const UltrasoundAnatomy& anatomy, const UltrasoundSettings& settings, PlaneKind kind);

  // Forms the image of `scene` (positions, probe, rods, overlays). No allocation once warm.
  const UsImage& render(const UltrasoundScene& scene);
  const UsImage& image() const { return img_; }

  PlaneKind kind() const { return kind_; }
  const UltrasoundSettings& settings() const { return set_; }
  PlaneFrame frame(const ProbeView& probe) const;
  // world point -> continuous pixel (col, row; pixel centres at integers) and elevation [m]
  void world_to_pixel(const ProbeView& probe, const Vec3& p, double* col, double* row, double* elevation = nullptr) const;
  Vec3 pixel_to_world(const ProbeView& probe, double col, double row) const;
  // plane coordinates (s right, t up) [m] of a pixel centre
  double pixel_s(double col) const { return s0_ + col * px_; }
  double pixel_t(double row) const { return t0_ - row * px_; }
  double wavelength() const { return 1540.0 / set_.frequency; }  // [m]

 private:
  struct Seg {
    float s0, t0, s1, t1;    // plane coordinates [m]
    float nr, nu;            // in-plane components of the surface's unit normal (right, up)
    int comp;
  };
  void cut_surfaces(const UltrasoundScene& sc, const PlaneFrame& f);
  void fill_labels();
  void wall_bands();
  void displacement_fields(const UltrasoundScene& sc, const PlaneFrame& f);
  void scatter(const PlaneFrame& f);
  void coherent_surfaces();
  void coherent_rods(const UltrasoundScene& sc, const PlaneFrame& f);
  void splat(float col, float row, float amp);
  void blur();
  void transmission(const UltrasoundScene& sc, const PlaneFrame& f);
  void compress();
  void overlays(const UltrasoundScene& sc, const PlaneFrame& f);
  // beam direction (unit, plane coords) at plane point (s, t)
  void beam_dir(float s, float t, float* bs, float* bt) const;

  const UltrasoundAnatomy& an_;
  UltrasoundSettings set_;
  PlaneKind kind_;
  int W_, H_;
  double px_ = 0, s0_ = 0, t0_ = 0;   // pixel size; plane coords of pixel (0,0)'s centre [m]
  UsImage img_;
  // per pixel, fixed by the settings
  std::vector<float> depth_;          // from the array surface [m], <0 outside the view
  std::vector<float> tgc_;            // TGC x gain x 1/reference amplitude
  std::vector<int> lut_i_;            // beam-grid cell (b * NS + k) of the pixel, -1 outside
  std::vector<float> lut_wb_, lut_wk_;
  // beam grid
  int NB_ = 0, NS_ = 0;
  std::vector<int> beam_pix_;         // [NB*NS] nearest pixel of each beam sample, -1 outside
  std::vector<float> T_, mark_;       // [NB*NS] transmitted amplitude; rod shadow marks
  std::vector<int> rod_k_;            // [NB] per rod: shallowest depth cell where the beam meets it (NS: none)
  std::vector<float> rod_m_;          // [NB] per rod: fraction of the beam it lets through there
  // PSF
  std::vector<float> klat_, kax_;     // normalised Gaussian taps
  float lattice_ = 1e-4f;             // speckle lattice step [m]
  float ref_ = 1.0f;                  // rms envelope of unit-backscatter speckle (calibrated)
  // per frame
  std::vector<float> ps_, pt_, pe_;   // [particles] plane coordinates [m]
  std::vector<float> rest_;           // [3 * particles] rest positions (float) [m]
  std::vector<Seg> segs_;
  std::vector<uint32_t> mask_;
  int gx_ = 0, gy_ = 0;               // displacement grid nodes
  double g_ = 2e-3, gs0_ = 0, gt0_ = 0;
  std::vector<float> field_;          // [(ncomp+1) * gx*gy * 4]: ux, uy, uz, weight
  std::vector<int> rank_comp_;        // priority rank -> component
  std::vector<TissueAcoustics> comp_ac_;  // [components] acoustics of each component's tissue
  std::vector<uint8_t> comp_prostate_;    // [components] 1: the gland (echo from the rest volume)
  std::vector<int> col_a_;            // [W] displacement-grid cell of each pixel column
  std::vector<float> col_wa_;         // [W] its bilinear weight
  std::vector<float> cre_, cim_, tmp_re_, tmp_im_, pad_;
  int tx_ = 0, ty_ = 0;               // heterogeneity texture grid (every kTexStep pixels)
  std::vector<float> tex_;
  std::vector<float> row_q_;          // [6 * W] one row's lattice coordinates, amplitude, noise
  std::vector<int> row_i_;            // [W] their columns
};

// Both planes of the biplane probe.
class BiplaneImager {
 public:
  BiplaneImager(const UltrasoundAnatomy& anatomy, const UltrasoundSettings& settings)
      : transverse_(anatomy, settings, PlaneKind::Transverse), sagittal_(anatomy, settings, PlaneKind::Sagittal) {}
  void render(const UltrasoundScene& scene) {
    transverse_.render(scene);
    sagittal_.render(scene);
  }
  PlaneImager& transverse() { return transverse_; }
  PlaneImager& sagittal() { return sagittal_; }

 private:
  PlaneImager transverse_, sagittal_;
};

}  // namespace ps::us
