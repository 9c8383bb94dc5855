// Valid variants of the formats that writers in the wild produce (docs/mesh-input.md, "Formats
// and their variants"): each test writes the variant from generated data and reads it back,
// positions and faces exactly.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <string>
#include <typeinfo>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"
#include "support/byte_writer.hpp"
#include "support/error_messages.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

using testing::expect_mentions;
using testing::message_of;

using testing::ByteWriter;

std::string write_variant_file(const std::string& name, const std::string& content) {
  return testing::write_text_file(testing::suite_tmp_dir("mesh_read_variants") / name, content);
}

using Rows = std::vector<std::vector<double>>;
using Faces = std::vector<std::vector<int>>;

/// Expects the mesh to hold exactly these positions and triangles, in this order.
void expect_mesh(const Mesh& mesh, const Rows& positions, const Faces& triangles) {
  ASSERT_EQ(mesh.num_vertices(), static_cast<int>(positions.size()));
  ASSERT_EQ(mesh.num_faces(), static_cast<int>(triangles.size()));
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(mesh.positions(v, k), positions[v][k]) << "vertex " << v;
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(mesh.triangles(f, k), triangles[f][k]) << "face " << f;
  }
}

// ------------------------------------------------------------------------------------------
// STL

/// A regular tetrahedron's four triangles as ASCII STL facets.
const Rows kTetrahedronPositions = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1.25}};
const Faces kTetrahedronFaces = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};

std::string ascii_stl_facets() {
  std::string text;
  for (const auto& face : kTetrahedronFaces) {
    text += "facet normal 0 0 0\n outer loop\n";
    for (int v : face) {
      text += "  vertex " + std::to_string(kTetrahedronPositions[v][0]) + " " +
              std::to_string(kTetrahedronPositions[v][1]) + " " +
              std::to_string(kTetrahedronPositions[v][2]) + "\n";
    }
    text += " endloop\nendfacet\n";
  }
  return text;
}

TEST(ReadVariants, AsciiStlWithoutASolidName) {
  // "solid" alone, followed by blanks, with CRLF; the name's absence made the first bytes read as
  // a binary header ("the header declares 1919252000 triangles").
  for (const std::string solid : {"solid\n", "solid   \t\n", "solid\r\n", "  solid\n"}) {
    const std::string path =
        write_variant_file("unnamed.stl", solid + ascii_stl_facets() + "endsolid\n");
    const ReadResult result = read_mesh(path);
    SCOPED_TRACE(solid);
    expect_mesh(result.mesh, kTetrahedronPositions, kTetrahedronFaces);
  }
  // A broken one is still ASCII: its error names the line.
  const std::string broken = write_variant_file(
      "unnamed_broken.stl", "solid\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertx 1 0 0\n");
  expect_mentions(message_of<IoError>([&] { read_mesh(broken); }),
                  {"unnamed_broken.stl", "line 5", "'vertx'"});
}

TEST(ReadVariants, BinaryStlWhoseHeaderReadsLikeAsciiIsBinary) {
  // The 80-byte comment says "solid", ends its line and even starts a facet: the size and the
  // binary count still make it binary.
  std::string header = "solid tetra\nfacet normal 0 0 1\n";
  header.resize(80, ' ');
  ByteWriter out(false);
  out.text(header).put<std::uint32_t>(4);
  for (const auto& face : kTetrahedronFaces) {
    out.put(0.0F).put(0.0F).put(0.0F);
    for (int v : face) {
      for (double x : kTetrahedronPositions[v]) out.put(static_cast<float>(x));
    }
    out.put<std::uint16_t>(0);
  }
  const ReadResult result = read_mesh(write_variant_file("header_like_ascii.stl", out.data()));
  expect_mesh(result.mesh, kTetrahedronPositions, kTetrahedronFaces);
}

// ------------------------------------------------------------------------------------------
// PLY triangle strips

/// A 4 by 2 grid: vertices 0-3 along y = 1, 4-7 along y = 0.
const Rows kGrid = {{0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {3, 1, 0},
                    {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
/// The strip 4 0 5 1 6 2 7 3 over the whole grid, every other triangle turned.
const Faces kGridStrip = {{4, 0, 5}, {5, 0, 1}, {5, 1, 6}, {6, 1, 2}, {6, 2, 7}, {7, 2, 3}};

/// The grid as a PLY: its strips as one tristrips item, after a face element with `faces` when
/// that is not empty.
std::string grid_ply(const std::string& format, const std::vector<std::int64_t>& strips,
                     const Faces& faces, bool unsigned_strips = false) {
  const bool big = format == "binary_big_endian";
  const bool ascii = format == "ascii";
  ByteWriter out(big);
  out.text("ply\nformat " + format + " 1.0\nelement vertex 8\n");
  out.text("property float x\nproperty float y\nproperty float z\n");
  if (!faces.empty()) {
    out.text("element face " + std::to_string(faces.size()) +
             "\nproperty list uchar int vertex_indices\n");
  }
  out.text("element tristrips 1\nproperty list int " +
           std::string(unsigned_strips ? "uint" : "int") + " vertex_indices\nend_header\n");
  for (const auto& p : kGrid) {
    if (ascii) {
      out.text(std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) +
               "\n");
    } else {
      for (double x : p) out.put(static_cast<float>(x));
    }
  }
  for (const auto& face : faces) {
    if (ascii) {
      out.text(std::to_string(face.size()));
      for (int v : face) out.text(" " + std::to_string(v));
      out.text("\n");
    } else {
      out.put(static_cast<std::uint8_t>(face.size()));
      for (int v : face) out.put<std::int32_t>(v);
    }
  }
  if (ascii) {
    out.text(std::to_string(strips.size()));
    for (std::int64_t v : strips) out.text(" " + std::to_string(v));
    out.text("\n");
  } else {
    out.put(static_cast<std::int32_t>(strips.size()));
    for (std::int64_t v : strips) {
      if (unsigned_strips) {
        out.put(static_cast<std::uint32_t>(v));
      } else {
        out.put(static_cast<std::int32_t>(v));
      }
    }
  }
  return out.data();
}

TEST(ReadVariants, PlyTriangleStripsAlone) {
  for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(format);
    // One strip; the same split in two by -1; a trailing repeated vertex (a degenerate triangle,
    // as strips are joined) that is skipped.
    for (const std::vector<std::int64_t>& strips :
         {std::vector<std::int64_t>{4, 0, 5, 1, 6, 2, 7, 3},
          std::vector<std::int64_t>{4, 0, 5, 1, 6, 2, -1, 6, 2, 7, 3},
          std::vector<std::int64_t>{4, 0, 5, 1, 6, 2, 7, 3, 3}}) {
      const std::string path = write_variant_file("strips.ply", grid_ply(format, strips, {}));
      expect_mesh(read_mesh(path).mesh, kGrid, kGridStrip);
    }
  }
  // An unsigned index type stores -1 as its largest value.
  const std::string path = write_variant_file(
      "unsigned_strips.ply",
      grid_ply("binary_little_endian", {4, 0, 5, 1, 6, 2, -1, 6, 2, 7, 3}, {}, true));
  expect_mesh(read_mesh(path).mesh, kGrid, kGridStrip);
}

TEST(ReadVariants, PlyTriangleStripsBesideFaces) {
  // The last column a quad of the face element, the first two a strip.
  const Faces quad = {{6, 2, 3, 7}};
  const Faces expected = {{6, 2, 3}, {6, 3, 7}, {4, 0, 5}, {5, 0, 1}, {5, 1, 6}, {6, 1, 2}};
  for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(format);
    const std::string path =
        write_variant_file("strips_and_faces.ply", grid_ply(format, {4, 0, 5, 1, 6, 2}, quad));
    expect_mesh(read_mesh(path).mesh, kGrid, expected);
  }
  const std::string bad =
      write_variant_file("strip_range.ply", grid_ply("ascii", {4, 0, 5, 1, 6, 12}, quad));
  expect_mentions(message_of<InvalidInput>([&] { read_mesh(bad); }),
                  {"strip_range.ply", "line 21", "index 12", "tristrips 0"});
}

// ------------------------------------------------------------------------------------------
// Binary OFF

// A square pyramid: the base a quad (facing down), four triangles up to the apex; coordinates
// exact in float.
const Rows kPyramid = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1.25}};
const Faces kPyramidFaces = {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
/// The pyramid's triangles as read: the base fanned from its first corner.
const Faces kPyramidTriangles = {{0, 3, 2}, {0, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};

/// The pyramid as `OFF BINARY` (or `COFF BINARY`, a colour of 4 floats per vertex): big-endian
/// with a colour count per face as Geomview documents it, or as pmp-library writes it
/// (little-endian, no colour count), or the two other combinations.
std::string binary_off(bool big_endian, bool face_colours, bool vertex_colours) {
  ByteWriter out(big_endian);
  out.text(vertex_colours ? "COFF BINARY\n" : "OFF BINARY\n");
  out.put<std::int32_t>(5).put<std::int32_t>(5).put<std::int32_t>(8);
  for (const auto& p : kPyramid) {
    for (double x : p) out.put(static_cast<float>(x));
    if (vertex_colours) out.put(1.0F).put(0.5F).put(0.25F).put(1.0F);
  }
  static constexpr int kColours[] = {0, 4, 3, 0, 4};  // floats per face
  for (std::size_t f = 0; f < kPyramidFaces.size(); ++f) {
    out.put(static_cast<std::int32_t>(kPyramidFaces[f].size()));
    for (int v : kPyramidFaces[f]) out.put<std::int32_t>(v);
    if (!face_colours) continue;
    const int colours = kColours[f];
    out.put<std::int32_t>(colours);
    for (int k = 0; k < colours; ++k) out.put(0.5F);
  }
  return out.data();
}

TEST(ReadVariants, BinaryOffInEitherByteOrderWithOrWithoutFaceColours) {
  for (const bool big_endian : {true, false}) {
    for (const bool face_colours : {true, false}) {
      for (const bool vertex_colours : {false, true}) {
        SCOPED_TRACE(std::string(big_endian ? "big" : "little") + "-endian" +
                     (face_colours ? ", face colours" : "") +
                     (vertex_colours ? ", vertex colours" : ""));
        const std::string path =
            write_variant_file("binary.off", binary_off(big_endian, face_colours, vertex_colours));
        expect_mesh(read_mesh(path).mesh, kPyramid, kPyramidTriangles);
      }
    }
  }
}

TEST(ReadVariants, BadBinaryOffNamesTheByte) {
  std::string cut = binary_off(false, false, false);
  cut.resize(cut.size() - 2);
  expect_mentions(
      message_of<IoError>([&] { read_mesh(write_variant_file("cut_binary.off", cut)); }),
      {"cut_binary.off", "byte ", "truncated"});
  // Index 9 for the second corner of the last face (little-endian, no colours): after the
  // header line, the counts, 5 vertices, the quad, 3 triangles and the last one's count. Only
  // this reading keeps the file's structure, so its error is the one reported.
  std::string range = binary_off(false, false, false);
  const std::size_t at = 11 + 12 + 5 * 12 + 20 + 3 * 16 + 4 + 4;
  range[at] = 9;
  expect_mentions(
      message_of<InvalidInput>([&] { read_mesh(write_variant_file("range_binary.off", range)); }),
      {"range_binary.off", "byte " + std::to_string(at), "face 4", "index 9", "little-endian"});
}

// ------------------------------------------------------------------------------------------
// OFF records over several lines

TEST(ReadVariants, OffRecordsSpreadOverLines) {
  const std::string path = write_variant_file(
      "wrapped.off",
      "OFF\n5\n5 8\n0 0 0\n1 0 0\n1 1 0\n0 1 0 # comment\n0.5 0.5\n1.25\n"
      "4\n0 3 2 1\n"              // the corner count alone on its line
      "3 0\n# between\n1\n\n4\n"  // a face over three lines, a comment and a blank among them
      "3 1 2 4 0.5 0.5 0.5\n"     // on one line, with a colour
      "3\n2 3 4\n3 3 0 4\n");
  const ReadResult result = read_mesh(path);
  expect_mesh(result.mesh, kPyramid, kPyramidTriangles);
}

TEST(ReadVariants, OffRecordErrorsNameTheLine) {
  // Face 0 lists 2 of its 3 corners; read on, it would take the next face's count: the data left
  // on that line gives it away.
  const std::string head = "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n";
  expect_mentions(message_of<IoError>([&] {
                    read_mesh(write_variant_file("short_face.off", head + "3 0 1\n3 1 3 2\n"));
                  }),
                  {"short_face.off", "line 8", "face 0 continues from line 7", "'1'"});
  // An index out of range on a continuation line: that line.
  expect_mentions(
      message_of<InvalidInput>([&] {
        read_mesh(write_variant_file("wrapped_range.off", head + "3\n0 1\n7\n3 0 2 1\n"));
      }),
      {"wrapped_range.off", "line 9", "face 0", "index 7"});
  expect_mentions(message_of<IoError>([&] {
                    read_mesh(write_variant_file("wrapped_cut.off", head + "3 0 1 2\n4 0\n1\n"));
                  }),
                  {"wrapped_cut.off", "line 9", "ends inside face 1", "begun at line 8"});
}

// ------------------------------------------------------------------------------------------
// OBJ continuation lines

TEST(ReadVariants, ObjStatementsContinuedByABackslash) {
  const std::string path =
      write_variant_file("continued.obj",
                         "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 \\\n 0.5 1.25\n"
                         "f 1 4 \\\r\n3 2\r\n"  // CRLF, as in trimesh's wallhole.obj
                         "f 1 2\\\n5\n"         // no blank before the backslash
                         "# a comment that ends in a backslash continues nothing \\\n"
                         "f 2 \\   \n3 \\\n 5\nf 3 4 5\nf 4 1 5\n");
  const ReadResult result = read_mesh(path);
  expect_mesh(result.mesh, kPyramid, kPyramidTriangles);

  // Errors name the line where the statement starts.
  const std::string bad = write_variant_file(
      "continued_bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n2 \\\n4\nf 1 2 3\n");
  expect_mentions(message_of<InvalidInput>([&] { read_mesh(bad); }),
                  {"continued_bad.obj", "line 4", "face 0", "index 4"});
}

TEST(ReadVariants, TexturedObjStatementsContinuedByABackslash) {
  const std::string path = write_variant_file(
      "continued_textured.obj",
      "v 0 0 0\nv 1 0 0\nv 1 1 \\\n0\nv 0 1 0\nvt 0 0\nvt 1 \\\n 0\nvt 1 1\nvt 0 1\n"
      "f 1/1 2/2 \\\n3/3\nf 1/1 \\\r\n3/3 4/4\r\n");
  const TexturedMesh read = read_textured_obj(path);
  expect_mesh(read.mesh, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}});
  ASSERT_EQ(read.uv.rows(), 4);
  EXPECT_EQ(read.uv(1, 0), 1.0);
  EXPECT_EQ(read.uv(1, 1), 0.0);
  EXPECT_EQ(read.uv_triangles(1, 2), 3);
  const std::string bad =
      write_variant_file("continued_textured_bad.obj", "v 0 0 0\nvt 0 0\nf 1/1 \\\n1/1 1/x\n");
  expect_mentions(message_of<IoError>([&] { read_textured_obj(bad); }),
                  {"continued_textured_bad.obj", "line 3", "'1/x'"});
}

}  // namespace
}  // namespace ricci
