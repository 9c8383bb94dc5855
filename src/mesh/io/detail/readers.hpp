#pragma once
/// \file
/// Private to the mesh readers: one parser per format, each turning a whole file's bytes into the
/// raw polygon soup that read_mesh assembles. Every parser throws IoError (or InvalidInput for an
/// index out of range) naming `path` and the line or byte offset of the offending element.

#include <string>
#include <string_view>

#include "mesh/io/detail/reader_support.hpp"

namespace ricci::io_detail {

/// Wavefront OBJ: v and f statements (1-based or negative indices), a statement continued over
/// lines by a trailing backslash; texture coordinates, normals, groups and materials are
/// ignored, free-form geometry is refused.
RawMesh parse_obj(const std::string& path, std::string_view data);

/// OFF and its [ST][C][N]OFF variants; the extra per-vertex and per-face numbers are skipped. A
/// vertex or face record may continue over several lines. `OFF BINARY`: either byte order, faces
/// with or without colour counts, whichever reads the whole file.
RawMesh parse_off(const std::string& path, std::string_view data);

/// PLY 1.0, ASCII or binary of either byte order: the vertex element's x, y, z, the face
/// element's vertex_indices (or vertex_index) list and the tristrips element's (strips
/// separated by -1); other elements are skipped with a warning.
RawMesh parse_ply(const std::string& path, std::string_view data);

/// STL, ASCII or binary (told apart by the size a binary header implies and by whether the text
/// reads as "solid ... facet normal"); corners at exactly equal positions become one vertex.
RawMesh parse_stl(const std::string& path, std::string_view data);

}  // namespace ricci::io_detail
