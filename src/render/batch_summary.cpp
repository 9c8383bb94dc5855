#include "ricci/render/batch_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "cairo_support.hpp"
#include "ricci/errors.hpp"

namespace ricci {
namespace {

using render_detail::draw_text;
using render_detail::kTickSlack;
using render_detail::nice_step;
using render_detail::set_colour;

const Rgb kInk{0.1, 0.1, 0.1};
const Rgb kGrid{0.86, 0.86, 0.86};
const Rgb kOkColour{0.2, 0.6, 0.3};
const Rgb kFailedColour{0.8, 0.22, 0.18};
const Rgb kSecondsColour{0.2, 0.4, 0.75};
const Rgb kDistortionColour{0.88, 0.5, 0.1};

/// A plot rectangle in pixels with a linear x range and a count axis from 0 to y_hi.
struct HistogramFrame {
  double left = 0, right = 0, top = 0, bottom = 0;
  double x_lo = 0, x_hi = 1;
  double y_hi = 1;

  double px(double x) const { return left + (x - x_lo) / (x_hi - x_lo) * (right - left); }
  double py(double y) const { return bottom - y / y_hi * (bottom - top); }
};

/// A number with at most `digits` decimals, trailing zeros dropped ("1.5", "2", "0.25").
std::string format_number(double x, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, x);
  std::string s = text;
  if (s.find('.') != std::string::npos) {
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.') s.pop_back();
  }
  return s == "-0" ? "0" : s;
}

/// 10^e seconds as a tick label: "0.001" .. "10000", then "1e5".
std::string decade_label(int e) {
  if (e >= -3 && e <= 4) return format_number(std::pow(10.0, e), 3);
  return "1e" + std::to_string(e);
}

/// Axis label rotated to read upwards, centred on (x, y).
void draw_vertical_text(cairo_t* cr, const std::string& text, double x, double y, double size) {
  render_detail::cairo_api().save(cr);
  render_detail::cairo_api().translate(cr, x, y);
  render_detail::cairo_api().rotate(cr, -std::numbers::pi / 2);
  draw_text(cr, text, 0, 0, size, 0.5, 0);
  render_detail::cairo_api().restore(cr);
}

/// Adds a line across the frame at x (frame units) to the path.
void add_vertical_line(cairo_t* cr, const HistogramFrame& f, double x) {
  render_detail::cairo_api().move_to(cr, f.px(x), f.top);
  render_detail::cairo_api().line_to(cr, f.px(x), f.bottom);
}

/// A light grid line across the frame at x (frame units).
void draw_grid_line(cairo_t* cr, const HistogramFrame& f, double x) {
  set_colour(cr, kGrid);
  add_vertical_line(cr, f, x);
  render_detail::cairo_api().stroke(cr);
}

void draw_box(cairo_t* cr, const HistogramFrame& f) {
  set_colour(cr, {0.2, 0.2, 0.2});
  render_detail::cairo_api().set_line_width(cr, 1.2);
  render_detail::cairo_api().rectangle(cr, f.left, f.top, f.right - f.left, f.bottom - f.top);
  render_detail::cairo_api().stroke(cr);
}

/// Counts per bin, `bins` equal bins over [lo, hi]; values outside fall in the end bins.
std::vector<int> bin_values(const std::vector<double>& values, double lo, double hi, int bins) {
  std::vector<int> counts(static_cast<std::size_t>(bins), 0);
  for (double v : values) {
    const double t = std::floor((v - lo) / (hi - lo) * bins);
    counts[static_cast<std::size_t>(std::clamp(t, 0.0, bins - 1.0))] += 1;
  }
  return counts;
}

/// The count axis (grid lines, tick labels, its label) and the bars of a histogram whose bins
/// split [frame.x_lo, frame.x_hi] equally.
void draw_histogram(cairo_t* cr, HistogramFrame& f, const std::vector<int>& counts,
                    const Rgb& colour, double font) {
  const int most = std::max(1, *std::max_element(counts.begin(), counts.end()));
  const double step = std::max(1.0, nice_step(most, 5));
  f.y_hi = std::ceil(most / step) * step;
  if (f.y_hi < most * 1.05) f.y_hi += step;  // room above the tallest bar
  render_detail::cairo_api().set_line_width(cr, 1.0);
  for (double y = 0; y <= f.y_hi + kTickSlack; y += step) {
    set_colour(cr, kGrid);
    render_detail::cairo_api().move_to(cr, f.left, f.py(y));
    render_detail::cairo_api().line_to(cr, f.right, f.py(y));
    render_detail::cairo_api().stroke(cr);
    set_colour(cr, kInk);
    draw_text(cr, format_number(y, 0), f.left - 6, f.py(y), font, 1, 0.5);
  }
  const double bin_width = (f.x_hi - f.x_lo) / static_cast<double>(counts.size());
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (counts[i] == 0) continue;
    const double x0 = f.px(f.x_lo + static_cast<double>(i) * bin_width);
    const double x1 = f.px(f.x_lo + static_cast<double>(i + 1) * bin_width);
    render_detail::cairo_api().rectangle(cr, x0 + 0.5, f.py(counts[i]), std::max(1.0, x1 - x0 - 1),
                                         f.bottom - f.py(counts[i]));
  }
  set_colour(cr, colour);
  render_detail::cairo_api().fill(cr);
  set_colour(cr, kInk);
  draw_vertical_text(cr, "meshes", f.left - 3.4 * font, 0.5 * (f.top + f.bottom), font);
}

/// A dashed vertical line at x (frame units) with a label at its top.
void draw_marker(cairo_t* cr, const HistogramFrame& f, double x, const std::string& label,
                 double font) {
  if (!std::isfinite(x) || x < f.x_lo || x > f.x_hi) return;
  const double dash[] = {5.0, 4.0};
  render_detail::cairo_api().set_dash(cr, dash, 2, 0);
  set_colour(cr, {0.3, 0.3, 0.3});
  render_detail::cairo_api().set_line_width(cr, 1.2);
  add_vertical_line(cr, f, x);
  render_detail::cairo_api().stroke(cr);
  render_detail::cairo_api().set_dash(cr, nullptr, 0, 0);
  draw_text(cr, label, f.px(x) + 3, f.top + 3, 0.8 * font, 0, 0);
}

/// A panel's title, centred above [x0, x1].
void draw_panel_title(cairo_t* cr, const std::string& title, double x0, double x1, double top,
                      double font) {
  set_colour(cr, kInk);
  draw_text(cr, title, 0.5 * (x0 + x1), top, 1.1 * font, 0.5, 0);
}

/// Panel (a): meshes by outcome, one horizontal bar each ("ok" always, the others when > 0).
void draw_outcomes(cairo_t* cr, const BatchSummary& s, double x0, double x1, double height,
                   double top, double font) {
  std::vector<std::pair<std::string, int>> rows;
  for (const auto& [name, count] : s.counts) {
    if (count > 0 || name == "ok") rows.emplace_back(name, count);
  }
  if (rows.empty()) rows.emplace_back("ok", 0);  // a summary without counts
  draw_panel_title(cr, "meshes by outcome (" + std::to_string(s.total) + ")", x0, x1, top, font);

  render_detail::cairo_api().select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                                              CAIRO_FONT_WEIGHT_NORMAL);
  render_detail::cairo_api().set_font_size(cr, font);
  double name_width = 0, count_width = 0;
  int most = 1;
  for (const auto& [name, count] : rows) {
    cairo_text_extents_t e;
    render_detail::cairo_api().text_extents(cr, name.c_str(), &e);
    name_width = std::max(name_width, e.width);
    render_detail::cairo_api().text_extents(cr, std::to_string(count).c_str(), &e);
    count_width = std::max(count_width, e.width);
    most = std::max(most, count);
  }
  HistogramFrame f;
  f.left = x0 + name_width + 1.5 * font;
  f.right = x1 - count_width - 1.5 * font;
  f.top = top + 2.2 * font;
  f.bottom = height - 1.5 * font;
  f.x_hi = most;

  const double row = (f.bottom - f.top) / static_cast<double>(rows.size());
  const double bar = std::min(row * 0.7, 3.0 * font);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& [name, count] = rows[i];
    const double yc = f.top + (static_cast<double>(i) + 0.5) * row;
    set_colour(cr, name == "ok" ? kOkColour : kFailedColour);
    render_detail::cairo_api().rectangle(cr, f.left, yc - 0.5 * bar, f.px(count) - f.left, bar);
    render_detail::cairo_api().fill(cr);
    set_colour(cr, kInk);
    draw_text(cr, name, f.left - 0.6 * font, yc, font, 1, 0.5);
    draw_text(cr, std::to_string(count), f.px(count) + 0.5 * font, yc, font, 0, 0.5);
  }
  set_colour(cr, {0.2, 0.2, 0.2});
  render_detail::cairo_api().set_line_width(cr, 1.2);
  render_detail::cairo_api().move_to(cr, f.left, f.top);
  render_detail::cairo_api().line_to(cr, f.left, f.bottom);
  render_detail::cairo_api().stroke(cr);
}

/// Panels (b) and (c) start alike: the title, then the plot rectangle under it, which this
/// returns.
HistogramFrame start_histogram_panel(cairo_t* cr, const std::string& title, double x0, double x1,
                                     double height, double top, double font) {
  draw_panel_title(cr, title, x0, x1, top, font);
  HistogramFrame f;
  f.left = x0 + 5.0 * font;
  f.right = x1 - 1.5 * font;
  f.top = top + 2.2 * font;
  f.bottom = height - 3.6 * font;
  return f;
}

/// ... and end alike: the frame's box and the label of its x axis.
void finish_histogram_panel(cairo_t* cr, const HistogramFrame& f, const std::string& x_label,
                            double height, double font) {
  draw_box(cr, f);
  set_colour(cr, kInk);
  draw_text(cr, x_label, 0.5 * (f.left + f.right), height - 0.6 * font, font, 0.5, 1);
}

/// Panel (b): seconds per mesh on a log10 axis over whole decades.
void draw_seconds(cairo_t* cr, const BatchSummary& s, double x0, double x1, double height,
                  double top, double font) {
  HistogramFrame f = start_histogram_panel(cr, "seconds per mesh", x0, x1, height, top, font);

  std::vector<double> logs;
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (double t : s.all_seconds) {
    if (!std::isfinite(t)) continue;
    if (t > 0) {
      lo = std::min(lo, std::log10(t));
      hi = std::max(hi, std::log10(t));
    }
    logs.push_back(t > 0 ? std::log10(t) : -HUGE_VAL);  // <= 0: the first bin
  }
  if (lo > hi) lo = hi = 0;  // no positive time: the decades around 1 s
  const int decade_lo = static_cast<int>(std::floor(lo));
  const int decade_hi = std::max(static_cast<int>(std::ceil(hi)), decade_lo + 1);
  f.x_lo = decade_lo;
  f.x_hi = decade_hi;
  const int decades = decade_hi - decade_lo;
  const int per_decade = std::clamp(30 / decades, 1, 10);

  // Decade lines and labels, and light lines at 2..9 times each decade when there is room.
  render_detail::cairo_api().set_line_width(cr, 1.0);
  const int label_every = (decades + 7) / 8;
  for (int e = decade_lo; e <= decade_hi; ++e) {
    draw_grid_line(cr, f, e);
    if (decades <= 6 && e < decade_hi) {
      set_colour(cr, {0.94, 0.94, 0.94});
      for (int m = 2; m <= 9; ++m) add_vertical_line(cr, f, e + std::log10(m));
      render_detail::cairo_api().stroke(cr);
    }
    if ((e - decade_lo) % label_every == 0) {
      set_colour(cr, kInk);
      draw_text(cr, decade_label(e), f.px(e), f.bottom + 6, font, 0.5, 0);
    }
  }
  if (logs.empty()) {
    set_colour(cr, kInk);
    draw_text(cr, "no mesh", 0.5 * (f.left + f.right), 0.5 * (f.top + f.bottom), font, 0.5, 0.5);
  } else {
    draw_histogram(cr, f, bin_values(logs, f.x_lo, f.x_hi, decades * per_decade), kSecondsColour,
                   font);
    if (s.seconds.count > 0 && s.seconds.p50 > 0) {
      draw_marker(cr, f, std::log10(s.seconds.p50), "median", font);
    }
    if (s.seconds.count > 0 && s.seconds.p90 > 0 && s.seconds.p90 != s.seconds.p50) {
      draw_marker(cr, f, std::log10(s.seconds.p90), "p90", font);
    }
  }
  finish_histogram_panel(cr, f, "seconds (log scale)", height, font);
}

/// Panel (c): angle distortion of the Ok meshes, axis from 1 (conformal).
void draw_angle_distortion(cairo_t* cr, const BatchSummary& s, double x0, double x1, double height,
                           double top, double font) {
  HistogramFrame f =
      start_histogram_panel(cr, "angle distortion of the Ok meshes", x0, x1, height, top, font);

  std::vector<double> values;
  double most = 1;
  for (double v : s.all_angle_distortion) {
    if (!std::isfinite(v)) continue;
    values.push_back(v);
    most = std::max(most, v);
  }
  // Ticks no finer than 0.01: closer figures are all but conformal alike.
  const double step = most > 1 ? std::max(0.01, nice_step(most - 1, 5)) : 0.1;
  f.x_lo = 1;
  f.x_hi = 1 + std::max(1.0, std::ceil((most - 1) / step)) * step;
  if (f.x_hi < most) f.x_hi += step;
  const int digits = std::max(0, -static_cast<int>(std::floor(std::log10(step))));

  render_detail::cairo_api().set_line_width(cr, 1.0);
  const auto ticks = std::lround((f.x_hi - f.x_lo) / step);
  for (long k = 0; k <= ticks; ++k) {
    const double x = f.x_lo + static_cast<double>(k) * step;
    draw_grid_line(cr, f, x);
    set_colour(cr, kInk);
    draw_text(cr, format_number(x, digits), f.px(x), f.bottom + 6, font, 0.5, 0);
  }
  if (values.empty()) {
    set_colour(cr, kInk);
    draw_text(cr, "no Ok mesh", 0.5 * (f.left + f.right), 0.5 * (f.top + f.bottom), 1.2 * font, 0.5,
              0.5);
  } else {
    draw_histogram(cr, f, bin_values(values, f.x_lo, f.x_hi, 20), kDistortionColour, font);
    if (s.angle_distortion.count > 0) draw_marker(cr, f, s.angle_distortion.p50, "median", font);
  }
  finish_histogram_panel(cr, f, "mean singular value ratio (1: conformal)", height, font);
}

void draw_summary(cairo_t* cr, const BatchSummary& s, const BatchSummaryPictureOptions& options) {
  const double w = options.width, h = options.height;
  const double panel = w / 3;
  const double font = std::clamp(std::min(panel, h) / 34.0, 9.0, 18.0);
  set_colour(cr, {1, 1, 1});
  render_detail::cairo_api().paint(cr);
  double top = 0.6 * font;
  if (!options.title.empty()) {
    set_colour(cr, kInk);
    draw_text(cr, options.title, 0.5 * w, top, 1.25 * font, 0.5, 0);
    top += 2.0 * font;
  }
  const double pad = 0.8 * font;
  draw_outcomes(cr, s, pad, panel - pad, h, top, font);
  draw_seconds(cr, s, panel + pad, 2 * panel - pad, h, top, font);
  draw_angle_distortion(cr, s, 2 * panel + pad, w - pad, h, top, font);
}

}  // namespace

Image plot_batch_summary(const BatchSummary& summary, const BatchSummaryPictureOptions& options) {
  render_detail::check_picture_size("plot_batch_summary", options.width, options.height, 150);
  Image image = make_image(options.width, options.height, {1, 1, 1});
  render_detail::draw_on_image(image, [&](cairo_t* cr) { draw_summary(cr, summary, options); });
  return image;
}

void write_batch_summary_picture(const BatchSummary& summary, const std::string& png_path,
                                 const BatchSummaryPictureOptions& options) {
  write_png(png_path, plot_batch_summary(summary, options));
}

}  // namespace ricci
