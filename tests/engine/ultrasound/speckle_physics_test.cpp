// The TRUS image's physics (engine/ultrasound/imager.cpp), measured on the image as a sonographer's
// phantom would be: speckle statistics and grain against the point-spread function the imager
// sets (both planes, two depths), the grain and penetration as the frequency changes, posterior
// enhancement behind fluid, the shadow behind bone, and both in the default biopsy scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/anatomy/shapes.h"
#include "engine/ultrasound/imager.h"
#include "tests/engine/ultrasound/us_scenes.h"

namespace ps {
namespace {

using us::PlaneImager;
using us::PlaneKind;

const char* name(PlaneKind k) { return k == PlaneKind::Sagittal ? "sagittal" : "transverse"; }

// A phantom: homogeneous soft tissue (a 200 mm cube around the field of view) with optional
// inclusions, each a closed surface with its own tissue class.
struct Phantom {
  us::UltrasoundAnatomy anatomy;
  std::vector<float> x;
  void add(const TriMesh& m, us::Tissue t, const char* nm) {
    us::UsComponent c;
    c.name = nm;
    c.tissue = t;
    c.first_particle = static_cast<int>(anatomy.rest.size());
    c.particle_count = static_cast<int>(m.vertices.size());
    c.spacing = 0.01;
    for (const auto& f : m.faces) c.faces.push_back({f[0] + c.first_particle, f[1] + c.first_particle, f[2] + c.first_particle});
    for (const Vec3& v : m.vertices) {
      anatomy.rest.push_back(v);
      for (int d = 0; d < 3; ++d) x.push_back(static_cast<float>(v[d]));
    }
    c.priority = 0;
    for (auto& o : anatomy.components) ++o.priority;  // added from the outside in: the last is smallest
    anatomy.components.push_back(c);
    anatomy.component_index.push_back(static_cast<int>(anatomy.components.size()) - 1);
  }
  us::UltrasoundScene scene(const us::ProbeView& probe) const {
    us::UltrasoundScene sc;
    sc.x = x.data();
    sc.particle_count = static_cast<int>(x.size() / 3);
    sc.probe = probe;
    return sc;
  }
};

TriMesh cube(const Vec3& lo, const Vec3& hi) { return anatomy::grid_box(lo, hi, (hi - lo).maxCoeff()); }

TriMesh sphere(const Vec3& c, double r) {
  return anatomy::map_sphere(anatomy::icosphere(3), [&](const Vec3& u) { return Vec3(c + r * u); });
}

// Envelope statistics over a window centred on the central beam at `depth` below the array:
// half-widths `ax` (along the beam) and `lat` (across it) [m]. On the central beam the beam runs
// up the screen in both planes: axial = rows, lateral = columns.
struct Stats {
  double log_sd_db = 0, snr = 0, axial_fwhm = 0, lateral_fwhm = 0, mean = 0;
};

// FWHM [m] of the normalised autocovariance of the intensity along one axis (lags in pixels)
double acf_fwhm(const std::vector<double>& I, int w, int h, bool along_rows, double pixel) {
  double m = 0;
  for (double v : I) m += v;
  m /= I.size();
  double var = 0;
  for (double v : I) var += (v - m) * (v - m);
  var /= I.size();
  double prev = 1.0;
  for (int lag = 1; lag < 40; ++lag) {
    double s = 0;
    int n = 0;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const int i2 = along_rows ? i : i + lag, j2 = along_rows ? j + lag : j;
        if (i2 >= w || j2 >= h) continue;
        s += (I[static_cast<size_t>(j) * w + i] - m) * (I[static_cast<size_t>(j2) * w + i2] - m);
        ++n;
      }
    const double c = s / n / var;
    if (c <= 0.5) return 2.0 * pixel * (lag - 1 + (prev - 0.5) / (prev - c));
    prev = c;
  }
  return 2.0 * pixel * 40;
}

Stats window_stats(const PlaneImager& im, const us::UsImage& img, const us::ProbeView& probe, double depth, double ax, double lat) {
  const us::PlaneFrame f = im.frame(probe);
  double col, row;
  im.world_to_pixel(probe, f.origin + (im.settings().convex_radius + depth) * f.up, &col, &row);
  const int hw = static_cast<int>(lat / img.pixel), hh = static_cast<int>(ax / img.pixel);
  const int w = 2 * hw + 1, h = 2 * hh + 1;
  std::vector<double> I;
  double s = 0, s2 = 0, l = 0, l2 = 0;
  for (int j = static_cast<int>(row) - hh; j <= static_cast<int>(row) + hh; ++j)
    for (int i = static_cast<int>(col) - hw; i <= static_cast<int>(col) + hw; ++i) {
      const double e = img.envelope[static_cast<size_t>(j) * img.width + i];
      I.push_back(e * e);
      s += e, s2 += e * e;
      const double db = 20.0 * std::log10(std::max(e, 1e-12));
      l += db, l2 += db * db;
    }
  const double n = static_cast<double>(I.size());
  Stats st;
  st.mean = s / n;
  st.snr = st.mean / std::sqrt(s2 / n - st.mean * st.mean);
  st.log_sd_db = std::sqrt(l2 / n - (l / n) * (l / n));
  st.axial_fwhm = acf_fwhm(I, w, h, true, img.pixel);
  st.lateral_fwhm = acf_fwhm(I, w, h, false, img.pixel);
  return st;
}

Phantom soft_phantom(const us::PlaneFrame& f) {
  Phantom ph;
  const Vec3 c = f.origin + 0.035 * f.up;
  ph.add(cube(c - Vec3::Constant(0.1), c + Vec3::Constant(0.1)), us::Tissue::Soft, "block");
  return ph;
}

// Fully developed speckle: log-compressed sd 5.57 dB and envelope SNR 1.91 (Rayleigh; Wagner et al.
// 1983), and a grain (intensity autocorrelation FWHM) equal to the PSF the imager sets, in
// millimetres, in both planes and at two depths; the sector's lateral grain grows with depth.
TEST(UltrasoundSpeckle, GrainFollowsThePointSpreadFunctionInBothPlanes) {
  const auto& S = test::us_biopsy_scene();
  double axial[2][2] = {}, lateral[2][2] = {};
  for (PlaneKind kind : {PlaneKind::Transverse, PlaneKind::Sagittal}) {
    PlaneImager probe_im(S.anatomy, S.settings, kind);
    const Phantom ph = soft_phantom(probe_im.frame(S.probe));
    PlaneImager im(ph.anatomy, S.settings, kind);
    const us::UsImage& img = im.render(ph.scene(S.probe));
    const double depths[2] = {0.018, 0.045};
    for (int d = 0; d < 2; ++d) {
      const double z = depths[d];
      const Stats st = window_stats(im, img, S.probe, z, 0.004, 0.010);
      const double want_ax = im.psf_axial_fwhm(), want_lat = im.psf_lateral_fwhm(z);
      std::printf("%s %.0f mm (%.3f mm/px): log sd %.2f dB, SNR %.3f; grain axial %.3f mm (PSF %.3f), lateral %.3f mm (PSF %.3f)\n",
                  name(kind), z * 1e3, img.pixel * 1e3, st.log_sd_db, st.snr, st.axial_fwhm * 1e3, want_ax * 1e3, st.lateral_fwhm * 1e3,
                  want_lat * 1e3);
      EXPECT_GE(st.log_sd_db, 5.2);
      EXPECT_LE(st.log_sd_db, 6.3);
      EXPECT_NEAR(st.snr, 1.913, 0.2);
      EXPECT_NEAR(st.axial_fwhm, want_ax, 0.25 * want_ax);
      EXPECT_NEAR(st.lateral_fwhm, want_lat, 0.25 * want_lat);
      axial[kind == PlaneKind::Sagittal][d] = st.axial_fwhm;
      lateral[kind == PlaneKind::Sagittal][d] = st.lateral_fwhm;
    }
  }
  // the same probe gives the same grain in millimetres in both planes
  for (int d = 0; d < 2; ++d) {
    EXPECT_NEAR(axial[0][d], axial[1][d], 0.2 * axial[1][d]);
    EXPECT_NEAR(lateral[0][d], lateral[1][d], 0.25 * lateral[1][d]);
  }
  // the beam widens away from the focus (30 mm): deeper is coarser laterally
  EXPECT_GT(lateral[0][1], 1.3 * lateral[0][0]);
}

// The frequency knob changes the grain (finer at 10 MHz than at 5 MHz) and the penetration: with
// the TGC off, the mean echo of soft tissue falls by 2 alpha f dz (alpha = 0.6 dB/(cm MHz)).
TEST(UltrasoundSpeckle, FrequencySetsGrainAndPenetration) {
  const auto& S = test::us_biopsy_scene();
  double grain[2] = {};
  const double freqs[2] = {5e6, 10e6};
  for (int q = 0; q < 2; ++q) {
    us::UltrasoundSettings set = S.settings;
    set.frequency = freqs[q];
    set.tgc_db_cm_mhz = 0.0;
    set.dynamic_range_db = 100.0;
    PlaneImager probe_im(S.anatomy, set, PlaneKind::Sagittal);
    const Phantom ph = soft_phantom(probe_im.frame(S.probe));
    PlaneImager im(ph.anatomy, set, PlaneKind::Sagittal);
    const us::UsImage& img = im.render(ph.scene(S.probe));
    const Stats a = window_stats(im, img, S.probe, 0.015, 0.003, 0.02), b = window_stats(im, img, S.probe, 0.035, 0.003, 0.02);
    const double fall_db = 20.0 * std::log10(a.mean / b.mean);
    const double want_db = 2.0 * us::acoustics(us::Tissue::Soft).atten * freqs[q] * 1e-6 * 2.0;  // 2 cm deeper
    grain[q] = a.axial_fwhm;
    std::printf("%.0f MHz: axial grain %.3f mm (PSF %.3f), mean echo 15 -> 35 mm falls %.1f dB (2 alpha f dz = %.1f dB)\n", freqs[q] * 1e-6,
                a.axial_fwhm * 1e3, im.psf_axial_fwhm() * 1e3, fall_db, want_db);
    EXPECT_NEAR(fall_db, want_db, 1.5);
  }
  EXPECT_LT(grain[1], 0.75 * grain[0]);
}

// Posterior enhancement behind fluid and the shadow behind bone, in a phantom: a 20 mm water
// sphere and a 6 mm bone slab in soft tissue, in the sagittal plane. Behind the sphere the echo is
// higher by the attenuation the water did not have (2 x 0.6 dB/(cm MHz) x 7.5 MHz x 2 cm = 18 dB);
// behind the bone it is gone.
TEST(UltrasoundAcoustics, EnhancementBehindFluidAndShadowBehindBone) {
  const auto& S = test::us_biopsy_scene();
  PlaneImager probe_im(S.anatomy, S.settings, PlaneKind::Sagittal);
  const us::PlaneFrame f = probe_im.frame(S.probe);
  const double r = S.settings.convex_radius;
  Phantom ph = soft_phantom(f);
  const Vec3 water = f.origin + (r + 0.020) * f.up - 0.012 * f.right;
  ph.add(sphere(water, 0.010), us::Tissue::Bladder, "water");
  const Vec3 bone = f.origin + (r + 0.025) * f.up + 0.015 * f.right;
  TriMesh slab = cube(Vec3(-0.006, -0.003, -0.006), Vec3(0.006, 0.003, 0.006));
  for (Vec3& v : slab.vertices) v = bone + v.x() * f.right + v.y() * f.up + v.z() * f.normal;
  ph.add(slab, us::Tissue::Bone, "bone");
  PlaneImager im(ph.anatomy, S.settings, PlaneKind::Sagittal);
  const us::UsImage& img = im.render(ph.scene(S.probe));
  // mean envelope in a 4 x 3 mm box centred at depth z below the array and s across it
  auto box = [&](double s, double z) {
    double col, row, sum = 0;
    int n = 0;
    im.world_to_pixel(S.probe, f.origin + (r + z) * f.up + s * f.right, &col, &row);
    const int hw = static_cast<int>(0.002 / img.pixel), hh = static_cast<int>(0.0015 / img.pixel);
    for (int j = static_cast<int>(row) - hh; j <= static_cast<int>(row) + hh; ++j)
      for (int i = static_cast<int>(col) - hw; i <= static_cast<int>(col) + hw; ++i) sum += img.envelope[static_cast<size_t>(j) * img.width + i], ++n;
    return sum / n;
  };
  const double behind_water = box(-0.012, 0.036), beside = box(0.0, 0.036);
  const double behind_bone = box(0.015, 0.036);
  const double enh_db = 20.0 * std::log10(behind_water / beside), shadow_db = 20.0 * std::log10(std::max(behind_bone, 1e-12) / beside);
  const double want = 2.0 * us::acoustics(us::Tissue::Soft).atten * 7.5 * 2.0;
  std::printf("phantom: enhancement behind 20 mm of water %+.1f dB (expected %+.1f), behind 6 mm of bone %+.1f dB\n", enh_db, want,
              shadow_db);
  EXPECT_NEAR(enh_db, want, 3.0);
  EXPECT_LT(shadow_db, -30.0);
}

// The same in the default biopsy scene, the probe pushed 20 mm further in (as the operator does to
// survey the base: the initial pose images apex to mid-gland): the tissue behind the bladder
// (sagittal plane, beams that crossed urine) is brighter than at the same depth in beams that
// did not, and the pubic arch's shadow is dark.
TEST(UltrasoundAcoustics, BladderEnhancesAndPubicArchShadowsInTheBiopsyScene) {
  const auto& S = test::us_biopsy_scene();
  const std::vector<float> x = test::rest_positions(*S.model);
  us::UltrasoundScene sc;
  sc.x = x.data();
  sc.particle_count = static_cast<int>(x.size() / 3);
  sc.probe = test::moved_probe(S.probe, 0.020, 0.0);
  int bladder = -1, bone = -1;
  for (size_t c = 0; c < S.anatomy.components.size(); ++c) {
    if (S.anatomy.components[c].tissue == us::Tissue::Bladder) bladder = static_cast<int>(c);
    if (S.anatomy.components[c].tissue == us::Tissue::Bone) bone = static_cast<int>(c);
  }
  ASSERT_GE(bladder, 0);
  ASSERT_GE(bone, 0);
  for (PlaneKind kind : {PlaneKind::Sagittal, PlaneKind::Transverse}) {
    PlaneImager im(S.anatomy, S.settings, kind);
    const us::UsImage& img = im.render(sc);
    // per column (the central columns are beams in both planes' middle): walk up from the probe;
    // after the column leaves the bladder or the bone, gather the envelope of the next 4 mm of
    // tissue; compare with the columns that crossed neither, at the same rows
    const int W = img.width, H = img.height;
    std::vector<double> row_sum(H, 0.0);
    std::vector<int> row_n(H, 0);
    struct Hit { int col, row; bool bone; };
    std::vector<Hit> hits;
    for (int i = 0; i < W; ++i) {
      bool in_b = false, crossed_b = false, crossed_bone = false;
      int after = -1;
      for (int j = H - 1; j >= 0; --j) {
        const size_t p = static_cast<size_t>(j) * W + i;
        if (!img.in_view[p]) continue;
        const int lab = img.label[p];
        if (lab == bladder) in_b = crossed_b = true;
        else if (lab == bone) crossed_bone = true;
        else if (in_b && lab != 255 && lab < 64) in_b = false, after = j;
      }
      (void)after;
      if (!crossed_b && !crossed_bone) {
        for (int j = 0; j < H; ++j) {
          const size_t p = static_cast<size_t>(j) * W + i;
          if (img.in_view[p] && img.label[p] != 255 && img.label[p] < 64 && img.label[p] != bladder && img.label[p] != bone)
            row_sum[j] += img.envelope[p], ++row_n[j];
        }
      }
    }
    // tissue just beyond the bladder or the bone (first 4 mm of non-bladder, non-bone tissue)
    double enh = 0, shadow = 0;
    int ne = 0, ns = 0;
    const int band = static_cast<int>(0.004 / img.pixel);
    for (int i = 0; i < W; ++i) {
      int state = 0;  // 0 before, 1 inside bladder/bone, 2 after
      bool is_bone = false;
      int left = band;
      for (int j = H - 1; j >= 0 && left > 0; --j) {
        const size_t p = static_cast<size_t>(j) * W + i;
        if (!img.in_view[p]) continue;
        const int lab = img.label[p];
        if (lab == bladder || lab == bone) {
          if (state == 0) state = 1, is_bone = lab == bone;
          continue;
        }
        if (state >= 1 && lab != 255 && lab < 64 && row_n[j] > 20) {
          state = 2;
          const double ref = row_sum[j] / row_n[j];
          const double v = 20.0 * std::log10(std::max(static_cast<double>(img.envelope[p]), 1e-9) / ref);
          if (is_bone) shadow += v, ++ns;
          else enh += v, ++ne;
          --left;
        }
      }
    }
    std::printf("%s: behind the bladder %+.1f dB over %d px, behind the pubic arch %+.1f dB over %d px\n", name(kind), ne ? enh / ne : 0.0,
                ne, ns ? shadow / ns : 0.0, ns);
    if (kind == PlaneKind::Sagittal) {
      ASSERT_GT(ne, 50);
      EXPECT_GT(enh / ne, 3.0);
    }
    if (ns > 50) EXPECT_LT(shadow / ns, -20.0);
  }
}

// The default anatomy's calcifications (assets/anatomy/calcifications.csv): each is a bright focus
// on the transverse plane through it, with a shadow behind it.
TEST(UltrasoundAcoustics, CalcificationsAreBrightWithAShadow) {
  const auto& S = test::us_biopsy_scene();
  ASSERT_GE(S.anatomy.calcifications.size(), 1u);
  const std::vector<float> x = test::rest_positions(*S.model);
  us::UltrasoundScene sc;
  sc.x = x.data();
  sc.particle_count = static_cast<int>(x.size() / 3);
  for (const auto& [c, radius] : S.anatomy.calcifications) {
    // the transverse plane through the calcification: the probe moved along its axis
    PlaneImager im(S.anatomy, S.settings, PlaneKind::Transverse);
    const double adv = (c - im.frame(S.probe).origin).dot(S.probe.axis);
    sc.probe = test::moved_probe(S.probe, adv, 0.0);
    const us::UsImage& img = im.render(sc);
    const us::PlaneFrame f = im.frame(sc.probe);
    const Vec3 d = c - f.origin;
    const double s = d.dot(f.right), t = d.dot(f.up), rho = std::hypot(s, t);
    const Vec3 beam = (s * f.right + t * f.up) / rho;
    // brightest gray within 1.5 mm of the centre; mean envelope 3-6 mm behind it along its beam and
    // beside it (the same depth, 4 mm across)
    double peak = 0;
    for (double a = -1.5e-3; a <= 1.5e-3; a += 0.25e-3)
      for (double b = -1.5e-3; b <= 1.5e-3; b += 0.25e-3) {
        double col, row;
        im.world_to_pixel(sc.probe, c + a * f.right + b * f.up, &col, &row);
        peak = std::max(peak, static_cast<double>(img.pixels[static_cast<size_t>(std::lround(row)) * img.width + std::lround(col)]));
      }
    auto mean_env = [&](const Vec3& from, const Vec3& dir) {
      double sum = 0;
      int n = 0;
      for (double q = 3e-3; q <= 6e-3; q += 0.25e-3) {
        double col, row;
        im.world_to_pixel(sc.probe, from + q * dir, &col, &row);
        sum += img.envelope[static_cast<size_t>(std::lround(row)) * img.width + std::lround(col)], ++n;
      }
      return sum / n;
    };
    const Vec3 dir = beam;
    const Vec3 side = f.normal.cross(dir);
    const double behind = mean_env(c, dir);
    const double beside = 0.5 * (mean_env(c + 4e-3 * side, dir) + mean_env(c - 4e-3 * side, dir));
    const double shadow_db = 20.0 * std::log10(std::max(behind, 1e-12) / beside);
    std::printf("calcification r %.1f mm at depth %.1f mm: peak gray %.0f, shadow %+.1f dB\n", radius * 1e3,
                (rho - S.settings.convex_radius) * 1e3, peak, shadow_db);
    EXPECT_GE(peak, 180.0);  // the gland's speckle: ~100-130
    EXPECT_LT(shadow_db, -10.0);
  }
}

}  // namespace
}  // namespace ps
