// Headless frames of a run: renders each published Snapshot through the same renderer as the
// window (render/renderer.h) into an offscreen framebuffer (EGL surfaceless, OSMesa fallback),
// hands the pixels to a PNG writer thread, and at the end writes the event log, the
// force-versus-depth samples, a summary and a contact sheet (a few frames and the
// force-versus-depth plot in one PNG). Output layout in DIR:
//   <view>/frame_000000.png ...   one folder per view (3d, anterior, lateral, probe, needle;
//                                 us_transverse, us_sagittal: 8-bit grayscale simulated TRUS,
//                                 RGB with the isodose lines when the scene has seeds)
//   events.log                    one line per event (time, tool, what, depth, force)
//   force_depth.csv               every tick of the active needle: t_s, depth_mm, force_n
//   summary.json                  frames, views, size, timings, event count, fault
//   contact_sheet.png             four frames of the first view and the force-versus-depth plot
// Deterministic: the same snapshots give the same PNG bytes (no clock in the pixels).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "app/frames/frame_options.h"
#include "app/frames/snapshot_dose.h"
#include "app/frames/template_overlay.h"
#include "engine/contract/snapshot.h"
#include "engine/ultrasound/anatomy.h"
#include "engine/ultrasound/settings.h"

namespace ps {
struct Model;
}

namespace ps::frames {

// What the ultrasound views need (opt.us_views): the scene's imaged anatomy and scanner settings.
struct UltrasoundInput {
  us::UltrasoundAnatomy anatomy;
  us::UltrasoundSettings settings;
  // a probe with a brachytherapy template (0 x 0: none): its labelled grid and the scene's planned
  // holes are burnt into the transverse frames (template_overlay.h)
  int template_cols = 0, template_rows = 0;
  std::vector<PlannedHole> plan;
};

struct FrameSummary {
  int frames = 0;                 // frames per view
  int files = 0;                  // PNG frames written
  double render_ms_median = 0.0;  // render + read-back per view [ms]
  double render_ms_max = 0.0;
  std::string backend, gl_renderer;
};

class FrameRecorder {
 public:
  // Creates the GL context, then prepares the output folder (prepare_output_dir: InputError when
  // it is not empty without force, or not writable), then the renderer. Throws
  // render::RenderError when no headless GL is available (nothing written then). `us` is needed
  // (InputError otherwise) when opt.us_views is not empty; its settings are validated first.
  // `dose` (a scene with seeds): the 3D views show the prescription isodose surface and the
  // ultrasound planes the 50/100/150/200 % isodose lines once a seed is in (snapshot_dose.h).
  FrameRecorder(const Model& model, FrameOptions opt, const UltrasoundInput* us = nullptr,
                std::unique_ptr<SnapshotDose> dose = nullptr);
  ~FrameRecorder();

  // Every tick (or every snapshot read): logs its events and samples the active needle's depth
  // and force for the plot and force_depth.csv.
  void observe(const Snapshot& snap);
  // Renders and queues one frame of every view (the ultrasound planes from the snapshot only:
  // probe pose, needles and seeds from its DrawList, positions from its x).
  void add_frame(const Snapshot& snap);
  // Prints the progress bar line (stderr) for frame i of n.
  void progress(int i, int n, double sim_time) const;
  // Waits for the PNGs and writes events.log, force_depth.csv, contact_sheet.png and
  // summary.json (with `extra` JSON members merged in, e.g. the scenario and fault).
  FrameSummary finish(const std::string& extra_json = "{}");

  const std::string& backend() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace ps::frames
