// Dragging in the editor's 3D view (app/editor/view_drag.h: the calls editor_window.cpp makes
// for the mouse): a press on a lesion picks it, a pointer motion moves it in the view plane, and
// the release edits the document through the command path. Checked against the camera, not
// against the drag code: with an anterior camera 0.3 m from the lesion in a 900 px high view,
// one pixel is 2 * 0.3 m * tan(17.5 deg) / 900 = 0.2102 mm, so (-20, +15) px (left, down) moves
// it +4.20 mm along x (patient right: the anterior view's left) and -3.15 mm along z; the file
// holds the rounded centre, the compiled scenario's region and the tagged particles follow it.
// A needle target dragged under an oblique orbit camera lands where the pointer ended (its
// projection within the whole-mm rounding).
#include "app/editor/view_drag.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/engine/tools/needle/needle_scenes.h"

namespace ps::editor {
namespace {

std::string block_scene() {
  std::string y = test::block_yaml(test::BlockOptions{}, test::vertical_needle("n", 0, 0, "[[0, 0], [0.5, 13]]", "      target_mm: [0, 0, -12]\n"));
  y += "tags:\n  - name: lesion_a\n    component: tissue\n    region: {sphere: {center_mm: [-6, 0, -12], radius_mm: 3}}\n";
  return y;
}

// Presses at the handle's pixel, moves in `steps` pointer motions of (dx, dy) / steps, releases.
EditResult drag(ViewDrag& d, EditorCommands& c, FieldErrors& errs, const render::Camera& cam, const ViewRect& v, const Vec3& from_mm,
                float dx, float dy, int steps = 4) {
  float px = 0, py = 0;
  EXPECT_TRUE(project(cam, v, 1e-3 * from_mm, px, py));
  EXPECT_TRUE(d.press(c, cam, v, px + 2.0f, py - 1.0f)) << "nothing picked at the handle";
  for (int k = 0; k < steps; ++k) d.move(c, cam, v, dx / steps, dy / steps);
  return d.release(c, errs);
}

TEST(ViewDrag, DraggingALesionMovesItByTheCamerasMillimetresInTheFileAndTheModel) {
  EditorCommands c(ScenarioDocument(block_scene(), "block.yaml"));
  ASSERT_TRUE(c.doc().valid()) << c.doc().error()->message;
  const Vec3 c0(-6, 0, -12);
  render::Camera cam;  // anterior: looking along -y (posterior), z up
  cam.target = 1e-3 * c0;
  cam.eye = cam.target + Vec3(0, 0.3, 0);
  cam.up = Vec3::UnitZ();
  cam.fov_y_deg = 35.0;
  const ViewRect v{440.0f, 0.0f, 1160.0f, 900.0f};
  const double mm_per_px = 2.0 * 300.0 * std::tan(17.5 * M_PI / 180.0) / 900.0;
  EXPECT_NEAR(mm_per_px, 0.2102, 1e-4);

  ViewDrag d;
  FieldErrors errs;
  // a press far from every handle picks nothing (the window orbits instead)
  EXPECT_FALSE(d.press(c, cam, v, 450.0f, 10.0f));
  const EditResult r = drag(d, c, errs, cam, v, c0, -20.0f, 15.0f);
  ASSERT_TRUE(r.ok) << r.issue->message;
  EXPECT_EQ(d.selected(), "lesion_a");
  const Vec3 expect_exact = c0 + Vec3(20 * mm_per_px, 0, -15 * mm_per_px);  // (-1.80, 0, -15.15)
  const Vec3 expect = expect_exact.array().round().matrix();                 // whole mm: (-2, 0, -15)
  std::printf("lesion dragged (-20, +15) px: %.2f, %.2f, %.2f mm exact, %g, %g, %g mm in the file\n", expect_exact.x(), expect_exact.y(),
              expect_exact.z(), expect.x(), expect.y(), expect.z());
  // the document
  EXPECT_EQ(c.doc().value_text("tags[lesion_a].region.sphere.center_mm"), "[-2, 0, -15]");
  EXPECT_TRUE(c.doc().modified());
  // the compiled scenario: the region, and the particles the tag now selects
  const RegionView rv = c.regions().at(0);
  EXPECT_NEAR((rv.center_mm - expect).norm(), 0.0, 1e-9);
  const Model& m = *c.doc().model();
  const int t = m.find_tag("lesion_a");
  ASSERT_GE(t, 0);
  int n = 0;
  for (int p = 0; p < m.particle_count(); ++p) {
    if (!(m.particle_tags[p] >> t & 1)) continue;
    ++n;
    EXPECT_LE((1e3 * m.rest_pos[p] - expect).norm(), 3.0 + 1e-9) << "a tagged particle outside the moved sphere";
  }
  EXPECT_GT(n, 0) << "the moved lesion holds no particle";
  // undo puts it back, in the file and the model
  ASSERT_TRUE(c.undo());
  EXPECT_EQ(c.doc().value_text("tags[lesion_a].region.sphere.center_mm"), "[-6, 0, -12]");
}

TEST(ViewDrag, ANeedleTargetDraggedUnderAnObliqueCameraEndsUnderThePointer) {
  EditorCommands c(ScenarioDocument(block_scene(), "block.yaml"));
  ASSERT_TRUE(c.doc().valid());
  render::OrbitCamera orbit;  // the editor's default orbit angles
  orbit.target = Vec3(0, 0, -0.012);
  orbit.distance = 0.12;
  const render::Camera cam = orbit.camera();
  const ViewRect v{440.0f, 0.0f, 1160.0f, 900.0f};
  const Vec3 t0(0, 0, -12);
  float x0 = 0, y0 = 0;
  ASSERT_TRUE(project(cam, v, 1e-3 * t0, x0, y0));
  ViewDrag d;
  FieldErrors errs;
  const float dx = 60.0f, dy = -45.0f;
  const EditResult r = drag(d, c, errs, cam, v, t0, dx, dy, 6);
  ASSERT_TRUE(r.ok) << r.issue->message;
  EXPECT_EQ(d.selected(), "n");
  EXPECT_EQ(d.selected_kind(), Handle::Target);
  const NeedleSpec& ns = c.spec()->needles.needles.at(0);
  ASSERT_TRUE(ns.target.has_value());
  const Vec3 t1 = 1e3 * *ns.target;  // the compiled scenario's target [mm]
  EXPECT_EQ(t1, t1.array().round().matrix().eval()) << "not whole mm";
  float x1 = 0, y1 = 0, ppm = 0;
  ASSERT_TRUE(project(cam, v, 1e-3 * t1, x1, y1, &ppm));
  const double px_per_mm = 1e-3 * ppm;
  std::printf("target dragged (%.0f, %.0f) px at %.2f px/mm: moved to [%g, %g, %g] mm, now %.1f, %.1f px from the press\n", dx, dy,
              px_per_mm, t1.x(), t1.y(), t1.z(), x1 - x0, y1 - y0);
  // it ends under the pointer: off by at most the rounding to whole mm (half a mm on each axis)
  const double tol = std::sqrt(3.0) * 0.5 * px_per_mm + 0.5;
  EXPECT_NEAR(x1 - x0, dx, tol);
  EXPECT_NEAR(y1 - y0, dy, tol);
  EXPECT_GT((t1 - t0).norm(), 5.0) << "the target barely moved";
  const std::string text = c.doc().value_text("needles.instruments[n].target_mm");
  EXPECT_EQ(text.find('.'), std::string::npos) << "the file holds whole mm: " << text;
}

}  // namespace
}  // namespace ps::editor
