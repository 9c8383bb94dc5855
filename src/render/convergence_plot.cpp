#include "ricci/render/convergence_plot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "cairo_support.hpp"
#include "ricci/errors.hpp"

namespace ricci {
namespace {

using render_detail::draw_text;
using render_detail::kTickSlack;
using render_detail::nice_step;
using render_detail::set_colour;

/// Axes and their mapping onto the picture.
struct Frame {
  double left = 0, right = 0, top = 0, bottom = 0;  ///< plot rectangle, pixels
  double x_lo = 0, x_hi = 1;                        ///< iteration axis (log10 of it + 1 if log)
  int decade_lo = 0, decade_hi = 1;                 ///< error axis: 10^lo .. 10^hi
  bool log_x = false;
  std::size_t last = 1;  ///< the last iteration with a plottable error (at least 1)

  double px(double iteration) const {
    const double x = log_x ? std::log10(iteration + 1) : iteration;
    return left + (x - x_lo) / (x_hi - x_lo) * (right - left);
  }
  double py(double error) const {
    return bottom - (std::log10(error) - decade_lo) / (decade_hi - decade_lo) * (bottom - top);
  }
};

bool plottable(double e) {
  return std::isfinite(e) && e > 0;
}

/// "10" with a raised exponent, its right end at (x, y) (vertically centred).
void draw_power_of_ten(cairo_t* cr, int exponent, double x, double y, double size) {
  const std::string power =
      exponent < 0 ? "\xE2\x88\x92" + std::to_string(-exponent) : std::to_string(exponent);
  render_detail::cairo_api().select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                                              CAIRO_FONT_WEIGHT_NORMAL);
  render_detail::cairo_api().set_font_size(cr, 0.7 * size);
  cairo_text_extents_t small;
  render_detail::cairo_api().text_extents(cr, power.c_str(), &small);
  const double power_x = x - small.x_advance;
  draw_text(cr, "10", power_x - 1, y, size, 1, 0.5);
  draw_text(cr, power, power_x, y - 0.45 * size, 0.7 * size, 0, 0.5);
}

bool use_log_axis(const std::vector<ConvergenceCurve>& curves, IterationAxis axis) {
  if (axis != IterationAxis::Auto) return axis == IterationAxis::Log;
  std::size_t shortest = std::numeric_limits<std::size_t>::max(), longest = 0;
  for (const ConvergenceCurve& c : curves) {
    if (c.max_error.empty()) continue;
    shortest = std::min(shortest, c.max_error.size());
    longest = std::max(longest, c.max_error.size());
  }
  return longest > 100 && longest > 10 * shortest;
}

/// The plot rectangle and the ranges of both axes, from the plottable errors and the tolerance.
Frame fit_frame(const std::vector<ConvergenceCurve>& curves, const ConvergencePlotOptions& options,
                double font) {
  const double w = options.width, h = options.height;
  Frame frame;
  frame.log_x = use_log_axis(curves, options.iteration_axis);
  frame.left = 4.6 * font + 10;
  frame.right = w - 1.5 * font;
  frame.top = (options.title.empty() ? 1.5 : 3.0) * font;
  frame.bottom = h - 3.6 * font;

  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  std::size_t last = 1;
  for (const ConvergenceCurve& c : curves) {
    for (std::size_t i = 0; i < c.max_error.size(); ++i) {
      if (!plottable(c.max_error[i])) continue;
      lo = std::min(lo, c.max_error[i]);
      hi = std::max(hi, c.max_error[i]);
      last = std::max(last, i);
    }
  }
  if (plottable(options.tolerance)) {
    lo = std::min(lo, options.tolerance);
    hi = std::max(hi, options.tolerance);
  }
  frame.decade_lo = static_cast<int>(std::floor(std::log10(lo)));
  frame.decade_hi = static_cast<int>(std::ceil(std::log10(hi)));
  if (frame.decade_hi <= frame.decade_lo) frame.decade_hi = frame.decade_lo + 1;
  frame.last = last;
  frame.x_lo = 0;
  frame.x_hi = frame.log_x ? std::log10(static_cast<double>(last) + 1) : static_cast<double>(last);
  if (frame.x_hi <= frame.x_lo) frame.x_hi = frame.x_lo + 1;
  return frame;
}

/// The error axis: a line per decade, light lines at its multiples 2..9 when there are few
/// decades, and powers of ten as labels (at most twelve of them).
void draw_error_grid(cairo_t* cr, const Frame& frame, double font) {
  render_detail::cairo_api().set_line_width(cr, 1.0);
  const int decades = frame.decade_hi - frame.decade_lo;
  const int label_every = (decades + 11) / 12;
  for (int e = frame.decade_lo; e <= frame.decade_hi; ++e) {
    const double y = frame.py(std::pow(10.0, e));
    set_colour(cr, {0.82, 0.82, 0.82});
    render_detail::cairo_api().move_to(cr, frame.left, y);
    render_detail::cairo_api().line_to(cr, frame.right, y);
    render_detail::cairo_api().stroke(cr);
    if (decades <= 6 && e < frame.decade_hi) {
      set_colour(cr, {0.93, 0.93, 0.93});
      for (int m = 2; m <= 9; ++m) {
        const double ym = frame.py(m * std::pow(10.0, e));
        render_detail::cairo_api().move_to(cr, frame.left, ym);
        render_detail::cairo_api().line_to(cr, frame.right, ym);
      }
      render_detail::cairo_api().stroke(cr);
    }
    if ((e - frame.decade_lo) % label_every == 0) {
      set_colour(cr, {0.1, 0.1, 0.1});
      draw_power_of_ten(cr, e, frame.left - 6, y, font);
    }
  }
}

/// A vertical grid line at `iteration`, labelled below the plot.
void draw_iteration_tick(cairo_t* cr, const Frame& frame, double iteration,
                         const std::string& label, double font) {
  const double x = frame.px(iteration);
  set_colour(cr, {0.88, 0.88, 0.88});
  render_detail::cairo_api().move_to(cr, x, frame.top);
  render_detail::cairo_api().line_to(cr, x, frame.bottom);
  render_detail::cairo_api().stroke(cr);
  set_colour(cr, {0.1, 0.1, 0.1});
  draw_text(cr, label, x, frame.bottom + 6, font, 0.5, 0);
}

/// The iteration axis: ticks at powers of ten (log) or at a round step (linear).
void draw_iteration_grid(cairo_t* cr, const Frame& frame, double font) {
  const std::size_t last = frame.last;
  if (frame.log_x) {
    // Ticks where iteration + 1 is a power of ten; light lines at its multiples 2..9.
    const double end = static_cast<double>(last) + 1;
    set_colour(cr, {0.95, 0.95, 0.95});
    for (double p = 1; p <= end; p *= 10) {
      for (int m = 2; m <= 9 && m * p <= end; ++m) {
        render_detail::cairo_api().move_to(cr, frame.px(m * p - 1), frame.top);
        render_detail::cairo_api().line_to(cr, frame.px(m * p - 1), frame.bottom);
      }
    }
    render_detail::cairo_api().stroke(cr);
    for (int e = 0; std::pow(10.0, e) <= end; ++e) {
      draw_iteration_tick(
          cr, frame, std::pow(10.0, e) - 1,
          e <= 5 ? std::to_string(static_cast<long long>(std::llround(std::pow(10.0, e))))
                 : "1e" + std::to_string(e),
          font);
    }
  } else {
    const double step = std::max(1.0, nice_step(static_cast<double>(last), 6));
    for (double it = 0; it <= static_cast<double>(last) + kTickSlack; it += step) {
      draw_iteration_tick(cr, frame, it, std::to_string(static_cast<long long>(std::llround(it))),
                          font);
    }
  }
}

/// The tolerance (dashed) and the curves, clipped to the plot rectangle.
void draw_curves(cairo_t* cr, const Frame& frame, const std::vector<ConvergenceCurve>& curves,
                 const ConvergencePlotOptions& options, double font) {
  render_detail::cairo_api().rectangle(cr, frame.left, frame.top, frame.right - frame.left,
                                       frame.bottom - frame.top);
  render_detail::cairo_api().save(cr);
  render_detail::cairo_api().clip(cr);
  if (plottable(options.tolerance)) {
    const double dash[] = {6.0, 4.0};
    render_detail::cairo_api().set_dash(cr, dash, 2, 0);
    set_colour(cr, {0.45, 0.45, 0.45});
    render_detail::cairo_api().move_to(cr, frame.left, frame.py(options.tolerance));
    render_detail::cairo_api().line_to(cr, frame.right, frame.py(options.tolerance));
    render_detail::cairo_api().stroke(cr);
    render_detail::cairo_api().set_dash(cr, nullptr, 0, 0);
    draw_text(cr, "tolerance", frame.right - 6, frame.py(options.tolerance) - 4, 0.85 * font, 1, 1);
  }
  render_detail::cairo_api().set_line_width(cr, 2.0);
  render_detail::cairo_api().set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (const ConvergenceCurve& c : curves) {
    bool open = false;
    for (std::size_t i = 0; i < c.max_error.size(); ++i) {
      if (!plottable(c.max_error[i])) {
        open = false;
        continue;
      }
      const double x = frame.px(static_cast<double>(i)), y = frame.py(c.max_error[i]);
      if (open) {
        render_detail::cairo_api().line_to(cr, x, y);
      } else {
        render_detail::cairo_api().move_to(cr, x, y);
      }
      open = true;
    }
    set_colour(cr, c.colour);
    render_detail::cairo_api().stroke(cr);
    if (c.markers) {
      for (std::size_t i = 0; i < c.max_error.size(); ++i) {
        if (!plottable(c.max_error[i])) continue;
        render_detail::cairo_api().new_sub_path(cr);
        render_detail::cairo_api().arc(cr, frame.px(static_cast<double>(i)),
                                       frame.py(c.max_error[i]), 3.5, 0, 2 * std::numbers::pi);
      }
      render_detail::cairo_api().fill(cr);
    }
  }
  render_detail::cairo_api().restore(cr);
}

/// The legend (curves with a label), in the plot's top right corner.
void draw_legend(cairo_t* cr, const Frame& frame, const std::vector<ConvergenceCurve>& curves,
                 double font) {
  double ly = frame.top + 1.2 * font;
  for (const ConvergenceCurve& c : curves) {
    if (c.label.empty()) continue;
    const double lx = frame.right - 11 * font;
    set_colour(cr, c.colour);
    render_detail::cairo_api().set_line_width(cr, 2.0);
    render_detail::cairo_api().move_to(cr, lx, ly);
    render_detail::cairo_api().line_to(cr, lx + 2 * font, ly);
    render_detail::cairo_api().stroke(cr);
    if (c.markers) {
      render_detail::cairo_api().arc(cr, lx + font, ly, 3.5, 0, 2 * std::numbers::pi);
      render_detail::cairo_api().fill(cr);
    }
    set_colour(cr, {0.1, 0.1, 0.1});
    draw_text(cr, c.label, lx + 2.5 * font, ly, font, 0, 0.5);
    ly += 1.5 * font;
  }
}

void draw_plot(cairo_t* cr, const std::vector<ConvergenceCurve>& curves,
               const ConvergencePlotOptions& options) {
  const double w = options.width, h = options.height;
  const double font = std::clamp(std::min(w, h) / 40.0, 9.0, 18.0);
  set_colour(cr, {1, 1, 1});
  render_detail::cairo_api().paint(cr);
  const Frame frame = fit_frame(curves, options, font);
  draw_error_grid(cr, frame, font);
  draw_iteration_grid(cr, frame, font);
  draw_curves(cr, frame, curves, options, font);

  set_colour(cr, {0.2, 0.2, 0.2});
  render_detail::cairo_api().set_line_width(cr, 1.2);
  render_detail::cairo_api().rectangle(cr, frame.left, frame.top, frame.right - frame.left,
                                       frame.bottom - frame.top);
  render_detail::cairo_api().stroke(cr);
  draw_legend(cr, frame, curves, font);

  set_colour(cr, {0.1, 0.1, 0.1});
  draw_text(cr, frame.log_x ? options.x_label + " + 1" : options.x_label,
            0.5 * (frame.left + frame.right), h - 0.6 * font, font, 0.5, 1);
  render_detail::cairo_api().save(cr);
  render_detail::cairo_api().translate(cr, 1.0 * font, 0.5 * (frame.top + frame.bottom));
  render_detail::cairo_api().rotate(cr, -std::numbers::pi / 2);
  draw_text(cr, options.y_label, 0, 0, font, 0.5, 0);
  render_detail::cairo_api().restore(cr);
  if (!options.title.empty()) {
    draw_text(cr, options.title, 0.5 * w, 0.8 * font, 1.15 * font, 0.5, 0);
  }
}

void check_curves(const char* fn, const std::vector<ConvergenceCurve>& curves,
                  const ConvergencePlotOptions& options) {
  render_detail::check_picture_size(fn, options.width, options.height, 64);
  for (const ConvergenceCurve& c : curves) {
    if (std::any_of(c.max_error.begin(), c.max_error.end(), plottable)) return;
  }
  throw InvalidInput(std::string(fn) + ": no curve has a positive finite error to plot");
}

}  // namespace

ConvergenceCurve convergence_curve(const std::string& label,
                                   const std::vector<IterationRecord>& history, const Rgb& colour) {
  ConvergenceCurve curve;
  curve.label = label;
  curve.colour = colour;
  curve.max_error.reserve(history.size());
  for (const IterationRecord& r : history) curve.max_error.push_back(r.max_error);
  curve.markers = history.size() <= 61;
  return curve;
}

Image plot_convergence(const std::vector<ConvergenceCurve>& curves,
                       const ConvergencePlotOptions& options) {
  check_curves("plot_convergence", curves, options);
  Image image = make_image(options.width, options.height, {1, 1, 1});
  render_detail::draw_on_image(image, [&](cairo_t* cr) { draw_plot(cr, curves, options); });
  return image;
}

std::string plot_convergence_svg(const std::vector<ConvergenceCurve>& curves,
                                 const ConvergencePlotOptions& options) {
  check_curves("plot_convergence_svg", curves, options);
  return render_detail::draw_svg(options.width, options.height,
                                 [&](cairo_t* cr) { draw_plot(cr, curves, options); });
}

}  // namespace ricci
