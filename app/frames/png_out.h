// One PNG written atomically. Forwards to engine/io/png_write.h (write_png_atomic) once that is
// on main; until then the same contract here (stb encoder, temp + rename, InputError on failure).
#pragma once
#include <cstdint>
#include <string>

namespace ps::frames {

void write_png(const std::string& path, int width, int height, int channels, const uint8_t* pixels);

}  // namespace ps::frames
