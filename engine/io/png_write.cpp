#include "engine/io/png_write.h"

#include <stb_image_write.h>

#include <string_view>

#include "engine/util/atomic_file.h"
#include "engine/util/error.h"

namespace ps {
namespace {

void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  const auto* bytes = static_cast<const uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

// 16384 px a side is far beyond any frame or report and keeps w*h*c inside int for stb.
constexpr int kMaxSide = 16384;

}  // namespace

std::vector<uint8_t> encode_png(int width, int height, int channels, const uint8_t* pixels) {
  if (width <= 0 || height <= 0 || width > kMaxSide || height > kMaxSide)
    throw InputError("", 0, "size",
                     "image size " + std::to_string(width) + "x" + std::to_string(height) +
                         " is outside 1.." + std::to_string(kMaxSide));
  if (channels != 1 && channels != 3 && channels != 4)
    throw InputError("", 0, "channels", "PNG needs 1, 3 or 4 channels, got " +
                                            std::to_string(channels));
  if (pixels == nullptr) throw InputError("", 0, "pixels", "no pixel data");
  std::vector<uint8_t> out;
  out.reserve(static_cast<size_t>(width) * height * channels / 2 + 1024);
  if (stbi_write_png_to_func(append_bytes, &out, width, height, channels, pixels,
                             width * channels) == 0)
    throw InputError("", 0, "pixels", "PNG encoding failed");
  return out;
}

void write_png_atomic(const std::string& path, int width, int height, int channels,
                      const uint8_t* pixels) {
  std::vector<uint8_t> bytes;
  try {
    bytes = encode_png(width, height, channels, pixels);
  } catch (const InputError& e) {
    throw InputError(path, 0, e.field(), e.what());
  }
  try {
    write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(bytes.data()),
                                             bytes.size()));
  } catch (const std::exception& e) {
    throw InputError(path, 0, "", e.what());
  }
}

}  // namespace ps
