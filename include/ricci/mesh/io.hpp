#pragma once
/// \file
/// Reading triangle meshes from OBJ, OFF, PLY (ASCII and binary) and STL (ASCII and binary),
/// writing them (write_mesh: one writer per format beside each reader, src/mesh/io/), and writing
/// files atomically. The readers are strict: a malformed file throws an error naming the
/// file and the line (or byte offset) instead of dropping what it cannot read. (OpenMesh's own
/// readers silently drop faces on non-manifold edges and on bad indices, which is why ricci parses
/// these simple formats itself.)

#include <array>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "ricci/enum_names.hpp"
#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/polygons.hpp"
#include "ricci/mesh/repair.hpp"
#include "ricci/mesh/textured_mesh.hpp"
#include "ricci/mesh/validate.hpp"

namespace ricci {

/// Mesh file formats: read_mesh reads Obj, Off, Ply and Stl; write_mesh writes those and Glb
/// (glTF 2.0 binary, through the writer of the picture library: WriteOptions::glb_writer).
enum class MeshFormat { Obj, Off, Ply, Stl, Glb };

/// The formats by their usual extension: what Python's write_mesh(format=...) parses.
template <>
struct EnumNames<MeshFormat> {
  static constexpr const char* noun = "mesh format";
  static constexpr std::array<EnumName<MeshFormat>, 5> names{{
      {MeshFormat::Obj, "obj"},
      {MeshFormat::Off, "off"},
      {MeshFormat::Ply, "ply"},
      {MeshFormat::Stl, "stl"},
      {MeshFormat::Glb, "glb"},
  }};
};

/// Options of read_mesh.
struct ReadOptions {
  bool validate = true;  ///< run validate_mesh on the result and throw on the first defect
  /// Run repair_mesh on the file's triangles before validating (mesh/repair.hpp): weld
  /// duplicate vertices, remove duplicate and collapsed faces and slivers, split non-manifold
  /// edges and vertices, orient consistently. ReadResult::repair says what changed.
  bool repair = false;
  /// Run repair_mesh only when the file has a defect (find_defects; unreferenced vertices, which
  /// are dropped anyway, do not count), and say so in a warning that names the first defect and
  /// its file position; a file without defects is read as it is (duplicate positions stay
  /// apart). Off by default: the library reads what the file says unless asked. The command
  /// line and Python's read_mesh set it (their `auto` repair mode); `repair` overrides it.
  bool auto_repair = false;
  RepairOptions repair_options = {};  ///< options of that repair
  /// Called with the repair report after repairing and before validating, so that a caller can
  /// show what was changed even when a defect that repair cannot fix then throws. May be empty.
  std::function<void(const RepairReport&)> on_repair = {};
  /// Faces are dropped? Never: polygons with more than three corners are triangulated (fan from
  /// their first corner, or ear clipping for non-convex planar polygons), reported as warnings,
  /// and kept as ReadResult::polygons.
};

/// What read_mesh returns.
struct ReadResult {
  Mesh mesh;  ///< the triangles, unreferenced vertices removed
  MeshFormat format = MeshFormat::Obj;
  int file_vertices = 0;              ///< vertices in the file, referenced or not
  std::vector<std::string> warnings;  ///< e.g. "bunny.obj: 12 polygons triangulated"
  int polygons_triangulated = 0;      ///< faces with more than three corners in the file
  /// The file's faces over mesh.triangles (ricci/mesh/polygons.hpp): which triangles make up
  /// each face and its corners in order, faces in file order, so that a result computed on the
  /// triangles can be written on the file's own faces (ParamOptions::polygons). Empty when every
  /// face is a triangle. With options.repair a face keeps its polygon when repair kept all its
  /// triangles and each of its corners one vertex (reversed all together, it is listed turned
  /// over); otherwise its triangles left are faces of their own.
  Polygons polygons;
  /// File indices (0-based) of unreferenced vertices dropped (with options.repair also those
  /// left without faces by the repair; vertices welded onto another are not listed).
  std::vector<int> dropped_vertices;
  /// #V: file index (0-based) of each output vertex (with options.repair, several output
  /// vertices may copy one file vertex that was split).
  std::vector<int> vertex_map;
  /// Defects found when options.validate is set (then only warnings such as unreferenced
  /// vertices, since errors throw); empty otherwise. Its vertex elements are file indices
  /// (0-based, before unreferenced vertices were dropped), its face elements triangle indices
  /// (with options.repair: indices of the repaired mesh).
  ValidationReport validation;
  /// repair_mesh ran: options.repair was set, or options.auto_repair and the file had a defect
  bool repaired = false;
  /// What repair_mesh changed (when repaired). Its vertex indices are file indices (0-based),
  /// its face indices those of the file's faces after polygons were triangulated (the file's
  /// face numbers when it holds triangles only).
  RepairReport repair;
};

/// Format from the file extension (case-insensitive: .obj .off .ply .stl .glb).
/// \throw IoError naming the file when the extension is none of these
MeshFormat format_from_path(const std::string& path);

/// Reads a mesh file. Every error message starts with the path and the line (text formats) or
/// byte offset (binary formats) of the offending element; vertices and faces are numbered from 0
/// in file order, while index values quoted from the file appear as written (1-based in OBJ).
/// \throw IoError naming the file (and line or byte offset) when the file is missing, empty,
///        truncated or malformed, or its format is unknown or .glb (a textured format: read_glb
///        of ricci/render/textured_files.hpp reads it)
/// \throw InvalidInput naming the file and line when a face index is out of range
/// \throw InvalidInput / TopologyError (from validate_mesh, with the file name as context) when
///        options.validate is set and the mesh has a defect; after a repair the message names the
///        file position of the element, its index in the repaired mesh and why repair left it
///        (zero-area faces it cannot remove exactly, non-finite coordinates, non-orientable
///        surfaces). Without a repair, when repair_mesh would make the mesh valid, fixes() holds
///        {"repair", "true"} (ReadOptions::repair).
ReadResult read_mesh(const std::string& path, const ReadOptions& options = {});

/// Reads an OBJ file whose every face corner names a texture coordinate (`f v/vt` or
/// `f v/vt/vn`; negative indices count back from the last element read); read_mesh reads the
/// geometry only and ignores `vt`. Texture coordinates with a positive third component on every
/// `vt` are read as homogeneous (TexturedMesh::uv_weights). Polygons are split as a fan from their
/// first corner and kept as TexturedMesh::polygons (when a face has more than three corners);
/// normals, groups, materials and smoothing groups are ignored. Vertices are kept in
/// file order, referenced or not; the mesh is not validated.
/// \throw IoError "path: line N: ..." when the file is missing, empty of faces, or a statement is
///        malformed (a corner without a texture index, a bad number, free-form geometry, an
///        unknown statement, a coordinate that is not finite)
/// \throw InvalidInput "path: line N: ..." when a face refers to a vertex or texture coordinate
///        that the file has not defined
TexturedMesh read_textured_obj(const std::string& path);

/// Writes a mesh as OBJ (`v`, `f`), atomically (see write_file_atomically): the OBJ writer behind
/// write_mesh, for callers that hold a Mesh.
void write_obj(const std::string& path, const Mesh& mesh);

/// The material an OBJ with texture coordinates refers to: `mtllib LIBRARY` before the vertices
/// and `usemtl NAME` before the faces (ricci/render/textured_files.hpp writes the library and
/// its texture). An empty library writes neither.
struct ObjMaterial {
  std::string library;  ///< the .mtl file, relative to the OBJ's folder
  std::string name = "ricci_texture";
};

/// Writes a mesh with per-corner texture coordinates as OBJ (`v`, `vt`, `f v/vt`), atomically.
/// \param uv_triangles #F by 3 indices into uv (corners that share a uv index share a `vt`)
/// \param uv #UV by 2 texture coordinates
void write_obj(const std::string& path, const Mesh& mesh, const Triangles& uv_triangles,
               const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv,
               const ObjMaterial& material = {});

/// The same with three-component texture coordinates (`vt u v w`), e.g. homogeneous ones whose
/// linear interpolation divided by w gives a projective map
/// (ricci/param/refinement/common_refinement.hpp). \param uvw_triangles #F by 3 indices into uvw
/// \param uvw #UVW by 3 texture coordinates
void write_obj(const std::string& path, const Mesh& mesh, const Triangles& uvw_triangles,
               const Eigen::Matrix<double, Eigen::Dynamic, 3>& uvw,
               const ObjMaterial& material = {});

/// Writes a TexturedMesh to `path` (atomically, see write_file_atomically); write_mesh's hook for
/// a format whose writer lives outside ricci_lib (Glb: glb_writer() of
/// ricci/render/textured_files.hpp, which needs tinygltf and the picture library).
using MeshWriter = std::function<void(const std::string& path, const TexturedMesh& mesh)>;

/// Options of write_mesh.
struct WriteOptions {
  /// The file format; empty: from the extension of the path (format_from_path).
  std::optional<MeshFormat> format = std::nullopt;
  /// Obj: the material the file names (`mtllib`, `usemtl`); an empty library writes none. Only
  /// with texture coordinates.
  ObjMaterial material = {};
  /// Off, Ply, Stl: write a mesh with texture coordinates without them. Unset, such a mesh is
  /// refused, since those formats cannot hold texture coordinates.
  bool drop_uv = false;
  /// Glb: the glTF binary writer (glb_writer() of ricci/render/textured_files.hpp). ricci_lib
  /// does not link tinygltf; unset, Glb is refused with a message saying where the writer is.
  MeshWriter glb_writer = {};
};

/// Writes a mesh, with or without texture coordinates, in the format of options.format or of the
/// path's extension, atomically (the target is untouched when anything fails):
/// - Obj: `v`, then (with texture coordinates) `vt` per uv row and `f v/vt`, with
///   homogeneous coordinates (uv_weights) `vt u*w v*w w`; the bytes write_obj writes.
/// - Off: ASCII OFF, positions in the shortest decimal that reads back as the same double (exact).
/// - Ply: binary little-endian PLY, double positions and int indices (exact).
/// - Stl: binary STL: positions rounded to float, per-face normals, no vertex sharing (reading
///   welds corners at equal positions again); vertices without faces are lost.
/// - Glb: options.glb_writer.
/// With mesh.polygons (a polygon mesh's faces over the triangles) Obj, Off and Ply write one face
/// per polygon (`f v/vt v/vt v/vt v/vt`, each corner's vertex and uv row those of the triangle
/// corner it names); Stl and Glb write the triangles.
/// \pre mesh.mesh.triangles index mesh.mesh.positions; with texture coordinates, uv_triangles has
///      a row per face indexing uv, and uv_weights is empty or has a positive weight per uv row
/// \throw InvalidInput "write_mesh: path: ..." naming the face, corner or row when an index is out
///        of range or a coordinate is not finite, naming the polygon when mesh.polygons does not
///        fit the triangles (check_polygons), when the format cannot hold the texture
///        coordinates (and options.drop_uv is unset), when a material is given without texture
///        coordinates, or for Glb without options.glb_writer
/// \throw IoError naming the file when the extension is unknown or the file cannot be written
void write_mesh(const std::string& path, const TexturedMesh& mesh,
                const WriteOptions& options = {});

/// Writes a file through a temporary file in the same folder, renamed into place only when
/// write succeeded; on any error the temporary is removed and the target is left untouched.
/// \throw IoError naming the file when it cannot be written
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write);

/// Removes (unlink(2)) every temporary file write_file_atomically is writing at this moment, so
/// that a program interrupted by a signal leaves none behind. Async-signal-safe: meant for a
/// program's SIGINT/SIGTERM handler (the library installs no handlers); the targets are untouched.
void remove_pending_temporary_files() noexcept;

}  // namespace ricci
