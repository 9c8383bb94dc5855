#pragma once
/// \file
/// Raster pictures in memory and their PNG and SVG files. Pixels use Cairo's ARGB32 layout, so
/// that the renderer, Cairo's drawing and the PNG writer share one buffer without conversion.

#include <cstdint>
#include <string>
#include <vector>

namespace ricci {

/// A colour with components in [0, 1].
struct Rgb {
  double r = 0, g = 0, b = 0;
};

/// An opaque ARGB32 pixel (alpha 255) of a colour; components are clamped to [0, 1] and rounded.
std::uint32_t pack_rgb(const Rgb& colour);

/// The colour of a pixel (alpha ignored: the pictures ricci draws are opaque).
Rgb unpack_rgb(std::uint32_t pixel);

/// A raster picture.
struct Image {
  int width = 0;   ///< pixels
  int height = 0;  ///< pixels
  /// width * height pixels, row by row from the top, each 0xAARRGGBB with premultiplied alpha
  /// (Cairo's CAIRO_FORMAT_ARGB32 in native byte order; its stride is 4 width bytes).
  std::vector<std::uint32_t> pixels;

  /// The pixel in column x, row y (0, 0 is the top left corner). \pre 0 <= x < width, 0 <= y <
  /// height
  std::uint32_t at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
};

/// A picture of the given size filled with one colour.
/// \throw InvalidInput when width or height is outside [1, 16384]
Image make_image(int width, int height, const Rgb& fill);

/// Writes an image as PNG, atomically (write_file_atomically).
/// \throw InvalidInput when the image is empty or its pixel count differs from width * height
/// \throw IoError naming the file when Cairo cannot encode it or the file cannot be written
void write_png(const std::string& path, const Image& image);

/// The PNG file's bytes of an image (what write_png writes).
/// \throw InvalidInput as write_png; IoError when Cairo cannot encode it
std::string encode_png(const Image& image);

/// Reads a PNG file (any PNG that Cairo reads; RGB files come back with alpha 255).
/// \throw IoError naming the file when it is missing or not a PNG Cairo can read
Image read_png(const std::string& path);

/// Writes SVG text (from the plot_*_svg functions) to a file, atomically.
/// \throw IoError naming the file when it cannot be written
void write_svg(const std::string& path, const std::string& svg);

}  // namespace ricci
