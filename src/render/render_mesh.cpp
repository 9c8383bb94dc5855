#include "ricci/render/render_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <unordered_set>
#include <vector>

#include <Eigen/Geometry>

#include "cairo_support.hpp"
#include "ricci/errors.hpp"
#include "ricci/render/uv_chart.hpp"

namespace ricci {
namespace {

using UV = Eigen::Matrix<double, Eigen::Dynamic, 2>;

constexpr double kDegree = std::numbers::pi / 180;

/// A given view direction shorter than this is no direction (a zero vector with round-off).
constexpr double kShortestView = 1e-12;
/// A given up direction whose part across the view is below this fraction of its length is
/// parallel to the view: the picture's vertical would be round-off.
constexpr double kParallelUp = 1e-9;
/// The framed extent is at least this, so that a mesh of no extent across the view (a point, a
/// segment seen end-on) gets a finite scale instead of a division by zero.
constexpr double kTinyExtent = 1e-300;

void check_positions(const char* function, const Mesh& mesh) {
  if (mesh.num_faces() == 0) throw InvalidInput(std::string(function) + ": the mesh has no faces");
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!mesh.positions.row(v).allFinite()) {
      throw InvalidInput(std::string(function) + ": vertex " + std::to_string(v) +
                         " has a coordinate that is not finite");
    }
  }
}

/// Vertices that some face uses (the others do not count for the view or the framing).
std::vector<char> used_vertices(const Mesh& mesh) {
  std::vector<char> used(mesh.num_vertices(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.triangles(f, c);
      if (v >= 0 && v < mesh.num_vertices()) used[v] = 1;
    }
  }
  return used;
}

/// +y projected off the view, or -z / +z when looking along y.
Eigen::Vector3d default_up(const Eigen::Vector3d& view) {
  if (std::abs(view.y()) < 0.99) {
    return (Eigen::Vector3d::UnitY() - view.y() * view).normalized();
  }
  return view.y() > 0 ? Eigen::Vector3d(0, 0, -1) : Eigen::Vector3d(0, 0, 1);
}

/// Per-sample buffers of the rasteriser (supersampled).
struct SampleBuffer {
  int width = 0, height = 0;
  std::vector<float> depth;  ///< -inf where no face covers the sample
  std::vector<int> face;     ///< -1 where no face covers the sample
};

/// Faces whose doubled screen area (in samples squared) is at most this are seen edge-on and
/// cover no sample: their barycentric coordinates would divide by nearly zero.
constexpr double kEdgeOnArea = 1e-12;

/// At most this many samples (2^27, 1 GiB of buffers): large pictures get fewer samples per
/// pixel.
constexpr double kMaxSamples = 134217728.0;

/// Overlays (edges, seams, cones) show where the z-buffer near them lies within this fraction
/// of the mesh's extent along the camera's axes: close enough to hide what is behind the
/// surface, loose enough for the depth interpolated along a line that crosses faces.
constexpr double kOverlayDepthTolerance = 0.01;

/// Overlay lines are tested for visibility every half pixel.
constexpr double kOverlayStep = 0.5;

/// Lambert shading: ambient plus diffuse light, darker on the back of an open surface.
constexpr double kAmbient = 0.35, kDiffuse = 0.65, kBackFace = 0.6;

/// Twice the signed area of (a, b, p) with p = (x, y): the rasteriser's edge function.
double edge_function(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double x, double y) {
  return (b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x());
}

/// Checks render_textured_mesh's input and options (InvalidInput otherwise).
void check_render_input(const char* fn, const Mesh& mesh, const Triangles& uv_triangles,
                        const UV& uv, const RenderOptions& options) {
  check_uv_layout(fn, mesh, uv_triangles, uv);
  check_positions(fn, mesh);
  render_detail::check_picture_size(fn, options.width, options.height);
  if (options.checker < 1) {
    throw InvalidInput(std::string(fn) + ": checker must be >= 1, not " +
                       std::to_string(options.checker));
  }
  if (options.supersampling < 1 || options.supersampling > 8) {
    throw InvalidInput(std::string(fn) + ": supersampling must be in [1, 8], not " +
                       std::to_string(options.supersampling));
  }
  const bool projective = options.uv_weights.size() > 0;
  if (projective && (options.uv_weights.size() != uv.rows() || !options.uv_weights.allFinite() ||
                     (options.uv_weights.array() <= 0).any())) {
    throw InvalidInput(std::string(fn) + ": uv_weights needs one positive weight per texture " +
                       "coordinate (" + std::to_string(uv.rows()) + ")");
  }
  if (!std::isfinite(options.margin) || options.margin < 0 || options.margin >= 0.5) {
    throw InvalidInput(std::string(fn) + ": margin must be in [0, 0.5)");
  }
}

/// The given camera (with the picture's size), or one fitted to the mesh.
Camera render_camera(const char* fn, const Mesh& mesh, const RenderOptions& options) {
  if (!options.camera) return fit_camera(mesh, options);
  Camera camera = *options.camera;
  camera.width = options.width;
  camera.height = options.height;
  if (!camera.view.allFinite() || !camera.up.allFinite() || !camera.right.allFinite() ||
      !camera.centre.allFinite() || !std::isfinite(camera.scale) || !(camera.scale > 0)) {
    throw InvalidInput(std::string(fn) +
                       ": the given camera needs finite axes and centre and a positive scale");
  }
  return camera;
}

/// The diagonal of the used vertices' box along the camera's axes.
double camera_box_diagonal(const Mesh& mesh, const Camera& camera) {
  const std::vector<char> used = used_vertices(mesh);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!used[v]) continue;
    const Eigen::Vector3d p = mesh.positions.row(v);
    const Eigen::Vector3d q(p.dot(camera.right), p.dot(camera.up), p.dot(camera.view));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  return (hi - lo).norm();
}

/// The faces as the camera sees them: corners in sample coordinates (3 f + c), their depths,
/// and the shading.
struct ProjectedFaces {
  std::vector<Eigen::Vector2d> screen;
  std::vector<double> depth;
  std::vector<double> shade;      ///< #F: flat shading factor (0 for a face without a normal)
  std::vector<char> back_facing;  ///< #F: 1 where the face turns its back to the camera
  Positions vertex_normals;       ///< smooth shading: area-weighted sums of the face normals
  Eigen::Vector3d light;          ///< towards the light
};

ProjectedFaces project_faces(const Mesh& mesh, const Camera& camera, int ss, bool smooth) {
  const int nf = mesh.num_faces();
  ProjectedFaces out;
  out.screen.resize(static_cast<std::size_t>(nf) * 3);
  out.depth.resize(static_cast<std::size_t>(nf) * 3);
  out.shade.assign(nf, 0.0);
  out.back_facing.assign(nf, 0);
  out.light = (camera.view + 0.6 * camera.up - 0.4 * camera.right).normalized();
  if (smooth) out.vertex_normals = Positions::Zero(mesh.num_vertices(), 3);
  for (int f = 0; f < nf; ++f) {
    Eigen::Vector3d p[3];
    for (int c = 0; c < 3; ++c) {
      p[c] = mesh.positions.row(mesh.triangles(f, c));
      out.screen[3 * f + c] = ss * camera.project(p[c]);
      out.depth[3 * f + c] = camera.depth(p[c]);
    }
    const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    const double length = n.norm();
    if (!(length > 0)) continue;
    out.back_facing[f] = n.dot(camera.view) < 0;  // the inside of an open surface
    out.shade[f] = (kAmbient + kDiffuse * std::abs(n.dot(out.light)) / length) *
                   (out.back_facing[f] ? kBackFace : 1.0);
    if (smooth) {
      for (int c = 0; c < 3; ++c) out.vertex_normals.row(mesh.triangles(f, c)) += n.transpose();
    }
  }
  return out;
}

/// The shading factor at barycentric coordinates w of face f.
double shading(const Mesh& mesh, const ProjectedFaces& faces, bool smooth, int f, double w0,
               double w1, double w2) {
  if (!smooth) return faces.shade[f];
  const Positions& normals = faces.vertex_normals;
  const Eigen::Vector3d n = w0 * normals.row(mesh.triangles(f, 0)).transpose() +
                            w1 * normals.row(mesh.triangles(f, 1)).transpose() +
                            w2 * normals.row(mesh.triangles(f, 2)).transpose();
  const double length = n.norm();
  if (!(length > 0)) return faces.shade[f];
  return (kAmbient + kDiffuse * std::abs(n.dot(faces.light)) / length) *
         (faces.back_facing[f] ? kBackFace : 1.0);
}

/// Rasterise: the nearest face wins each sample.
SampleBuffer rasterise(const ProjectedFaces& faces, int width, int height) {
  SampleBuffer buffer;
  buffer.width = width;
  buffer.height = height;
  const std::size_t num_samples = static_cast<std::size_t>(buffer.width) * buffer.height;
  buffer.depth.assign(num_samples, -std::numeric_limits<float>::infinity());
  buffer.face.assign(num_samples, -1);
  const int nf = static_cast<int>(faces.shade.size());
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector2d& s0 = faces.screen[3 * f];
    const Eigen::Vector2d& s1 = faces.screen[3 * f + 1];
    const Eigen::Vector2d& s2 = faces.screen[3 * f + 2];
    const double area = edge_function(s0, s1, s2.x(), s2.y());
    if (!(std::abs(area) > kEdgeOnArea)) continue;  // seen edge-on
    const double inv = 1.0 / area;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({s0.x(), s1.x(), s2.x()}))));
    const int x1 =
        std::min(buffer.width - 1, static_cast<int>(std::ceil(std::max({s0.x(), s1.x(), s2.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({s0.y(), s1.y(), s2.y()}))));
    const int y1 = std::min(buffer.height - 1,
                            static_cast<int>(std::ceil(std::max({s0.y(), s1.y(), s2.y()}))));
    const double d0 = faces.depth[3 * f], d1 = faces.depth[3 * f + 1], d2 = faces.depth[3 * f + 2];
    constexpr double kInside = -1e-9;  // shared edges: no cracks between neighbours
    for (int y = y0; y <= y1; ++y) {
      const double py = y + 0.5;
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5;
        const double b0 = edge_function(s1, s2, px, py) * inv;
        const double b1 = edge_function(s2, s0, px, py) * inv;
        const double b2 = 1.0 - b0 - b1;
        if (b0 < kInside || b1 < kInside || b2 < kInside) continue;
        const auto z = static_cast<float>(b0 * d0 + b1 * d1 + b2 * d2);
        const std::size_t i = static_cast<std::size_t>(y) * buffer.width + x;
        if (z > buffer.depth[i]) {
          buffer.depth[i] = z;
          buffer.face[i] = f;
        }
      }
    }
  }
  return buffer;
}

/// What the picture's surface is drawn from.
struct Surface {
  const Mesh& mesh;
  const Triangles& uv_triangles;
  const UV& uv;
  const RenderOptions& options;
  const ProjectedFaces& faces;
};

/// The colour of face f at sample (sx, sy): the checkerboard of its texture coordinates, shaded.
Rgb sample_colour(const Surface& surface, int f, int sx, int sy) {
  const RenderOptions& options = surface.options;
  const Triangles& uv_triangles = surface.uv_triangles;
  const Eigen::Vector2d& s0 = surface.faces.screen[3 * f];
  const Eigen::Vector2d& s1 = surface.faces.screen[3 * f + 1];
  const Eigen::Vector2d& s2 = surface.faces.screen[3 * f + 2];
  const double inv = 1.0 / edge_function(s0, s1, s2.x(), s2.y());
  const double w0 = edge_function(s1, s2, sx + 0.5, sy + 0.5) * inv;
  const double w1 = edge_function(s2, s0, sx + 0.5, sy + 0.5) * inv;
  const double w2 = 1.0 - w0 - w1;
  double b0 = w0, b1 = w1, b2 = w2;
  if (options.uv_weights.size() > 0) {  // projective texture coordinates
    b0 *= options.uv_weights[uv_triangles(f, 0)];
    b1 *= options.uv_weights[uv_triangles(f, 1)];
    b2 *= options.uv_weights[uv_triangles(f, 2)];
    const double sum = b0 + b1 + b2;
    b0 /= sum;
    b1 /= sum;
    b2 /= sum;
  }
  const Eigen::Vector2d t = b0 * Eigen::Vector2d(surface.uv.row(uv_triangles(f, 0))) +
                            b1 * Eigen::Vector2d(surface.uv.row(uv_triangles(f, 1))) +
                            b2 * Eigen::Vector2d(surface.uv.row(uv_triangles(f, 2)));
  const double n_checker = options.checker;
  const auto parity = static_cast<long long>(std::floor(t.x() * n_checker)) +
                      static_cast<long long>(std::floor(t.y() * n_checker));
  const Rgb& base = (parity & 1) ? options.checker_dark : options.checker_light;
  const double k = shading(surface.mesh, surface.faces, options.smooth_shading, f, w0, w1, w2);
  return {base.r * k, base.g * k, base.b * k};
}

/// Shade the samples and average them into pixels; the number of faces some sample shows.
int shade_pixels(const Surface& surface, const SampleBuffer& buffer, int ss, Image& image) {
  const RenderOptions& options = surface.options;
  std::vector<char> seen(surface.mesh.num_faces(), 0);
  for (int y = 0; y < options.height; ++y) {
    for (int x = 0; x < options.width; ++x) {
      double r = 0, g = 0, b = 0;
      for (int j = 0; j < ss; ++j) {
        for (int i = 0; i < ss; ++i) {
          const int sx = x * ss + i, sy = y * ss + j;
          const int f = buffer.face[static_cast<std::size_t>(sy) * buffer.width + sx];
          Rgb c = options.background;
          if (f >= 0) {
            seen[f] = 1;
            c = sample_colour(surface, f, sx, sy);
          }
          r += c.r;
          g += c.g;
          b += c.b;
        }
      }
      const double w = 1.0 / (ss * ss);
      image.pixels[static_cast<std::size_t>(y) * options.width + x] =
          pack_rgb({r * w, g * w, b * w});
    }
  }
  return static_cast<int>(std::count(seen.begin(), seen.end(), 1));
}

/// Whether a point of the surface shows in the picture: the z-buffer near its pixel holds a
/// depth within `tolerance` of its own.
struct DepthTest {
  const SampleBuffer& buffer;
  int ss;
  double tolerance;

  bool visible(const Eigen::Vector2d& pixel, double z) const {
    const int cx = static_cast<int>(std::floor(pixel.x() * ss));
    const int cy = static_cast<int>(std::floor(pixel.y() * ss));
    for (int y = std::max(0, cy - ss); y <= std::min(buffer.height - 1, cy + ss); ++y) {
      for (int x = std::max(0, cx - ss); x <= std::min(buffer.width - 1, cx + ss); ++x) {
        const float d = buffer.depth[static_cast<std::size_t>(y) * buffer.width + x];
        if (std::abs(d - z) <= tolerance) return true;
      }
    }
    return false;
  }
};

/// Adds the visible stretches of edge (a, b) to the current path.
void add_visible_edge(cairo_t* cr, const Mesh& mesh, const Camera& camera, const DepthTest& test,
                      int a, int b) {
  const Eigen::Vector3d pa = mesh.positions.row(a), pb = mesh.positions.row(b);
  const Eigen::Vector2d qa = camera.project(pa), qb = camera.project(pb);
  const double za = camera.depth(pa), zb = camera.depth(pb);
  const int steps = std::max(1, static_cast<int>(std::ceil((qb - qa).norm() / kOverlayStep)));
  bool open = false;
  for (int s = 0; s <= steps; ++s) {
    const double t = static_cast<double>(s) / steps;
    const Eigen::Vector2d q = (1 - t) * qa + t * qb;
    if (test.visible(q, (1 - t) * za + t * zb)) {
      if (open) {
        render_detail::cairo_api().line_to(cr, q.x(), q.y());
      } else {
        render_detail::cairo_api().move_to(cr, q.x(), q.y());
        open = true;
      }
    } else {
      open = false;
    }
  }
}

/// Strokes the visible parts of the mesh's edges; the number of edges.
int draw_edges(cairo_t* cr, const Mesh& mesh, const Camera& camera, const DepthTest& test,
               const RenderOptions& options) {
  const std::int64_t nv = mesh.num_vertices();
  render_detail::set_colour(cr, options.edge_colour);
  render_detail::cairo_api().set_line_width(cr, options.edge_width);
  std::unordered_set<std::int64_t> drawn;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles(f, k), b = mesh.triangles(f, (k + 1) % 3);
      if (!drawn.insert(std::min(a, b) * nv + std::max(a, b)).second) continue;
      add_visible_edge(cr, mesh, camera, test, a, b);
    }
  }
  render_detail::cairo_api().stroke(cr);
  return static_cast<int>(drawn.size());
}

/// Strokes the visible parts of the seams (each edge once).
void draw_seams(cairo_t* cr, const Mesh& mesh, const Camera& camera, const DepthTest& test,
                const RenderOptions& options, const std::vector<int>& seam_halfedges) {
  const std::int64_t nv = mesh.num_vertices();
  render_detail::set_colour(cr, options.seam_colour);
  render_detail::cairo_api().set_line_width(cr, options.seam_width);
  std::unordered_set<std::int64_t> drawn;
  for (int h : seam_halfedges) {
    const int a = mesh.triangles(h / 3, (h % 3 + 1) % 3);
    const int b = mesh.triangles(h / 3, (h % 3 + 2) % 3);
    if (!drawn.insert(std::min(a, b) * nv + std::max(a, b)).second) continue;
    add_visible_edge(cr, mesh, camera, test, a, b);
  }
  render_detail::cairo_api().stroke(cr);
}

/// Dots on the visible cones; the number of them.
int mark_cones(cairo_t* cr, const Mesh& mesh, const Camera& camera, const DepthTest& test,
               const RenderOptions& options, const std::vector<int>& cones) {
  const double radius = options.cone_radius > 0
                            ? options.cone_radius
                            : std::max(3.0, std::min(options.width, options.height) / 140.0);
  int visible_cones = 0;
  for (int v : cones) {
    const Eigen::Vector3d p = mesh.positions.row(v);
    const Eigen::Vector2d q = camera.project(p);
    if (!test.visible(q, camera.depth(p))) continue;
    ++visible_cones;
    render_detail::cairo_api().new_sub_path(cr);
    render_detail::cairo_api().arc(cr, q.x(), q.y(), radius, 0, 2 * std::numbers::pi);
  }
  render_detail::set_colour(cr, options.cone_colour);
  render_detail::cairo_api().fill_preserve(cr);
  render_detail::cairo_api().set_line_width(cr, std::max(1.0, radius / 4));
  render_detail::set_colour(cr, {0.15, 0, 0});
  render_detail::cairo_api().stroke(cr);
  return visible_cones;
}

}  // namespace

Eigen::Vector2d Camera::project(const Eigen::Vector3d& point) const {
  const Eigen::Vector3d d = point - centre;
  return {scale * d.dot(right) + 0.5 * width, 0.5 * height - scale * d.dot(up)};
}

Eigen::Vector3d automatic_view(const Mesh& mesh, Eigen::Vector3d* up) {
  check_positions("automatic_view", mesh);
  const std::vector<char> used = used_vertices(mesh);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!used[v]) continue;
    lo = lo.cwiseMin(mesh.positions.row(v).transpose());
    hi = hi.cwiseMax(mesh.positions.row(v).transpose());
  }
  const Eigen::Vector3d extent = hi - lo;
  // Axes by decreasing extent (ties keep x before y before z).
  int axes[3] = {0, 1, 2};
  std::stable_sort(axes, axes + 3, [&](int a, int b) { return extent[a] > extent[b]; });
  const int middle = axes[1], least = axes[2];
  const double ratio = extent[axes[0]] > 0 ? extent[least] / extent[axes[0]] : 0;

  Eigen::Vector3d view, screen_up;
  if (ratio < 0.35) {
    // Seen from the side that most of the surface faces (for a closed surface: +axis).
    double facing = 0, total = 0;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const Eigen::Vector3d p0 = mesh.positions.row(mesh.triangles(f, 0));
      const Eigen::Vector3d n =
          (Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 1))) - p0)
              .cross(Eigen::Vector3d(mesh.positions.row(mesh.triangles(f, 2))) - p0);
      facing += n[least];
      total += n.norm();
    }
    const Eigen::Vector3d normal =
        (facing < -0.2 * total ? -1.0 : 1.0) * Eigen::Vector3d::Unit(least);
    const Eigen::Vector3d side = Eigen::Vector3d::Unit(middle);
    const double elevation = (ratio < 0.05 ? 90 : 40) * kDegree;
    view = std::sin(elevation) * normal - std::cos(elevation) * side;
    screen_up = std::cos(elevation) * normal + std::sin(elevation) * side;
  } else {
    const double azimuth = 30 * kDegree, elevation = 20 * kDegree;
    view = Eigen::Vector3d(std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
                           std::cos(azimuth) * std::cos(elevation));
    screen_up = Eigen::Vector3d(-std::sin(azimuth) * std::sin(elevation), std::cos(elevation),
                                -std::cos(azimuth) * std::sin(elevation));
  }
  if (up) *up = screen_up.normalized();
  return view.normalized();
}

Camera fit_camera(const Mesh& mesh, const RenderOptions& options, const Positions& also_frame) {
  const char* fn = "fit_camera";
  check_positions(fn, mesh);
  render_detail::check_picture_size(fn, options.width, options.height);
  if (!std::isfinite(options.margin) || options.margin < 0 || options.margin >= 0.5) {
    throw InvalidInput(std::string(fn) + ": margin must be in [0, 0.5)");
  }
  if (!also_frame.allFinite()) {
    throw InvalidInput(std::string(fn) + ": a point to frame has a coordinate that is not finite");
  }
  Camera camera;
  camera.width = options.width;
  camera.height = options.height;
  Eigen::Vector3d up;
  if (options.view.isZero(0)) {
    camera.view = automatic_view(mesh, &up);
  } else {
    if (!options.view.allFinite() || options.view.norm() < kShortestView) {
      throw InvalidInput(std::string(fn) + ": the view direction must be finite and non-zero");
    }
    camera.view = options.view.normalized();
    up = default_up(camera.view);
  }
  if (!options.up.isZero(0)) {
    up = options.up - options.up.dot(camera.view) * camera.view;
    if (!up.allFinite() || up.norm() < kParallelUp * options.up.norm()) {
      throw InvalidInput(std::string(fn) + ": the up direction is parallel to the view");
    }
  }
  camera.up = up.normalized();
  camera.right = camera.up.cross(camera.view);

  const std::vector<char> used = used_vertices(mesh);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  auto include = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d q(p.dot(camera.right), p.dot(camera.up), p.dot(camera.view));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  };
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (used[v]) include(mesh.positions.row(v).transpose());
  }
  for (Eigen::Index i = 0; i < also_frame.rows(); ++i) include(also_frame.row(i).transpose());
  const Eigen::Vector3d mid = 0.5 * (lo + hi);
  camera.centre = mid.x() * camera.right + mid.y() * camera.up + mid.z() * camera.view;
  const double border = options.margin * std::min(options.width, options.height);
  const double fit_x = (options.width - 2 * border) / std::max(hi.x() - lo.x(), kTinyExtent);
  const double fit_y = (options.height - 2 * border) / std::max(hi.y() - lo.y(), kTinyExtent);
  camera.scale = std::min(fit_x, fit_y);
  if (!std::isfinite(camera.scale) || camera.scale <= 0) camera.scale = 1;
  return camera;
}

RenderResult render_textured_mesh(const Mesh& mesh, const Triangles& uv_triangles, const UV& uv,
                                  const RenderOptions& options) {
  const char* fn = "render_textured_mesh";
  check_render_input(fn, mesh, uv_triangles, uv, options);
  const Camera camera = render_camera(fn, mesh, options);
  // The mesh's extent along the camera's axes: the depth tolerance of the overlays.
  const double diagonal = camera_box_diagonal(mesh, camera);

  int ss = options.supersampling;
  while (ss > 1 && static_cast<double>(options.width) * options.height * ss * ss > kMaxSamples)
    --ss;
  const ProjectedFaces faces = project_faces(mesh, camera, ss, options.smooth_shading);
  const SampleBuffer buffer = rasterise(faces, options.width * ss, options.height * ss);

  RenderResult result;
  result.camera = camera;
  result.image = make_image(options.width, options.height, options.background);
  result.visible_faces =
      shade_pixels({mesh, uv_triangles, uv, options, faces}, buffer, ss, result.image);

  // Seams and cones, where the z-buffer shows their surface.
  const UvChart chart = analyse_uv_chart(mesh, uv_triangles, uv, options.cone_tolerance);
  result.seam_edges = chart.seam_edges;
  result.cones = static_cast<int>(chart.cones.size());
  const DepthTest test{buffer, ss, kOverlayDepthTolerance * diagonal};
  const bool any_overlay = options.draw_edges ||
                           (options.draw_seams && !chart.seam_halfedges.empty()) ||
                           (options.mark_cones && !chart.cones.empty());
  if (!any_overlay) return result;
  render_detail::draw_on_image(result.image, [&](cairo_t* cr) {
    render_detail::cairo_api().set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    render_detail::cairo_api().set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    if (options.draw_edges) result.edges = draw_edges(cr, mesh, camera, test, options);
    if (options.draw_seams) draw_seams(cr, mesh, camera, test, options, chart.seam_halfedges);
    if (options.mark_cones) {
      result.visible_cones = mark_cones(cr, mesh, camera, test, options, chart.cones);
    }
  });
  return result;
}

}  // namespace ricci
