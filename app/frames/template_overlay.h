// The brachytherapy template as the trainee reads it on the TRUS and in 3D (issue 46 item 1): the
// holes where their lines cross the transverse plane (the grid of dots a TRUS unit prints over the
// image), labelled as clinical templates are (engine/dosimetry/template_grid.h: columns A a B b ...
// G from the patient's right along the bottom, rows 1 1.5 ... 7 up from the probe down the side),
// picking the hole nearest an image click, the scene's planned needle of each hole and how far
// each is implanted. Pure geometry on plain data: the window (app/gui) draws it with ImGui, the
// headless frames (replay, `prostatesim ultrasound`) burn it into the PNG (draw_template_gray).
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/dosimetry/isodose.h"
#include "engine/draw/draw_sink.h"
#include "engine/spec/scenario_spec.h"

namespace ps::frames {

// One template hole's line at the template's current place.
struct TemplateHole {
  int col = 0, row = 0;
  Vec3 entry = Vec3::Zero();       // where the line leaves the template [m]
  Vec3 direction = Vec3::UnitZ();  // unit, into the patient (the probe axis)
};

// The holes of a cols x rows template as a snapshot's DrawList shows them: the spheres of role
// TemplateGrid at the hole entries (engine/tools/probe/probe_draw.cpp draws them row by row from
// row 0, columns from 0 within a row), lines along `axis` (the probe's). Empty when the list
// holds another number of them (no template, or a probe drawn otherwise).
std::vector<TemplateHole> template_holes_from_draw(const DrawList& draw, int cols, int rows, const Vec3& axis);

// A point of the image: continuous pixel coordinates, pixel centres at integers (x: column, y: row
// from the top), as dosimetry::PixelPlane places them.
struct ImagePoint {
  double x = 0.0, y = 0.0;
};

// Orthogonal projection of world point p [m] onto the plane, in its pixels; `off_plane_mm`, when
// given, gets the signed distance from the plane [mm].
ImagePoint plane_pixel(const dosimetry::PixelPlane& plane, const Vec3& p, double* off_plane_mm = nullptr);
// Where the line entry + s direction [m] crosses the plane, in its pixels; nullopt when the line
// runs parallel to it.
std::optional<ImagePoint> line_crossing_pixel(const dosimetry::PixelPlane& plane, const Vec3& entry, const Vec3& direction);

// The template as it shows on one transverse image: where each hole's line crosses the plane, and
// the hole spacing there [px].
struct HoleMarks {
  std::vector<TemplateHole> holes;
  std::vector<ImagePoint> at;      // [holes]
  double pitch_px = 0.0;           // distance between neighbouring holes on the image [px]
};
HoleMarks transverse_hole_marks(const dosimetry::PixelPlane& plane, const std::vector<TemplateHole>& holes);

// The hole whose mark is nearest to pixel (x, y), if it lies within half a hole spacing (a click
// between two holes, or off the grid, picks nothing): an index into marks.holes, or -1.
int pick_hole(const HoleMarks& marks, double x, double y);

// A square part of an n x n image shown in a square view of `side` screen units at `origin` (the
// window's TRUS panel zooms the transverse image onto the template, as a brachytherapy TRUS is
// set up: the grid then spans the view instead of a third of the sector).
struct ImageCrop {
  int n = 0;                       // image side [px]
  double x0 = 0.0, y0 = 0.0;       // top-left corner of the part shown, pixel coordinates (pixel centres at integers)
  double size = 0.0;               // its side [px]
  double ox = 0.0, oy = 0.0, side = 0.0;  // the view: top-left corner and side [screen units]
  ImagePoint to_view(const ImagePoint& p) const { return {ox + (p.x - x0) * side / size, oy + (p.y - y0) * side / size}; }
  ImagePoint to_image(double vx, double vy) const { return {x0 + (vx - ox) * size / side, y0 + (vy - oy) * size / side}; }
  // texture coordinates of the part's corners (0..1)
  double u0() const { return (x0 + 0.5) / n; }
  double v0() const { return (y0 + 0.5) / n; }
  double u1() const { return (x0 + size + 0.5) / n; }
  double v1() const { return (y0 + size + 0.5) / n; }
};
// The whole image in the view.
ImageCrop whole_image(int n, double ox, double oy, double side);
// The square around the template's marks with room for the labels (2 hole spacings left of
// column A for the row numbers, 1.6 below row 1 for the letters, 0.75 on the others), kept inside the image; the whole image when there are no
// marks or the square would not be smaller.
ImageCrop template_crop(const HoleMarks& marks, int n, double ox, double oy, double side);

// Where the labels go: each column's letter one hole spacing below its bottom hole (row 0, toward
// the probe), each row's number one spacing left of its first hole (column A, the patient's
// right, on the screen's left). `whole` is true for the capitals and whole numbers, false for the
// half-steps (a, b, ..., 1.5, 2.5, ...), which a small image may leave out.
struct GridLabel {
  std::string text;
  ImagePoint at;                   // centre of the label [px]
  bool whole = true;
};
std::vector<GridLabel> grid_labels(const HoleMarks& marks, int cols, int rows);

// The scene's planned needle of a template hole: a needle that carries seeds along a hole's line
// (its start within 1 mm of the line at the probe's start pose, its direction within 1 degree of
// the line's): a plan the scene read (`needles: {plan: ...}`, one needle named after each hole),
// or needles written through template holes by hand or by the scenario editor.
struct PlannedHole {
  int col = 0, row = 0;
  std::string label;               // "C3.5"
  int needle = -1;                 // index in the scene's needles
  std::string needle_name;
  double depth_mm = 0.0;           // the deepest point of its script past the template [mm]
  std::vector<double> seeds_mm;    // its seeds' depths past the template [mm], as listed (deepest first)
};
std::vector<PlannedHole> planned_holes(const ScenarioSpec& spec);
// index into `plan` of hole (col, row), -1 when it has no planned needle
int find_planned(const std::vector<PlannedHole>& plan, int col, int row);

// Seeds deposited through each hole: every seed centre [m] counts for the hole whose line passes
// nearest to it, if that is within half a hole spacing (`pitch` [m]); the result has one count per
// hole. Seeds are where the tissue carries them now, so one pushed more than half a spacing
// sideways counts for a neighbour or for none.
std::vector<int> seeds_per_hole(const std::vector<TemplateHole>& holes, const std::vector<Vec3>& seeds, double pitch);
// The seed centres [m] of a snapshot's DrawList (capsules and spheres of role Seed).
std::vector<Vec3> drawn_seeds(const DrawList& draw);

enum class HoleStatus : uint8_t { Pending, Partial, Done };
// Done once as many seeds as planned are in (none planned: done with any), Partial with some.
HoleStatus hole_status(int deposited, int planned);
const char* hole_status_name(HoleStatus s);  // "pending", "partial", "done"

// The colour of the plan's holes and needles (green: apart from the isodose lines' blue, red,
// yellow and magenta, us_isodose.h).
inline constexpr std::array<uint8_t, 3> kPlanRgb = {80, 230, 120};

// Burns the grid into a grayscale image (rows top-down, w x h), over the imager's crosses at the
// holes (engine/ultrasound/imager.cpp): a ring of radius 3 px round each planned hole's cross, and
// the labels of grid_labels() in the bitmap font of the charts (app/plot/canvas.h), the whole ones
// always and the half-steps when the hole spacing leaves room for them. Labels are white on a
// dark 1 px outline, so they read on speckle.
void draw_template_gray(std::vector<uint8_t>& gray, int w, int h, const HoleMarks& marks, int cols, int rows,
                        const std::vector<PlannedHole>& plan);
// The same into an RGB image (w x h x 3); planned holes in the plan colour.
void draw_template_rgb(std::vector<uint8_t>& rgb, int w, int h, const HoleMarks& marks, int cols, int rows,
                       const std::vector<PlannedHole>& plan);

}  // namespace ps::frames
