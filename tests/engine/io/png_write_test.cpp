#include "engine/io/png_write.h"

#include <gtest/gtest.h>
#include <stb_image.h>

#include <filesystem>

#include "engine/util/error.h"

namespace ps {
namespace {

TEST(PngWrite, RoundTripsRgbPixelsTopDown) {
  const int w = 5, h = 3;
  std::vector<uint8_t> px(w * h * 3);
  for (int i = 0; i < w * h * 3; ++i) px[i] = static_cast<uint8_t>(i * 7);
  const auto bytes = encode_png(w, h, 3, px.data());
  int rw = 0, rh = 0, rc = 0;
  uint8_t* back = stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &rw, &rh, &rc, 3);
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(rw, w);
  EXPECT_EQ(rh, h);
  EXPECT_TRUE(std::equal(px.begin(), px.end(), back));
  stbi_image_free(back);
}

TEST(PngWrite, RefusesBadSizeAndUnwritablePathLeavingNothing) {
  std::vector<uint8_t> px(4, 0);
  EXPECT_THROW(encode_png(0, 1, 1, px.data()), InputError);
  EXPECT_THROW(encode_png(100000, 1, 1, px.data()), InputError);
  EXPECT_THROW(encode_png(2, 2, 2, px.data()), InputError);
  const std::string bad = "/nonexistent_dir_for_png_test/x.png";
  EXPECT_THROW(write_png_atomic(bad, 2, 2, 1, px.data()), InputError);
  EXPECT_FALSE(std::filesystem::exists(bad));
}

TEST(PngWrite, WritesAFileAtomically) {
  const auto dir = std::filesystem::temp_directory_path() / "ps_png_write_test";
  std::filesystem::create_directories(dir);
  const auto path = (dir / "a.png").string();
  std::vector<uint8_t> px(16, 200);
  write_png_atomic(path, 4, 4, 1, px.data());
  EXPECT_GT(std::filesystem::file_size(path), 8u);
  size_t files = 0;
  for (auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);  // no temp file left beside it
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ps
