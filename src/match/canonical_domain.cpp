#include "ricci/match/canonical_domain.hpp"

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "ricci/errors.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/mesh/validate.hpp"
#include "ricci/numerics/timer.hpp"
#include "ricci/param/parameterize.hpp"
#include "ricci/sphere/sphere.hpp"

namespace ricci {
namespace {

double triangle_area_3d(const Positions& p, const Triangles& t, Eigen::Index f) {
  const Eigen::Vector3d a = p.row(t(f, 0)), b = p.row(t(f, 1)), c = p.row(t(f, 2));
  return 0.5 * (b - a).cross(c - a).norm();
}

double triangle_area_2d(const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv, const Triangles& t,
                        Eigen::Index f) {
  const Eigen::Vector2d a = uv.row(t(f, 0)), b = uv.row(t(f, 1)), c = uv.row(t(f, 2));
  const Eigen::Vector2d u = b - a, v = c - a;
  return 0.5 * std::abs(u.x() * v.y() - u.y() * v.x());
}

// The flat metric of a disk or a torus without cones, laid out exactly (no polish, no charts: a
// matching needs the conformal map itself); untangled only on the second try, where the exact
// layout folds (a few vertices then move off the conformal map into their stars).
ParamResult flat_layout(const Mesh& mesh, const CanonicalDomainOptions& options,
                        BoundaryMode boundary, bool untangle) {
  ParamOptions param;
  param.cone_mode = ConeMode::None;
  param.boundary = boundary;
  param.structure = options.structure;
  param.flow = options.flow;
  param.polish.enabled = false;
  param.fold_free.untangle = untangle;
  param.fold_free.charts = false;
  MeshParamResult result = parameterize(mesh, param);
  ParamResult one;
  static_cast<Parameterization&>(one) = static_cast<Parameterization&>(result);
  return one;
}

// Kasa's algebraic circle fit: x^2 + y^2 + D x + E y + F = 0 in least squares.
void fit_unit_circle(const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
                     const std::vector<int>& boundary, Eigen::Vector2d& centre, double& radius) {
  Eigen::MatrixXd a(boundary.size(), 3);
  Eigen::VectorXd rhs(boundary.size());
  for (std::size_t i = 0; i < boundary.size(); ++i) {
    const Eigen::Vector2d p = uv.row(boundary[i]);
    a.row(static_cast<Eigen::Index>(i)) << p.x(), p.y(), 1.0;
    rhs(static_cast<Eigen::Index>(i)) = -p.squaredNorm();
  }
  const Eigen::Vector3d def = a.colPivHouseholderQr().solve(rhs);
  centre = Eigen::Vector2d(-def(0) / 2, -def(1) / 2);
  radius = std::sqrt(std::max(centre.squaredNorm() - def(2), 0.0));
}

}  // namespace

std::array<std::complex<double>, 2> reduce_lattice(std::complex<double> b0,
                                                   std::complex<double> b1) {
  for (int step = 0; step < 200; ++step) {
    if (std::norm(b1) < std::norm(b0)) std::swap(b0, b1);
    const double m = std::round((std::conj(b0) * b1).real() / std::norm(b0));
    if (m == 0) break;
    b1 -= m * b0;
  }
  if ((b1 / b0).imag() < 0) b1 = -b1;
  return {b0, b1};
}

namespace {

// One try at the domain: `exact` with the options as given and the sphere's exact pole star,
// otherwise with the flow's isometric start and the length-proportional pole boundary.
CanonicalDomain map_to_domain(const Mesh& mesh, const CanonicalDomainOptions& options, bool exact) {
  const auto start = Clock::now();
  const Topology topology = build_topology(mesh.triangles, mesh.num_vertices());
  if (topology.components.size() != 1) {
    throw InvalidInput("matching needs one connected surface; this mesh has " +
                       std::to_string(topology.components.size()) + " components");
  }
  const Component& component = topology.components.front();
  CanonicalDomain domain;
  if (component.genus == 0 && component.num_boundary_loops == 0) {
    domain.kind = DomainKind::Sphere;
  } else if (component.genus == 0 && component.num_boundary_loops == 1) {
    domain.kind = DomainKind::Disk;
  } else if (component.genus == 1 && component.num_boundary_loops == 0) {
    domain.kind = DomainKind::Torus;
  } else {
    throw InvalidInput(
        "matching maps closed genus-0 surfaces, disks and closed genus-1 surfaces; "
        "this one has genus " +
        std::to_string(component.genus) + " and " + std::to_string(component.num_boundary_loops) +
        " boundary loops");
  }
  const int nv = mesh.num_vertices();
  const Eigen::Index nf = mesh.triangles.rows();
  domain.points = Positions::Zero(nv, 3);
  domain.area_share.resize(nf);
  for (Eigen::Index f = 0; f < nf; ++f) {
    domain.area_share(f) = triangle_area_3d(mesh.positions, mesh.triangles, f);
  }
  domain.area_share /= domain.area_share.sum();
  Eigen::VectorXd domain_area(nf);

  if (domain.kind == DomainKind::Sphere) {
    SphereOptions sphere;
    sphere.structure = options.structure;
    sphere.flow = options.flow;
    sphere.flow.isometric_start = options.flow.isometric_start || !exact;
    sphere.exact_pole_star = exact;
    const SphereResult map = sphere_map(mesh, sphere);
    domain.exact = map.exact_pole_star && !sphere.flow.isometric_start;
    domain.converged = map.valid;
    domain.message = map.message;
    domain.points = map.positions;
    domain.domain_triangles = mesh.triangles;
    for (const auto& c : map.flow.components) domain.flow_iterations += c.flow.iterations;
    for (Eigen::Index f = 0; f < nf; ++f) {
      domain_area(f) = triangle_area_3d(domain.points, mesh.triangles, f);
    }
  } else {
    const bool disk = domain.kind == DomainKind::Disk;
    CanonicalDomainOptions flat_options = options;
    flat_options.flow.isometric_start = options.flow.isometric_start || !exact;
    const ParamResult flat = flat_layout(
        mesh, flat_options, disk ? BoundaryMode::DiskLength : BoundaryMode::Free, !exact);
    // The disk's boundary turns in proportion to its length: never exact.
    domain.exact = !disk && !flat_options.flow.isometric_start;
    for (const auto& c : flat.flow.components) domain.flow_iterations += c.flow.iterations;
    const int flipped = flat.untangle.flipped_before > 0 ? flat.untangle.flipped_after
                                                         : flat.layout.num_flipped_faces;
    domain.converged = flat.converged && flipped == 0;
    domain.message = flat.message;
    if (flat.converged && flipped > 0) {
      domain.message = "the layout of the flat metric flips " + std::to_string(flipped) + " faces";
    }
    domain.untangled_vertices = flat.untangle.moved_vertices;
    Eigen::Matrix<double, Eigen::Dynamic, 2> uv = flat.layout.uv;
    domain.domain_triangles = flat.cut_mesh.triangles;
    domain.domain_vertex = flat.cut_mesh.to_original;
    if (disk) {
      Eigen::Vector2d centre;
      double radius = 1;
      fit_unit_circle(uv, topology.boundary_loops.front(), centre, radius);
      uv = (uv.rowwise() - centre.transpose()) / radius;
    } else {
      if (flat.layout.lattice.size() != 2) {
        domain.converged = false;
        if (domain.message.empty()) domain.message = "the flat torus's lattice was not found";
        domain.lattice = {std::complex<double>(1, 0), std::complex<double>(0, 1)};
      } else {
        auto lattice = reduce_lattice(flat.layout.lattice[0], flat.layout.lattice[1]);
        // Area 1, and the shorter period along the positive real axis.
        const double area = std::abs((std::conj(lattice[0]) * lattice[1]).imag());
        const std::complex<double> turn =
            std::conj(lattice[0]) / std::abs(lattice[0]) / std::sqrt(area);
        for (Eigen::Index i = 0; i < uv.rows(); ++i) {
          const std::complex<double> z = turn * std::complex<double>(uv(i, 0), uv(i, 1));
          uv.row(i) << z.real(), z.imag();
        }
        domain.lattice = {lattice[0] * turn, lattice[1] * turn};
        domain.modulus = domain.lattice[1] / domain.lattice[0];
      }
    }
    domain.domain_uv = uv;
    // Vertex v keeps row v of the cut mesh for its first copy (slice), so the first #V rows are
    // the vertices' own points.
    domain.points.leftCols(2) = uv.topRows(nv);
    for (Eigen::Index f = 0; f < nf; ++f)
      domain_area(f) = triangle_area_2d(uv, domain.domain_triangles, f);
  }

  domain_area /= domain_area.sum();
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(nv);
  domain.log_area_factor = Eigen::VectorXd::Zero(nv);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const double ratio =
        domain_area(f) > 0 ? std::log(domain_area(f) / domain.area_share(f)) : -50.0;
    for (int k = 0; k < 3; ++k) {
      domain.log_area_factor(mesh.triangles(f, k)) += domain.area_share(f) * ratio;
      weight(mesh.triangles(f, k)) += domain.area_share(f);
    }
  }
  for (int v = 0; v < nv; ++v) {
    if (weight(v) > 0) domain.log_area_factor(v) /= weight(v);
  }
  domain.seconds = seconds_since(start);
  return domain;
}

}  // namespace

CanonicalDomain canonical_domain(const Mesh& mesh, const CanonicalDomainOptions& options) {
  validate_mesh(mesh, "canonical_domain");
  // A flow that breaks a triangle at its start (the exact pole star's boundary) or a layout that
  // folds is tried again the default way: a map, if not an exactly Moebius-invariant one.
  std::string first_failure;
  try {
    CanonicalDomain domain = map_to_domain(mesh, options, true);
    if (domain.converged) return domain;
    first_failure = domain.message;
  } catch (const TopologyError&) {
    throw;
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    // Topology and defect refusals are final; a flow's refusal of its start is not.
    if (what.rfind("RicciFlow", 0) != 0) throw;
    first_failure = what;
  }
  CanonicalDomain domain = map_to_domain(mesh, options, false);
  domain.exact = false;
  if (!domain.converged && domain.message != first_failure) {
    domain.message += " (with the exact options: " + first_failure + ")";
  }
  return domain;
}

}  // namespace ricci
