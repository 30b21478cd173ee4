#include "app/frames/png_out.h"

#include <stb_image_write.h>

#include <string>

#include "engine/util/atomic_file.h"
#include "engine/util/error.h"

namespace ps::frames {

void write_png(const std::string& path, int w, int h, int channels, const uint8_t* pixels) {
  std::string bytes;
  auto sink = [](void* ctx, void* data, int size) { static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), size); };
  if (!stbi_write_png_to_func(sink, &bytes, w, h, channels, pixels, w * channels))
    throw InputError(path, 0, "", "PNG encoding failed");
  try {
    write_file_atomic(path, bytes);
  } catch (const std::exception& e) {
    throw InputError(path, 0, "", std::string("cannot write: ") + e.what());
  }
}

}  // namespace ps::frames
