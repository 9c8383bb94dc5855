#pragma once
/// \file
/// Private to the picture writers: owning handles for Cairo objects, drawing one function onto a
/// raster image or into SVG text, and the small drawing helpers the plots share.

#include "render/detail/cairo_library.hpp"

#include <functional>
#include <memory>
#include <string>

#include "ricci/render/image.hpp"

namespace ricci::render_detail {

struct SurfaceDeleter {
  void operator()(cairo_surface_t* surface) const { cairo_api().surface_destroy(surface); }
};
struct ContextDeleter {
  void operator()(cairo_t* cr) const { cairo_api().destroy(cr); }
};
using SurfaceHandle = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
using ContextHandle = std::unique_ptr<cairo_t, ContextDeleter>;

/// \throw InvalidInput "function: picture size W x H is outside [lo, 16384]" otherwise
void check_picture_size(const char* function, int width, int height, int smallest = 1);

/// A Cairo surface drawing straight into the image's pixels (the image must outlive it).
SurfaceHandle surface_on(Image& image);

/// Draws on the whole image with `draw` (Cairo context in pixel units), then flushes.
/// \throw Error when Cairo reports a failure
void draw_on_image(Image& image, const std::function<void(cairo_t*)>& draw);

/// Runs `draw` on an SVG surface of width x height px and returns the document.
/// \throw Error when Cairo reports a failure
std::string draw_svg(int width, int height, const std::function<void(cairo_t*)>& draw);

inline void set_colour(cairo_t* cr, const Rgb& c, double alpha = 1.0) {
  cairo_api().set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

/// Text in the sans-serif face at the current point, aligned: ax, ay in [0, 1] pick which point
/// of the text's extents lands on (x, y) (0, 0: left, top; 0.5, 0.5: centre; 1, 1: right,
/// bottom of the ink).
void draw_text(cairo_t* cr, const std::string& text, double x, double y, double size, double ax,
               double ay);

/// A "nice" axis step (1, 2 or 5 times a power of ten) giving about `count` ticks over `span`.
double nice_step(double span, int count);
/// Axes of whole numbers (counts, iterations) run to their last value inclusive: the ticks'
/// loop allows this much over it, so that the step's rounding error never drops the last tick
/// (any slack below 1 would do).
constexpr double kTickSlack = 1e-9;

}  // namespace ricci::render_detail
