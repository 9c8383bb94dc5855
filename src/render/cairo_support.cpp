#include "cairo_support.hpp"

#include <cmath>

#include "ricci/errors.hpp"

namespace ricci::render_detail {
namespace {

void check_status(cairo_status_t status, const char* what) {
  if (status != CAIRO_STATUS_SUCCESS) {
    throw Error(std::string(what) + ": Cairo failed: " + cairo_api().status_to_string(status));
  }
}

cairo_status_t append_to_string(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

void check_picture_size(const char* function, int width, int height, int smallest) {
  constexpr int kLargest = 16384;
  if (width < smallest || height < smallest || width > kLargest || height > kLargest) {
    throw InvalidInput(std::string(function) + ": picture size " + std::to_string(width) + " x " +
                       std::to_string(height) + " is outside [" + std::to_string(smallest) + ", " +
                       std::to_string(kLargest) + "]");
  }
}

SurfaceHandle surface_on(Image& image) {
  const int stride = cairo_api().format_stride_for_width(CAIRO_FORMAT_ARGB32, image.width);
  if (stride != 4 * image.width) throw Error("surface_on: unexpected ARGB32 stride");
  SurfaceHandle surface(cairo_api().image_surface_create_for_data(
      reinterpret_cast<unsigned char*>(image.pixels.data()), CAIRO_FORMAT_ARGB32, image.width,
      image.height, stride));
  check_status(cairo_api().surface_status(surface.get()), "surface_on");
  return surface;
}

void draw_on_image(Image& image, const std::function<void(cairo_t*)>& draw) {
  const SurfaceHandle surface = surface_on(image);
  {
    const ContextHandle cr(cairo_api().create(surface.get()));
    check_status(cairo_api().status(cr.get()), "draw_on_image");
    draw(cr.get());
    check_status(cairo_api().status(cr.get()), "draw_on_image");
  }
  cairo_api().surface_flush(surface.get());
}

std::string draw_svg(int width, int height, const std::function<void(cairo_t*)>& draw) {
  std::string svg;
  {
    const SurfaceHandle surface(
        cairo_api().svg_surface_create_for_stream(&append_to_string, &svg, width, height));
    check_status(cairo_api().surface_status(surface.get()), "draw_svg");
    cairo_api().svg_surface_set_document_unit(surface.get(), CAIRO_SVG_UNIT_PX);
    {
      const ContextHandle cr(cairo_api().create(surface.get()));
      draw(cr.get());
      check_status(cairo_api().status(cr.get()), "draw_svg");
    }
    cairo_api().surface_finish(surface.get());
    check_status(cairo_api().surface_status(surface.get()), "draw_svg");
  }
  return svg;
}

void draw_text(cairo_t* cr, const std::string& text, double x, double y, double size, double ax,
               double ay) {
  cairo_api().select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_api().set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_api().text_extents(cr, text.c_str(), &e);
  cairo_api().move_to(cr, x - e.x_bearing - ax * e.width, y - e.y_bearing - ay * e.height);
  cairo_api().show_text(cr, text.c_str());
  cairo_api().new_path(cr);
}

double nice_step(double span, int count) {
  const double raw = span / count;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * magnitude >= raw) return m * magnitude;
  }
  return 10 * magnitude;
}

}  // namespace ricci::render_detail
