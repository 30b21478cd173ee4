// Isodose lines over the simulated TRUS planes (issue 46): each plane's pixel raster placed in
// the world (from the imager's plane frame for the probe's pose), the lines of 50/100/150/200 %
// of the prescription traced on it (engine/dosimetry/isodose.h), and drawn into an RGB copy of
// the grayscale image for the replay frames (the window draws the same segments with ImGui).
// Colours: 50 % blue, 100 % (prescription) red, 150 % yellow, 200 % magenta.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "engine/dosimetry/isodose.h"
#include "engine/ultrasound/imager.h"

namespace ps::frames {

inline constexpr std::array<std::array<uint8_t, 3>, 4> kIsodoseRgb = {{{70, 150, 255}, {255, 40, 40}, {255, 220, 0}, {255, 80, 255}}};

// The plane's pixel (col, row) centres in the world [mm].
dosimetry::PixelPlane pixel_plane(const us::PlaneImager& imager, const us::ProbeView& probe);
// The levels drawn [Gy]: kIsodoseLevels x the prescription.
std::vector<double> isodose_levels_gy(double prescription_gy);
// The isodose segments of the plane (sampled every 2 px).
void plane_isodose_lines(const dosimetry::DoseField& f, const dosimetry::PixelPlane& plane, std::vector<dosimetry::IsoSegment>& out);
// rgb = the gray image (w x h) in colour, with the segments drawn 2 px wide.
void draw_isodose_rgb(const std::vector<uint8_t>& gray, int w, int h, const std::vector<dosimetry::IsoSegment>& segs,
                      std::vector<uint8_t>& rgb);

}  // namespace ps::frames
