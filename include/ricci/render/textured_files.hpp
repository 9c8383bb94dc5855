#pragma once
/// \file
/// Texture-mapped files other tools open textured: an OBJ's material library (.mtl) with its
/// texture image, and glTF 2.0 binary (.glb) with the texture inside. Blender, MeshLab and
/// three.js show a parameterization's checkerboard from either without further set-up.

#include <Eigen/Core>
#include <string>

#include "ricci/mesh/io.hpp"
#include "ricci/mesh/textured_mesh.hpp"
#include "ricci/render/image.hpp"

namespace ricci {

/// The default texture: a checkerboard of `squares` x `squares` squares over the unit square of
/// texture coordinates, in render_mesh's two colours (the squares of `ricci render`).
/// \throw InvalidInput when pixels is outside [8, 16384] or squares < 1 or > pixels
Image checkerboard_texture(int pixels = 1024, int squares = 16);

/// What write_obj_material wrote.
struct ObjMaterialFiles {
  std::string mtl;      ///< the material library (STEM.mtl beside the OBJ)
  std::string texture;  ///< the texture it refers to (STEM.png, or the user's image)
  std::string library;  ///< the library's name as the OBJ's `mtllib` gives it (relative)
};

/// Writes the material library of an OBJ with texture coordinates: STEM.mtl beside obj_path,
/// one material (ObjMaterial's name) whose diffuse map is the texture. texture_path empty: the
/// checkerboard is written as STEM.png; otherwise the MTL refers to that image (by its path
/// relative to the OBJ's folder; it is not copied). Both written atomically.
/// \throw IoError when a file cannot be written or texture_path is missing
ObjMaterialFiles write_obj_material(const std::string& obj_path,
                                    const std::string& texture_path = "");

/// Options of glb_writer.
struct GlbOptions {
  /// The texture image's file (PNG or JPEG, embedded as it is); empty: the checkerboard.
  std::string texture_path;
  /// Smooth vertex normals (area-weighted over each vertex's faces) for shading.
  bool normals = true;
};

/// The glTF 2.0 binary writer that write_mesh calls for MeshFormat::Glb (set it as
/// WriteOptions::glb_writer; ricci_lib does not link tinygltf): one mesh, one primitive,
/// positions, normals, texture coordinates per corner (vertices split where uv differs across a
/// seam; glTF's t = 1 - v; homogeneous uv_weights are not written: uv as divided), one material
/// whose base colour texture is embedded, written through tinygltf, atomically. write_mesh has
/// checked the arrays before it calls the writer.
/// The writer throws InvalidInput when the texture is not PNG or JPEG; IoError when a file cannot
/// be read or written, or ricci was built without tinygltf (see glb_supported).
MeshWriter glb_writer(const GlbOptions& options = {});

/// Reads glTF binary back (what glb_writer writes, or any .glb whose first mesh has triangles with
/// TEXCOORD_0): the triangles of every primitive of the first mesh, uv = (s, 1 - t); vertices that
/// glTF split at seams are welded again where their positions are bit for bit equal, so that
/// seams read as seams (TexturedMesh as read_textured_obj gives).
/// \throw IoError when the file cannot be read or is not glTF binary, or ricci was built without
///        tinygltf; InvalidInput when the mesh has no triangles or no texture coordinates
TexturedMesh read_glb(const std::string& path);

/// read_glb for a .glb file (any case), read_textured_obj otherwise: what `ricci render` and
/// `ricci view` open.
TexturedMesh read_textured_file(const std::string& path);

/// True when glb_writer can write (ricci was built with Debian's libtinygltf-dev).
bool glb_supported();

}  // namespace ricci
