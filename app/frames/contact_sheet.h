// The run at a glance: one PNG with four frames (start, two in between, end) above the
// force-versus-depth plot of the active needle with its punctures marked; in a scene without a
// needle, the plot of what its instruments did over time (the bladder's volume as it fills, or
// the probe's contact force), and no plot at all when there is none.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace ps::frames {

struct Thumb {
  int w = 0, h = 0;
  std::vector<uint8_t> rgb;        // rows top-down
  double time = 0.0;               // simulation time of the frame [s]
};

// Box-filtered copy of an RGB image at `width` pixels wide (aspect kept).
Thumb make_thumb(const std::vector<uint8_t>& rgb, int w, int h, int width, double time);

struct ContactSheetInput {
  std::string title;
  std::vector<Thumb> thumbs;                        // up to 4
  std::vector<double> depth_mm, force_n;            // active needle samples
  std::vector<std::pair<double, double>> marks;     // (depth mm, force N): punctures, bone, core
  // without needle samples: one instrument readout against time (empty: no plot)
  struct OverTime {
    std::string what, y_label;                      // "filled volume", "target volume of the filled organ [ml]"
    std::vector<double> t_s, y;
  } over_time;
};

// Writes the sheet atomically (throws InputError on failure).
void write_contact_sheet(const std::string& path, const ContactSheetInput& in);

}  // namespace ps::frames
