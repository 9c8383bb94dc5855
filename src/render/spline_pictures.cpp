#include "ricci/render/spline_pictures.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <system_error>

#include "ricci/errors.hpp"

namespace ricci {
namespace {

/// Barycentric coordinates below this are round-off: the points pictured lie on a side or at a
/// corner exactly, and their coordinates come out within a few ulps of 0.
constexpr double kBarycentricRoundOff = 1e-12;

/// A point's barycentric coordinates with round-off entries (a point on a side or at a corner)
/// set to exactly 0, so that both faces of an edge weigh its two ends alike.
Eigen::Vector3d clean_barycentric(const Eigen::Vector3d& w) {
  Eigen::Vector3d out = w;
  for (int c = 0; c < 3; ++c) {
    if (std::abs(out[c]) < kBarycentricRoundOff) out[c] = 0;
  }
  const double sum = out.sum();
  return sum > 0 ? Eigen::Vector3d(out / sum) : w;
}

/// Mean length of the face sides (edges inside the mesh count twice).
double mean_edge_length(const Mesh& mesh) {
  double sum = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      sum += (mesh.positions.row(mesh.triangles(f, k)) -
              mesh.positions.row(mesh.triangles(f, (k + 1) % 3)))
                 .norm();
    }
  }
  return mesh.num_faces() > 0 ? sum / (3.0 * mesh.num_faces()) : 0;
}

}  // namespace

SplineSurfaceTexture spline_surface_texture(const SplineResult& result) {
  const char* fn = "spline_surface_texture";
  const SplineDomain& domain = result.domain;
  const SplineTessellation& samples = result.surface_samples;
  const Parameterization& param = result.param;
  const Eigen::Index nf = domain.triangles.rows();
  const Eigen::Index nt = samples.triangles.rows();
  const Eigen::Index np = samples.values.rows();
  if (!result.converged || nf == 0 || nt == 0) {
    throw InvalidInput(std::string(fn) + ": the spline has no surface (" +
                       (result.converged ? "no faces" : "not converged: " + result.message) + ")");
  }
  if (nt % (nf * kPowellSabinPieces) != 0 || param.cut_mesh.triangles.rows() != nf ||
      samples.barycentric.rows() != np || static_cast<Eigen::Index>(samples.face.size()) != np) {
    throw InvalidInput(std::string(fn) + ": the surface's " + std::to_string(nt) +
                       " triangles and " + std::to_string(np) + " points do not match the " +
                       std::to_string(nf) + " faces of the domain");
  }
  // tessellate_spline writes the triangles face by face, the same number for every face.
  const Eigen::Index per_face = nt / nf;
  SplineSurfaceTexture texture;
  texture.uv_triangles.resize(nt, 3);
  texture.uv.resize(3 * nt, 2);
  for (Eigen::Index t = 0; t < nt; ++t) {
    const auto f = static_cast<int>(t / per_face);
    for (int c = 0; c < 3; ++c) {
      const int p = samples.triangles(t, c);
      if (p < 0 || p >= np) {
        throw InvalidInput(std::string(fn) + ": surface triangle " + std::to_string(t) +
                           " has point " + std::to_string(p) + " out of range");
      }
      const int g = samples.face[p];
      const Eigen::Vector3d w_g = clean_barycentric(samples.barycentric.row(p).transpose());
      // The point's weights in face f: those of the vertices f shares with the point's face g
      // (the point lies on their common side or corner).
      Eigen::Vector3d w = Eigen::Vector3d::Zero();
      if (g == f) {
        w = w_g;
      } else {
        for (int a = 0; a < 3; ++a) {
          if (w_g[a] == 0) continue;
          for (int b = 0; b < 3; ++b) {
            if (domain.triangles(f, b) == domain.triangles(g, a)) w[b] += w_g[a];
          }
        }
      }
      Eigen::Vector2d uv = Eigen::Vector2d::Zero();
      for (int b = 0; b < 3; ++b) {
        if (w[b] != 0) uv += w[b] * param.uv.row(param.cut_mesh.triangles(f, b)).transpose();
      }
      texture.uv_triangles(t, c) = static_cast<int>(3 * t + c);
      texture.uv.row(3 * t + c) = uv.transpose();
    }
  }
  return texture;
}

SplinePicturesResult write_spline_pictures(const std::string& folder, const SplineResult& result,
                                           const SplinePicturesOptions& options) {
  namespace fs = std::filesystem;
  if (!result.converged || result.surface.num_faces() == 0 || result.control_net.num_faces() == 0) {
    throw InvalidInput("write_spline_pictures: the spline has no surface" +
                       (result.converged ? std::string() : ": " + result.message));
  }
  const SplineSurfaceTexture texture = spline_surface_texture(result);
  std::error_code error;
  fs::create_directories(folder, error);
  if (error || !fs::is_directory(folder)) {
    throw IoError(folder + ": cannot create the pictures folder" +
                  (error ? ": " + error.message() : std::string()));
  }
  SplinePicturesResult written;
  auto path = [&](const char* name) {
    written.files.push_back((fs::path(folder) / name).string());
    return written.files.back();
  };

  // One camera framing all three stages.
  const Mesh& domain = result.param.mesh;
  RenderOptions render = options.render;
  if (!render.camera) {
    Positions others(result.surface.num_vertices() + result.control_net.num_vertices(), 3);
    others << result.surface.positions, result.control_net.positions;
    render.camera = fit_camera(domain, render, others);
  }
  written.camera = *render.camera;

  const RenderResult domain_render =
      render_textured_mesh(domain, result.param.cut_mesh.triangles, result.param.uv, render);
  write_png(path("domain.png"), domain_render.image);
  written.domain_visible_faces = domain_render.visible_faces;

  // The control net: no texture, every edge drawn.
  RenderOptions net = render;
  net.checker_light = net.checker_dark = options.net_face;
  net.draw_seams = false;
  net.mark_cones = false;
  net.draw_edges = true;
  net.edge_colour = options.net_edge;
  net.edge_width =
      options.net_edge_width > 0
          ? options.net_edge_width
          : std::clamp(written.camera.scale * mean_edge_length(result.control_net) / 8, 0.2, 1.2);
  const Eigen::Matrix<double, Eigen::Dynamic, 2> no_uv =
      Eigen::Matrix<double, Eigen::Dynamic, 2>::Zero(result.control_net.num_vertices(), 2);
  const RenderResult net_render =
      render_textured_mesh(result.control_net, result.control_net.triangles, no_uv, net);
  write_png(path("control_net.png"), net_render.image);
  written.net_visible_faces = net_render.visible_faces;

  RenderOptions surface = render;
  surface.smooth_shading = options.smooth_surface;
  const RenderResult surface_render =
      render_textured_mesh(result.surface, texture.uv_triangles, texture.uv, surface);
  write_png(path("surface.png"), surface_render.image);
  written.surface_visible_faces = surface_render.visible_faces;
  written.surface_cones = surface_render.cones;

  write_png(path("layout.png"),
            plot_uv_layout(domain, result.param.cut_mesh.triangles, result.param.uv, options.uv));
  return written;
}

}  // namespace ricci
