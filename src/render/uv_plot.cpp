#include "ricci/render/uv_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <set>
#include <string>

#include <Eigen/Geometry>

#include "cairo_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/render/uv_chart.hpp"

namespace ricci {
namespace {

using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;
using render_detail::set_colour;

const Rgb kBlue{0.16, 0.30, 0.78};
const Rgb kRed{0.80, 0.08, 0.10};
const Rgb kWhite{1, 1, 1};

double signed_uv_area(const Triangles& uv_triangles, const UV& uv, int f) {
  const Eigen::Vector2d a = uv.row(uv_triangles(f, 0));
  const Eigen::Vector2d e1 = Eigen::Vector2d(uv.row(uv_triangles(f, 1))) - a;
  const Eigen::Vector2d e2 = Eigen::Vector2d(uv.row(uv_triangles(f, 2))) - a;
  return 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
}

std::string format_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2g", value);
  return text;
}

/// Everything both plots draw, computed once.
struct LayoutDrawing {
  Eigen::VectorXd log_area;
  std::vector<char> flipped;
  UvChart chart;
  double range = 0;
  double scale = 1, u0 = 0, v1 = 0, ox = 0, oy = 0;  ///< uv -> pixels
  double bar_height = 0;
  UvPlotInfo info;

  Eigen::Vector2d to_pixel(const Eigen::Vector2d& t) const {
    return {ox + (t.x() - u0) * scale, oy + (v1 - t.y()) * scale};
  }
};

LayoutDrawing prepare(const char* fn, const Mesh& mesh, const Triangles& uv_triangles, const UV& uv,
                      const UvPlotOptions& options) {
  render_detail::check_picture_size(fn, options.width, options.height, 16);
  check_uv_layout(fn, mesh, uv_triangles, uv);
  if (mesh.num_faces() == 0) throw InvalidInput(std::string(fn) + ": the mesh has no faces");
  for (Eigen::Index t = 0; t < uv.rows(); ++t) {
    if (!uv.row(t).allFinite()) {
      throw InvalidInput(std::string(fn) + ": uv row " + std::to_string(t) + " is not finite");
    }
  }
  if (!(options.max_log_area > 0)) {
    throw InvalidInput(std::string(fn) + ": max_log_area must be > 0");
  }
  LayoutDrawing d;
  d.log_area = log_area_ratio(mesh, uv_triangles, uv);
  d.flipped.assign(mesh.num_faces(), 0);
  double largest = 0;
  d.info.log_area_min = std::numeric_limits<double>::infinity();
  d.info.log_area_max = -d.info.log_area_min;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    d.flipped[f] = signed_uv_area(uv_triangles, uv, f) < 0;
    d.info.flipped_faces += d.flipped[f];
    const double x = d.log_area[f];
    if (!std::isfinite(x)) continue;
    largest = std::max(largest, std::abs(x));
    d.info.log_area_min = std::min(d.info.log_area_min, x);
    d.info.log_area_max = std::max(d.info.log_area_max, x);
  }
  if (!std::isfinite(d.info.log_area_min)) d.info.log_area_min = d.info.log_area_max = 0;
  d.range = std::min(options.max_log_area, largest);
  d.info.colour_range = d.range;
  d.chart = analyse_uv_chart(mesh, uv_triangles, uv, options.cone_tolerance);
  d.info.seam_halfedges = static_cast<int>(d.chart.seam_halfedges.size());
  d.info.cones = static_cast<int>(d.chart.cones.size());

  // Only the used texture coordinates frame the picture.
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      lo = lo.cwiseMin(uv.row(uv_triangles(f, c)).transpose());
      hi = hi.cwiseMax(uv.row(uv_triangles(f, c)).transpose());
    }
  }
  d.bar_height = options.colour_bar ? std::max(48.0, 0.09 * options.height) : 0.0;
  const double margin = 0.04 * std::min(options.width, options.height);
  const double plot_w = options.width - 2 * margin;
  const double plot_h = options.height - d.bar_height - 2 * margin;
  // A layout of no extent (one point, a line) still gets a finite, positive scale.
  constexpr double kNoExtent = 1e-300, kTinyScale = 1e-300;
  const Eigen::Vector2d extent = (hi - lo).cwiseMax(kNoExtent);
  d.scale = std::max(std::min(plot_w / extent.x(), plot_h / extent.y()), kTinyScale);
  d.u0 = lo.x();
  d.v1 = hi.y();
  d.ox = margin + 0.5 * (plot_w - d.scale * (hi.x() - lo.x()));
  d.oy = margin + 0.5 * (plot_h - d.scale * (hi.y() - lo.y()));
  return d;
}

void draw_layout(cairo_t* cr, const LayoutDrawing& d, const Mesh& mesh,
                 const Triangles& uv_triangles, const UV& uv, const UvPlotOptions& options,
                 bool edges) {
  set_colour(cr, kWhite);
  render_detail::cairo_api().paint(cr);
  render_detail::cairo_api().set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  render_detail::cairo_api().set_line_width(cr, options.edge_width);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector2d p = d.to_pixel(uv.row(uv_triangles(f, c)));
      if (c == 0) {
        render_detail::cairo_api().move_to(cr, p.x(), p.y());
      } else {
        render_detail::cairo_api().line_to(cr, p.x(), p.y());
      }
    }
    render_detail::cairo_api().close_path(cr);
    const double x = d.log_area[f];
    const double t = d.range > 0 ? (std::isfinite(x) ? x / d.range : -1.0) : 0.0;
    set_colour(cr, d.flipped[f] ? options.flipped_colour : diverging_colour(t));
    if (edges) {
      render_detail::cairo_api().fill_preserve(cr);
      set_colour(cr, {0.25, 0.25, 0.25}, 0.6);
      render_detail::cairo_api().stroke(cr);
    } else {
      render_detail::cairo_api().fill(cr);
    }
  }
  if (!d.chart.seam_halfedges.empty()) {
    render_detail::cairo_api().set_line_width(cr, options.seam_width);
    render_detail::cairo_api().set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    for (int h : d.chart.seam_halfedges) {
      const int f = h / 3, k = h % 3;
      const Eigen::Vector2d a = d.to_pixel(uv.row(uv_triangles(f, (k + 1) % 3)));
      const Eigen::Vector2d b = d.to_pixel(uv.row(uv_triangles(f, (k + 2) % 3)));
      render_detail::cairo_api().move_to(cr, a.x(), a.y());
      render_detail::cairo_api().line_to(cr, b.x(), b.y());
    }
    set_colour(cr, {0.05, 0.05, 0.05});
    render_detail::cairo_api().stroke(cr);
  }
  if (options.mark_cones && !d.chart.cones.empty()) {
    const std::set<int> cones(d.chart.cones.begin(), d.chart.cones.end());
    std::set<int> copies;  // texture coordinates of the cones' corners
    for (int f = 0; f < mesh.num_faces(); ++f) {
      for (int c = 0; c < 3; ++c) {
        if (cones.count(mesh.triangles(f, c))) copies.insert(uv_triangles(f, c));
      }
    }
    const double radius = std::max(3.0, std::min(options.width, options.height) / 200.0);
    for (int t : copies) {
      const Eigen::Vector2d p = d.to_pixel(uv.row(t));
      render_detail::cairo_api().new_sub_path(cr);
      render_detail::cairo_api().arc(cr, p.x(), p.y(), radius, 0, 2 * std::numbers::pi);
    }
    set_colour(cr, {0.9, 0.05, 0.05});
    render_detail::cairo_api().fill_preserve(cr);
    render_detail::cairo_api().set_line_width(cr, 1.0);
    set_colour(cr, {0.15, 0, 0});
    render_detail::cairo_api().stroke(cr);
  }
  if (options.colour_bar) {
    const double w = options.width, h = options.height;
    const double bar_w = std::min(0.6 * w, 480.0), bar_h = std::max(10.0, 0.2 * d.bar_height);
    const double x0 = 0.5 * (w - bar_w), y0 = h - d.bar_height + 0.15 * d.bar_height;
    const double font = std::clamp(0.22 * d.bar_height, 9.0, 16.0);
    cairo_pattern_t* gradient =
        render_detail::cairo_api().pattern_create_linear(x0, 0, x0 + bar_w, 0);
    render_detail::cairo_api().pattern_add_color_stop_rgb(gradient, 0.0, kBlue.r, kBlue.g, kBlue.b);
    render_detail::cairo_api().pattern_add_color_stop_rgb(gradient, 0.5, 1, 1, 1);
    render_detail::cairo_api().pattern_add_color_stop_rgb(gradient, 1.0, kRed.r, kRed.g, kRed.b);
    render_detail::cairo_api().rectangle(cr, x0, y0, bar_w, bar_h);
    render_detail::cairo_api().set_source(cr, gradient);
    render_detail::cairo_api().fill_preserve(cr);
    render_detail::cairo_api().pattern_destroy(gradient);
    render_detail::cairo_api().set_line_width(cr, 1.0);
    set_colour(cr, {0.3, 0.3, 0.3});
    render_detail::cairo_api().stroke(cr);
    set_colour(cr, {0.1, 0.1, 0.1});
    const double ty = y0 + bar_h + 4;
    const std::string r = format_number(d.range);
    render_detail::draw_text(cr, d.range > 0 ? "\xE2\x88\x92" + r : "0", x0, ty, font, 0.5, 0);
    render_detail::draw_text(cr, "0", x0 + 0.5 * bar_w, ty, font, 0.5, 0);
    render_detail::draw_text(cr, d.range > 0 ? "+" + r : "0", x0 + bar_w, ty, font, 0.5, 0);
    std::string caption = "ln(A_uv / A_3d), areas normalised to 1";
    if (d.info.flipped_faces > 0) {
      caption += "; " + std::to_string(d.info.flipped_faces) + " flipped (yellow)";
    }
    render_detail::draw_text(cr, caption, 0.5 * w, y0 - 3, font, 0.5, 1);
  }
}

}  // namespace

Eigen::VectorXd log_area_ratio(const Mesh& mesh, const Triangles& uv_triangles, const UV& uv) {
  check_uv_layout("log_area_ratio", mesh, uv_triangles, uv);
  const int nf = mesh.num_faces();
  Eigen::VectorXd area_3d(nf), area_uv(nf);
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(f, 0));
    const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(f, 1));
    const Eigen::Vector3d c = mesh.positions.row(mesh.triangles(f, 2));
    area_3d[f] = 0.5 * (b - a).cross(c - a).norm();
    area_uv[f] = std::abs(signed_uv_area(uv_triangles, uv, f));
  }
  const double total_3d = area_3d.sum(), total_uv = area_uv.sum();
  if (!(total_3d > 0) || !std::isfinite(total_3d)) {
    throw InvalidInput("log_area_ratio: the mesh's total area is zero or not finite");
  }
  if (!(total_uv > 0) || !std::isfinite(total_uv)) {
    throw InvalidInput("log_area_ratio: the texture layout's total area is zero or not finite");
  }
  Eigen::VectorXd result(nf);
  for (int f = 0; f < nf; ++f) {
    result[f] = std::log((area_uv[f] / total_uv) / (area_3d[f] / total_3d));
  }
  return result;
}

Rgb diverging_colour(double t) {
  if (std::isnan(t)) t = 0;
  t = std::clamp(t, -1.0, 1.0);
  const Rgb& end = t < 0 ? kBlue : kRed;
  const double s = std::abs(t);
  return {(1 - s) + s * end.r, (1 - s) + s * end.g, (1 - s) + s * end.b};
}

Image plot_uv_layout(const Mesh& mesh, const Triangles& uv_triangles, const UV& uv,
                     const UvPlotOptions& options, UvPlotInfo* info) {
  const LayoutDrawing d = prepare("plot_uv_layout", mesh, uv_triangles, uv, options);
  // Edges only where faces are large enough for them not to grey the picture out.
  double area = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    area += std::abs(signed_uv_area(uv_triangles, uv, f));
  }
  const bool edges = options.draw_edges && area * d.scale * d.scale / mesh.num_faces() >= 20.0;
  Image image = make_image(options.width, options.height, kWhite);
  render_detail::draw_on_image(
      image, [&](cairo_t* cr) { draw_layout(cr, d, mesh, uv_triangles, uv, options, edges); });
  if (info) *info = d.info;
  return image;
}

std::string plot_uv_layout_svg(const Mesh& mesh, const Triangles& uv_triangles, const UV& uv,
                               const UvPlotOptions& options, UvPlotInfo* info) {
  const LayoutDrawing d = prepare("plot_uv_layout_svg", mesh, uv_triangles, uv, options);
  std::string svg = render_detail::draw_svg(options.width, options.height, [&](cairo_t* cr) {
    draw_layout(cr, d, mesh, uv_triangles, uv, options, options.draw_edges);
  });
  if (info) *info = d.info;
  return svg;
}

}  // namespace ricci
