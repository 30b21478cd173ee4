// Scanner settings of the simulated biplane TRUS probe (issue 12): the knobs a user turns (gain,
// depth, frequency, dynamic range, TGC) and the transducer geometry (transverse convex array
// radius and field of view, sagittal linear array width and position, slice thickness).
// Defaults follow a clinical biplane TRUS probe (B-K 8848 class: 10 mm convex radius, ~140 deg
// transverse sector, 60 mm linear array, 7.5 MHz); the convex radius defaults to the radius of the
// probe description (ProbeSpec::radius) when the settings are made from it.
#pragma once
#include <string>

#include "engine/spec/scenario_spec.h"

namespace ps::us {

struct UltrasoundSettings {
  // --- user knobs ---
  double frequency = 7.5e6;            // centre frequency [Hz]: speckle size ~ wavelength, attenuation ~ f
  double gain_db = 0.0;                // overall gain [dB]
  double depth = 0.060;                // imaging depth from the array surface [m]
  double dynamic_range_db = 60.0;      // log-compression window [dB]
  double tgc_db_cm_mhz = 0.6;          // time-gain compensation slope, one way [dB/(cm MHz)]
  // --- transducer geometry ---
  double convex_radius = 0.010;        // transverse convex array radius [m]
  double fov = 2.443460952792061;      // transverse sector angle [rad] (140 deg)
  double transverse_back = 0.0;        // transverse plane behind the probe's tip-hemisphere centre [m]
  double linear_width = 0.060;         // sagittal linear array length [m]
  double linear_front = 0.0;           // front end of the linear array behind the tip centre [m]
  double slice_thickness = 1.5e-3;     // elevation beam width, FWHM [m]
  // --- point-spread function (imager.h: axial from the pulse, lateral from aperture and focus) ---
  // Pulse-echo -6 dB fractional bandwidth: 18 % gives a 0.50 mm axial envelope FWHM at 7.5 MHz.
  // A finer axial grain aliases on the 512 px transverse image (0.26 mm/px over the 140 degree
  // sector): at 25-30 % the capsule's line breaks up there and a sub-pixel tissue motion
  // decorrelates the speckle (imager_test.cpp), so both planes keep this grain in millimetres.
  double bandwidth = 0.18;             // [-]
  double focus_depth = 0.030;          // transmit focus below the array surface [m]
  double f_number = 3.0;               // transmit f-number (focal depth / aperture) [-]
  // Receive aperture: a 10 mm radius convex array has only a few millimetres of elements facing a
  // point; with dynamic focus (f-number >= 2.5) the lateral PSF is 0.64 mm at 18 mm and 1.19 mm at
  // 45 mm, wider than the axial one below the focus, so the grain is elongated across the beam as
  // on a clinical image.
  double rx_aperture = 0.005;          // receive aperture (dynamic receive focus, f-number >= 2.5) [m]
  // --- output ---
  int width = 512, height = 512;       // pixels per plane
  bool overlays = true;                // biopsy guide line (sagittal) and template grid (transverse)
  bool lesion_contours = true;         // lesions as a fused MRI contour at their current position
};

// Defaults with the convex radius of the probe description.
UltrasoundSettings settings_for_probe(const ProbeSpec& probe);

// Throws InputError(file, 0, "ultrasound.<field>", ...) naming the first nonsensical field:
// non-finite values, frequency outside 1-20 MHz, gain outside +-60 dB, depth outside 10-150 mm,
// dynamic range outside 20-100 dB, TGC outside 0-3 dB/(cm MHz), convex radius outside 3-50 mm,
// field of view outside 10-180 deg, linear width outside 10-120 mm, slice thickness outside
// 0.1-10 mm, image size outside 16-4096 pixels, negative array offsets.
void validate(const UltrasoundSettings& s, const std::string& file = "");

}  // namespace ps::us
