#include "mesh/io/detail/reader_support.hpp"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <numeric>

#include <Eigen/Geometry>

#include "mesh/io/detail/file_polygons.hpp"
#include "ricci/errors.hpp"

namespace ricci::io_detail {

// ---------------------------------------------------------------------------------------------
// Error formatting

std::string describe(Where where) {
  return (where.is_byte ? "byte " : "line ") + std::to_string(where.value);
}

std::string quote(std::string_view token) {
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < 40; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (std::isprint(c)) {
      out += static_cast<char>(c);
    } else {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\x%02x", c);
      out += buffer;
    }
  }
  if (token.size() > 40) out += "...";
  return out + "'";
}

void io_error(const std::string& path, const std::string& what) {
  throw IoError(path + ": " + what);
}

void io_error(const std::string& path, Where where, const std::string& what) {
  throw IoError(path + ": " + describe(where) + ": " + what);
}

void bad_vertex_index(const std::string& path, Where where, std::int64_t face,
                      std::string_view index, const std::string& range) {
  throw InvalidInput(path + ": " + describe(where) + ": face " + std::to_string(face) +
                     " uses vertex index " + std::string(index) + ", " + range);
}

void too_few_corners(const std::string& path, Where where, std::int64_t face, std::int64_t count) {
  io_error(path, where,
           "face " + std::to_string(face) + " has " + std::to_string(count) +
               " corners, need at least 3");
}

// ---------------------------------------------------------------------------------------------
// Number parsing

std::optional<double> parse_double(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (end != token.data() + token.size() || token.empty()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) {
    // Overflow or underflow: strtod gives the limit value (inf or 0), which is what the number
    // means; validation rejects the infinite ones.
    return std::strtod(std::string(token).c_str(), nullptr);
  }
  if (ec != std::errc()) return std::nullopt;
  return value;
}

std::optional<std::int64_t> parse_integer(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (end != token.data() + token.size() || token.empty()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) {
    return token[0] == '-' ? std::numeric_limits<std::int64_t>::min()
                           : std::numeric_limits<std::int64_t>::max();
  }
  if (ec != std::errc()) return std::nullopt;
  return value;
}

namespace {

/// A fan triangle whose doubled area is below this fraction of its longest squared side is a
/// sliver (a sine under 1e-12: the angle a few rounding errors make): the polygon is then ear
/// clipped instead of fanned.
constexpr double kSliverFanArea = 1e-12;

/// Strips a trailing backslash (and the blanks around it) from `line`; true when there was one.
bool strip_continuation(std::string_view& line) {
  std::string_view trimmed = line;
  while (!trimmed.empty() && is_space(trimmed.back())) trimmed.remove_suffix(1);
  if (trimmed.empty() || trimmed.back() != '\\') return false;
  trimmed.remove_suffix(1);
  line = trimmed;
  return true;
}

}  // namespace

bool ObjStatementReader::next(std::string_view& statement) {
  std::string_view line;
  if (!lines_.next(line)) return false;
  first_line_ = lines_.line_number();
  line = strip_comment(line);
  if (!strip_continuation(line)) {
    statement = line;
    return true;
  }
  joined_.assign(line);
  bool more = true;
  while (more && lines_.next(line)) {
    line = strip_comment(line);
    more = strip_continuation(line);
    joined_ += ' ';
    joined_ += line;
  }
  statement = joined_;
  return true;
}

void add_text_vertex(const std::string& path, Where here, std::string_view rest, RawMesh& raw) {
  double x[3];
  int count = 0;
  for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
    const auto value = parse_double(token);
    if (!value) {
      io_error(
          path, here,
          "malformed number " + quote(token) + " in vertex " + std::to_string(raw.num_vertices()));
    }
    if (count < 3) x[count] = *value;
    ++count;
  }
  if (count < 3) {
    io_error(path, here,
             "vertex " + std::to_string(raw.num_vertices()) + " has " + std::to_string(count) +
                 " coordinates, need 3");
  }
  raw.add_vertex(x[0], x[1], x[2], here.value);
}

// ---------------------------------------------------------------------------------------------
// Triangulation and assembly

namespace {

/// Triangulates one planar-ish polygon by ear clipping in the plane of its Newell normal.
/// Returns false (leaving `out` untouched) when no ear can be found, e.g. for a self-intersecting
/// polygon.
bool ear_clip(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& normal,
              std::vector<std::array<int, 3>>& out) {
  const int n = static_cast<int>(points.size());
  Eigen::Vector3d u = normal.unitOrthogonal();
  Eigen::Vector3d w = normal.normalized().cross(u);
  std::vector<Eigen::Vector2d> plane(n);
  for (int i = 0; i < n; ++i) plane[i] = {points[i].dot(u), points[i].dot(w)};
  auto cross = [&](int a, int b, int c) {
    return (plane[b] - plane[a]).x() * (plane[c] - plane[a]).y() -
           (plane[b] - plane[a]).y() * (plane[c] - plane[a]).x();
  };
  std::vector<int> remaining(n);
  std::iota(remaining.begin(), remaining.end(), 0);
  std::vector<std::array<int, 3>> triangles;
  while (remaining.size() > 3) {
    const int m = static_cast<int>(remaining.size());
    bool clipped = false;
    for (int i = 0; i < m && !clipped; ++i) {
      const int a = remaining[(i + m - 1) % m], b = remaining[i], c = remaining[(i + 1) % m];
      if (cross(a, b, c) <= 0) continue;  // reflex or degenerate corner
      bool empty = true;
      for (int j : remaining) {
        if (j == a || j == b || j == c) continue;
        if (cross(a, b, j) >= 0 && cross(b, c, j) >= 0 && cross(c, a, j) >= 0) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      triangles.push_back({a, b, c});
      remaining.erase(remaining.begin() + i);
      clipped = true;
    }
    if (!clipped) return false;
  }
  if (cross(remaining[0], remaining[1], remaining[2]) <= 0) return false;
  triangles.push_back({remaining[0], remaining[1], remaining[2]});
  out = std::move(triangles);
  return true;
}

struct Triangulation {
  Triangles triangles;
  std::vector<int> polygon_of_triangle;
  /// 3 per triangle: the file corner (index into RawMesh::corners) at each of its corners.
  std::vector<int> triangle_corners;
  int polygons_triangulated = 0;
  int ear_clipped = 0;
};

/// Splits polygons into triangles: a fan from the first corner when every fan triangle is
/// non-degenerate and turns like the polygon, otherwise ear clipping.
Triangulation triangulate(const RawMesh& raw) {
  Triangulation out;
  const int np = raw.num_polygons();
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(raw.corners.size() / 3 + 1);
  out.polygon_of_triangle.reserve(triangles.capacity());
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> local;
  auto point = [&](int v) {
    return Eigen::Vector3d(raw.xyz[3 * v], raw.xyz[3 * v + 1], raw.xyz[3 * v + 2]);
  };
  for (int p = 0; p < np; ++p) {
    const int* corner = raw.corners.data() + raw.polygon_start[p];
    const int n = raw.polygon_start[p + 1] - raw.polygon_start[p];
    const int first = raw.polygon_start[p];
    if (n == 3) {
      triangles.push_back({corner[0], corner[1], corner[2]});
      out.polygon_of_triangle.push_back(p);
      out.triangle_corners.insert(out.triangle_corners.end(), {first, first + 1, first + 2});
      continue;
    }
    ++out.polygons_triangulated;
    points.resize(n);
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // Newell's normal
    for (int i = 0; i < n; ++i) points[i] = point(corner[i]);
    for (int i = 0; i < n; ++i) normal += points[i].cross(points[(i + 1) % n]);
    bool fan = true;
    if (normal.allFinite() && normal.squaredNorm() > 0) {
      for (int i = 1; i + 1 < n && fan; ++i) {
        const Eigen::Vector3d a = points[i] - points[0], b = points[i + 1] - points[0];
        const Eigen::Vector3d c = a.cross(b);
        const double longest = std::max({a.squaredNorm(), b.squaredNorm(), (b - a).squaredNorm()});
        fan = c.dot(normal) > 0 && c.norm() > kSliverFanArea * longest;
      }
      if (!fan && ear_clip(points, normal, local)) {
        ++out.ear_clipped;
        for (const auto& t : local) {
          triangles.push_back({corner[t[0]], corner[t[1]], corner[t[2]]});
          out.polygon_of_triangle.push_back(p);
          out.triangle_corners.insert(out.triangle_corners.end(),
                                      {first + t[0], first + t[1], first + t[2]});
        }
        continue;
      }
    }
    for (int i = 1; i + 1 < n; ++i) {  // the fan, also the fallback when ear clipping fails
      triangles.push_back({corner[0], corner[i], corner[i + 1]});
      out.polygon_of_triangle.push_back(p);
      out.triangle_corners.insert(out.triangle_corners.end(), {first, first + i, first + i + 1});
    }
  }
  out.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) out.triangles(static_cast<Eigen::Index>(t), k) = triangles[t][k];
  }
  return out;
}

bool element_is_vertex(DefectKind kind) {
  return kind == DefectKind::NonFiniteCoordinate || kind == DefectKind::NonManifoldVertex ||
         kind == DefectKind::UnreferencedVertex;
}

/// Moves `file_mesh` into result.mesh without the vertices no triangle uses, filling
/// result.dropped_vertices and result.vertex_map and warning about the dropped ones.
void drop_unreferenced_vertices(const std::string& path, const RawMesh& raw, Mesh file_mesh,
                                ReadResult& result) {
  const int nv = raw.num_vertices();
  std::vector<int> new_index(nv, -1);
  for (Eigen::Index f = 0; f < file_mesh.triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) new_index[file_mesh.triangles(f, k)] = 0;
  }
  for (int v = 0; v < nv; ++v) {
    if (new_index[v] < 0) {
      result.dropped_vertices.push_back(v);
    } else {
      new_index[v] = static_cast<int>(result.vertex_map.size());
      result.vertex_map.push_back(v);
    }
  }
  if (result.dropped_vertices.empty()) {
    result.mesh = std::move(file_mesh);
    return;
  }
  const int first = result.dropped_vertices.front();
  result.warnings.push_back(path + ": " + std::to_string(result.dropped_vertices.size()) +
                            " unreferenced vertices dropped (the first is vertex " +
                            std::to_string(first) + " at " + describe(raw.vertex_at(first)) + ")");
  result.mesh.positions.resize(static_cast<Eigen::Index>(result.vertex_map.size()), 3);
  for (std::size_t v = 0; v < result.vertex_map.size(); ++v) {
    result.mesh.positions.row(static_cast<Eigen::Index>(v)) =
        file_mesh.positions.row(result.vertex_map[v]);
  }
  result.mesh.triangles = std::move(file_mesh.triangles);
  for (Eigen::Index f = 0; f < result.mesh.triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      result.mesh.triangles(f, k) = new_index[result.mesh.triangles(f, k)];
    }
  }
}

/// throw_first_defect on the file's own triangles, with ReadOptions::repair as the fix when
/// repair_mesh would make them valid.
[[noreturn]] void throw_defect_with_repair_fix(const ValidationReport& report,
                                               const std::string& context, const Mesh& mesh,
                                               const RepairOptions& repair_options) {
  std::vector<OptionFix> fixes;
  try {
    if (find_defects(repair_mesh(mesh, repair_options).mesh).ok()) {
      fixes = fixes_of({{"repair", "true"}});
    }
  } catch (const Error&) {  // no fix known
  }
  try {
    throw_first_defect(report, context);
  } catch (const TopologyError& e) {
    throw TopologyError(e.what(), fixes);
  } catch (const InvalidInput& e) {
    throw InvalidInput(e.what(), fixes);
  }
  throw InvalidInput(context + ": defective mesh");  // throw_first_defect always throws
}

/// Why a defect is still there after repair_mesh.
std::string unrepaired_reason(DefectKind kind) {
  switch (kind) {
    case DefectKind::ZeroAreaFace:
      return "repair removes zero-area faces only where it can without changing the surface (a "
             "vertex on the longest edge of its face, the faces around it manifold): fix the "
             "geometry, or weld nearly coincident vertices (RepairOptions::weld_tolerance)";
    case DefectKind::NonFiniteCoordinate:
      return "repair does not change coordinates";
    case DefectKind::NonOrientable:
      return "repair cannot orient a non-orientable surface";
    default:
      return "repair could not fix this defect";
  }
}

/// A warning when referenced vertices share their exact position (unwelded seams, which make
/// boundaries where the surface looks closed); empty when none do.
std::string duplicate_position_warning(const std::string& path, const RawMesh& raw,
                                       const Mesh& mesh) {
  const int nv = raw.num_vertices();
  std::vector<char> referenced(nv, 0);
  for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f) {
    for (int k = 0; k < 3; ++k) referenced[mesh.triangles(f, k)] = 1;
  }
  // Positions in a hash table (open addressing, linear probing), vertices in increasing order:
  // each vertex whose position an earlier one holds counts, the first such is the example.
  // (-0 and 0 are one position, as they compare equal.)
  const auto& P = mesh.positions;
  std::size_t size = 16;
  while (size < 2 * static_cast<std::size_t>(nv)) size *= 2;
  std::vector<int> table(size, -1);
  const auto bits = [](double x) {
    const double zeroed = x + 0.0;  // -0 -> 0
    std::uint64_t b;
    std::memcpy(&b, &zeroed, sizeof b);
    return b;
  };
  int count = 0, example = -1, example_of = -1;
  for (int v = 0; v < nv; ++v) {
    if (!referenced[v] || !P.row(v).allFinite()) continue;
    std::uint64_t h = bits(P(v, 0)) * 0x9E3779B97F4A7C15ull;
    h = (h ^ (h >> 29) ^ bits(P(v, 1))) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 31) ^ bits(P(v, 2))) * 0x94D049BB133111EBull;
    std::size_t slot = (h ^ (h >> 32)) & (size - 1);
    while (table[slot] >= 0 && P.row(table[slot]) != P.row(v)) slot = (slot + 1) & (size - 1);
    if (table[slot] < 0) {
      table[slot] = v;
    } else if (count++ == 0) {
      example = v;
      example_of = table[slot];
    }
  }
  if (count == 0) return "";
  return path + ": " + std::to_string(count) +
         " vertices repeat the position of another vertex and are kept apart (e.g. vertex " +
         std::to_string(example) + " at " + describe(raw.vertex_at(example)) + " and vertex " +
         std::to_string(example_of) + "); repair welds them";
}

}  // namespace

ReadResult assemble(const std::string& path, MeshFormat format, RawMesh raw,
                    const ReadOptions& options) {
  ReadResult result;
  result.format = format;
  result.warnings = std::move(raw.warnings);
  const int nv = raw.num_vertices();
  if (raw.num_polygons() == 0) {
    io_error(path, "no faces (the file holds " + std::to_string(nv) + " vertices and no face)");
  }
  // OBJ may name vertices defined further down; now that all are known, check every index.
  for (int p = 0; p < raw.num_polygons(); ++p) {
    for (int i = raw.polygon_start[p]; i < raw.polygon_start[p + 1]; ++i) {
      if (raw.corners[i] < nv) continue;
      bad_vertex_index(path, raw.polygon_at(p), p,
                       std::to_string(static_cast<std::int64_t>(raw.corners[i]) + raw.index_base),
                       "but the file has only " + std::to_string(nv) + " vertices");
    }
  }

  Triangulation triangulation = triangulate(raw);
  result.polygons_triangulated = triangulation.polygons_triangulated;
  if (triangulation.polygons_triangulated > 0) {
    std::string warning = path + ": " + std::to_string(triangulation.polygons_triangulated) +
                          " polygons with more than 3 corners triangulated";
    if (triangulation.ear_clipped > 0) {
      warning += " (" + std::to_string(triangulation.ear_clipped) +
                 " by ear clipping, where a fan would fold or degenerate)";
    }
    result.warnings.push_back(warning);
  }

  Mesh file_mesh;
  file_mesh.positions = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      raw.xyz.data(), nv, 3);
  file_mesh.triangles = std::move(triangulation.triangles);
  result.file_vertices = nv;

  // The file position of a defect of the file's own triangles.
  auto file_position = [&](const Defect& defect) {
    return element_is_vertex(defect.kind)
               ? raw.vertex_at(defect.element)
               : raw.polygon_at(triangulation.polygon_of_triangle[defect.element]);
  };
  bool repair = options.repair;
  std::optional<ValidationReport> as_read;  // the file's defects, where auto_repair looked
  if (!repair && options.auto_repair) {
    as_read = find_defects(file_mesh);
    repair = !as_read->ok();
  }
  if (!repair) {
    if (std::string warning = duplicate_position_warning(path, raw, file_mesh); !warning.empty()) {
      result.warnings.push_back(std::move(warning));
    }
    if (options.validate) {
      result.validation = as_read ? std::move(*as_read) : find_defects(file_mesh);
      for (const Defect& defect : result.validation.defects) {
        if (defect.kind == DefectKind::UnreferencedVertex) continue;
        throw_defect_with_repair_fix(result.validation,
                                     path + ": " + describe(file_position(defect)), file_mesh,
                                     options.repair_options);
      }
    }
    drop_unreferenced_vertices(path, raw, std::move(file_mesh), result);
    result.polygons = file_polygons(raw.polygon_start, triangulation.polygon_of_triangle,
                                    triangulation.triangle_corners, result.mesh.triangles, {}, {});
    return result;
  }
  if (as_read) {
    for (const Defect& defect : as_read->defects) {
      if (defect.kind == DefectKind::UnreferencedVertex) continue;
      int all = 0;
      for (const auto& [kind, count] : as_read->counts) {
        if (kind != DefectKind::UnreferencedVertex) all += count;
      }
      result.warnings.push_back(
          path + ": " + describe(file_position(defect)) + ": " + defect.message +
          (all > 1 ? " (and " + std::to_string(all - 1) + " more defects)" : std::string()) +
          "; the mesh was repaired");
      break;
    }
  }

  RepairResult repaired = repair_mesh(file_mesh, options.repair_options);
  result.repaired = true;
  result.repair = std::move(repaired.report);
  if (options.on_repair) options.on_repair(result.repair);
  result.mesh = std::move(repaired.mesh);
  result.vertex_map = std::move(repaired.vertex_map);
  result.polygons = file_polygons(raw.polygon_start, triangulation.polygon_of_triangle,
                                  triangulation.triangle_corners, result.mesh.triangles,
                                  repaired.face_map, repaired.face_flipped);
  std::vector<char> copied(nv, 0);
  for (int v : result.vertex_map) copied[v] = 1;
  for (int v = 0; v < nv; ++v) {
    if (!copied[v] && repaired.weld_map[v] == v) result.dropped_vertices.push_back(v);
  }
  if (options.validate) {
    result.validation = find_defects(result.mesh);
    for (const Defect& defect : result.validation.defects) {
      if (defect.kind == DefectKind::UnreferencedVertex) continue;
      const Where where =
          element_is_vertex(defect.kind)
              ? raw.vertex_at(result.vertex_map[defect.element])
              : raw.polygon_at(
                    triangulation.polygon_of_triangle[repaired.face_map[defect.element]]);
      const std::string context = path + ": " + describe(where) + ": after repair";
      const std::string why = "; " + unrepaired_reason(defect.kind);
      try {
        throw_first_defect(result.validation, context);
      } catch (const TopologyError& e) {
        throw TopologyError(e.what() + why);
      } catch (const InvalidInput& e) {
        throw InvalidInput(e.what() + why);
      }
    }
  }
  return result;
}

}  // namespace ricci::io_detail
