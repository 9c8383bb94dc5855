#include "ricci/mesh/repair.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>

#include "mesh/detail/corner_fans.hpp"
#include "mesh/detail/edge_name.hpp"
#include "mesh/detail/face_keys.hpp"
#include "mesh/detail/orientation.hpp"
#include "mesh/detail/repair_passes.hpp"
#include "mesh/detail/slivers.hpp"
#include "ricci/errors.hpp"
#include "ricci/numerics/disjoint_sets.hpp"

namespace ricci {
namespace {

// The module's shared helpers (edge names, corner fans, the orientation search, face keys,
// sliver removal, the repair passes).
using namespace mesh_detail;

void note(RepairCount& count, int element, int max_examples) {
  if (static_cast<int>(count.examples.size()) < max_examples) count.examples.push_back(element);
  ++count.count;
}

/// " (e.g. vertices 3, 9)"; empty without examples.
std::string examples_text(const std::vector<int>& examples, const char* one, const char* many) {
  if (examples.empty()) return "";
  std::string text = std::string(" (e.g. ") + (examples.size() > 1 ? many : one) + " ";
  for (std::size_t i = 0; i < examples.size(); ++i) {
    text += (i == 0 ? "" : ", ") + std::to_string(examples[i]);
  }
  return text + ")";
}

}  // namespace

bool RepairReport::changed() const {
  return welded_vertices.count > 0 || repeated_vertex_faces_removed.count > 0 ||
         duplicate_faces_removed.count > 0 || slivers_removed.count > 0 || faces_split.count > 0 ||
         non_manifold_edges_split > 0 || non_manifold_vertices_split.count > 0 ||
         faces_flipped.count > 0 || unreferenced_vertices_dropped.count > 0 ||
         smaller_components_removed.count > 0;
}

namespace {

/// The smallest weld tolerance other than 0. A radius below 1e-15 of the diagonal is below the
/// resolution of the coordinates themselves (double precision is 2.2e-16 relative), and above
/// it the weld grid's cell coordinates (below 1 / tolerance) stay well within 64 bits.
constexpr double kMinWeldTolerance = 1e-15;

/// Rounds of splitting again on the reversed faces (step 4); each must save vertex copies, and
/// four have sufficed for every mesh met so far.
constexpr int kMaxOrientRounds = 4;

/// Checks the options and the vertex indices (InvalidInput otherwise); #V: 1 for the vertices
/// some face uses.
std::vector<char> check_repair_input(const Mesh& mesh, const RepairOptions& options) {
  const int nv = mesh.num_vertices();
  const int nf = mesh.num_faces();
  const double tolerance = options.weld_tolerance;
  if (!std::isfinite(tolerance) || tolerance < 0 ||
      (tolerance > 0 && tolerance < kMinWeldTolerance)) {
    throw InvalidInput("repair_mesh: weld_tolerance " + std::to_string(tolerance) +
                       " must be 0 (exact positions) or at least 1e-15 (relative to the "
                       "bounding-box diagonal)");
  }
  if (!(options.zero_area_tolerance >= 0 && options.zero_area_tolerance < 1)) {
    throw InvalidInput("repair_mesh: zero_area_tolerance " +
                       std::to_string(options.zero_area_tolerance) + " must be in [0, 1)");
  }
  std::vector<char> referenced(nv, 0);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles(f, k);
      if (v < 0 || v >= nv) {
        throw InvalidInput("repair_mesh: face " + std::to_string(f) + " uses vertex " +
                           std::to_string(v) + ", outside [0, " + std::to_string(nv) + ")");
      }
      referenced[v] = 1;
    }
  }
  return referenced;
}

/// (1) Welding, noted in the report: the representative of each input vertex (itself when it
/// was not welded, or when welding is off).
std::vector<int> weld_step(const Mesh& mesh, const std::vector<char>& referenced,
                           const RepairOptions& options, int max_examples, RepairReport& report) {
  const int nv = mesh.num_vertices();
  std::vector<int> representative(nv);
  std::iota(representative.begin(), representative.end(), 0);
  if (options.weld_vertices) {
    representative = weld(mesh.positions, referenced, options.weld_tolerance);
  }
  for (int v = 0; v < nv; ++v) {
    if (representative[v] != v) note(report.welded_vertices, v, max_examples);
  }
  return representative;
}

/// The faces on the welded vertices.
Triangles welded_triangles(const Triangles& triangles, const std::vector<int>& representative) {
  Triangles T(triangles.rows(), 3);
  for (int f = 0; f < static_cast<int>(triangles.rows()); ++f) {
    for (int k = 0; k < 3; ++k) T(f, k) = representative[triangles(f, k)];
  }
  return T;
}

/// What step (2) keeps: keep[f] is 0 for the faces removed; duplicate_of as
/// find_duplicate_faces gives it, for the report's example.
struct FaceDrops {
  std::vector<char> keep;
  std::vector<int> duplicate_of;
};

/// (2) Faces that use a vertex twice, then faces with the vertex set of an earlier face; noted
/// in the report.
FaceDrops drop_faces(const Triangles& T, int max_examples, RepairReport& report) {
  const int nf = static_cast<int>(T.rows());
  FaceDrops out;
  out.keep.assign(nf, 1);
  for (int f = 0; f < nf; ++f) {
    if (T(f, 0) != T(f, 1) && T(f, 1) != T(f, 2) && T(f, 0) != T(f, 2)) continue;
    out.keep[f] = 0;
    note(report.repeated_vertex_faces_removed, f, max_examples);
  }
  out.duplicate_of = find_duplicate_faces(T, out.keep);
  for (int f = 0; f < nf; ++f) {
    if (out.duplicate_of[f] < 0) continue;
    out.keep[f] = 0;
    note(report.duplicate_faces_removed, f, max_examples);
  }
  return out;
}

/// The faces that steps (3) to (5) take: the kept faces in input order, then (2b) with slivers
/// removed; source[i] is the input face of row i, piece[i] whether it is a piece of it.
struct WorkFaces {
  Triangles triangles;
  std::vector<int> source;
  std::vector<char> piece;
  std::string sliver_left_example;  ///< why the first zero-area face left was left
};

/// The kept faces of the welded triangles T, then (2b) the slivers removed (with
/// options.remove_slivers), noted in the report.
WorkFaces remove_sliver_step(const Positions& P, const Triangles& T, const std::vector<char>& keep,
                             const RepairOptions& options, int max_examples, RepairReport& report) {
  WorkFaces work;
  work.triangles.resize(std::count(keep.begin(), keep.end(), 1), 3);
  work.source.reserve(work.triangles.rows());
  for (int f = 0; f < static_cast<int>(T.rows()); ++f) {
    if (!keep[f]) continue;
    work.triangles.row(static_cast<Eigen::Index>(work.source.size())) = T.row(f);
    work.source.push_back(f);
  }
  work.piece.assign(work.source.size(), 0);
  if (!options.remove_slivers) return work;
  const std::vector<int>& source = work.source;
  SliverRemoval slivers = remove_slivers(P, work.triangles, options.zero_area_tolerance);
  for (std::size_t i = 0; i < slivers.removed.size(); ++i) {
    note(report.slivers_removed, source[slivers.removed[i]], max_examples);
    report.boundary_slivers_removed += slivers.on_boundary[i];
  }
  for (int row : slivers.split) note(report.faces_split, source[row], max_examples);
  for (std::size_t i = 0; i < slivers.left.size(); ++i) {
    // Counted per face; the pieces of one input face are one example.
    if (i == 0) work.sliver_left_example = sliver_left_reason(slivers.left_why[i]);
    RepairCount& left = report.zero_area_faces_left;
    if (i > 0 && slivers.left[i] == slivers.left[i - 1]) {
      ++left.count;
    } else {
      note(left, source[slivers.left[i]], max_examples);
    }
  }
  if (slivers.changed) {
    for (int& row : slivers.origin) row = source[row];
    work.triangles = std::move(slivers.triangles);
    work.source = std::move(slivers.origin);
    work.piece = std::move(slivers.piece);
  }
  return work;
}

/// The outcome of steps (3) and (4): the last split, and the faces reversed before it
/// (reversed[i] relative to the work faces; split.flip relative to those reversed ones).
struct OrientedSplit {
  Split split;
  std::vector<signed char> reversed;
};

/// (3) and (4). A non-manifold edge whose faces all run the same way has no pair to keep until
/// the orientation is fixed; so split again on the reversed faces while that saves copies.
OrientedSplit split_and_orient_rounds(const Positions& P, const Triangles& work, int nv,
                                      const RepairOptions& options) {
  const int nk = static_cast<int>(work.rows());
  std::vector<int> kept(nk);  // the rows of `work` that steps (3) to (5) take: all of them
  std::iota(kept.begin(), kept.end(), 0);
  Triangles oriented = work;  // work with the faces reversed so far
  OrientedSplit out;
  out.reversed.assign(nk, 0);
  Split& split = out.split;
  split = split_and_orient(P, oriented, kept, nv, options);
  for (int round = 0;
       round < kMaxOrientRounds && options.split_non_manifold && options.orient &&
       !split.non_manifold_edges.empty() && std::count(split.flip.begin(), split.flip.end(), 1) > 0;
       ++round) {
    Triangles next_oriented = oriented;
    for (int i = 0; i < nk; ++i) {
      if (split.flip[i]) std::swap(next_oriented(kept[i], 1), next_oriented(kept[i], 2));
    }
    Split next = split_and_orient(P, next_oriented, kept, nv, options);
    if (next.vertex_map.size() >= split.vertex_map.size() ||
        next.non_orientable.size() > split.non_orientable.size()) {
      break;
    }
    for (int i = 0; i < nk; ++i) out.reversed[i] ^= split.flip[i];
    oriented = std::move(next_oriented);
    split = std::move(next);
  }
  return out;
}

/// Notes steps (3) and (4) in the report: the non-manifold edges and vertices split, the
/// vertices no copy is left of, the non-orientable components and the faces reversed.
void note_split(const OrientedSplit& oriented, const std::vector<int>& representative,
                const std::vector<int>& source, const RepairOptions& options, int max_examples,
                RepairReport& report) {
  const Split& split = oriented.split;
  const int nv = static_cast<int>(representative.size());
  report.non_manifold_edges_split =
      options.split_non_manifold ? static_cast<int>(split.non_manifold_edges.size()) : 0;
  if (options.split_non_manifold) {
    for (std::size_t i = 0;
         i < split.non_manifold_edges.size() && static_cast<int>(i) < max_examples; ++i) {
      report.non_manifold_edge_examples.push_back(split.non_manifold_edges[i]);
    }
  }
  std::vector<int> copies(nv, 0);
  for (int v : split.vertex_map) ++copies[v];
  for (int v = 0; v < nv; ++v) {
    if (copies[v] > 1) note(report.non_manifold_vertices_split, v, max_examples);
    if (copies[v] == 0 && representative[v] == v) {
      note(report.unreferenced_vertices_dropped, v, max_examples);
    }
  }
  report.vertex_copies_added =
      static_cast<int>(split.vertex_map.size()) -
      static_cast<int>(std::count_if(copies.begin(), copies.end(), [](int n) { return n > 0; }));

  for (int i : split.non_orientable) {
    note(report.non_orientable_components, source[i], max_examples);
  }
  for (std::size_t i = 0; i < source.size(); ++i) {
    if (oriented.reversed[i] != split.flip[i]) {
      note(report.faces_flipped, source[i], max_examples);
    }
  }
}

/// (5) Which work faces go to the output: all of them, or with largest_component_only those of
/// the component with the most faces (the first on ties; the others noted in the report).
std::vector<char> output_faces(const Split& split, const std::vector<int>& source,
                               const RepairOptions& options, int max_examples,
                               RepairReport& report) {
  const int nk = static_cast<int>(source.size());
  std::vector<char> output_face(nk, 1);
  if (!options.largest_component_only || nk == 0) return output_face;
  const std::vector<int>& corner_output = split.corner_output;
  const int num_copies = static_cast<int>(split.vertex_map.size());
  DisjointSets parts(num_copies);
  for (int f = 0; f < nk; ++f) {
    parts.unite(corner_output[3 * f], corner_output[3 * f + 1]);
    parts.unite(corner_output[3 * f], corner_output[3 * f + 2]);
  }
  std::vector<int> faces_in(num_copies, 0), first_face(num_copies, -1);
  for (int f = 0; f < nk; ++f) {
    const int part = parts.find(corner_output[3 * f]);
    if (faces_in[part]++ == 0) first_face[part] = f;
  }
  int largest = parts.find(corner_output[0]);  // most faces; the first one on ties
  for (int f = 0; f < nk; ++f) {
    const int part = parts.find(corner_output[3 * f]);
    if (faces_in[part] > faces_in[largest]) largest = part;
  }
  for (int f = 0; f < nk; ++f) {
    const int part = parts.find(corner_output[3 * f]);
    if (part == largest) continue;
    output_face[f] = 0;
    ++report.smaller_component_faces_removed;
    if (first_face[part] == f) note(report.smaller_components_removed, source[f], max_examples);
  }
  return output_face;
}

/// (5) The output mesh and its maps. Unreferenced vertices are gone already: copies exist only
/// for corners; the copies of the faces removed go too.
void write_output(const Positions& P, const OrientedSplit& oriented, const WorkFaces& work,
                  const std::vector<char>& output_face, RepairResult& result) {
  const std::vector<int>& corner_output = oriented.split.corner_output;
  const std::vector<int>& vertex_map = oriented.split.vertex_map;
  const std::vector<signed char>& flip = oriented.split.flip;
  const int nk = static_cast<int>(work.source.size());
  std::vector<int> renumber(vertex_map.size(), -1);
  for (int f = 0; f < nk; ++f) {
    if (!output_face[f]) continue;
    for (int k = 0; k < 3; ++k) renumber[corner_output[3 * f + k]] = 0;
  }
  for (std::size_t v = 0; v < vertex_map.size(); ++v) {
    if (renumber[v] < 0) continue;
    renumber[v] = static_cast<int>(result.vertex_map.size());
    result.vertex_map.push_back(vertex_map[v]);
  }
  const int no = static_cast<int>(result.vertex_map.size());
  result.mesh.positions.resize(no, 3);
  for (int v = 0; v < no; ++v) result.mesh.positions.row(v) = P.row(result.vertex_map[v]);
  const int nout = static_cast<int>(std::count(output_face.begin(), output_face.end(), 1));
  result.mesh.triangles.resize(nout, 3);
  result.face_map.reserve(nout);
  result.face_flipped.reserve(nout);
  result.face_split.reserve(nout);
  for (int f = 0; f < nk; ++f) {
    if (!output_face[f]) continue;
    const int row = static_cast<int>(result.face_map.size());
    const int a = renumber[corner_output[3 * f]], b = renumber[corner_output[3 * f + 1]],
              c = renumber[corner_output[3 * f + 2]];
    if (flip[f]) {
      result.mesh.triangles.row(row) << a, c, b;
    } else {
      result.mesh.triangles.row(row) << a, b, c;
    }
    result.face_map.push_back(work.source[f]);
    result.face_flipped.push_back(oriented.reversed[f] != flip[f] ? 1 : 0);
    result.face_split.push_back(work.piece[f]);
  }
  result.report.output_vertices = no;
  result.report.output_faces = nout;
}

/// The report's lines for steps (1) and (2): welding, faces removed, slivers.
void removal_messages(const RepairOptions& options, const std::vector<int>& weld_map,
                      const std::vector<int>& duplicate_of, RepairReport& report) {
  std::vector<std::string>& out = report.messages;
  if (report.welded_vertices.count > 0) {
    const int v = report.welded_vertices.examples.empty() ? -1 : report.welded_vertices.examples[0];
    out.push_back("welded " + std::to_string(report.welded_vertices.count) +
                  " vertices onto earlier vertices at the same position" +
                  (options.weld_tolerance > 0 ? " (within the weld tolerance)" : std::string()) +
                  (v >= 0 ? " (e.g. vertex " + std::to_string(v) + " onto vertex " +
                                std::to_string(weld_map[v]) + ")"
                          : std::string()));
  }
  if (report.repeated_vertex_faces_removed.count > 0) {
    out.push_back("removed " + std::to_string(report.repeated_vertex_faces_removed.count) +
                  " faces that use a vertex twice" +
                  (report.welded_vertices.count > 0 ? " after welding" : "") +
                  examples_text(report.repeated_vertex_faces_removed.examples, "face", "faces"));
  }
  if (report.duplicate_faces_removed.count > 0) {
    const int f = report.duplicate_faces_removed.examples.empty()
                      ? -1
                      : report.duplicate_faces_removed.examples[0];
    out.push_back("removed " + std::to_string(report.duplicate_faces_removed.count) +
                  " duplicate faces" +
                  (f >= 0 ? " (e.g. face " + std::to_string(f) + ", the same vertices as face " +
                                std::to_string(duplicate_of[f]) + ")"
                          : std::string()));
  }
  if (report.slivers_removed.count > 0) {
    const int inside = report.slivers_removed.count - report.boundary_slivers_removed;
    std::string line = "removed " + std::to_string(report.slivers_removed.count) +
                       " zero-area faces with a vertex on their longest edge (slivers)" +
                       examples_text(report.slivers_removed.examples, "face", "faces") + ": ";
    if (inside > 0) {
      line += std::to_string(inside) + " by splitting the face across that edge at the vertex (" +
              std::to_string(report.faces_split.count) + " faces split" +
              examples_text(report.faces_split.examples, "face", "faces") +
              "; the surface is unchanged)";
    }
    if (report.boundary_slivers_removed > 0) {
      line += std::string(inside > 0 ? ", " : "") +
              std::to_string(report.boundary_slivers_removed) +
              " on the boundary (they cover nothing)";
    }
    out.push_back(line);
  }
}

/// The report's lines for steps (3) to (5), then one per defect left unrepaired.
void topology_messages(const std::string& sliver_left_example, RepairReport& report) {
  std::vector<std::string>& out = report.messages;
  if (report.non_manifold_edges_split > 0) {
    std::string line = "split " + std::to_string(report.non_manifold_edges_split) +
                       " non-manifold edges (more than two faces) into pairs of faces";
    if (!report.non_manifold_edge_examples.empty()) {
      line += " (e.g. edge " +
              edge_name(report.non_manifold_edge_examples[0][0],
                        report.non_manifold_edge_examples[0][1]) +
              ")";
    }
    out.push_back(line);
  }
  if (report.non_manifold_vertices_split.count > 0) {
    out.push_back("split " + std::to_string(report.non_manifold_vertices_split.count) +
                  " non-manifold vertices into one copy per fan of faces (" +
                  std::to_string(report.vertex_copies_added) + " copies added)" +
                  examples_text(report.non_manifold_vertices_split.examples, "vertex", "vertices"));
  }
  if (report.faces_flipped.count > 0) {
    out.push_back("reversed " + std::to_string(report.faces_flipped.count) +
                  " faces to orient their components consistently" +
                  examples_text(report.faces_flipped.examples, "face", "faces"));
  }
  if (report.unreferenced_vertices_dropped.count > 0) {
    out.push_back(
        "dropped " + std::to_string(report.unreferenced_vertices_dropped.count) +
        " unreferenced vertices" +
        examples_text(report.unreferenced_vertices_dropped.examples, "vertex", "vertices"));
  }
  if (report.smaller_components_removed.count > 0) {
    out.push_back("removed " + std::to_string(report.smaller_components_removed.count) +
                  " components smaller than the largest (" +
                  std::to_string(report.smaller_component_faces_removed) + " faces; " +
                  std::to_string(report.output_faces) + " faces kept)" +
                  examples_text(report.smaller_components_removed.examples, "the one with face",
                                "those with faces"));
  }
  if (report.non_orientable_components.count > 0) {
    out.push_back("not repaired: " + std::to_string(report.non_orientable_components.count) +
                  " non-orientable components (like a Moebius strip) cannot be oriented" +
                  examples_text(report.non_orientable_components.examples, "face", "faces"));
  }
  if (report.zero_area_faces_left.count > 0) {
    out.push_back("not repaired: " + std::to_string(report.zero_area_faces_left.count) +
                  " zero-area faces cannot be removed without changing the surface" +
                  examples_text(report.zero_area_faces_left.examples, "face", "faces") +
                  "; the first: " + sliver_left_example);
  }
}

}  // namespace

RepairResult repair_mesh(const Mesh& mesh, const RepairOptions& options) {
  const std::vector<char> referenced = check_repair_input(mesh, options);
  const int max_examples = std::max(options.max_examples, 0);
  RepairResult result;
  RepairReport& report = result.report;
  report.input_vertices = mesh.num_vertices();
  report.input_faces = mesh.num_faces();

  std::vector<int> representative = weld_step(mesh, referenced, options, max_examples, report);
  const Triangles T = welded_triangles(mesh.triangles, representative);
  const FaceDrops drops = drop_faces(T, max_examples, report);
  const WorkFaces work =
      remove_sliver_step(mesh.positions, T, drops.keep, options, max_examples, report);
  const OrientedSplit oriented =
      split_and_orient_rounds(mesh.positions, work.triangles, mesh.num_vertices(), options);
  note_split(oriented, representative, work.source, options, max_examples, report);
  const std::vector<char> output_face =
      output_faces(oriented.split, work.source, options, max_examples, report);
  write_output(mesh.positions, oriented, work, output_face, result);
  result.weld_map = std::move(representative);

  // Messages, in the order of the steps.
  removal_messages(options, result.weld_map, drops.duplicate_of, report);
  topology_messages(work.sliver_left_example, report);
  return result;
}

}  // namespace ricci
