// Images in memory and their PNG files.

#include <gtest/gtest.h>

#include <filesystem>

#include "render_test_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/render/image.hpp"

namespace ricci {
namespace {

TEST(Image, PackAndUnpackRoundTripOnBytes) {
  const std::uint32_t p = pack_rgb({1.0, 0.5, 0.0});
  EXPECT_EQ(p, 0xFFFF8000u);  // 0.5 * 255 = 127.5 rounds to 128
  const Rgb c = unpack_rgb(p);
  EXPECT_DOUBLE_EQ(c.r, 1.0);
  EXPECT_DOUBLE_EQ(c.g, 128 / 255.0);
  EXPECT_DOUBLE_EQ(c.b, 0.0);
  EXPECT_EQ(pack_rgb({-1, 2, std::nan("")}), 0xFF00FF00u);  // clamped, NaN as 0
}

TEST(Image, PngRoundTripKeepsSizeAndPixels) {
  Image image = make_image(37, 23, {0.2, 0.4, 0.6});
  image.pixels[5 * 37 + 7] = pack_rgb({1, 0, 0});
  const auto path = testing::render_tmp_dir() / "round_trip.png";
  std::filesystem::remove(path);
  write_png(path.string(), image);
  ASSERT_TRUE(std::filesystem::exists(path));
  const Image back = read_png(path.string());
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 23);
  EXPECT_EQ(back.pixels, image.pixels);
  EXPECT_EQ(back.at(7, 5), pack_rgb({1, 0, 0}));
  // No temporary file is left beside it.
  for (const auto& entry : std::filesystem::directory_iterator(path.parent_path())) {
    EXPECT_EQ(entry.path().filename().string().find(".round_trip.png.tmp"), std::string::npos);
  }
}

TEST(Image, RejectsBadSizesAndMissingFiles) {
  EXPECT_THROW(make_image(0, 10, {}), InvalidInput);
  EXPECT_THROW(make_image(10, 20000, {}), InvalidInput);
  Image broken;
  broken.width = 4;
  broken.height = 4;
  broken.pixels.resize(3);
  EXPECT_THROW(write_png((testing::render_tmp_dir() / "broken.png").string(), broken),
               InvalidInput);
  const auto missing = testing::render_tmp_dir() / "does_not_exist.png";
  try {
    read_png(missing.string());
    FAIL() << "read_png accepted a missing file";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("does_not_exist.png"), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_png((testing::render_tmp_dir() / "no_such_dir" / "x.png").string(),
                         make_image(2, 2, {})),
               IoError);
}

}  // namespace
}  // namespace ricci
