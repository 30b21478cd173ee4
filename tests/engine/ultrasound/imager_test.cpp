// Simulated TRUS image (engine/ultrasound/imager.cpp): geometry against an independent ray-mesh
// intersection, needle position, speckle tracking under translation, speckle statistics,
// determinism, robustness, display conventions.
#include "engine/ultrasound/imager.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "tests/engine/ultrasound/us_scenes.h"

namespace ps {
namespace {

using us::PlaneImager;
using us::PlaneKind;

// Möller-Trumbore: distance along the unit ray (o, d) to triangle (a, b, c), or -1.
double ray_triangle(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-18) return -1;
  const Vec3 t = o - a;
  const double u = t.dot(p) / det;
  if (u < 0 || u > 1) return -1;
  const Vec3 q = t.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0 || u + v > 1) return -1;
  const double s = e2.dot(q) / det;
  return s > 0 ? s : -1;
}

// all hits of the ray with a component's surface at positions x, sorted (vertices past the particles
// are the anatomy's carried vertices: the smoothed bladder and bone, the seminal vesicles)
std::vector<double> ray_hits(const us::UltrasoundAnatomy& an, const us::UsComponent& c, const std::vector<float>& x, const Vec3& o,
                             const Vec3& d) {
  const int n = static_cast<int>(x.size() / 3);
  auto P = [&](int i) {
    if (i < n) return Vec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    const size_t v = static_cast<size_t>(i - n);
    Vec3 q = an.carried_offsets[v];
    for (int k = 0; k < 4; ++k) {
      const int p = an.carried_particles[v][k];
      q += static_cast<double>(an.carried_weights[v][k]) * Vec3(x[3 * p], x[3 * p + 1], x[3 * p + 2]);
    }
    return q;
  };
  std::vector<double> h;
  for (const auto& f : c.faces) {
    const double s = ray_triangle(o, d, P(f[0]), P(f[1]), P(f[2]));
    if (s > 0) h.push_back(s);
  }
  std::sort(h.begin(), h.end());
  return h;
}

using test::scene_of;

// bilinear sample of the 8-bit image at continuous pixel (col, row)
double sample(const us::UsImage& im, double col, double row) {
  const int i = static_cast<int>(std::floor(col)), j = static_cast<int>(std::floor(row));
  if (i < 0 || j < 0 || i >= im.width - 1 || j >= im.height - 1) return -1;
  const double u = col - i, v = row - j;
  auto at = [&](int a, int b) { return static_cast<double>(im.pixels[static_cast<size_t>(b) * im.width + a]); };
  return (1 - u) * (1 - v) * at(i, j) + u * (1 - v) * at(i + 1, j) + (1 - u) * v * at(i, j + 1) + u * v * at(i + 1, j + 1);
}

// Deformation states of the gland: rest, a rigid shift, a smooth non-rigid field, a local push
// from the rectal side (what the probe does), all with the surrounding tissue moving with it.
std::vector<std::vector<float>> deformation_states(const Model& m) {
  const std::vector<float> rest = test::rest_positions(m);
  std::vector<std::vector<float>> out(4, rest);
  for (size_t p = 0; p < m.rest_pos.size(); ++p) {
    const Vec3 X = m.rest_pos[p];
    const Vec3 shift(2.0e-3, -1.5e-3, 2.5e-3);
    const Vec3 wave(2.0e-3 * std::sin(X.y() / 0.015), 1.5e-3 * std::sin(X.z() / 0.012), 2.0e-3 * std::sin(X.x() / 0.018));
    const double g = std::exp(-(X.x() * X.x() + (X.z() - 0.002) * (X.z() - 0.002)) / (2 * 0.012 * 0.012)) *
                     std::exp(-std::max(0.0, X.y() + 0.02) / 0.02);
    const Vec3 push(0, 5.0e-3 * g, 0);  // toward anterior, strongest at the posterior surface
    const Vec3 u[3] = {shift, wave, push};
    for (int s = 0; s < 3; ++s)
      for (int d = 0; d < 3; ++d) out[s + 1][3 * p + d] = static_cast<float>(X[d] + u[s][d]);
  }
  return out;
}

TEST(UltrasoundImager, ProstateBoundaryLiesOnTheCutOfTheDeformedSurface) {
  const auto& S = test::us_biopsy_scene();
  ASSERT_GE(S.anatomy.prostate, 0);
  const us::UsComponent& gland = S.anatomy.components[S.anatomy.prostate];
  PlaneImager tr(S.anatomy, S.settings, PlaneKind::Transverse), sg(S.anatomy, S.settings, PlaneKind::Sagittal);
  const auto states = deformation_states(*S.model);
  double sum = 0.0, worst = 0.0;
  int rays = 0, images = 0;
  for (const auto& x : states)
    for (double adv : {-0.012, -0.004, 0.004})
      for (double roll : {-0.2, 0.0, 0.15})
        for (PlaneImager* im : {&tr, &sg}) {
          const us::ProbeView probe = test::moved_probe(S.probe, adv, roll);
          const us::UsImage& img = im->render(scene_of(x, probe));
          const us::PlaneFrame f = im->frame(probe);
          // a centre inside the section: the gland's current centroid projected on the plane
          Vec3 c = Vec3::Zero();
          for (int p = gland.first_particle; p < gland.first_particle + gland.particle_count; ++p)
            c += Vec3(x[3 * p], x[3 * p + 1], x[3 * p + 2]);
          c /= gland.particle_count;
          c -= (c - f.origin).dot(f.normal) * f.normal;
          ++images;
          for (int k = 0; k < 24; ++k) {
            const double a = 2 * 3.141592653589793 * k / 24;
            const Vec3 d = std::cos(a) * f.right + std::sin(a) * f.up;
            const auto hits = ray_hits(S.anatomy, gland, x, c, d);
            if (hits.size() != 1) continue;  // centre outside the section, or a re-entrant cut
            const double r = hits[0];
            // skip where another organ's surface is within 3.5 mm of the capsule on this ray
            bool crowded = false;
            for (size_t o = 0; o < S.anatomy.components.size() && !crowded; ++o) {
              if (static_cast<int>(o) == S.anatomy.prostate || S.anatomy.components[o].tissue == us::Tissue::Fat) continue;
              for (double hh : ray_hits(S.anatomy, S.anatomy.components[o], x, c, d)) crowded = crowded || std::abs(hh - r) < 3.5e-3;
            }
            if (crowded) continue;
            // the capsule's bright line: brightest point along the ray within +-3 mm of the true cut,
            // on the image smoothed over 0.3 mm along the ray
            double best = -1, best_r = 0;
            bool inside = true;
            for (double q = r - 3e-3; q <= r + 3e-3 && inside; q += 5e-5) {
              double v = 0;
              for (int m = -3; m <= 3; ++m) {
                double col, row;
                im->world_to_pixel(probe, c + (q + m * 5e-5) * d, &col, &row);
                const double sv = sample(img, col, row);
                const size_t pi = static_cast<size_t>(std::lround(row)) * img.width + static_cast<size_t>(std::lround(col));
                if (sv < 0 || !img.in_view[pi]) inside = false;
                v += sv;
              }
              if (v > best) best = v, best_r = q;
            }
            if (!inside) continue;
            const double err = std::abs(best_r - r);
            sum += err;
            worst = std::max(worst, err);
            ++rays;
          }
        }
  ASSERT_GT(rays, 200) << "too few rays measured over " << images << " images";
  const double mean = sum / rays;
  std::printf("capsule line vs true cut: mean %.3f mm, worst %.3f mm over %d rays, %d images\n", mean * 1e3,
              worst * 1e3, rays, images);
  EXPECT_LT(mean, 0.5e-3);
}

TEST(UltrasoundImager, NeedleAppearsWhereItCrossesThePlane) {
  const auto& S = test::us_biopsy_scene();
  const std::vector<float> x = test::rest_positions(*S.model);
  PlaneImager tr(S.anatomy, S.settings, PlaneKind::Transverse);
  const us::ProbeView& probe = S.probe;
  const us::PlaneFrame f = tr.frame(probe);
  // template-style needles parallel to the probe axis at several grid positions, crossing the
  // transverse plane; and an oblique one
  struct Case { double right, up, tilt; };
  for (const Case& k : {Case{0.0, 0.020, 0.0}, Case{-0.012, 0.016, 0.0}, Case{0.010, 0.028, 0.0}, Case{0.005, 0.022, 0.4}}) {
    const Vec3 cross = f.origin + k.right * f.right + k.up * f.up;
    const Vec3 dir = (std::cos(k.tilt) * probe.axis + std::sin(k.tilt) * f.right).normalized();
    us::UltrasoundScene sc = scene_of(x, probe);
    us::Rod rod;
    rod.a = cross + 0.03 * dir;  // tip 30 mm beyond the plane
    rod.b = cross - 0.10 * dir;
    rod.radius = 0.635e-3;       // 18 G
    sc.rods.push_back(rod);
    const us::UsImage& img = tr.render(sc);
    // brightest envelope pixel in the image
    size_t best = 0;
    for (size_t p = 0; p < img.envelope.size(); ++p)
      if (img.envelope[p] > img.envelope[best]) best = p;
    double col, row;
    tr.world_to_pixel(probe, cross, &col, &row);
    const double ec = (static_cast<double>(best % img.width) - col) * img.pixel;
    const double er = (static_cast<double>(best / img.width) - row) * img.pixel;
    EXPECT_LT(std::hypot(ec, er), 0.6e-3) << "needle at (" << k.right * 1e3 << ", " << k.up * 1e3 << ") mm: brightest pixel "
                                          << std::hypot(ec, er) * 1e3 << " mm away";
    EXPECT_EQ(img.pixels[best], 255) << "the needle's dot is not saturated";
  }
  // the same needle 6 mm out of the plane (parallel to it) is not seen: visibility follows the slice
  us::UltrasoundScene sc = scene_of(x, probe);
  us::PlaneImager sg(S.anatomy, S.settings, PlaneKind::Sagittal);
  const us::PlaneFrame fs = sg.frame(probe);
  const Vec3 in_plane_a = fs.origin + 0.02 * fs.up - 0.02 * probe.axis, in_plane_b = fs.origin + 0.02 * fs.up + 0.02 * probe.axis;
  auto line_level = [&](double offset) {
    us::UltrasoundScene s2 = scene_of(x, probe);
    us::Rod rod;
    rod.a = in_plane_a + offset * fs.normal;
    rod.b = in_plane_b + offset * fs.normal;
    rod.radius = 0.635e-3;
    s2.rods.push_back(rod);
    const us::UsImage& img = sg.render(s2);
    double col0, row0, col1, row1;
    sg.world_to_pixel(probe, in_plane_a, &col0, &row0);
    sg.world_to_pixel(probe, in_plane_b, &col1, &row1);
    double sum = 0;
    int n = 0;
    for (int k = 1; k < 20; ++k) {
      const double u = k / 20.0;
      sum += sample(img, col0 + u * (col1 - col0), row0 + u * (row1 - row0));
      ++n;
    }
    return sum / n;
  };
  const double on = line_level(0.0), half = line_level(0.8e-3), off = line_level(6e-3);
  std::printf("in-plane needle gray level: in plane %.0f, 0.8 mm off %.0f, 6 mm off %.0f\n", on, half, off);
  EXPECT_GT(on, 230);
  EXPECT_LT(off, on - 80);
  EXPECT_LE(half, on);
}

// normalised cross-correlation of a block of `a` at (i, j) with `b` at (i + di, j + dj)
double ncc(const us::UsImage& a, const us::UsImage& b, int i, int j, int di, int dj, int n) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double va = a.pixels[static_cast<size_t>(j + y) * a.width + i + x];
      const double vb = b.pixels[static_cast<size_t>(j + y + dj) * b.width + i + x + di];
      sa += va, sb += vb, saa += va * va, sbb += vb * vb, sab += va * vb;
    }
  const double m = n * n;
  const double cov = sab - sa * sb / m, va = saa - sa * sa / m, vb = sbb - sb * sb / m;
  return va > 0 && vb > 0 ? cov / std::sqrt(va * vb) : 0.0;
}

// the same with `b` resampled (bilinear) at the fractional offset (dx, dy) [px]
double ncc_subpixel(const us::UsImage& a, const us::UsImage& b, int i, int j, double dx, double dy, int n) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double va = a.pixels[static_cast<size_t>(j + y) * a.width + i + x];
      const double vb = sample(b, i + x + dx, j + y + dy);
      sa += va, sb += vb, saa += va * va, sbb += vb * vb, sab += va * vb;
    }
  const double m = n * n;
  const double cov = sab - sa * sb / m, va = saa - sa * sa / m, vb = sbb - sb * sb / m;
  return va > 0 && vb > 0 ? cov / std::sqrt(va * vb) : 0.0;
}

TEST(UltrasoundImager, BlockMatchingRecoversAnInPlaneTranslation) {
  const auto& S = test::us_biopsy_scene();
  const std::vector<float> x0 = test::rest_positions(*S.model);
  for (PlaneKind kind : {PlaneKind::Sagittal, PlaneKind::Transverse}) {
    PlaneImager im(S.anatomy, S.settings, kind);
    const us::PlaneFrame f = im.frame(S.probe);
    const Vec3 shift = 0.73e-3 * f.right + 0.41e-3 * f.up;  // not a whole number of pixels  // not a whole number of pixels
    std::vector<float> x1 = x0;
    for (size_t p = 0; p < x1.size() / 3; ++p)
      for (int d = 0; d < 3; ++d) x1[3 * p + d] += static_cast<float>(shift[d]);
    const us::UsImage a = im.render(scene_of(x0, S.probe));
    const us::UsImage b = im.render(scene_of(x1, S.probe));
    // blocks inside the gland (label = prostate in both images, whole block in view)
    const int n = 32, search = 10;
    int blocks = 0;
    double worst = 0, worst_ncc = 1, worst_int = 1;
    for (int j = search; j + n + search < a.height; j += n)
      for (int i = search; i + n + search < a.width; i += n) {
        bool ok = true;
        for (int y = -search; y < n + search && ok; ++y)
          for (int xx = -search; xx < n + search && ok; ++xx) {
            const size_t p = static_cast<size_t>(j + y) * a.width + i + xx;
            ok = a.in_view[p] && a.label[p] == S.anatomy.prostate;
          }
        if (!ok) continue;
        double best = -2;
        int bi = 0, bj = 0;
        for (int dj = -search; dj <= search; ++dj)
          for (int di = -search; di <= search; ++di) {
            const double c = ncc(a, b, i, j, di, dj, n);
            if (c > best) best = c, bi = di, bj = dj;
          }
        // sub-pixel: parabola through the peak and its neighbours on each axis
        auto para = [](double l, double c, double r) { const double d = l - 2 * c + r; return d < 0 ? 0.5 * (l - r) / d : 0.0; };
        const double sx = bi + (std::abs(bi) < search ? para(ncc(a, b, i, j, bi - 1, bj, n), best, ncc(a, b, i, j, bi + 1, bj, n)) : 0);
        const double sy = bj + (std::abs(bj) < search ? para(ncc(a, b, i, j, bi, bj - 1, n), best, ncc(a, b, i, j, bi, bj + 1, n)) : 0);
        // screen: right = +col, up = -row
        const double er = sx * a.pixel - shift.dot(f.right), eu = -sy * a.pixel - shift.dot(f.up);
        worst = std::max(worst, std::hypot(er, eu));
        worst_int = std::min(worst_int, best);
        worst_ncc = std::min(worst_ncc, ncc_subpixel(a, b, i, j, sx, sy, n));
        ++blocks;
      }
    std::printf("%s: %d blocks (32 px), worst error %.3f mm, lowest NCC at the sub-pixel match %.3f (at the whole-pixel peak %.3f)\n",
                kind == PlaneKind::Sagittal ? "sagittal" : "transverse", blocks, worst * 1e3, worst_ncc, worst_int);
    ASSERT_GE(blocks, 3);
    EXPECT_LT(worst, 0.2e-3);
    EXPECT_GE(worst_ncc, 0.9);
  }
}

TEST(UltrasoundImager, HomogeneousTissueHasFullyDevelopedSpeckle) {
  const auto& S = test::us_biopsy_scene();
  for (PlaneKind kind : {PlaneKind::Sagittal, PlaneKind::Transverse}) {
    // a 200 mm cube of uniform tissue around the probe's field of view
    PlaneImager probe_im(S.anatomy, S.settings, kind);
    const us::PlaneFrame f = probe_im.frame(S.probe);
    const Vec3 centre = f.origin + 0.035 * f.up;
    const us::UltrasoundAnatomy box = test::box_anatomy(centre, 0.2);
    PlaneImager im(box, S.settings, kind);
    std::vector<float> x = test::rest_positions(Model{});
    for (const Vec3& p : box.rest)
      for (int d = 0; d < 3; ++d) x.push_back(static_cast<float>(p[d]));
    const us::UsImage& img = im.render(scene_of(x, S.probe));
    // envelope over a 16 x 16 mm window centred 30 mm deep on the beam axis
    double col, row;
    im.world_to_pixel(S.probe, f.origin + (S.settings.convex_radius + 0.03) * f.up, &col, &row);
    const int half = static_cast<int>(0.008 / img.pixel);
    double s = 0, s2 = 0;
    int n = 0;
    for (int j = static_cast<int>(row) - half; j <= static_cast<int>(row) + half; ++j)
      for (int i = static_cast<int>(col) - half; i <= static_cast<int>(col) + half; ++i) {
        const double e = img.envelope[static_cast<size_t>(j) * img.width + i];
        s += e, s2 += e * e, ++n;
      }
    const double mean = s / n, sd = std::sqrt(s2 / n - mean * mean);
    std::printf("%s: envelope SNR %.3f over %d px (Rayleigh: 1.913)\n", kind == PlaneKind::Sagittal ? "sagittal" : "transverse",
                mean / sd, n);
    EXPECT_NEAR(mean / sd, 1.913, 0.15);
  }
}

// A rod (needle, seed) stops the same part of each beam that crosses it whatever its angle to the
// beams: the envelope behind it falls by (1 - shadow), once. (An oblique rod covers several depth
// samples of one beam; counting each of them darkened the region behind the 25 deg biopsy needle by
// 22 dB instead of 4.4 dB: the dark band over the gland in the sagittal replay at 1.8 s.)
TEST(UltrasoundImager, RodShadowIsTheSameAtAnyAngleToTheBeams) {
  const auto& S = test::us_biopsy_scene();
  for (PlaneKind kind : {PlaneKind::Sagittal, PlaneKind::Transverse}) {
    PlaneImager probe_im(S.anatomy, S.settings, kind);
    const us::PlaneFrame f = probe_im.frame(S.probe);
    const us::UltrasoundAnatomy box = test::box_anatomy(f.origin + 0.035 * f.up, 0.2);  // homogeneous tissue
    PlaneImager im(box, S.settings, kind);
    std::vector<float> x;
    for (const Vec3& p : box.rest)
      for (int d = 0; d < 3; ++d) x.push_back(static_cast<float>(p[d]));
    const std::vector<float> plain = im.render(scene_of(x, S.probe)).envelope;
    const double r = S.settings.convex_radius, depth0 = 0.015;  // rod centre 15 mm deep [m]
    for (double deg : {0.0, 25.0, 45.0, 70.0}) {
      const double a = deg * 3.141592653589793 / 180.0, half = 0.008;  // 16 mm rod [m]
      const double cs = 0.0, ct = r + depth0, ds = std::cos(a), dt = std::sin(a);
      us::UltrasoundScene sc = scene_of(x, S.probe);
      us::Rod rod;
      rod.a = f.origin + (cs + half * ds) * f.right + (ct + half * dt) * f.up;
      rod.b = f.origin + (cs - half * ds) * f.right + (ct - half * dt) * f.up;
      rod.radius = 0.635e-3;  // 18 G, in the plane
      sc.rods.push_back(rod);
      const us::UsImage& img = im.render(sc);
      std::vector<double> behind, before;
      for (int j = 0; j < img.height; ++j)
        for (int i = 0; i < img.width; ++i) {
          const size_t p = static_cast<size_t>(j) * img.width + i;
          if (!img.in_view[p] || plain[p] <= 0) continue;
          const double s = im.pixel_s(i), t = im.pixel_t(j);
          // the beam through this pixel: from (s, 0) along up (linear) or from the apex (sector)
          double os = s, ot = 0, bs = 0, bt = 1;
          if (kind == PlaneKind::Transverse) os = 0, bs = s / std::hypot(s, t), bt = t / std::hypot(s, t);
          const double dist = (s - os) * bs + (t - ot) * bt;
          // where the beam crosses the rod's line: os + L b = c + v d
          const double det = bs * (-dt) - bt * (-ds);
          if (std::abs(det) < 1e-9) continue;
          const double rs = cs - os, rt = ct - ot;
          const double L = (rs * (-dt) - rt * (-ds)) / det, v = (bs * rt - bt * rs) / det;
          if (std::abs(v) > 0.7 * half) continue;  // away from the rod's ends
          const double ratio = img.envelope[p] / plain[p];
          if (dist > L + 3e-3 && dist < L + 15e-3) behind.push_back(ratio);
          if (dist < L - 3e-3 && dist > L - 10e-3) before.push_back(ratio);
        }
      ASSERT_GT(behind.size(), 500u) << deg;
      ASSERT_GT(before.size(), 200u) << deg;
      std::sort(behind.begin(), behind.end());
      std::sort(before.begin(), before.end());
      const double mb = behind[behind.size() / 2], mf = before[before.size() / 2];
      std::printf("%s, rod at %2.0f deg to the array: envelope ratio behind %.3f, in front %.3f (1 - shadow = %.2f)\n",
                  kind == PlaneKind::Sagittal ? "sagittal" : "transverse", deg, mb, mf, 1.0 - rod.shadow);
      EXPECT_NEAR(mb, 1.0 - rod.shadow, 0.05) << deg << " deg";
      EXPECT_NEAR(mf, 1.0, 1e-3) << deg << " deg";
    }
  }
}

TEST(UltrasoundImager, IdenticalInputsGiveIdenticalImages) {
  const auto& S = test::us_biopsy_scene();
  const std::vector<float> x = deformation_states(*S.model)[2];
  us::UltrasoundScene sc = scene_of(x, S.probe);
  us::Rod rod;
  rod.a = S.probe.tip_centre + 0.02 * S.probe.anterior;
  rod.b = rod.a - 0.1 * S.probe.axis;
  sc.rods.push_back(rod);
  for (PlaneKind kind : {PlaneKind::Transverse, PlaneKind::Sagittal}) {
    PlaneImager a(S.anatomy, S.settings, kind), b(S.anatomy, S.settings, kind);
    const std::vector<uint8_t> first = a.render(sc).pixels;
    a.render(scene_of(test::rest_positions(*S.model), S.probe));  // something else in between
    EXPECT_EQ(a.render(sc).pixels, first);
    EXPECT_EQ(b.render(sc).pixels, first);
    EXPECT_GT(std::count_if(first.begin(), first.end(), [](uint8_t v) { return v > 0; }), 10000);
  }
}

TEST(UltrasoundImager, NoTissueInViewGivesAValidDarkImage) {
  const auto& S = test::us_biopsy_scene();
  const std::vector<float> x = test::rest_positions(*S.model);
  us::ProbeView away = S.probe;
  away.tip_centre += Vec3(1.0, 1.0, 1.0);  // a metre away from everything
  std::vector<float> bad = x;
  bad[0] = std::numeric_limits<float>::quiet_NaN();  // and a corrupt particle
  for (PlaneKind kind : {PlaneKind::Transverse, PlaneKind::Sagittal})
    for (const std::vector<float>* pos : {&x, static_cast<const std::vector<float>*>(&bad)}) {
      PlaneImager im(S.anatomy, S.settings, kind);
      const us::UsImage& img = im.render(scene_of(*pos, away));
      EXPECT_EQ(*std::max_element(img.pixels.begin(), img.pixels.end()), 0);
      for (float e : img.envelope) ASSERT_TRUE(std::isfinite(e));
      const us::UsImage& img2 = im.render(scene_of(*pos, S.probe));  // and back in the body
      for (float e : img2.envelope) ASSERT_TRUE(std::isfinite(e));
      EXPECT_GT(std::accumulate(img2.pixels.begin(), img2.pixels.end(), 0.0) / img2.pixels.size(), 10.0);
    }
}

TEST(UltrasoundImager, DisplayConventions) {
  const auto& S = test::us_biopsy_scene();
  const std::vector<float> x = test::rest_positions(*S.model);
  PlaneImager tr(S.anatomy, S.settings, PlaneKind::Transverse), sg(S.anatomy, S.settings, PlaneKind::Sagittal);
  // transverse: a point on the patient's right (+x, RAS) is on the screen's left; anterior is up
  const us::PlaneFrame f = tr.frame(S.probe);
  const Vec3 c = f.origin + 0.025 * f.up;
  double col_r, row_r, col_a, row_a, col_c, row_c;
  tr.world_to_pixel(S.probe, c, &col_c, &row_c);
  tr.world_to_pixel(S.probe, c + Vec3(0.01, 0, 0), &col_r, &row_r);
  tr.world_to_pixel(S.probe, c + Vec3(0, 0.01, 0), &col_a, &row_a);
  EXPECT_LT(col_r, col_c - 20);
  EXPECT_LT(row_a, row_c - 20);
  // sagittal: cranial (+z, toward the probe tip) on the left, anterior up, the probe at the bottom
  const us::PlaneFrame g = sg.frame(S.probe);
  const Vec3 d = g.origin + 0.025 * g.up;
  double col_d, row_d, col_s, row_s;
  sg.world_to_pixel(S.probe, d, &col_d, &row_d);
  sg.world_to_pixel(S.probe, d + Vec3(0, 0, 0.01), &col_s, &row_s);
  EXPECT_LT(col_s, col_d - 20);
  double col_p, row_p;
  sg.world_to_pixel(S.probe, S.probe.tip_centre - 0.03 * S.probe.axis, &col_p, &row_p);
  EXPECT_GT(row_p, 0.9 * S.settings.height);
  // the rectal side is dark: the lumen around the probe anechoic, the rectal wall hypoechoic
  const us::UsImage& img = tr.render(scene_of(x, S.probe));
  int rectum = -1;
  for (size_t c = 0; c < S.anatomy.components.size(); ++c)
    if (S.anatomy.components[c].tissue == us::Tissue::Rectum) rectum = static_cast<int>(c);
  ASSERT_GE(rectum, 0);
  double lumen = 0, wall = 0, gland = 0;
  int nl = 0, nw = 0, ng = 0;
  for (size_t p = 0; p < img.pixels.size(); ++p) {
    if (!img.in_view[p]) continue;
    if (img.label[p] == rectum) lumen += img.pixels[p], ++nl;
    else if (img.label[p] == 64 + rectum) wall += img.pixels[p], ++nw;
    else if (img.label[p] == S.anatomy.prostate) gland += img.pixels[p], ++ng;
  }
  ASSERT_GT(nl, 100);
  ASSERT_GT(nw, 100);
  ASSERT_GT(ng, 1000);
  std::printf("mean gray: lumen %.0f, rectal wall %.0f, gland %.0f\n", lumen / nl, wall / nw, gland / ng);
  EXPECT_LT(lumen / nl, 0.3 * gland / ng);
  EXPECT_LT(wall / nw, gland / ng);
}

}  // namespace
}  // namespace ps

#include "tests/engine/counting_allocator.h"
namespace ps {
TEST(UltrasoundImager, RenderDoesNotAllocateOnceWarm) {
  const auto& S = test::us_biopsy_scene();
  const std::vector<float> x = test::rest_positions(*S.model);
  us::UltrasoundScene sc;
  sc.x = x.data();
  sc.particle_count = static_cast<int>(x.size() / 3);
  sc.probe = S.probe;
  us::Rod rod;
  rod.a = S.probe.tip_centre + 0.02 * S.probe.anterior;
  rod.b = rod.a - 0.1 * S.probe.axis;
  sc.rods.push_back(rod);
  us::BiplaneImager im(S.anatomy, S.settings);
  im.render(sc);
  const long before = test::allocation_count();
  im.render(sc);
  sc.probe = test::moved_probe(S.probe, -0.004, 0.1);
  im.render(sc);
  EXPECT_EQ(test::allocation_count() - before, 0);
}
}  // namespace ps
