#include "ricci/flow/target.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/metric/curvature.hpp"

namespace ricci {
namespace {

std::string format_value(double x) {
  std::ostringstream out;
  out.precision(12);
  out << x;
  return out.str();
}

/// The number a message shows for vertex v: its label when labels are given (e.g. its index in
/// the file the mesh came from), else v.
std::string vertex_label(int v, const std::vector<int>& labels) {
  return std::to_string(v >= 0 && v < static_cast<int>(labels.size()) ? labels[v] : v);
}

std::string trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t\r\n");
  return s.substr(begin, end - begin + 1);
}

/// Strict number parse: the whole text must be a finite number.
bool parse_number(const std::string& text, double& value) {
  if (text.empty()) return false;
  std::size_t used = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == text.size() && std::isfinite(value);
}

int parse_vertex_index(const std::string& text, const std::string& where) {
  std::size_t used = 0;
  long long value = -1;
  try {
    value = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || value < 0 || value > 2147483647LL) {
    throw InvalidInput(where + ": '" + text + "' is not a vertex index");
  }
  return static_cast<int>(value);
}

/// Total boundary length around each boundary vertex: half of each of its two boundary edges.
Eigen::VectorXd boundary_vertex_lengths(const Topology& t, const Eigen::VectorXd& lengths) {
  Eigen::VectorXd share = Eigen::VectorXd::Zero(t.num_vertices);
  for (int e = 0; e < t.num_edges; ++e) {
    if (!t.is_boundary_edge[e]) continue;
    share[t.edge_vertices(e, 0)] += 0.5 * lengths[e];
    share[t.edge_vertices(e, 1)] += 0.5 * lengths[e];
  }
  return share;
}

}  // namespace

bool Target::has_fixed_vertices() const {
  for (char f : fixed) {
    if (f) return true;
  }
  return false;
}

BoundaryMode parse_boundary_mode(const std::string& name) {
  return parse_enum<BoundaryMode>(name, "parse_boundary_mode");
}

const char* boundary_mode_name(BoundaryMode mode) {
  return enum_name(mode);
}

Target flat_target(const Topology& t, const std::vector<Cone>& cones, BoundaryMode boundary,
                   const Eigen::VectorXd& input_lengths, const std::vector<int>& labels) {
  Target target;
  target.curvature = Eigen::VectorXd::Zero(t.num_vertices);
  target.fixed.assign(t.num_vertices, 0);
  std::vector<char> is_cone(t.num_vertices, 0);
  std::vector<double> cone_total(t.components.size(), 0.0);
  for (const Cone& cone : cones) {
    if (cone.vertex < 0 || cone.vertex >= t.num_vertices || t.vertex_component[cone.vertex] < 0) {
      throw InvalidInput("flat_target: cone at vertex " + vertex_label(cone.vertex, labels) +
                         ", which is not a vertex of the mesh (it has " +
                         std::to_string(t.num_vertices) + ")");
    }
    if (is_cone[cone.vertex]) {
      throw InvalidInput("flat_target: vertex " + vertex_label(cone.vertex, labels) +
                         " is given two cones");
    }
    if (!std::isfinite(cone.curvature)) {
      throw InvalidInput("flat_target: cone at vertex " + vertex_label(cone.vertex, labels) +
                         " has curvature " + format_value(cone.curvature));
    }
    if (t.is_boundary_vertex[cone.vertex] && boundary == BoundaryMode::Free) {
      throw InvalidInput(
          "flat_target: cone at boundary vertex " + vertex_label(cone.vertex, labels) +
              ", whose log radius the free boundary keeps fixed; use a disk boundary "
              "or an interior vertex",
          fixes_of({{"boundary", "disk"}}));
    }
    is_cone[cone.vertex] = 1;
    target.curvature[cone.vertex] = cone.curvature;
    cone_total[t.vertex_component[cone.vertex]] += cone.curvature;
  }

  if (t.num_boundary_loops() > 0) {
    if (boundary == BoundaryMode::Free) {
      for (int v = 0; v < t.num_vertices; ++v) target.fixed[v] = t.is_boundary_vertex[v];
    } else if (boundary == BoundaryMode::Geodesic) {
      // K-bar = 0 on the boundary already (zero geodesic curvature); cones keep theirs.
    } else {
      if (boundary == BoundaryMode::DiskLength && input_lengths.size() != t.num_edges) {
        throw InvalidInput("flat_target: the disk-length boundary needs the #E input lengths");
      }
      const Eigen::VectorXd share = boundary == BoundaryMode::DiskLength
                                        ? boundary_vertex_lengths(t, input_lengths)
                                        : Eigen::VectorXd();
      for (std::size_t c = 0; c < t.components.size(); ++c) {
        const Component& comp = t.components[c];
        double total_weight = 0;
        for (int v : comp.vertices) {
          if (t.is_boundary_vertex[v] && !is_cone[v]) {
            total_weight += boundary == BoundaryMode::DiskLength ? share[v] : 1.0;
          }
        }
        if (total_weight <= 0) continue;
        const double remaining = 2 * std::numbers::pi * comp.euler_characteristic - cone_total[c];
        for (int v : comp.vertices) {
          if (t.is_boundary_vertex[v] && !is_cone[v]) {
            const double w = boundary == BoundaryMode::DiskLength ? share[v] : 1.0;
            target.curvature[v] = remaining * w / total_weight;
          }
        }
      }
    }
  }
  std::ostringstream d;
  d << "flat with " << cones.size() << (cones.size() == 1 ? " cone" : " cones");
  if (t.num_boundary_loops() > 0) d << ", " << boundary_mode_name(boundary) << " boundary";
  target.description = d.str();
  return target;
}

Target uniform_target(const Topology& t) {
  Target target;
  target.curvature = Eigen::VectorXd::Zero(t.num_vertices);
  target.fixed.assign(t.num_vertices, 0);
  for (const Component& comp : t.components) {
    const double k = 2 * std::numbers::pi * comp.euler_characteristic /
                     static_cast<double>(comp.vertices.size());
    for (int v : comp.vertices) target.curvature[v] = k;
  }
  target.description = "uniform curvature 2 pi chi / n";
  return target;
}

Target values_target(const Topology& t, const Eigen::VectorXd& values) {
  if (values.size() != t.num_vertices) {
    throw InvalidInput("values_target: " + std::to_string(values.size()) +
                       " curvature values given for " + std::to_string(t.num_vertices) +
                       " vertices");
  }
  for (int v = 0; v < t.num_vertices; ++v) {
    if (!std::isfinite(values[v])) {
      throw InvalidInput("values_target: vertex " + std::to_string(v) + " has curvature " +
                         format_value(values[v]));
    }
  }
  Target target;
  target.curvature = values;
  target.fixed.assign(t.num_vertices, 0);
  target.description = "per-vertex values";
  return target;
}

namespace {

/// Each free vertex's target below its top (2 pi inside, pi on the boundary) and, without edge
/// flips, above the single-vertex bound.
void check_vertex_targets(const Topology& t, const ConformalStructure& structure,
                          const Target& target, const AdmissibilityOptions& options) {
  const SchemeTraits& scheme = scheme_traits(structure.scheme);

  // Sum over the faces of each vertex of (pi - Phi of the opposite edge): the single-vertex
  // bound, which edge flips lift (not computed then).
  Eigen::VectorXd bound_sum;
  std::vector<int> faces_at;  // faces around each vertex, for the tangential scheme's bound
  if (!options.edge_flips) {
    bound_sum.setZero(t.num_vertices);
    faces_at.assign(t.num_vertices, 0);
    for (int f = 0; f < t.num_faces; ++f) {
      for (int k = 0; k < 3; ++k) {
        bound_sum[t.triangles(f, k)] += max_face_angle(scheme, structure.eta[t.face_edges(f, k)]);
        ++faces_at[t.triangles(f, k)];
      }
    }
  }
  for (int v = 0; v < t.num_vertices; ++v) {
    if (t.vertex_component[v] < 0 || target.fixed[v]) continue;
    const double k = target.curvature[v];
    const double top = t.is_boundary_vertex[v] ? std::numbers::pi : 2 * std::numbers::pi;
    const double lower = options.edge_flips ? 0.0 : top - bound_sum[v];
    const char* where = t.is_boundary_vertex[v] ? "boundary vertex " : "vertex ";
    if (!std::isfinite(k)) {
      throw InvalidInput("check_admissible: " + std::string(where) +
                         vertex_label(v, options.vertex_labels) + " has target curvature " +
                         format_value(k));
    }
    if (!(k < top)) {
      throw InvalidInput("check_admissible: " + std::string(where) +
                         vertex_label(v, options.vertex_labels) + " has target curvature " +
                         format_value(k) + ", which must be below " + format_value(top) +
                         " (its angle sum must stay positive)");
    }
    if (!options.edge_flips && !(k > lower)) {
      // The tangential scheme (Phi = 0, pi per face) has the widest bound of the packings: a
      // fix only where the target keeps to it.
      const bool tangential =
          scheme.fitted_intersection_angles && k > top - std::numbers::pi * faces_at[v];
      throw InvalidInput(
          "check_admissible: " + std::string(where) + vertex_label(v, options.vertex_labels) +
              " (valence " + std::to_string(t.vertex_degree[v]) + ") has target curvature " +
              format_value(k) + ", which breaks the single-vertex bound K > " +
              format_value(lower) +
              (scheme.circle_packing ? " (2 pi - sum of (pi - Phi) over its faces)"
                                     : " (each angle below pi)") +
              "; split edges around it to raise its valence, or use vertex scaling with edge flips "
              "(no such bound)" +
              (tangential ? ", or the tangential scheme (Phi = 0 gives the widest bound)" : ""),
          scheme.ptolemy_flips ? fixes_of({{"flips", "auto"}})
          : tangential         ? fixes_of({{"scheme", "vertex-scaling"}, {"scheme", "tangential"}})
                               : fixes_of({{"scheme", "vertex-scaling"}}));
    }
  }
}

/// Gauss-Bonnet of each component's target (fixed vertices exempt it): sum K-bar = 2 pi chi, or
/// above it by the area in the hyperbolic background.
void check_gauss_bonnet(const Topology& t, const ConformalStructure& structure,
                        const Target& target, const AdmissibilityOptions& options) {
  for (std::size_t c = 0; c < t.components.size(); ++c) {
    const Component& comp = t.components[c];
    bool any_fixed = false;
    double sum = 0, compensation = 0, magnitude = 0;
    for (int v : comp.vertices) {
      any_fixed = any_fixed || target.fixed[v];
      const double x = target.curvature[v];
      const double s = sum + x;
      compensation += std::abs(sum) >= std::abs(x) ? (sum - s) + x : (x - s) + sum;
      sum = s;
      magnitude += std::abs(x);
    }
    if (any_fixed) continue;
    sum += compensation;
    const double expected = 2 * std::numbers::pi * comp.euler_characteristic;
    if (geometry_traits(structure.geometry).area_in_gauss_bonnet) {
      // sum K - area = 2 pi chi with a positive area: the sum must exceed 2 pi chi.
      if (!(sum - expected >
            options.gauss_bonnet_tolerance * std::max(2 * std::numbers::pi, magnitude))) {
        throw InvalidInput("check_admissible: component " + std::to_string(c) +
                               " cannot carry a hyperbolic metric with this target: its target "
                               "curvatures sum to " +
                               format_value(sum) +
                               ", which must exceed 2 pi chi = " + format_value(expected) +
                               " (chi = " + std::to_string(comp.euler_characteristic) +
                               ") by the metric's area; zero curvature needs chi < 0 (genus >= 2, "
                               "or boundaries); use the Euclidean geometry for this surface",
                           fixes_of({{"geometry", "euclidean"}}));
      }
      continue;
    }
    if (std::abs(sum - expected) >
        options.gauss_bonnet_tolerance * std::max(2 * std::numbers::pi, magnitude)) {
      throw InvalidInput("check_admissible: component " + std::to_string(c) +
                             " breaks Gauss-Bonnet: its target curvatures sum to " +
                             format_value(sum) +
                             " but must sum to 2 pi chi = " + format_value(expected) +
                             " (chi = " + std::to_string(comp.euler_characteristic) +
                             "); give cones that make up the difference, or use the natural or "
                             "uniform target (automatic cones: parameterize)",
                         fixes_of({{"target", "natural"}, {"target", "uniform"}}));
    }
  }
}

}  // namespace

void check_admissible(const Topology& t, const ConformalStructure& structure, const Target& target,
                      const AdmissibilityOptions& options) {
  if (target.curvature.size() != t.num_vertices ||
      static_cast<int>(target.fixed.size()) != t.num_vertices) {
    throw InvalidInput("check_admissible: the target has " +
                       std::to_string(target.curvature.size()) + " values for " +
                       std::to_string(t.num_vertices) + " vertices");
  }
  check_vertex_targets(t, structure, target, options);
  check_gauss_bonnet(t, structure, target, options);
}

double parse_curvature(const std::string& raw) {
  const std::string text = trim(raw);
  double value = 0;
  if (parse_number(text, value)) return value;
  // Forms with pi: [sign][number][*]pi[/number]
  const auto at = text.find("pi");
  if (at != std::string::npos) {
    std::string before = trim(text.substr(0, at));
    std::string after = trim(text.substr(at + 2));
    if (!before.empty() && before.back() == '*') before = trim(before.substr(0, before.size() - 1));
    double factor = 1;
    if (before == "-") {
      factor = -1;
    } else if (before == "+" || before.empty()) {
      factor = 1;
    } else if (!parse_number(before, factor)) {
      factor = NAN;
    }
    double divisor = 1;
    if (!after.empty()) {
      if (after[0] != '/' || !parse_number(trim(after.substr(1)), divisor) || divisor == 0) {
        divisor = NAN;
      }
    }
    value = factor * std::numbers::pi / divisor;
    if (std::isfinite(value)) return value;
  }
  throw InvalidInput("parse_curvature: '" + raw +
                     "' is not a curvature (examples: 1.5708, pi/2, -0.5pi, 3*pi/4)");
}

std::vector<Cone> parse_cone_list(const std::string& text) {
  std::vector<Cone> cones;
  std::stringstream items(text);
  std::string item;
  while (std::getline(items, item, ',')) {
    item = trim(item);
    if (item.empty()) continue;
    const auto colon = item.find(':');
    if (colon == std::string::npos) {
      throw InvalidInput("parse_cone_list: '" + item +
                         "' is not VERTEX:CURVATURE (for example 17:pi/2)");
    }
    Cone cone;
    cone.vertex = parse_vertex_index(trim(item.substr(0, colon)), "parse_cone_list");
    cone.curvature = parse_curvature(item.substr(colon + 1));
    cones.push_back(cone);
  }
  return cones;
}

namespace {

/// Calls visit(text, where) for every line of a text file that holds more than a comment
/// ('#' to the end of the line); where is "path:line" for messages.
template <class Visit>
void for_each_data_line(const std::string& path, const char* what, Visit visit) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open the " + what + " file");
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    const std::string text = trim(line);
    if (!text.empty()) visit(text, path + ":" + std::to_string(number));
  }
}

}  // namespace

std::vector<Cone> read_cone_file(const std::string& path) {
  std::vector<Cone> cones;
  for_each_data_line(path, "cone", [&](const std::string& text, const std::string& where) {
    std::stringstream fields(text);
    std::string vertex, curvature, extra;
    fields >> vertex;
    if (!(fields >> curvature) || (fields >> extra)) {
      throw InvalidInput(where + ": expected 'vertex curvature', got '" + text + "'");
    }
    Cone cone;
    cone.vertex = parse_vertex_index(vertex, where);
    try {
      cone.curvature = parse_curvature(curvature);
    } catch (const InvalidInput&) {
      throw InvalidInput(where + ": '" + curvature + "' is not a curvature");
    }
    cones.push_back(cone);
  });
  return cones;
}

Eigen::VectorXd read_values_file(const std::string& path) {
  std::vector<double> values;
  for_each_data_line(path, "curvature", [&](const std::string& text, const std::string& where) {
    try {
      values.push_back(parse_curvature(text));
    } catch (const InvalidInput&) {
      throw InvalidInput(where + ": '" + text + "' is not a curvature value");
    }
  });
  if (values.empty()) throw IoError(path + ": no curvature values in the file");
  return Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

}  // namespace ricci
