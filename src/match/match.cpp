#include "ricci/match/match.hpp"

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "ricci/errors.hpp"
#include "ricci/match/domain_locator.hpp"
#include "ricci/numerics/timer.hpp"

namespace ricci {
namespace {

SurfaceMap map_vertices(const CanonicalDomain& source, const DomainAlignment& alignment,
                        const DomainLocator& target, const Triangles& source_triangles) {
  const Eigen::Index nv = source.points.rows();
  std::vector<char> used(static_cast<std::size_t>(nv), 0);
  for (Eigen::Index f = 0; f < source_triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(source_triangles(f, k))] = 1;
  }
  SurfaceMap map;
  map.face = Eigen::VectorXi::Constant(nv, -1);
  map.weights = Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(nv, 3);
  for (Eigen::Index v = 0; v < nv; ++v) {
    if (!used[static_cast<std::size_t>(v)]) continue;
    const FaceLocation at =
        target.locate(apply_alignment(alignment, source.points.row(v).transpose()));
    map.face(v) = at.face;
    map.weights.row(v) = at.weights.transpose();
    if (!at.inside) {
      ++map.outside;
      map.max_outside = std::max(map.max_outside, at.outside_by);
    }
  }
  return map;
}

Eigen::Vector3d face_normal(const Mesh& mesh, int f) {
  const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(f, 0));
  const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(f, 1));
  const Eigen::Vector3d c = mesh.positions.row(mesh.triangles(f, 2));
  return (b - a).cross(c - a);
}

// The image of a face's centroid in its domain (on the sphere, projected back onto it; on a
// torus, of the face's own copy in the laid-out fundamental domain).
Eigen::Vector3d domain_centroid(const CanonicalDomain& d, Eigen::Index f) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    const int corner = d.domain_triangles(f, k);
    if (d.kind == DomainKind::Sphere) {
      c += d.points.row(corner).transpose();
    } else {
      c.head<2>() += d.domain_uv.row(corner).transpose();
    }
  }
  return d.kind == DomainKind::Sphere ? Eigen::Vector3d(c.normalized()) : Eigen::Vector3d(c / 3);
}

// Each face of A against the triangle of its corners' images on B, flattened in its own plane,
// and mirrored when it turns against the face of B that the image of its centroid lies in.
Distortion map_distortion(const Mesh& a, const Mesh& b, const SurfaceMap& map,
                          const CanonicalDomain& domain_a, const DomainAlignment& alignment,
                          const DomainLocator& locator_b) {
  const Positions image = mapped_positions(b, map);
  const Eigen::Index nf = a.triangles.rows();
  Triangles corners(nf, 3);
  Eigen::Matrix<double, Eigen::Dynamic, 2> uv(3 * nf, 2);
  for (Eigen::Index f = 0; f < nf; ++f) {
    Eigen::Vector3d q[3];
    for (int k = 0; k < 3; ++k) {
      q[k] = image.row(a.triangles(f, k)).transpose();
      corners(f, k) = static_cast<int>(3 * f + k);
    }
    const FaceLocation centre =
        locator_b.locate(apply_alignment(alignment, domain_centroid(domain_a, f)));
    const Eigen::Vector3d surface_normal =
        centre.face >= 0 ? face_normal(b, centre.face) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d e1 = q[1] - q[0], e2 = q[2] - q[0];
    const Eigen::Vector3d n = e1.cross(e2);
    const double length = e1.norm();
    uv.row(3 * f) << 0, 0;
    if (!(length > 0) || !(n.norm() > 0)) {
      uv.row(3 * f + 1) << length, 0;
      uv.row(3 * f + 2) << length, 0;  // degenerate: measured as such
      continue;
    }
    const Eigen::Vector3d x = e1 / length;
    const Eigen::Vector3d y = n.normalized().cross(x);
    const double sign = n.dot(surface_normal) < 0 ? -1.0 : 1.0;
    uv.row(3 * f + 1) << length, 0;
    uv.row(3 * f + 2) << e2.dot(x), sign * e2.dot(y);
  }
  return measure_distortion(a, corners, uv);
}

}  // namespace

Positions mapped_positions(const Mesh& target, const SurfaceMap& map) {
  Positions p = Positions::Constant(map.face.size(), 3, std::numeric_limits<double>::quiet_NaN());
  for (Eigen::Index v = 0; v < map.face.size(); ++v) {
    const int f = map.face(v);
    if (f < 0) continue;
    p.row(v).setZero();
    for (int k = 0; k < 3; ++k)
      p.row(v) += map.weights(v, k) * target.positions.row(target.triangles(f, k));
  }
  return p;
}

MatchResult match_surfaces(const Mesh& a, const Mesh& b, const MatchOptions& options) {
  const auto start = Clock::now();
  MatchResult result;
  auto step = Clock::now();
  const auto domain_of = [&](const Mesh& mesh, const char* name) {
    try {
      return canonical_domain(mesh, options.domain);
    } catch (const InvalidInput& e) {
      throw InvalidInput(std::string(name) + ": " + e.what());
    }
  };
  const CanonicalDomain domain_a = domain_of(a, "A");
  const CanonicalDomain domain_b = domain_of(b, "B");
  result.domain_seconds = seconds_since(step);
  if (domain_a.kind != domain_b.kind) {
    throw InvalidInput(std::string("A maps to the ") + enum_name(domain_a.kind) + " and B to the " +
                       enum_name(domain_b.kind) + ": matching needs surfaces of the same topology");
  }
  result.domain = domain_a.kind;
  result.flow_iterations_a = domain_a.flow_iterations;
  result.flow_iterations_b = domain_b.flow_iterations;
  result.modulus_a = domain_a.modulus;
  result.modulus_b = domain_b.modulus;
  result.converged = domain_a.converged && domain_b.converged;
  result.exact = domain_a.exact && domain_b.exact;
  if (!domain_a.converged) result.message = "A: " + domain_a.message;
  if (!domain_b.converged)
    result.message += (result.message.empty() ? "B: " : "; B: ") + domain_b.message;

  step = Clock::now();
  AlignmentOptions align;
  align.landmarks = options.landmarks;
  align.max_samples = options.max_samples;
  result.alignment = align_domains(domain_a, domain_b, align);
  result.align_seconds = seconds_since(step);

  step = Clock::now();
  const DomainLocator locator_a(domain_a), locator_b(domain_b);
  result.forward = map_vertices(domain_a, result.alignment, locator_b, a.triangles);
  if (options.reverse)
    result.backward = map_vertices(domain_b, inverse(result.alignment), locator_a, b.triangles);
  result.locate_seconds = seconds_since(step);

  const Positions image = mapped_positions(b, result.forward);
  double sum = 0;
  for (const auto& [i, j] : options.landmarks) {
    LandmarkResidual r{i, j, (image.row(i) - b.positions.row(j)).norm()};
    sum += r.distance * r.distance;
    result.landmark_max = std::max(result.landmark_max, r.distance);
    result.landmarks.push_back(r);
  }
  if (!options.landmarks.empty())
    result.landmark_rms = std::sqrt(sum / static_cast<double>(options.landmarks.size()));
  result.b_diagonal = (b.positions.colwise().maxCoeff() - b.positions.colwise().minCoeff()).norm();
  result.distortion = map_distortion(a, b, result.forward, domain_a, result.alignment, locator_b);
  result.seconds = seconds_since(start);
  return result;
}

std::vector<Positions> morph_frames(const Mesh& a, const Positions& target, int frames,
                                    bool rigid) {
  if (frames < 2)
    throw InvalidInput("morph_frames: frames must be at least 2, not " + std::to_string(frames));
  if (target.rows() != a.positions.rows()) {
    throw InvalidInput("morph_frames: the target has " + std::to_string(target.rows()) +
                       " rows, A has " + std::to_string(a.positions.rows()) + " vertices");
  }
  Positions goal = target;
  if (rigid) {
    // Weighted Kabsch: the rotation R and translation t minimising sum w |R target + t - A|^2.
    Eigen::VectorXd w = Eigen::VectorXd::Zero(a.positions.rows());
    for (Eigen::Index f = 0; f < a.triangles.rows(); ++f) {
      const double area = 0.5 * face_normal(a, static_cast<int>(f)).norm();
      for (int k = 0; k < 3; ++k) w(a.triangles(f, k)) += area / 3;
    }
    for (Eigen::Index v = 0; v < w.size(); ++v) {
      if (!target.row(v).allFinite()) w(v) = 0;
    }
    const double total = w.sum();
    if (total > 0) {
      Eigen::RowVector3d ca = Eigen::RowVector3d::Zero(), ct = Eigen::RowVector3d::Zero();
      for (Eigen::Index v = 0; v < w.size(); ++v) {
        if (w(v) == 0) continue;
        ca += w(v) * a.positions.row(v);
        ct += w(v) * target.row(v);
      }
      ca /= total;
      ct /= total;
      Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
      for (Eigen::Index v = 0; v < w.size(); ++v) {
        if (w(v) == 0) continue;
        h += w(v) * (target.row(v) - ct).transpose() * (a.positions.row(v) - ca);
      }
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
      d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
      const Eigen::Matrix3d r = svd.matrixV() * d * svd.matrixU().transpose();
      for (Eigen::Index v = 0; v < goal.rows(); ++v) {
        goal.row(v) = (r * (target.row(v) - ct).transpose()).transpose() + ca;
      }
    }
  }
  std::vector<Positions> result;
  for (int k = 0; k < frames; ++k) {
    const double t = static_cast<double>(k) / (frames - 1);
    Positions p = (1 - t) * a.positions + t * goal;
    // Vertices with no image (unreferenced) stay where they are.
    for (Eigen::Index v = 0; v < p.rows(); ++v) {
      if (!p.row(v).allFinite()) p.row(v) = a.positions.row(v);
    }
    result.push_back(std::move(p));
  }
  return result;
}

}  // namespace ricci
