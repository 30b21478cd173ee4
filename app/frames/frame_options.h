// Options of the headless frame writer (`prostatesim replay ... --out DIR`), and their checks:
// every bad value is refused before anything is written (InputError naming the option).
#pragma once
#include <string>
#include <vector>

#include "engine/anatomy/display_meshes.h"
#include "engine/ultrasound/imager.h"
#include "render/camera.h"
#include "render/post_antialias.h"

namespace ps::frames {

inline constexpr int kMaxImageSide = 8192;   // [px]

struct FrameOptions {
  std::string out_dir;
  int width = 1280, height = 720;            // [px]
  double fps = 30.0;                         // frames per simulated second
  std::vector<render::View> views{render::View::Orbit};
  std::vector<us::PlaneKind> us_views;       // simulated TRUS planes (us_transverse, us_sagittal)
  int us_size = 512;                         // ultrasound frames are square [px]
  bool force = false;                        // allow a non-empty out_dir (our files replaced)
  // auto: 4x multisampling on a hardware GL; on a software rasteriser one sample per pixel and
  // FXAA on the encoder thread: 12 instead of 31 ms of the render thread per 720p frame on
  // llvmpipe (render/post_antialias.h, docs/rendering.md)
  render::Antialias antialias = render::Antialias::Auto;
  bool displacement = false;                 // colour by displacement [mm]
  double displacement_max_mm = 5.0;
  bool progress = true;                      // progress bar on stderr
  int expected_frames = 0;                   // for the progress bar and the contact sheet
  // shapes drawn but not simulated (seminal vesicles, pubic bone): anatomy::display_meshes_for_scenario()
  std::vector<anatomy::DisplayMesh> shapes;
};

// "1280x720" -> width, height in 1..kMaxImageSide. Throws InputError (field --size).
void parse_size(const std::string& s, int& width, int& height);
// "3d,lateral,us_sagittal" -> views (3D views and, when `us` is given, ultrasound planes); unknown
// names throw InputError (field --views) listing the known ones. At least one view.
std::vector<render::View> parse_views(const std::string& s, std::vector<us::PlaneKind>* us = nullptr);
const char* us_view_name(us::PlaneKind k);  // "us_transverse" / "us_sagittal"
// "auto", "msaa", "fxaa" or "none". Throws InputError (field --aa) listing them.
render::Antialias parse_antialias_option(const std::string& s);
// Refuses a non-empty folder unless `force`, creates it, checks it is writable (a probe file
// written and removed). With force, removes the files a previous replay wrote there (and only
// those). Throws InputError (field --out).
void prepare_output_dir(const std::string& dir, bool force);

}  // namespace ps::frames
