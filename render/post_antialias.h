// Antialiasing of rendered frames: multisampling in GL, or a post pass on the CPU.
//
// On a software rasteriser (llvmpipe) 4x multisampling doubles the CPU of a frame: depth test,
// blend and clear run per sample, and the resolve is a full-screen pass. A GL post pass is no
// better there (nine texture fetches per pixel cost llvmpipe ~16 ms at 720p). So headless frames
// on a software rasteriser are drawn with one sample per pixel and antialiased here, on the CPU,
// on the thread that encodes them (docs/rendering.md). The window keeps multisampling.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace ps::render {

enum class Antialias : uint8_t {
  Auto,  // Msaa on a hardware GL, Fxaa on a software rasteriser
  Msaa,  // 4 samples per pixel, resolved in GL
  Fxaa,  // one sample per pixel, then fxaa_rgb()
  None,
};

// "auto", "msaa", "fxaa", "none"; false for anything else.
bool parse_antialias(const std::string& s, Antialias& out);
const char* antialias_name(Antialias a);
// True for Mesa's software rasterisers (llvmpipe, softpipe, swrast) by their GL_RENDERER string.
bool is_software_renderer(const std::string& gl_renderer);
// Auto resolved for a GL_RENDERER string; any other value is returned as it is.
Antialias resolve_antialias(Antialias a, const std::string& gl_renderer);

// Fast approximate antialiasing of an RGB image, after the edge search of T. Lottes' FXAA 3
// "quality": 3 bytes per pixel, rows top-down, from `src` into `dst` (w h 3 bytes each, distinct).
// Where the luma of a pixel and its 4 neighbours varies by less than max(1/16, 1/8 of the local
// maximum) the pixel is copied. Elsewhere the second differences tell whether the edge runs along
// x or y; a walk along it (up to 22 px each way) finds where it ends, and the pixel is resampled
// across the edge by its distance to the nearer end, which for a straight edge is the pixel's
// area coverage. Isolated pixels (sub-pixel detail) are softened by how far they stand out from
// their 3x3 mean. Deterministic; `luma` is scratch (resized; kept by the caller so a replay does
// not allocate per frame).
void fxaa_rgb(const uint8_t* src, int w, int h, uint8_t* dst, std::vector<uint8_t>& luma);

}  // namespace ps::render
