#include "ricci/render/image.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "cairo_support.hpp"
#include "render/detail/indexed_png.hpp"
#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"

namespace ricci {
namespace {

std::uint32_t to_byte(double component) {
  if (!(component > 0)) return 0;  // NaN too
  return static_cast<std::uint32_t>(std::lround(std::min(component, 1.0) * 255.0));
}

cairo_status_t write_to_stream(void* closure, const unsigned char* data, unsigned int length) {
  auto& out = *static_cast<std::ostream*>(closure);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(length));
  return out ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

}  // namespace

std::uint32_t pack_rgb(const Rgb& colour) {
  return 0xFF000000u | (to_byte(colour.r) << 16) | (to_byte(colour.g) << 8) | to_byte(colour.b);
}

Rgb unpack_rgb(std::uint32_t pixel) {
  return {((pixel >> 16) & 0xFF) / 255.0, ((pixel >> 8) & 0xFF) / 255.0, (pixel & 0xFF) / 255.0};
}

Image make_image(int width, int height, const Rgb& fill) {
  render_detail::check_picture_size("make_image", width, height);
  Image image;
  image.width = width;
  image.height = height;
  image.pixels.assign(static_cast<std::size_t>(width) * height, pack_rgb(fill));
  return image;
}

void write_png(const std::string& path, const Image& image) {
  render_detail::check_picture_size("write_png", image.width, image.height);
  if (image.pixels.size() != static_cast<std::size_t>(image.width) * image.height) {
    throw InvalidInput("write_png: " + path + ": the image holds " +
                       std::to_string(image.pixels.size()) + " pixels, not " +
                       std::to_string(image.width) + " x " + std::to_string(image.height));
  }
  const std::string bytes = encode_png(image);
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

std::string encode_png(const Image& image) {
  render_detail::check_picture_size("encode_png", image.width, image.height);
  if (image.pixels.size() != static_cast<std::size_t>(image.width) * image.height) {
    throw InvalidInput("encode_png: the image holds " + std::to_string(image.pixels.size()) +
                       " pixels, not " + std::to_string(image.width) + " x " +
                       std::to_string(image.height));
  }
  // Few colours (the checkerboard texture, flat plots): a palette image, much smaller and
  // faster to write than Cairo's RGBA.
  if (std::optional<std::string> indexed = render_detail::encode_indexed_png(image)) {
    return std::move(*indexed);
  }
  // Cairo reads the pixels only; the copy keeps the const promise without a cast.
  Image copy = image;
  const render_detail::SurfaceHandle surface = render_detail::surface_on(copy);
  std::ostringstream out;
  const cairo_status_t status =
      render_detail::cairo_api().surface_write_to_png_stream(surface.get(), &write_to_stream, &out);
  if (status != CAIRO_STATUS_SUCCESS) {
    throw IoError(std::string("encode_png: PNG encoding failed: ") +
                  render_detail::cairo_api().status_to_string(status));
  }
  return out.str();
}

Image read_png(const std::string& path) {
  const render_detail::SurfaceHandle surface(
      render_detail::cairo_api().image_surface_create_from_png(path.c_str()));
  const cairo_status_t status = render_detail::cairo_api().surface_status(surface.get());
  if (status != CAIRO_STATUS_SUCCESS) {
    throw IoError(path +
                  ": cannot read PNG: " + render_detail::cairo_api().status_to_string(status));
  }
  render_detail::cairo_api().surface_flush(surface.get());
  const cairo_format_t format = render_detail::cairo_api().image_surface_get_format(surface.get());
  Image image;
  image.width = render_detail::cairo_api().image_surface_get_width(surface.get());
  image.height = render_detail::cairo_api().image_surface_get_height(surface.get());
  image.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
  if (format == CAIRO_FORMAT_ARGB32 || format == CAIRO_FORMAT_RGB24) {
    const unsigned char* data = render_detail::cairo_api().image_surface_get_data(surface.get());
    const int stride = render_detail::cairo_api().image_surface_get_stride(surface.get());
    for (int y = 0; y < image.height; ++y) {
      const auto* row =
          reinterpret_cast<const std::uint32_t*>(data + static_cast<long>(y) * stride);
      for (int x = 0; x < image.width; ++x) {
        std::uint32_t p = row[x];
        if (format == CAIRO_FORMAT_RGB24) p |= 0xFF000000u;
        image.pixels[static_cast<std::size_t>(y) * image.width + x] = p;
      }
    }
  } else {
    // Grey or 1-bit PNGs: let Cairo convert by painting onto an ARGB32 surface.
    image.pixels.assign(image.pixels.size(), 0);
    render_detail::draw_on_image(image, [&](cairo_t* cr) {
      render_detail::cairo_api().set_source_surface(cr, surface.get(), 0, 0);
      render_detail::cairo_api().paint(cr);
    });
  }
  return image;
}

void write_svg(const std::string& path, const std::string& svg) {
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(svg.data(), static_cast<std::streamsize>(svg.size()));
  });
}

}  // namespace ricci
