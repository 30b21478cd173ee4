// Offscreen pixel tests with known geometry: a primitive drawn at a known place has the expected
// colour there and not elsewhere; surfaces follow the snapshot; transparency blends; the
// displacement colouring reaches the top of the scale. Headless context errors are clear.
#include "render/offscreen_target.h"
#include "render/renderer.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "engine/contract/snapshot.h"
#include "engine/dosimetry/isodose.h"
#include "render/headless_context.h"
#include "render/render_error.h"

namespace ps::render {
namespace {

constexpr int kW = 160, kH = 120;

struct Px {
  int r, g, b;
};
Px at(const std::vector<uint8_t>& rgb, int x, int y) {
  const uint8_t* p = &rgb[3 * (static_cast<size_t>(y) * kW + x)];
  return {p[0], p[1], p[2]};
}

// a camera on +z looking at the origin, y up, 35 deg field: 1 cm at 0.3 m spans ~15 px of 120
Camera front_camera() {
  Camera c;
  c.eye = Vec3(0, 0, 0.3);
  c.target = Vec3::Zero();
  c.up = Vec3::UnitY();
  c.near_m = 0.01;
  c.far_m = 2.0;
  return c;
}

// projected pixel of a world point (the same math as the shader)
std::pair<int, int> project(const Camera& c, const Vec3& p) {
  const Eigen::Vector4f h = c.projection(static_cast<double>(kW) / kH) * c.view() * Eigen::Vector4f(p.x(), p.y(), p.z(), 1.0f);
  const double x = h.x() / h.w(), y = h.y() / h.w();
  return {static_cast<int>((x * 0.5 + 0.5) * kW), static_cast<int>((0.5 - y * 0.5) * kH)};
}

RenderScene empty_scene() {
  RenderScene sc;
  sc.name = "test";
  return sc;
}

// one square of two triangles in the plane z = z0, side 2a, 4 particles
RenderScene square_scene(double a, double z0, Rgba colour) {
  RenderScene sc;
  sc.name = "square";
  sc.particle_count = 4;
  const double xy[4][2] = {{-a, -a}, {a, -a}, {a, a}, {-a, a}};
  for (auto& q : xy)
    for (double v : {q[0], q[1], z0}) sc.rest.push_back(static_cast<float>(v));
  RenderSurface s;
  s.name = "square";
  s.particles = {0, 1, 2, 3};
  s.indices = {0, 1, 2, 0, 2, 3};
  s.colour = colour;
  sc.surfaces.push_back(s);
  return sc;
}

Snapshot snapshot_of(const RenderScene& sc) {
  Snapshot s;
  s.x = sc.rest;
  return s;
}

class RendererTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ctx_ = new HeadlessContext(); }
  static void TearDownTestSuite() {
    delete ctx_;
    ctx_ = nullptr;
  }
  std::vector<uint8_t> draw(Renderer& r, const Camera& cam, RenderOptions opt = {}) {
    OffscreenTarget t(kW, kH, 4);
    opt.hud = false;
    t.bind();
    r.render(cam, kW, kH, opt);
    std::vector<uint8_t> rgb;
    t.read_rgb(rgb);
    return rgb;
  }
  static HeadlessContext* ctx_;
};
HeadlessContext* RendererTest::ctx_ = nullptr;

TEST_F(RendererTest, ContextIsCoreProfileWithARenderer) {
  EXPECT_TRUE(ctx_->backend() == "egl" || ctx_->backend() == "osmesa");
  EXPECT_FALSE(ctx_->renderer().empty());
}

TEST_F(RendererTest, SphereAppearsWhereProjectedAndNowhereElse) {
  Renderer r(empty_scene());
  Snapshot s;
  const Vec3 centre(0.02, 0.01, 0.0);
  s.draw.sphere(centre, 0.006, {1.0f, 0.0f, 0.0f, 1.0f}, DrawRole::Target);
  r.update(s);
  const Camera cam = front_camera();
  RenderOptions opt;
  opt.background = {0.0f, 0.0f, 1.0f, 1.0f};
  const auto rgb = draw(r, cam, opt);
  const auto [cx, cy] = project(cam, centre);
  ASSERT_GT(cx, 10);
  ASSERT_LT(cx, kW - 10);
  const Px c = at(rgb, cx, cy);
  EXPECT_GT(c.r, 150) << "sphere centre not red";
  EXPECT_LT(c.g, 60);
  EXPECT_LT(c.b, 60);
  // the mirror image position (left of centre, below) and the corners show the background
  const auto [mx, my] = project(cam, Vec3(-0.02, -0.01, 0.0));
  for (auto [x, y] : {std::pair{mx, my}, std::pair{1, 1}, std::pair{kW - 2, kH - 2}}) {
    const Px b = at(rgb, x, y);
    EXPECT_EQ(b.r, 0) << x << "," << y;
    EXPECT_EQ(b.g, 0);
    EXPECT_EQ(b.b, 255);
  }
  // red pixels lie within the projected radius (+2 px of antialiasing) of the centre
  const auto [ex, ey] = project(cam, centre + Vec3(0.006, 0, 0));
  const double rad = std::abs(ex - cx) + 2.0;
  int red = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (at(rgb, x, y).r > 100) {
        ++red;
        EXPECT_LE(std::hypot(x - cx, y - cy), rad) << x << "," << y;
      }
  EXPECT_GT(red, 20);
}

// Spheres are drawn at a level of detail chosen by their radius on screen (renderer.cpp): a small
// one must still cover the area of its projected disc (an inscribed hexagon would cover 17 % less:
// the seed and target dots would shrink), and a large one stays round.
TEST_F(RendererTest, SpheresCoverTheirProjectedDiscAtEverySize) {
  const Camera cam = front_camera();
  const double px_per_m = 0.5 * kH / std::tan(0.5 * cam.fov_y_deg * 3.14159265358979323846 / 180.0) / 0.3;  // at 0.3 m
  for (double r_px : {2.0, 2.9, 4.0, 6.0, 9.5, 14.0}) {
    Renderer r(empty_scene());
    Snapshot s;
    s.draw.sphere(Vec3::Zero(), r_px / px_per_m, {0.0f, 0.0f, 0.0f, 1.0f}, DrawRole::Target);
    r.update(s);
    RenderOptions opt;
    opt.background = {1.0f, 1.0f, 1.0f, 1.0f};
    const auto rgb = draw(r, cam, opt);
    // covered area from the multisampled coverage: a black sphere on white (its specular
    // highlight, at most 0.22, biases this by well under 1 %)
    double area = 0.0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) area += (255.0 - at(rgb, x, y).b) / 255.0;
    const double disc = 3.14159265358979323846 * r_px * r_px;
    std::printf("sphere of %.1f px radius: %.1f px covered, disc %.1f px (ratio %.3f)\n", r_px, area, disc, area / disc);
    EXPECT_NEAR(area / disc, 1.0, 0.05) << r_px << " px radius";
  }
}

TEST_F(RendererTest, CapsuleCoversItsSegmentOnly) {
  Renderer r(empty_scene());
  Snapshot s;
  s.draw.capsule(Vec3(-0.03, 0, 0), Vec3(0.03, 0, 0), 0.003, {0, 1, 0, 1}, DrawRole::Needle);
  r.update(s);
  const Camera cam = front_camera();
  RenderOptions opt;
  opt.background = {0, 0, 0, 1};
  const auto rgb = draw(r, cam, opt);
  for (double x : {-0.025, 0.0, 0.025}) {
    const auto [px, py] = project(cam, Vec3(x, 0, 0));
    EXPECT_GT(at(rgb, px, py).g, 120) << x;
  }
  for (const Vec3& p : {Vec3(0, 0.02, 0), Vec3(0.045, 0, 0), Vec3(-0.045, 0, 0)}) {
    const auto [px, py] = project(cam, p);
    EXPECT_EQ(at(rgb, px, py).g, 0) << p.transpose();
  }
}

TEST_F(RendererTest, SurfaceFollowsTheSnapshot) {
  RenderScene sc = square_scene(0.01, 0.0, {1, 1, 1, 1});
  Renderer r(sc);
  Snapshot s = snapshot_of(sc);
  r.update(s);
  const Camera cam = front_camera();
  RenderOptions opt;
  opt.background = {0, 0, 0, 1};
  auto rgb = draw(r, cam, opt);
  const auto [x0, y0] = project(cam, Vec3(0, 0, 0));
  const auto [x1, y1] = project(cam, Vec3(0.03, 0, 0));
  EXPECT_GT(at(rgb, x0, y0).r, 100);
  EXPECT_EQ(at(rgb, x1, y1).r, 0);
  // move every vertex 3 cm along +x: the square leaves the centre and covers the new place
  for (int p = 0; p < 4; ++p) s.x[3 * p] += 0.03f;
  r.update(s);
  EXPECT_FLOAT_EQ(r.surface_vertices(0)[0], sc.rest[0] + 0.03f);
  rgb = draw(r, cam, opt);
  EXPECT_EQ(at(rgb, x0, y0).r, 0);
  EXPECT_GT(at(rgb, x1, y1).r, 100);
}

TEST_F(RendererTest, TransparentSurfaceShowsWhatIsBehindIt) {
  // a clear blue square in front of an opaque red sphere: the pixel mixes both
  RenderScene sc = square_scene(0.02, 0.02, {0.0f, 0.0f, 1.0f, 0.4f});
  Renderer r(sc);
  Snapshot s = snapshot_of(sc);
  s.draw.sphere(Vec3::Zero(), 0.008, {1, 0, 0, 1}, DrawRole::Target);
  r.update(s);
  const Camera cam = front_camera();
  RenderOptions opt;
  opt.background = {0, 0, 0, 1};
  auto rgb = draw(r, cam, opt);
  const auto [cx, cy] = project(cam, Vec3::Zero());
  const Px mixed = at(rgb, cx, cy);
  EXPECT_GT(mixed.r, 60);
  EXPECT_GT(mixed.b, 40);
  // fully opaque: the sphere is hidden
  opt.opacity = {1.0f};
  rgb = draw(r, cam, opt);
  EXPECT_LT(at(rgb, cx, cy).r, 40);  // specular highlight only
  EXPECT_GT(at(rgb, cx, cy).b, 100);
  // hidden: the sphere alone
  opt.hidden = {1};
  rgb = draw(r, cam, opt);
  EXPECT_LT(at(rgb, cx, cy).b, 40);
  EXPECT_GT(at(rgb, cx, cy).r, 150);
}

// The prescription isodose surface (Renderer::set_isodose, render/isodose_mesh.cpp): a one-seed
// surface (~5 mm radius, given in millimetres) tints the background translucently where it
// projects and nowhere else, an opaque sphere inside it shows through, and an empty surface
// removes it.
TEST_F(RendererTest, IsodoseSurfaceIsTranslucentWhereProjectedAndRemovable) {
  dosimetry::DoseField f;
  f.spec = dosimetry::grid_around(Vec3(-12, -12, -12), Vec3(12, 12, 12), 0.0, 1.0);
  dosimetry::DoseAccumulator acc(*dosimetry::find_source_model("I125_6711"), f.spec);
  acc.rebuild({dosimetry::Seed{Vec3::Zero(), Vec3::UnitY(), 0.5}});
  f.dose_gy = acc.dose_gy();
  const dosimetry::IsoSurface iso = dosimetry::isodose_surface(f, 40.0);  // ~5 mm from the seed
  ASSERT_FALSE(iso.faces.empty());
  Renderer r(empty_scene());
  Snapshot s;
  s.draw.sphere(Vec3::Zero(), 0.002, {1.0f, 1.0f, 1.0f, 1.0f}, DrawRole::Target);  // white, inside the surface
  r.update(s);
  const Camera cam = front_camera();
  RenderOptions opt;
  opt.background = {0.0f, 0.0f, 0.0f, 1.0f};
  const auto plain = draw(r, cam, opt);
  r.set_isodose(iso, {1.0f, 0.0f, 0.0f, 0.3f});
  const auto tinted = draw(r, cam, opt);
  const auto [cx, cy] = project(cam, Vec3::Zero());
  const auto [ex, ey] = project(cam, Vec3(0.0045, 0, 0));  // between the white sphere and the surface
  const auto [fx, fy] = project(cam, Vec3(0.009, 0, 0));   // outside the surface
  EXPECT_GT(at(tinted, ex, ey).r, at(plain, ex, ey).r + 40) << "the surface tints the background red";
  EXPECT_EQ(at(tinted, fx, fy).r, at(plain, fx, fy).r) << "nothing outside it";
  const Px c = at(tinted, cx, cy);
  EXPECT_GT(c.g, 80) << "the white sphere inside shows through (" << c.r << "," << c.g << "," << c.b << ")";
  EXPECT_LT(c.g, at(plain, cx, cy).g) << "through a tint";
  r.set_isodose(dosimetry::IsoSurface{});
  const auto again = draw(r, cam, opt);
  EXPECT_EQ(again, plain) << "an empty surface removes it";
}

TEST_F(RendererTest, DisplacementColouringReachesTheTopOfTheScale) {
  RenderScene sc = square_scene(0.02, 0.0, {1, 1, 1, 1});
  Renderer r(sc);
  Snapshot s = snapshot_of(sc);
  for (int p = 0; p < 4; ++p) s.x[3 * p + 2] += 0.005f;  // 5 mm towards the camera
  r.update(s);
  RenderOptions opt;
  opt.displacement = true;
  opt.displacement_max_mm = 5.0;
  const Camera cam = front_camera();
  const auto rgb = draw(r, cam, opt);
  const auto [cx, cy] = project(cam, Vec3(0, 0, 0.005));
  const Px c = at(rgb, cx, cy);
  // top of the map is yellow (0.99, 0.91, 0.14) before lighting: red and green high, blue low
  EXPECT_GT(c.r, 150);
  EXPECT_GT(c.g, 140);
  EXPECT_LT(c.b, 90);
  const Rgba top = colour_map(1.0);
  EXPECT_NEAR(top.r, 0.993f, 1e-3);
}

TEST_F(RendererTest, SnapshotOfTheWrongSizeIsRefused) {
  RenderScene sc = square_scene(0.01, 0.0, {1, 1, 1, 1});
  Renderer r(sc);
  Snapshot s;
  s.x.assign(3, 0.0f);
  EXPECT_THROW(r.update(s), RenderError);
}

TEST_F(RendererTest, OffscreenTargetRefusesAbsurdSizes) {
  EXPECT_THROW(OffscreenTarget(0, 10), RenderError);
  EXPECT_THROW(OffscreenTarget(100000, 10), RenderError);
}

TEST(HeadlessContextTest, UnknownBackendAndMissingLibrariesGiveOneClearMessage) {
  ::setenv("PROSTATESIM_GL", "vulkan", 1);
  try {
    HeadlessContext c;
    FAIL() << "no error";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("PROSTATESIM_GL=vulkan"), std::string::npos) << e.what();
  }
  ::setenv("PROSTATESIM_GL", "auto", 1);
  ::setenv("PROSTATESIM_EGL_LIB", "/nonexistent/libEGL.so.1", 1);
  ::setenv("PROSTATESIM_OSMESA_LIB", "/nonexistent/libOSMesa.so.8", 1);
  try {
    HeadlessContext c;
    FAIL() << "no error";
  } catch (const RenderError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("EGL"), std::string::npos) << w;
    EXPECT_NE(w.find("OSMesa"), std::string::npos) << w;
  }
  ::unsetenv("PROSTATESIM_GL");
  ::unsetenv("PROSTATESIM_EGL_LIB");
  ::unsetenv("PROSTATESIM_OSMESA_LIB");
}

}  // namespace
}  // namespace ps::render
