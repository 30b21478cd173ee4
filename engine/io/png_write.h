// PNG output shared by every picture the program writes (frames, plots, ultrasound, reports).
// Encoding is Debian's stb_image_write (libstb); the file is written atomically (temp + rename),
// so a crash never leaves a half-written PNG.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace ps {

// pixels: width*height*channels bytes, rows top-down, channels 1 (gray), 3 (RGB) or 4 (RGBA).
// Throws ps::InputError naming the path when the size is invalid or the file cannot be written.
void write_png_atomic(const std::string& path, int width, int height, int channels,
                      const uint8_t* pixels);

// The encoded PNG bytes (for writers that batch files or hash images).
std::vector<uint8_t> encode_png(int width, int height, int channels, const uint8_t* pixels);

}  // namespace ps
