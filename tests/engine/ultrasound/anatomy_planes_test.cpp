// The anatomy as the default planes show it (issue 47, "anatomy that reads right"): the default
// probe pose's sagittal plane spans the gland from base to apex; the seminal vesicles are
// hypoechoic and lie posterior-superior to the base (sagittal, the probe turned to each side, and
// transverse at their level, both sides: the "bow-tie"); the edges of the bladder and of the pubic
// arch seen from the probe are curves, not polygons of straight walls; the urethra is a subtle
// hypoechoic line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/ultrasound/anatomy.h"
#include "engine/ultrasound/imager.h"
#include "tests/engine/ultrasound/us_scenes.h"

namespace ps {
namespace {

using us::PlaneImager;
using us::PlaneKind;

using test::scene_of;

// the scenario's own initial probe pose (us_biopsy_scene().probe is the pose the older tests were
// written for)
us::ProbeView default_pose() {
  const auto& S = test::us_biopsy_scene();
  const RectalFrame rf = rectal_frame(*S.spec.probe);
  return us::probe_view(probe_frame(*S.spec.probe, rf, S.spec.probe->pose), S.spec.probe->radius);
}

int component_of(const us::UltrasoundAnatomy& a, us::Tissue t, int nth = 0) {
  for (size_t c = 0; c < a.components.size(); ++c)
    if (a.components[c].tissue == t && nth-- == 0) return static_cast<int>(c);
  return -1;
}

// rest extent of the gland along z (its base and apex) [m]
std::pair<double, double> gland_z(const test::UsBiopsyScene& S) {
  const us::UsComponent& g = S.anatomy.components[S.anatomy.prostate];
  double lo = 1e9, hi = -1e9;
  for (int p = g.first_particle; p < g.first_particle + g.particle_count; ++p) {
    lo = std::min(lo, S.anatomy.rest[p].z());
    hi = std::max(hi, S.anatomy.rest[p].z());
  }
  return {lo, hi};
}

TEST(UltrasoundAnatomyPlanes, DefaultSagittalPlaneSpansBaseToApex) {
  const auto& S = test::us_biopsy_scene();
  const std::vector<float> x = test::rest_positions(*S.model);
  PlaneImager sg(S.anatomy, S.settings, PlaneKind::Sagittal);
  const us::ProbeView pose = default_pose();
  const us::UsImage& img = sg.render(scene_of(x, pose));
  // the gland's label along the image: its cranial-most and caudal-most columns
  int first = img.width, last = -1;
  for (int j = 0; j < img.height; ++j)
    for (int i = 0; i < img.width; ++i)
      if (img.label[static_cast<size_t>(j) * img.width + i] == S.anatomy.prostate) first = std::min(first, i), last = std::max(last, i);
  const auto [apex, base] = gland_z(S);
  const double margin_base = first * img.pixel, margin_apex = (img.width - 1 - last) * img.pixel;
  std::printf("sagittal at the default pose: gland from column %d to %d of %d (%.1f mm clear of the cranial edge, %.1f mm of the caudal); "
              "gland %.1f mm long (z %.1f to %.1f mm)\n",
              first, last, img.width, margin_base * 1e3, margin_apex * 1e3, (base - apex) * 1e3, apex * 1e3, base * 1e3);
  // base and apex both inside the image, with room around them (bladder neck, apex and beyond)
  EXPECT_GT(margin_base, 4e-3);
  EXPECT_GT(margin_apex, 4e-3);
  EXPECT_GT((last - first + 1) * img.pixel, 0.9 * (base - apex)) << "the plane shows the whole length";
}

// Mean gray and world centroid of the pixels labelled `comp` in view.
struct Region {
  int n = 0;
  double gray = 0.0;
  Vec3 centre = Vec3::Zero();
};
Region region(const PlaneImager& im, const us::UsImage& img, const us::ProbeView& pose, int comp) {
  Region r;
  for (int j = 0; j < img.height; ++j)
    for (int i = 0; i < img.width; ++i) {
      const size_t p = static_cast<size_t>(j) * img.width + i;
      if (!img.in_view[p] || img.label[p] != comp) continue;
      ++r.n;
      r.gray += img.pixels[p];
      r.centre += im.pixel_to_world(pose, i, j);
    }
  if (r.n) r.gray /= r.n, r.centre /= r.n;
  return r;
}

TEST(UltrasoundAnatomyPlanes, SeminalVesiclesArePosteriorSuperiorToTheBaseAndHypoechoic) {
  const auto& S = test::us_biopsy_scene();
  const std::vector<float> x = test::rest_positions(*S.model);
  const int sv0 = component_of(S.anatomy, us::Tissue::SeminalVesicle, 0), sv1 = component_of(S.anatomy, us::Tissue::SeminalVesicle, 1);
  ASSERT_GE(sv0, 0) << "no seminal vesicles in the default anatomy";
  ASSERT_GE(sv1, 0);
  const auto [apex, base] = gland_z(S);
  const us::ProbeView pose = default_pose();
  // sagittal, the probe pushed 8 mm in (the vesicles run superolaterally out of the default field)
  // and turned 25 degrees to each side: the right vesicle, then the left
  PlaneImager sg(S.anatomy, S.settings, PlaneKind::Sagittal);
  for (const double roll : {-0.44, 0.44}) {
    const us::ProbeView p = test::moved_probe(pose, 0.008, roll);
    const us::UsImage& img = sg.render(scene_of(x, p));
    const Region a = region(sg, img, p, sv0), b = region(sg, img, p, sv1), g = region(sg, img, p, S.anatomy.prostate);
    const Region& v = a.n > b.n ? a : b;
    std::printf("sagittal 8 mm in, rolled %+.0f deg: vesicle %d px, centre (%.1f, %.1f, %.1f) mm, gray %.0f; gland gray %.0f; base z %.1f mm\n",
                roll * 180 / 3.14159265, v.n, v.centre.x() * 1e3, v.centre.y() * 1e3, v.centre.z() * 1e3, v.gray, g.gray, base * 1e3);
    ASSERT_GT(v.n * img.pixel * img.pixel, 20e-6) << "less than 20 mm^2 of vesicle in the plane";
    EXPECT_GT(v.centre.z(), base - 2e-3) << "superior to the base";
    EXPECT_LT(v.centre.y(), pose.tip_centre.y() + 0.02) << "posterior: on the probe's side of the bladder";
    EXPECT_LT(v.gray, 0.8 * g.gray) << "hypoechoic to the gland";
    EXPECT_EQ(v.centre.x() > 0, roll < 0) << "the plane turned to the patient's right shows the right vesicle";
  }
  // transverse at the vesicles' level: both, one each side of the midline, behind the bladder
  PlaneImager tr(S.anatomy, S.settings, PlaneKind::Transverse);
  const us::UsImage& img = tr.render(scene_of(x, pose));
  const Region a = region(tr, img, pose, sv0), b = region(tr, img, pose, sv1);
  std::printf("transverse at the default pose: vesicles %d and %d px, centres x %.1f and %.1f mm\n", a.n, b.n, a.centre.x() * 1e3,
              b.centre.x() * 1e3);
  ASSERT_GT(std::min(a.n, b.n) * img.pixel * img.pixel, 15e-6);
  EXPECT_LT(a.centre.x() * b.centre.x(), 0.0) << "one on each side";
}

// The bladder as the sagittal plane cuts it, from the probe's side: for each column the edge
// nearest the probe. It must be curved (far from its chord) and smooth: a quadratic fits it to
// within the pixel rounding over every 4 mm of it (the same measure for the pubic arch below, where
// the cut through its 7 mm particle triangles, smooth_subdivisions = 0, is a polygon).
struct NearEdge {
  size_t columns = 0;
  double chord_dev = 0.0, fit_rms = 0.0;  // [px]
  size_t windows = 0;                      // 4 mm windows fitted
};
NearEdge near_edge(const us::UltrasoundAnatomy& an, const us::UltrasoundSettings& set, const std::vector<float>& x,
                   const us::ProbeView& pose, us::Tissue tissue) {
  const int comp = component_of(an, tissue);
  PlaneImager sg(an, set, PlaneKind::Sagittal);
  const us::UsImage& img = sg.render(scene_of(x, pose));
  std::vector<std::pair<double, double>> edge;  // column, lowest row of the component (nearest the probe) [px]
  for (int i = 0; i < img.width; ++i)
    for (int j = img.height - 1; j >= 0; --j)
      if (img.label[static_cast<size_t>(j) * img.width + i] == comp && img.in_view[static_cast<size_t>(j) * img.width + i]) {
        edge.emplace_back(i, j);
        break;
      }
  NearEdge r;
  r.columns = edge.size();
  if (edge.size() < 3) return r;
  const auto [i0, j0] = edge.front();
  const auto [i1, j1] = edge.back();
  for (const auto& [i, j] : edge) r.chord_dev = std::max(r.chord_dev, std::abs(j - (j0 + (j1 - j0) * (i - i0) / std::max(1.0, i1 - i0))));
  // least-squares quadratic row(column) over each 4 mm window (half overlapping) where the edge runs
  // within 45 degrees of the image's rows (row per column well defined): rms of the residuals
  const size_t w = static_cast<size_t>(std::lround(4e-3 / img.pixel));
  double ss = 0.0;
  size_t n = 0;
  for (size_t a = 0; a + w <= edge.size(); a += w / 2) {
    if (std::abs(edge[a + w - 1].second - edge[a].second) > static_cast<double>(w)) continue;
    if (edge[a + w - 1].first - edge[a].first != static_cast<double>(w - 1)) continue;  // contiguous columns
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    const double c0 = edge[a + w / 2].first;
    for (size_t k = a; k < a + w; ++k) {
      const Eigen::Vector3d v(1.0, edge[k].first - c0, (edge[k].first - c0) * (edge[k].first - c0));
      A += v * v.transpose();
      b += edge[k].second * v;
    }
    const Eigen::Vector3d q = A.ldlt().solve(b);
    for (size_t k = a; k < a + w; ++k) {
      const double d = edge[k].first - c0, e = edge[k].second - (q[0] + q[1] * d + q[2] * d * d);
      ss += e * e;
      ++n;
    }
  }
  r.windows = n / std::max<size_t>(1, w);
  r.fit_rms = n ? std::sqrt(ss / n) : 0.0;
  return r;
}

// The edge of `tissue` nearest the probe in the sagittal image, through the smoothed surfaces (the
// scene's anatomy) and through the particle triangles (no subdivision); and the pixel size [m].
struct EdgePair {
  NearEdge smooth, poly;
  double px;
};
EdgePair edges_smooth_and_coarse(const std::vector<float>& x, const us::ProbeView& pose, us::Tissue tissue) {
  const auto& S = test::us_biopsy_scene();
  us::AnatomyOptions coarse_opt;
  coarse_opt.smooth_subdivisions = 0;
  const us::UltrasoundAnatomy coarse = us::build_anatomy(*S.model, coarse_opt);
  return {near_edge(S.anatomy, S.settings, x, pose, tissue), near_edge(coarse, S.settings, x, pose, tissue),
          PlaneImager(S.anatomy, S.settings, PlaneKind::Sagittal).image().pixel};
}

TEST(UltrasoundAnatomyPlanes, BladderEdgeIsCurvedInTheSagittalPlane) {
  const auto& S = test::us_biopsy_scene();
  const std::vector<float> x = test::rest_positions(*S.model);
  const us::ProbeView pose = test::moved_probe(default_pose(), 0.012, 0.0);  // further in: more bladder in view
  const auto [smooth, poly, px] = edges_smooth_and_coarse(x, pose, us::Tissue::Bladder);
  std::printf("sagittal bladder edge over %zu columns (%.1f mm): %.1f mm from its chord; quadratic fit per 4 mm (%zu windows) rms %.2f px "
              "(%.3f mm); the particle triangles: rms %.2f px\n",
              smooth.columns, smooth.columns * px * 1e3, smooth.chord_dev * px * 1e3, smooth.windows, smooth.fit_rms, smooth.fit_rms * px * 1e3,
              poly.fit_rms);
  ASSERT_GT(smooth.columns * px, 10e-3) << "less than 10 mm of bladder edge in the plane";
  EXPECT_GT(smooth.chord_dev * px, 1.0e-3) << "the edge is a straight line";
  ASSERT_GE(smooth.windows, 3u);
  EXPECT_LT(smooth.fit_rms, 0.5) << "not a smooth curve: more than the pixel rounding (0.29 px rms)";
}

// The pubic arch in the midsagittal plane (anterior to the apex): its edge towards the probe is the
// arc of the 7 mm tube's section, not the V that its 7 mm particle triangles cut.
TEST(UltrasoundAnatomyPlanes, PubicArchEdgeIsAnArcInTheSagittalPlane) {
  const auto& S = test::us_biopsy_scene();
  const std::vector<float> x = test::rest_positions(*S.model);
  const us::ProbeView pose = default_pose();
  const auto [smooth, poly, px] = edges_smooth_and_coarse(x, pose, us::Tissue::Bone);
  std::printf("sagittal pubic arch edge over %zu columns (%.1f mm): %.1f mm from its chord; quadratic fit per 4 mm (%zu windows) rms %.2f px; "
              "the particle triangles: %zu columns, rms %.2f px\n",
              smooth.columns, smooth.columns * px * 1e3, smooth.chord_dev * px * 1e3, smooth.windows, smooth.fit_rms, poly.columns, poly.fit_rms);
  ASSERT_GT(smooth.columns * px, 8e-3) << "the arch is not in the plane";
  ASSERT_GE(smooth.windows, 2u);
  EXPECT_GT(smooth.chord_dev * px, 1.0e-3) << "a flat edge";
  EXPECT_LT(smooth.fit_rms, 0.5) << "not a smooth arc";
  EXPECT_LT(smooth.fit_rms, 0.6 * poly.fit_rms) << "no smoother than the particle triangles";
}

// The urethra (no catheter) reads as a subtle hypoechoic line in the midsagittal plane: darker
// than the gland around it, but not anechoic like urine or the balloon.
TEST(UltrasoundAnatomyPlanes, UrethraIsASubtleHypoechoicLine) {
  const auto& S = test::us_biopsy_scene();
  ASSERT_GE(S.anatomy.urethra.size(), 2u);
  const std::vector<float> x = test::rest_positions(*S.model);
  const us::ProbeView pose = default_pose();
  PlaneImager sg(S.anatomy, S.settings, PlaneKind::Sagittal);
  const us::UsImage& img = sg.render(scene_of(x, pose));
  double on = 0.0, off = 0.0;
  int n_on = 0, n_off = 0;
  for (size_t k = 0; k + 1 < S.anatomy.urethra.size(); ++k) {
    const Vec3 q = 0.5 * (S.anatomy.urethra[k] + S.anatomy.urethra[k + 1]);
    const Vec3 t = (S.anatomy.urethra[k + 1] - S.anatomy.urethra[k]).normalized();
    const Vec3 n = t.cross(pose.lateral).normalized();  // in the plane, across the line
    for (int s = -20; s <= 20; ++s) {
      double col, row;
      sg.world_to_pixel(pose, q + (s * 0.25e-3) * n, &col, &row);
      const int i = static_cast<int>(std::lround(col)), j = static_cast<int>(std::lround(row));
      if (i < 0 || j < 0 || i >= img.width || j >= img.height) continue;
      const size_t p = static_cast<size_t>(j) * img.width + i;
      if (img.label[p] != S.anatomy.prostate) continue;
      if (std::abs(s) <= 3) on += img.pixels[p], ++n_on;           // within 0.75 mm of the line
      else if (std::abs(s) >= 12) off += img.pixels[p], ++n_off;   // 3-5 mm away
    }
  }
  ASSERT_GT(n_on, 200);
  ASSERT_GT(n_off, 200);
  on /= n_on, off /= n_off;
  std::printf("midsagittal urethra: mean gray on the line %.0f, 3-5 mm beside it %.0f (%.0f %%)\n", on, off, 100.0 * on / off);
  EXPECT_LT(on, 0.95 * off) << "not hypoechoic";
  EXPECT_GT(on, 0.6 * off) << "a black band, not a subtle line";
}

}  // namespace
}  // namespace ps
