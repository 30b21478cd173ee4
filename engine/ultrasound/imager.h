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
//  4. echo formation on the acquisition grid (beams x depth samples: rays from the sector apex /
//     parallel beams): the scatterer field is read at each sample's rest point (speckle.h; in
//     rest space, stretched along the elevation so it decorrelates over the slice thickness
//     when the plane moves through the tissue) x the local backscatter amplitude; coherent
//     reflections are added: surfaces (specular ~ cos^4 of the angle of incidence + a diffuse
//     part; capsule and bladder wall brightest at normal incidence), needles and seeds as rods
//     weighted by the elevation beam profile, with comet tails, the probe's near-field
//     reverberation.
//  5. propagation on the same grid: each echo source x its round-trip attenuation per tissue and
//     frequency (total shadow behind bone, gas and calcifications, partial behind rods); then the
//     complex (I/Q) signal is convolved with the pulse-echo point-spread function: axial Gaussian
//     from the centre frequency and bandwidth, lateral from the transmit focus (Gaussian beam,
//     widening away from the focus) and the dynamically focused receive aperture, per depth
//     (attenuation before the blur: a bone surface's echo keeps its whole pulse length); time-gain
//     compensation; scan conversion (bilinear, I/Q) to the pixels, envelope |I + iQ|, gain, log
//     compression.
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
  double wavelength() const { return kSoundSpeed / set_.frequency; }  // [m]
  // Point-spread function of the echo amplitude, FWHM [m]: axial (the same at every depth) and
  // lateral at a depth below the array surface; both include the scatterer field's own
  // correlation (the speckle grain they give is the intensity autocorrelation's FWHM).
  double psf_axial_fwhm() const { return 2.3548 * sig_ax_total_; }
  double psf_lateral_fwhm(double depth) const;
  double lattice_step() const { return lattice_; }  // scatterer field lattice [m]
  int beams() const { return NB_; }
  int samples() const { return NS_; }

  static constexpr double kSoundSpeed = 1540.0;  // [m/s], soft-tissue average (Duck 1990, ICRU 61)

 private:
  struct Seg {
    float s0, t0, s1, t1;    // plane coordinates [m]
    float nr, nu;            // in-plane components of the surface's unit normal (right, up)
    int comp;
  };
  void cut_surfaces(const UltrasoundScene& sc, const PlaneFrame& f);
  // current position of surface vertex v (a particle, or a carried vertex after them)
  const float* vertex(const UltrasoundScene& sc, int v) const {
    const int n = sc.particle_count;
    return v < n ? sc.x + 3 * static_cast<size_t>(v) : &xc_[3 * static_cast<size_t>(v - n)];
  }
  void fill_labels();
  void wall_bands();
  void displacement_fields(const UltrasoundScene& sc, const PlaneFrame& f);
  void texture(const PlaneFrame& f);
  void scatter(const UltrasoundScene& sc, const PlaneFrame& f);
  void coherent_surfaces();
  void coherent_rods(const UltrasoundScene& sc, const PlaneFrame& f);
  void reverberation();
  // rest point X [m] into slot a of row_q_ (speckle() turns it into both lattices' coordinates)
  void store_rest_point(const float* X, int a);
  // complex scatterer field of the na slots of row_q_ (x their amplitude) into re, im
  void speckle(int na, float* re, float* im);
  // adds a coherent echo at plane point (s, t) [m] of amplitude `amp` per lateral sample
  void splat(float s, float t, float amp);
  void blur();
  void transmission(const UltrasoundScene& sc, const PlaneFrame& f);
  void calibrate();
  void compress();
  void overlays(const UltrasoundScene& sc, const PlaneFrame& f);
  // beam direction (unit, plane coords) at plane point (s, t)
  void beam_dir(float s, float t, float* bs, float* bt) const;
  // continuous grid coordinates (beam, sample) of plane point (s, t)
  void grid_coords(float s, float t, float* bf, float* kf) const;
  double lateral_spacing(int k) const;  // distance between neighbouring beams at sample k [m]

  const UltrasoundAnatomy& an_;
  UltrasoundSettings set_;
  PlaneKind kind_;
  int W_, H_;
  double px_ = 0, s0_ = 0, t0_ = 0;   // pixel size; plane coords of pixel (0,0)'s centre [m]
  UsImage img_;
  // per pixel, fixed by the settings
  std::vector<float> depth_;          // from the array surface [m], <0 outside the view
  std::vector<float> tgc_;            // TGC x gain
  int sub_ = 1;                       // display samples per pixel, the centre first
  std::vector<float> sub_w_;          // [sub_] their weights in the pixel's gray level
  std::vector<int> view_pix_;         // the pixels in the field of view, row-major
  std::vector<int> lut_i_;            // [sub_ * view pixels] grid sample (k * NB + b) of each display sample, point-major
  std::vector<float> lut_wb_, lut_wk_;
  std::vector<float> tgc_v_;          // [view pixels] TGC x gain
  std::vector<float> env_v_, gray_, mag2_;  // [view pixels] compress(): envelope, gray level summed over the display samples, |I/Q|^2
  std::vector<uint8_t> pix_v_;        // [view pixels] gray levels
  // acquisition grid: NS depth samples (rows) x NB beams, index k * NB + b
  int NB_ = 0, NS_ = 0;
  double dz_ = 0, dbeam_ = 0;         // sample spacing [m]; beam spacing [rad] (transverse) or [m] (sagittal)
  std::vector<float> samp_s_, samp_t_;  // plane coordinates of each sample [m]
  std::vector<int> samp_pix_;         // nearest pixel of each sample, -1 outside the window
  std::vector<float> mark_;           // rod shadow marks (1: none)
  std::vector<size_t> marked_;        // the entries of mark_ not 1, reset before the next frame's rods
  std::vector<uint8_t> stop_;         // 1: a calcification (stops the beam like bone)
  std::vector<uint8_t> glab_;         // label of each sample's pixel (255: none or outside the window)
  std::vector<float> gre_, gim_, gtr_, gti_;  // complex echo and scratch
  std::vector<float> eq_;             // [2 * (samples + NB + 1)] I/Q x transmission x calibration, interleaved (re, im)
  std::vector<int> rod_k_;            // [NB] per rod: shallowest depth sample where the beam meets it (NS: none)
  std::vector<float> rod_m_;          // [NB] per rod: fraction of the beam it lets through there
  std::vector<float> beam_T_;         // [NB] transmission(): each beam's amplitude so far
  // PSF
  std::vector<float> kax_;            // axial taps (in samples, normalised)
  std::vector<float> klat_;           // lateral taps of every row, concatenated
  std::vector<int> klat_off_, klat_r_;  // [NS] offset into klat_ and radius of each row's kernel
  std::vector<float> calib_;          // [NS] 1 / rms envelope of unit-backscatter speckle at that depth
  std::vector<float> line_gain_;      // [NS] coherent echo gain: unit reflection peaks at the speckle rms
  double sig_ax_total_ = 0;           // axial PSF incl. the field's correlation, sigma [m]
  float lattice_ = 1e-4f;             // speckle lattice step [m]
  float stretch_ = 0.0f;              // elevation stretch of the scatterer field: L / L_elev - 1
  // per frame
  std::vector<float> ps_, pt_, pe_;   // [particles + carried vertices] plane coordinates [m]
  std::vector<float> xc_;             // [3 * carried vertices] their current positions [m]
  std::vector<float> rest_;           // [3 * particles] rest positions (float) [m]
  std::vector<Seg> segs_;
  std::vector<uint32_t> mask_;
  int gx_ = 0, gy_ = 0;               // displacement grid nodes
  double g_ = 2e-3, gs0_ = 0, gt0_ = 0;
  std::vector<float> field_;          // [(ncomp+1) * gx*gy * 4]: ux, uy, uz, weight
  std::vector<int> rank_comp_;        // priority rank -> component
  std::vector<TissueAcoustics> comp_ac_;  // [components] acoustics of each component's tissue
  std::vector<uint8_t> comp_prostate_;    // [components] 1: the gland (echo from the rest volume)
  int tx_ = 0, ty_ = 0;               // heterogeneity texture grid (every kTexStep pixels)
  std::vector<float> tex_;
  std::vector<float> row_q_;          // [12 * NB] one row's lattice coordinates (2 x 3), amplitude, noise (re, im), rest points (3)
  std::vector<int> row_i_;            // [NB] their beams
  std::vector<float> sc_;             // [14 * NB] scatter()'s per-row scratch (floats)
  std::vector<int> sci_;              // [3 * NB] (beam, grid cell, component of each candidate)
  std::vector<uint8_t> scf_;          // [NB] (flags of each candidate)
  std::vector<float> pad_;
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
