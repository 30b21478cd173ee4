// The template overlay of the TRUS (app/frames/template_overlay.h, issue 46 item 1) on the
// brachytherapy scenes' own probe and template (13 x 13 holes at 5 mm, row 1 10 mm above the probe
// axis): where the holes fall on the transverse image, which hole a click picks, the labels, the
// plan's needle of each hole, the seeds counted per hole, and the grid burnt into a PNG's pixels.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "app/frames/template_overlay.h"
#include "app/frames/us_isodose.h"
#include "engine/dosimetry/template_grid.h"
#include "engine/scenario/compile.h"
#include "engine/scenario/parse_yaml.h"
#include "engine/state/state.h"
#include "engine/tools/probe/probe.h"
#include "engine/ultrasound/from_simulation.h"
#include "engine/ultrasound/imager.h"

namespace ps::frames {
namespace {

const std::string kConfig = std::string(PROSTATESIM_SOURCE_DIR) + "/config/";

// The plan-following scene's probe at its start pose, its transverse image's pixels (384 px, the
// window's) and the template holes where the probe tool draws them.
struct TransverseScene {
  ScenarioSpec spec;
  us::ProbeView probe;
  dosimetry::PixelPlane plane;
  std::vector<TemplateHole> holes;
  HoleMarks marks;
  double px_mm = 0.0;
};

const TransverseScene& scene() {
  static const TransverseScene t = [] {
    TransverseScene s;
    s.spec = parse_scenario_file(kConfig + "brachytherapy_plan.yaml");
    const auto model = compile_scenario(s.spec);
    auto tool = make_probe_tool(s.spec, *model);
    DrawList draw;
    tool->draw(draw, *model, State{});
    s.probe = us::probe_view(tool->frame(), s.spec.probe->radius);
    us::UltrasoundSettings set = us::settings_for_probe(*s.spec.probe);
    set.width = set.height = 384;
    const us::UltrasoundAnatomy none;
    const us::PlaneImager im(none, set, us::PlaneKind::Transverse);
    s.plane = pixel_plane(im, s.probe);
    s.px_mm = s.plane.dcol_mm.norm();
    s.holes = template_holes_from_draw(draw, s.spec.probe->template_cols, s.spec.probe->template_rows, s.probe.axis);
    s.marks = transverse_hole_marks(s.plane, s.holes);
    return s;
  }();
  return t;
}

const ImagePoint& mark_of(const std::string& label) {
  const auto cr = dosimetry::parse_template_hole(label, 13, 13);
  EXPECT_TRUE(cr.has_value()) << label;
  const HoleMarks& m = scene().marks;
  for (size_t i = 0; i < m.holes.size(); ++i)
    if (m.holes[i].col == cr->first && m.holes[i].row == cr->second) return m.at[i];
  ADD_FAILURE() << "no mark of " << label;
  static const ImagePoint none;
  return none;
}

TEST(TemplateOverlay, HolesFromTheDrawnTemplateAreTheStepperHoles) {
  const TransverseScene& s = scene();
  const ProbeSpec& ps = *s.spec.probe;
  ASSERT_EQ(s.holes.size(), 169u);
  const RectalFrame rf = rectal_frame(ps);
  for (const TemplateHole& h : s.holes) {
    const NeedlePath p = template_hole_path(ps, rf, ps.pose, h.col, h.row);
    EXPECT_LT((h.entry - p.entry).norm(), 1e-9) << dosimetry::template_hole_label(h.col, h.row);
    EXPECT_GT(h.direction.dot(p.direction), 1.0 - 1e-12);
  }
  // another number of grid spheres than cols x rows: not taken for a template
  DrawList two;
  two.sphere(Vec3::Zero(), 1e-3, {}, DrawRole::TemplateGrid);
  two.sphere(Vec3::UnitX(), 1e-3, {}, DrawRole::TemplateGrid);
  EXPECT_TRUE(template_holes_from_draw(two, 13, 13, Vec3::UnitZ()).empty());
}

TEST(TemplateOverlay, HoleD1IsOnTheProbeMidline10mmAboveTheProbeAxis) {
  const TransverseScene& s = scene();
  ASSERT_EQ(s.marks.at.size(), 169u);
  const auto apex = line_crossing_pixel(s.plane, s.probe.tip_centre, s.probe.axis);  // the probe axis on the image
  ASSERT_TRUE(apex.has_value());
  const ImagePoint& d1 = mark_of("D1");
  EXPECT_NEAR(d1.x, apex->x, 1e-6);
  EXPECT_NEAR((apex->y - d1.y) * s.px_mm, 10.0, 1e-6);  // up the screen = anterior
  // the patient's right on the screen's left: column A 30 mm left of D, G 30 mm right
  EXPECT_NEAR((d1.x - mark_of("A1").x) * s.px_mm, 30.0, 1e-6);
  EXPECT_NEAR((mark_of("G1").x - d1.x) * s.px_mm, 30.0, 1e-6);
  EXPECT_NEAR((d1.y - mark_of("D7").y) * s.px_mm, 60.0, 1e-6);  // rows 1 1.5 ... 7: 13 at 5 mm
  EXPECT_NEAR(s.marks.pitch_px * s.px_mm, 5.0, 1e-6);
}

TEST(TemplateOverlay, AClickPicksTheNearestHoleWithinHalfASpacing) {
  const TransverseScene& s = scene();
  const HoleMarks& m = s.marks;
  const ImagePoint c2 = mark_of("C2");
  auto picked = [&](double x, double y) {
    const int i = pick_hole(m, x, y);
    return i < 0 ? std::string("none") : dosimetry::template_hole_label(m.holes[i].col, m.holes[i].row);
  };
  EXPECT_EQ(picked(c2.x, c2.y), "C2");
  EXPECT_EQ(picked(c2.x + 0.4 * m.pitch_px, c2.y - 0.2 * m.pitch_px), "C2");
  EXPECT_EQ(picked(c2.x + 0.6 * m.pitch_px, c2.y), "c2");      // nearer the half-step right of it
  EXPECT_EQ(picked(c2.x, c2.y - 0.6 * m.pitch_px), "C2.5");    // and the one above
  // the middle of four holes is 0.71 spacings from each: none
  EXPECT_EQ(picked(c2.x + 0.5 * m.pitch_px, c2.y - 0.5 * m.pitch_px), "none");
  EXPECT_EQ(picked(-500.0, -500.0), "none");
  EXPECT_EQ(picked(mark_of("A1").x - 0.7 * m.pitch_px, mark_of("A1").y), "none");  // left of the grid
}

// The window zooms the transverse image onto the template (186 px wide here, the TRUS panel's
// image): the grid and its labels fill the view, and a click at the screen position of C2 picks C2.
TEST(TemplateOverlay, ZoomedViewHoldsTheGridAndAClickOnC2PicksC2) {
  const TransverseScene& s = scene();
  const frames::ImageCrop crop = template_crop(s.marks, 384, 100.0, 50.0, 186.0);
  EXPECT_LT(crop.size, 0.6 * 384);                           // zoomed: 60 mm of grid in a 134 mm sector
  EXPECT_GT(s.marks.pitch_px * crop.side / crop.size, 12.0);  // a hole spacing of over 12 screen px
  for (const ImagePoint& p : s.marks.at) {
    const ImagePoint v = crop.to_view(p);
    EXPECT_GE(v.x, 100.0);
    EXPECT_LE(v.x, 286.0);
    EXPECT_GE(v.y, 50.0);
    EXPECT_LE(v.y, 236.0);
  }
  for (const GridLabel& l : grid_labels(s.marks, 13, 13)) {
    const ImagePoint v = crop.to_view(l.at);
    EXPECT_GT(v.x, 100.0 + 4.0) << l.text;  // room for half a label
    EXPECT_LT(v.y, 236.0 - 4.0) << l.text;
  }
  const ImagePoint c2 = crop.to_view(mark_of("C2"));
  const ImagePoint back = crop.to_image(c2.x, c2.y);
  EXPECT_NEAR(back.x, mark_of("C2").x, 1e-9);
  const int i = pick_hole(s.marks, back.x, back.y);
  ASSERT_GE(i, 0);
  EXPECT_EQ(dosimetry::template_hole_label(s.marks.holes[i].col, s.marks.holes[i].row), "C2");
  // the whole image maps pixel centres as the window's isodose lines always did: (x + 0.5) * side / n
  const frames::ImageCrop whole = whole_image(384, 0.0, 0.0, 192.0);
  EXPECT_NEAR(whole.to_view({10.0, 20.0}).x, 10.5 * 0.5, 1e-12);
  EXPECT_NEAR(whole.u0(), 0.0, 1e-12);
  EXPECT_NEAR(whole.v1(), 1.0, 1e-12);
}

TEST(TemplateOverlay, LettersAlongTheBottomAndNumbersDownTheSide) {
  const TransverseScene& s = scene();
  const std::vector<GridLabel> labels = grid_labels(s.marks, 13, 13);
  ASSERT_EQ(labels.size(), 26u);
  auto find = [&](const std::string& t) {
    for (const GridLabel& l : labels)
      if (l.text == t) return l;
    ADD_FAILURE() << "no label " << t;
    return GridLabel{};
  };
  const GridLabel d = find("D"), a = find("a"), g = find("G"), one = find("1"), seven = find("7"), half = find("1.5");
  EXPECT_NEAR(d.at.x, mark_of("D1").x, 1e-6);
  EXPECT_NEAR(d.at.y - mark_of("D1").y, s.marks.pitch_px, 1e-6);  // one spacing below row 1
  EXPECT_NEAR(g.at.y, d.at.y, 1e-6);
  EXPECT_TRUE(d.whole);
  EXPECT_FALSE(a.whole);
  EXPECT_NEAR(one.at.y, mark_of("A1").y, 1e-6);
  EXPECT_NEAR(mark_of("A1").x - one.at.x, s.marks.pitch_px, 1e-6);  // one spacing left of column A
  EXPECT_NEAR(seven.at.y, mark_of("A7").y, 1e-6);
  EXPECT_FALSE(half.whole);
  EXPECT_TRUE(seven.whole);
}

TEST(TemplateOverlay, ThePlanSceneHasAPlannedNeedleInEachOfItsTwentyHoles) {
  const std::vector<PlannedHole> plan = planned_holes(scene().spec);
  ASSERT_EQ(plan.size(), 20u);
  // config/brachytherapy_plan_145gy.yaml: {hole: B3, col: 2, row: 4, depth_mm: 70.0, seeds_mm: [70.0, 65.0, 60.0, 55.0]}
  EXPECT_EQ(plan[0].label, "B3");
  EXPECT_EQ(plan[0].col, 2);
  EXPECT_EQ(plan[0].row, 4);
  EXPECT_EQ(plan[0].needle, 0);
  EXPECT_EQ(plan[0].needle_name, "B3");
  EXPECT_NEAR(plan[0].depth_mm, 70.0, 1e-6);
  ASSERT_EQ(plan[0].seeds_mm.size(), 4u);
  EXPECT_NEAR(plan[0].seeds_mm[0], 70.0, 1e-6);
  EXPECT_NEAR(plan[0].seeds_mm[3], 55.0, 1e-6);
  // every needle of the plan sits in the hole it is named after
  int seeds = 0;
  for (const PlannedHole& p : plan) {
    EXPECT_EQ(p.label, p.needle_name);
    seeds += static_cast<int>(p.seeds_mm.size());
  }
  EXPECT_EQ(seeds, 58);
  EXPECT_EQ(find_planned(plan, 4, 5), 6);  // C3.5
  EXPECT_EQ(find_planned(plan, 6, 0), -1);  // D1: not in the plan
  // the shipped single-needle scene: its `posterior` needle (start x 5, y -5, z -66 mm, to 75 mm)
  // runs 0.6 mm from hole c2.5's line (x 5, y -5.6 mm; the template at z -62 mm), its four seeds
  // 4 mm nearer the template than their depths from the needle's start
  const std::vector<PlannedHole> one = planned_holes(parse_scenario_file(kConfig + "brachytherapy.yaml"));
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].label, "c2.5");
  EXPECT_EQ(one[0].needle_name, "posterior");
  EXPECT_NEAR(one[0].depth_mm, 71.0, 1e-6);
  ASSERT_EQ(one[0].seeds_mm.size(), 4u);
  EXPECT_NEAR(one[0].seeds_mm[0], 68.0, 1e-6);
  EXPECT_NEAR(one[0].seeds_mm[3], 53.0, 1e-6);
}

TEST(TemplateOverlay, SeedsCountForTheHoleWhoseLineTheyLieOn) {
  const TransverseScene& s = scene();
  const double pitch = s.spec.probe->template_pitch;
  auto hole = [&](const std::string& label) {
    const auto cr = dosimetry::parse_template_hole(label, 13, 13);
    for (const TemplateHole& h : s.holes)
      if (h.col == cr->first && h.row == cr->second) return h;
    return TemplateHole{};
  };
  const TemplateHole c3 = hole("C3"), c35 = hole("C3.5");
  const Vec3 lateral = -s.probe.lateral.normalized();  // toward column A
  const Vec3 up = (c35.entry - c3.entry).normalized();
  const std::vector<Vec3> seeds = {
      c3.entry + 0.070 * c3.direction,                              // on C3's line
      c3.entry + 0.065 * c3.direction + 0.002 * up,                 // carried 2 mm up: still C3
      c3.entry + 0.060 * c3.direction + 0.003 * up,                 // 3 mm up: nearer C3.5
      c3.entry + 0.055 * c3.direction + 0.0026 * (up + lateral),    // 3.7 mm off diagonally: none
  };
  const std::vector<int> n = seeds_per_hole(s.holes, seeds, pitch);
  int i3 = -1, i35 = -1, total = 0;
  for (size_t k = 0; k < s.holes.size(); ++k) {
    if (s.holes[k].col == c3.col && s.holes[k].row == c3.row) i3 = static_cast<int>(k);
    if (s.holes[k].col == c35.col && s.holes[k].row == c35.row) i35 = static_cast<int>(k);
    total += n[k];
  }
  EXPECT_EQ(n[i3], 2);
  EXPECT_EQ(n[i35], 1);
  EXPECT_EQ(total, 3);
  EXPECT_EQ(hole_status(0, 3), HoleStatus::Pending);
  EXPECT_EQ(hole_status(2, 3), HoleStatus::Partial);
  EXPECT_EQ(hole_status(3, 3), HoleStatus::Done);
  EXPECT_STREQ(hole_status_name(HoleStatus::Partial), "partial");
  DrawList d;
  d.capsule(Vec3(0, 0, 0), Vec3(0, 0, 0.004), 0.4e-3, {}, DrawRole::Seed);
  d.capsule(Vec3(0, 0, 0), Vec3(0, 0, 0.1), 0.6e-3, {}, DrawRole::Needle);
  d.sphere(Vec3(0.01, 0, 0), 0.4e-3, {}, DrawRole::Seed);
  const std::vector<Vec3> drawn = drawn_seeds(d);
  ASSERT_EQ(drawn.size(), 2u);
  EXPECT_LT((drawn[0] - Vec3(0, 0, 0.002)).norm(), 1e-12);
}

TEST(TemplateOverlay, GridBurntIntoTheGrayImage) {
  const TransverseScene& s = scene();
  const int w = 384, h = 384;
  std::vector<uint8_t> gray(static_cast<size_t>(w) * h, 100);
  const std::vector<PlannedHole> plan = planned_holes(s.spec);
  draw_template_gray(gray, w, h, s.marks, 13, 13, plan);
  auto count = [&](const ImagePoint& c, int r, uint8_t v) {
    int n = 0;
    const int cx = static_cast<int>(std::lround(c.x)), cy = static_cast<int>(std::lround(c.y));
    for (int y = cy - r; y <= cy + r; ++y)
      for (int x = cx - r; x <= cx + r; ++x)
        if (x >= 0 && y >= 0 && x < w && y < h && gray[static_cast<size_t>(y) * w + x] == v) ++n;
    return n;
  };
  // the letter D under column D: white glyph pixels on a black outline
  for (const GridLabel& l : grid_labels(s.marks, 13, 13))
    if (l.text == "D" || l.text == "4") {
      EXPECT_GE(count(l.at, 5, 255), 8) << l.text;
      EXPECT_GE(count(l.at, 5, 0), 8) << l.text;
    }
  // a ring round the planned hole C3, none round D1 (not planned)
  EXPECT_GE(count(mark_of("C3"), 3, 255), 12);
  EXPECT_EQ(count(mark_of("D1"), 3, 255), 0);
}

}  // namespace
}  // namespace ps::frames
