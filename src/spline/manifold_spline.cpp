#include "ricci/spline/manifold_spline.hpp"

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci {
namespace {

using Vec3 = Eigen::Vector3d;

/// Closest point of triangle abc to p, by the Voronoi regions of its vertices, edges and face.
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  }
  const double denom = va + vb + vc;
  if (!(denom > 0)) return a;  // degenerate triangle: the vertex regions answered already
  return a + ab * (vb / denom) + ac * (vc / denom);
}

}  // namespace

SplineDomain spline_domain(const Parameterization& param) {
  if (!param.converged) {
    throw InvalidInput("spline_domain: the parameterization did not converge: " + param.message);
  }
  std::vector<int> cones;
  for (const Cone& c : param.cones) cones.push_back(c.vertex);
  // The layout is of the parameterized mesh's own faces (also after edge flips).
  const Topology topology = build_topology(param.mesh.triangles, param.mesh.num_vertices());
  return spline_domain(topology, param.cut_mesh.triangles, param.layout.uv, cones);
}

SplineError measure_spline_error(const SplineDomain& d, const Positions& positions,
                                 const SplineTessellation& samples, bool measure_distance) {
  SplineError err;
  const int nf = static_cast<int>(d.triangles.rows());
  const int np = static_cast<int>(samples.values.rows());
  if (positions.rows() != d.num_vertices || samples.values.cols() != 3) {
    throw InvalidInput("measure_spline_error: need #V = " + std::to_string(d.num_vertices) +
                       " positions and 3 columns of spline values");
  }
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (int v = 0; v < d.num_vertices; ++v) {
    if (!d.referenced[v]) continue;
    lo = lo.cwiseMin(positions.row(v).transpose());
    hi = hi.cwiseMax(positions.row(v).transpose());
  }
  err.bbox_diagonal = np > 0 ? (hi - lo).norm() : 0;
  err.samples = np;
  if (np == 0 || !(err.bbox_diagonal > 0)) return err;

  // Samples grouped by face.
  std::vector<int> start(nf + 1, 0), order(np);
  for (int q = 0; q < np; ++q) ++start[samples.face[q] + 1];
  for (int f = 0; f < nf; ++f) start[f + 1] += start[f];
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int q = 0; q < np; ++q) order[fill[samples.face[q]]++] = q;
  }
  std::vector<std::vector<int>> vertex_faces(d.num_vertices);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) vertex_faces[d.triangles(f, k)].push_back(f);
  }
  std::vector<int> face_mark(nf, -1), vertex_mark(d.num_vertices, -1);
  std::vector<int> ring;
  double sum_par = 0, sum_dist = 0;
  for (int f = 0; f < nf; ++f) {
    if (start[f] == start[f + 1]) continue;
    if (measure_distance) {
      // 2-ring: faces touching a vertex of a face touching a vertex of f.
      ring.clear();
      std::vector<int> ring1;
      for (int k = 0; k < 3; ++k) {
        for (int g : vertex_faces[d.triangles(f, k)]) {
          if (face_mark[g] != f) face_mark[g] = f, ring1.push_back(g), ring.push_back(g);
        }
      }
      for (int g : ring1) {
        for (int k = 0; k < 3; ++k) {
          const int v = d.triangles(g, k);
          if (vertex_mark[v] == f) continue;
          vertex_mark[v] = f;
          for (int h : vertex_faces[v]) {
            if (face_mark[h] != f) face_mark[h] = f, ring.push_back(h);
          }
        }
      }
    }
    for (int idx = start[f]; idx < start[f + 1]; ++idx) {
      const int q = order[idx];
      const Vec3 s = samples.values.row(q).transpose();
      const Eigen::Vector3d b = samples.barycentric.row(q).transpose();
      const Vec3 pl = b[0] * positions.row(d.triangles(f, 0)).transpose() +
                      b[1] * positions.row(d.triangles(f, 1)).transpose() +
                      b[2] * positions.row(d.triangles(f, 2)).transpose();
      const double par = (s - pl).norm();
      err.max_parametric = std::max(err.max_parametric, par);
      sum_par += par * par;
      if (!measure_distance) continue;
      double best = 1e300;
      for (int g : ring) {
        const Vec3 c = closest_on_triangle(s, positions.row(d.triangles(g, 0)).transpose(),
                                           positions.row(d.triangles(g, 1)).transpose(),
                                           positions.row(d.triangles(g, 2)).transpose());
        best = std::min(best, (s - c).squaredNorm());
      }
      err.max_distance = std::max(err.max_distance, std::sqrt(best));
      sum_dist += best;
    }
  }
  const double diag = err.bbox_diagonal;
  err.max_parametric /= diag;
  err.rms_parametric = std::sqrt(sum_par / np) / diag;
  if (measure_distance) {
    err.max_distance /= diag;
    err.rms_distance = std::sqrt(sum_dist / np) / diag;
  }
  return err;
}

SplineResult fit_manifold_spline(const Mesh& mesh, const SplineOptions& options) {
  const auto start = Clock::now();
  if (options.refine < 1) {
    throw InvalidInput("fit_manifold_spline: refine must be >= 1, got " +
                       std::to_string(options.refine));
  }
  SplineResult result;
  ParamOptions param_options = options.param;
  const Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  if (topology.components.size() != 1) {
    // The spline domain is one surface's atlas; parameterize would pack several into one square.
    throw InvalidInput("fit_manifold_spline: the mesh has " +
                       std::to_string(topology.components.size()) +
                       " connected components; fit them one by one");
  }
  if (options.choose_cone_mode) {
    const Topology& t = topology;
    if (t.components.size() == 1) {
      const Component& c = t.components.front();
      if (c.num_boundary_loops > 0 || c.genus == 1) param_options.cone_mode = ConeMode::None;
    }
  }
  auto t = Clock::now();
  result.param = parameterize(mesh, param_options);
  if (result.param.converged && result.param.distortion.flipped_faces > 0 &&
      param_options.structure.scheme == Scheme::VertexScaling) {
    // Spline pieces need every chart face with positive area. The circle packings are not
    // exact on needles, and so do not fold them (igea: 1 of 268,686 faces folded by vertex
    // scaling, none by Thurston); Thurston's single-vertex bound refuses valence-3 vertices that
    // must flatten, which the tangential packing (Phi = 0) allows.
    const std::string why = std::to_string(result.param.distortion.flipped_faces) +
                            " faces of the vertex-scaling map are flipped, where no spline piece "
                            "can live; the domain is ";
    for (Scheme fallback : {Scheme::Thurston, Scheme::Tangential}) {
      ParamOptions packing = param_options;
      packing.structure.scheme = fallback;
      MeshParamResult attempt;
      try {
        attempt = parameterize(mesh, packing);
      } catch (const InvalidInput&) {
        continue;  // inadmissible for this packing
      }
      if (!attempt.converged || attempt.distortion.flipped_faces > 0) continue;
      result.param = std::move(attempt);
      result.parameterization_note = why + "the " + scheme_name(fallback) + " circle packing's";
      break;
    }
  }
  result.seconds_param = seconds_since(t);
  result.converged = result.param.converged;
  if (!result.converged) {
    result.message = "parameterization: " + result.param.message;
    result.seconds = seconds_since(start);
    return result;
  }

  t = Clock::now();
  result.domain = spline_domain(result.param);
  SplineFitOptions fit_options;
  fit_options.smoothness = options.smoothness;
  result.fit = fit_spline(result.domain, result.param.mesh.positions, fit_options);
  result.seconds_fit = seconds_since(t);

  t = Clock::now();
  result.surface_samples = tessellate_spline(result.domain, result.fit.ordinates, options.refine);
  result.surface.positions = result.surface_samples.values;
  result.surface.triangles = result.surface_samples.triangles;
  const SplineTessellation net = spline_control_net(result.domain, result.fit.ordinates);
  result.control_net.positions = net.values;
  result.control_net.triangles = net.triangles;
  result.seconds_evaluate = seconds_since(t);

  t = Clock::now();
  result.error = measure_spline_error(result.domain, result.param.mesh.positions,
                                      result.surface_samples, options.measure_distance);
  result.continuity =
      measure_continuity(result.domain, result.fit.ordinates, options.continuity_samples);
  result.seconds_error = seconds_since(t);
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace ricci
