// Picking and dragging lesions, targets and needle targets in the editor's 3D view (issue 13):
// the window (editor_window.cpp) feeds this the mouse (press, motion, release, in ImGui pixels)
// and its camera; tests feed it the same events. A drag moves the picked handle in the view
// plane through it (camera right and up, scaled so the handle stays under the pointer at its
// depth); on release the move, rounded to whole mm, goes through EditorCommands (move_region /
// set_needle_target), so it is validated, undoable and saved like a typed value.
#pragma once
#include <string>
#include <vector>

#include "app/editor/editor_commands.h"
#include "render/camera.h"

namespace ps::editor {

// The 3D view's rectangle in window pixels (ImGui: x right, y down from the window's top).
struct ViewRect {
  float x = 0, y = 0, w = 1, h = 1;
};

// What the 3D view shows beside the tissue and can drag: a lesion / target region, or a needle's
// target point.
struct Handle {
  enum Kind { Region, Target } kind = Region;
  std::string name;                // tag or needle
  Vec3 pos_mm = Vec3::Zero();
  double radius_mm = 0.0;
  bool lesion = false;
};
std::vector<Handle> handles(const EditorCommands& c);

// Window pixel of a world point [m]; false behind the camera. px_per_m: pixels per metre at the
// point's depth.
bool project(const render::Camera& cam, const ViewRect& v, const Vec3& x_m, float& px, float& py, float* px_per_m = nullptr);

// The world move [mm] of a point at `at_mm` for a pointer motion of (dx, dy) pixels (y down):
// in the view plane through the point, one pixel = the view's height in metres at its depth / h.
Vec3 drag_move_mm(const render::Camera& cam, const ViewRect& v, const Vec3& at_mm, float dx, float dy);

class ViewDrag {
 public:
  // Pointer pressed at (mx, my): picks the nearest handle within its drawn circle (at least
  // kPickPx). True when one was picked (the caller orbits otherwise).
  bool press(const EditorCommands& c, const render::Camera& cam, const ViewRect& v, float mx, float my);
  // Pointer moved by (dx, dy) pixels while held.
  void move(const EditorCommands& c, const render::Camera& cam, const ViewRect& v, float dx, float dy);
  // Pointer released: the accumulated move, rounded to whole mm, through the command path (noted
  // in errs under the handle's key). ok=false without an edit when nothing was dragged.
  EditResult release(EditorCommands& c, FieldErrors& errs);

  bool dragging() const { return dragging_; }
  const std::string& selected() const { return selected_; }
  Handle::Kind selected_kind() const { return kind_; }
  void select(const std::string& name, Handle::Kind k) { selected_ = name; kind_ = k; }
  const Vec3& offset_mm() const { return offset_mm_; }  // of the dragged handle, so far

  static constexpr float kPickPx = 18.0f;

 private:
  bool dragging_ = false;
  std::string selected_;
  Handle::Kind kind_ = Handle::Region;
  Vec3 offset_mm_ = Vec3::Zero();
};

}  // namespace ps::editor
