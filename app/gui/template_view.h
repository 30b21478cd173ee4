// The brachytherapy template as the trainee window keeps it between frames (issue 46 item 1): the
// holes where the newest snapshot draws them (they ride on the stepper), the scene's planned needle
// of each hole and the seeds already in through each (app/frames/template_overlay.h), and picking a
// hole, the same from the needle panel's list, its plan list, a click on the transverse image.
#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "app/frames/template_overlay.h"
#include "engine/contract/snapshot.h"

struct ImDrawList;

namespace ps {
struct Scene;
}

namespace ps::gui {

class Session;

struct TemplateView {
  const Scene* for_scene = nullptr;
  int cols = 0, rows = 0;
  double pitch = 0.0;                        // hole spacing [m]
  std::vector<frames::PlannedHole> plan;     // the scene's planned needles (once per scene)
  std::vector<frames::TemplateHole> holes;   // at the newest snapshot's stepper; empty: no template
  std::vector<int> seeds;                    // [holes] seeds deposited through each
  int64_t tick = -1;                         // the snapshot they are from

  // Brings it up to date with the snapshot (once per tick; a new scene re-reads its plan).
  void update(const Session& s, const Snapshot& snap);
  bool has_template() const { return !holes.empty(); }
  int index(int col, int row) const;         // into holes, -1 when absent
  int seeds_in(int col, int row) const;
  // The planned needle of hole (col, row), or null.
  const frames::PlannedHole* planned(int col, int row) const;
  frames::HoleStatus status(const frames::PlannedHole& p) const;
};

// Drawing with ImGui (template_draw.cpp), in screen coordinates; (col, row) is the picked hole
// (-1: none).
//  - over the transverse image shown through `crop`: the column letters along the bottom and the
//    row numbers down the side (the half-steps smaller, when the spacing leaves room), the plan's
//    holes by status (pending: a green ring, partial: an amber ring, done: a filled grey disc; a hole
//    with seeds and no plan: a small cyan disc), the picked hole in a white ring;
void draw_transverse_template(ImDrawList* dl, const TemplateView& g, const frames::HoleMarks& marks, const frames::ImageCrop& crop,
                              int col, int row);
//  - over the sagittal image: the picked hole's planned needle when its line lies within half a
//    hole spacing of the plane (dashed from the template to the planned depth, the planned seeds as
//    dots, a tick and the depth at the planned depth), else how far off the plane the hole is;
void draw_sagittal_plan(ImDrawList* dl, const TemplateView& g, const dosimetry::PixelPlane& plane, const frames::ImageCrop& view,
                        int col, int row);
//  - in the 3D view (`vp`: the camera's projection x view; viewport at (x, y), w x h): the labels
//    beside the template's edge holes and each planned needle from its hole to its planned depth
//    with its seeds, coloured by status, the picked hole's brighter.
void draw_template_3d(ImDrawList* dl, const TemplateView& g, const Eigen::Matrix4f& vp, float x, float y, float w, float h, int col,
                      int row);

}  // namespace ps::gui
