// Images in memory and their PNG files.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

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

/// The PNG's bit depth and colour type (IHDR, the first chunk: bytes 24 and 25 of the file).
std::pair<int, int> png_depth_and_type(const std::string& bytes) {
  EXPECT_GE(bytes.size(), 26u);
  if (bytes.size() < 26) return {0, 0};
  return {static_cast<unsigned char>(bytes[24]), static_cast<unsigned char>(bytes[25])};
}

/// An image of `colours` distinct opaque colours, in runs and scattered.
Image image_of_colours(int colours) {
  Image image = make_image(61, 47, {0, 0, 0});
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const auto c = static_cast<std::uint32_t>((i * 7 / 5) % static_cast<std::size_t>(colours));
    image.pixels[i] = 0xFF000000u | (c * 0x010307u & 0xFFFFFFu);
  }
  return image;
}

Image png_round_trip(const Image& image, const std::string& name) {
  const auto path = testing::render_tmp_dir() / name;
  write_png(path.string(), image);
  return read_png(path.string());
}

// Few colours: a palette image at the smallest bit depth that holds them (1 bit for the
// checkerboard texture), the pixels given back exactly; more colours: RGB as Cairo writes it,
// with alpha where a pixel is translucent, also exact.
TEST(Image, PngWithFewColoursIsAPaletteImageAndRoundTrips) {
  for (const auto& [colours, depth] : std::vector<std::pair<int, int>>{{1, 1},
                                                                       {2, 1},
                                                                       {3, 2},
                                                                       {4, 2},
                                                                       {5, 4},
                                                                       {16, 4},
                                                                       {17, 8},
                                                                       {256, 8},
                                                                       {257, 8},
                                                                       {1000, 8}}) {
    SCOPED_TRACE(colours);
    const Image image = image_of_colours(colours);
    const std::string bytes = encode_png(image);
#ifdef RICCI_HAVE_LIBPNG
    const int type = colours <= 256 ? 3 : 2;  // palette, or RGB
    EXPECT_EQ(png_depth_and_type(bytes), std::make_pair(depth, type));
#endif
    const Image back = png_round_trip(image, "colours.png");
    EXPECT_EQ(back.width, image.width);
    EXPECT_EQ(back.pixels, image.pixels);
  }
  Image translucent = image_of_colours(2);
  translucent.pixels[3] = 0x80402010u;  // premultiplied: half transparent
  EXPECT_EQ(png_depth_and_type(encode_png(translucent)).second, 6);
  EXPECT_EQ(png_round_trip(translucent, "translucent.png").pixels, translucent.pixels);
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
