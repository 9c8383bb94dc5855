#include "ricci/mesh/io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <numbers>
#include <regex>
#include <string>
#include <typeinfo>

#include <Eigen/Geometry>

#include "ricci/errors.hpp"
#include "ricci/mesh/info.hpp"
#include "support/byte_writer.hpp"
#include "support/error_messages.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

using testing::expect_mentions;
using testing::message_of;

namespace fs = std::filesystem;

/// This file's own folder under the shared test folder, so that names cannot clash with other
/// suites running at the same time.
fs::path io_tmp_dir() {
  return testing::suite_tmp_dir("mesh_io");
}

/// Writes `content` to a fresh file of the given name in the test folder; returns its path.
std::string write_test_file(const std::string& name, const std::string& content) {
  return testing::write_text_file(io_tmp_dir() / name, content);
}

/// read_mesh of `content` written to a file of the given name.
ReadResult read_test_file(const std::string& name, const std::string& content) {
  return read_mesh(write_test_file(name, content));
}

using testing::ByteWriter;

// ------------------------------------------------------------------------------------------
// Reading good files

TEST(ReadObj, TetrahedronWithCommentsAndAttributes) {
  const ReadResult result = read_test_file(
      "attributes.obj",
      "mtllib tetra.mtl\r\no tetra\nv 1 1 1\nv 1 -1 -1\nv -1 1 -1 # trailing comment\n"
      "v -1 -1 1 1.0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\ng side\ns 1\nusemtl red\n"
      "f 1/1/1 2/2/1 3/3/1\nf 1//1 3//1 4//1\nf 1/1 4/2 2/3\nl 1 2\nf 2 4 3\n");
  EXPECT_EQ(result.format, MeshFormat::Obj);
  ASSERT_EQ(result.mesh.num_vertices(), 4);
  ASSERT_EQ(result.mesh.num_faces(), 4);
  EXPECT_EQ(result.mesh.positions(2, 0), -1.0);
  EXPECT_EQ(result.mesh.positions(3, 2), 1.0);
  EXPECT_EQ(result.mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_TRUE(result.warnings.empty());
  EXPECT_TRUE(result.dropped_vertices.empty());
  EXPECT_EQ(result.vertex_map, (std::vector<int>{0, 1, 2, 3}));
}

TEST(ReadObj, NegativeIndicesCountBackFromTheLastVertex) {
  const ReadResult result = read_test_file(
      "negative.obj",
      "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nf -3 -2 -1\nv -1 -1 1\nf -4 -2 -1\nf 1 -1 2\nf 2 4 3\n");
  ASSERT_EQ(result.mesh.num_faces(), 4);
  EXPECT_EQ(result.mesh.triangles.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(result.mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(result.mesh.triangles.row(2), Eigen::RowVector3i(0, 3, 1));
}

TEST(ReadObj, NonConvexPolygonIsEarClipped) {
  // A dart with a reflex corner at its second vertex: the fan from the first corner would give
  // a clockwise triangle (0, 1, 2), so ear clipping takes over. Its area is 1.7.
  const ReadResult result =
      read_test_file("dart.obj", "v 0 0 0\nv 1 0.3 0\nv 2 0 0\nv 1 2 0\nf 1 2 3 4\n");
  ASSERT_EQ(result.mesh.num_faces(), 2);
  ASSERT_EQ(result.warnings.size(), 1u);
  expect_mentions(result.warnings[0], {"1 polygons", "ear clipping"});
  double area = 0;
  for (int f = 0; f < 2; ++f) {
    const Eigen::Vector3d a = result.mesh.positions.row(result.mesh.triangles(f, 0));
    const Eigen::Vector3d b = result.mesh.positions.row(result.mesh.triangles(f, 1));
    const Eigen::Vector3d c = result.mesh.positions.row(result.mesh.triangles(f, 2));
    const double signed_area = 0.5 * (b - a).cross(c - a).z();
    EXPECT_GT(signed_area, 0) << "triangle " << f << " is flipped";
    area += signed_area;
  }
  EXPECT_NEAR(area, 1.7, 1e-14);
}

TEST(ReadOff, ColouredHeaderCommentsAndCountsOnTheHeaderLine) {
  const ReadResult result = read_test_file(
      "tetra.off",
      "COFF # coloured\n# counts next\n\n4 4 6\n1 1 1 255 0 0 255\n1 -1 -1 0 255 0 255\n"
      "-1 1 -1 0 0 255 255\n# a comment between vertices\n-1 -1 1 9 9 9 9\n"
      "3 0 1 2\n3 0 2 3 0.5 0.5 0.5\n3 0 3 1\n3 1 3 2\n\n");
  EXPECT_EQ(result.format, MeshFormat::Off);
  ASSERT_EQ(result.mesh.num_faces(), 4);
  EXPECT_EQ(result.mesh.positions.row(3), Eigen::RowVector3d(-1, -1, 1));
  EXPECT_EQ(result.mesh.triangles.row(3), Eigen::RowVector3i(1, 3, 2));

  const std::string same_line =
      write_test_file("sameline.off",
                      "NOFF 4 4 0\n1 1 1 0 0 1\n1 -1 -1 0 0 1\n-1 1 -1 0 0 1\n-1 -1 1 0 0 1\n"
                      "3 0 1 2\n3 0 2 3\n3 0 3 1\n3 1 3 2\n");
  EXPECT_EQ(read_mesh(same_line).mesh.num_faces(), 4);
}

/// A regular tetrahedron (alternate corners of a cube) as a PLY: vertices with extra properties (a
/// uchar colour, a list of doubles), faces with an extra int, and an extra element, in the given
/// encoding.
std::string tetrahedron_ply(const std::string& format, bool big_endian, bool double_coordinates,
                            const std::string& index_name) {
  ByteWriter out(big_endian);
  const std::string coordinate_type = double_coordinates ? "double" : "float";
  out.text("ply\nformat " + format + " 1.0\ncomment made by io_test\n");
  out.text("element vertex 4\nproperty " + coordinate_type + " x\nproperty uchar red\n");
  out.text("property " + coordinate_type + " y\nproperty list uint8 double weights\n");
  out.text("property " + coordinate_type + " z\n");
  out.text("element face 4\nproperty int flags\nproperty list ushort uint " + index_name + "\n");
  out.text("element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n");
  const double xyz[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1.25}};
  const unsigned faces[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  const bool ascii = format == "ascii";
  for (int v = 0; v < 4; ++v) {
    if (ascii) {
      out.text(std::to_string(xyz[v][0]) + " 200 " + std::to_string(xyz[v][1]) + " 2 0.5 0.25 " +
               std::to_string(xyz[v][2]) + "\n");
      continue;
    }
    auto coordinate = [&](double x) {
      if (double_coordinates) {
        out.put(x);
      } else {
        out.put(static_cast<float>(x));
      }
    };
    coordinate(xyz[v][0]);
    out.put<std::uint8_t>(200);
    coordinate(xyz[v][1]);
    out.put<std::uint8_t>(v);  // v weights: lists of different lengths
    for (int k = 0; k < v; ++k) out.put(0.25 * k);
    coordinate(xyz[v][2]);
  }
  for (const auto& face : faces) {
    if (ascii) {
      out.text("7 3 " + std::to_string(face[0]) + " " + std::to_string(face[1]) + " " +
               std::to_string(face[2]) + "\n");
      continue;
    }
    out.put<std::int32_t>(7).put<std::uint16_t>(3);
    for (unsigned index : face) out.put<std::uint32_t>(index);
  }
  if (ascii) {
    out.text("0 1\n");
  } else {
    out.put<std::int32_t>(0).put<std::int32_t>(1);
  }
  return out.data();
}

void expect_tetrahedron(const ReadResult& result) {
  ASSERT_EQ(result.mesh.num_vertices(), 4);
  ASSERT_EQ(result.mesh.num_faces(), 4);
  EXPECT_EQ(result.mesh.positions.row(1), Eigen::RowVector3d(1, -1, -1));
  EXPECT_EQ(result.mesh.positions(3, 2), 1.25);
  EXPECT_EQ(result.mesh.triangles.row(3), Eigen::RowVector3i(1, 3, 2));
}

TEST(ReadPly, BinaryLittleEndianFloat) {
  const ReadResult result = read_test_file(
      "le_float.ply", tetrahedron_ply("binary_little_endian", false, false, "vertex_indices"));
  EXPECT_EQ(result.format, MeshFormat::Ply);
  expect_tetrahedron(result);
  ASSERT_EQ(result.warnings.size(), 1u);
  expect_mentions(result.warnings[0], {"le_float.ply", "edge"});
}

TEST(ReadPly, BinaryBigEndianDouble) {
  expect_tetrahedron(read_test_file(
      "be_double.ply", tetrahedron_ply("binary_big_endian", true, true, "vertex_index")));
}

TEST(ReadPly, BinaryBigEndianFloatAndLittleEndianDouble) {
  expect_tetrahedron(read_test_file(
      "be_float.ply", tetrahedron_ply("binary_big_endian", true, false, "vertex_indices")));
  expect_tetrahedron(read_test_file(
      "le_double.ply", tetrahedron_ply("binary_little_endian", false, true, "vertex_indices")));
}

TEST(ReadPly, Ascii) {
  expect_tetrahedron(
      read_test_file("ascii.ply", tetrahedron_ply("ascii", false, false, "vertex_indices")));
}

/// Two triangles of a unit square sharing the diagonal (0,0,0)-(1,1,0), as STL corners.
const float kSquareCorners[2][3][3] = {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}},
                                       {{0, 0, 0}, {1, 1, 0}, {0, 1, 0}}};

TEST(ReadStl, BinaryWeldsEqualPositions) {
  ByteWriter out(false);
  out.text("solid but actually binary");
  out.text(std::string(80 - 25, ' '));
  out.put<std::uint32_t>(2);
  for (const auto& triangle : kSquareCorners) {
    out.put(0.0f).put(0.0f).put(1.0f);
    for (const auto& corner : triangle) out.put(corner[0]).put(corner[1]).put(corner[2]);
    out.put<std::uint16_t>(0);
  }
  const ReadResult result = read_test_file("square.stl", out.data());
  EXPECT_EQ(result.format, MeshFormat::Stl);
  ASSERT_EQ(result.mesh.num_vertices(), 4);  // six corners welded into four vertices
  ASSERT_EQ(result.mesh.num_faces(), 2);
  EXPECT_EQ(result.mesh.triangles.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(result.mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(result.mesh.positions.row(3), Eigen::RowVector3d(0, 1, 0));
}

TEST(ReadStl, AsciiWeldsEqualPositions) {
  std::string text = "solid square\n";
  for (const auto& triangle : kSquareCorners) {
    text += "  facet normal 0 0 1\n    outer loop\n";
    for (const auto& corner : triangle) {
      text += "      vertex " + std::to_string(corner[0]) + " " + std::to_string(corner[1]) + " " +
              std::to_string(corner[2]) + "\n";
    }
    text += "    endloop\n  endfacet\n";
  }
  text += "endsolid square\n";
  const ReadResult result = read_test_file("square_ascii.stl", text);
  ASSERT_EQ(result.mesh.num_vertices(), 4);
  ASSERT_EQ(result.mesh.num_faces(), 2);
  EXPECT_EQ(result.mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(result.mesh.positions.row(2), Eigen::RowVector3d(1, 1, 0));
}

TEST(Formats, FromExtensionIgnoringCase) {
  EXPECT_EQ(format_from_path("a/b.OBJ"), MeshFormat::Obj);
  EXPECT_EQ(format_from_path("x.Off"), MeshFormat::Off);
  EXPECT_EQ(format_from_path("x.ply"), MeshFormat::Ply);
  EXPECT_EQ(format_from_path("x.stl"), MeshFormat::Stl);
}

// ------------------------------------------------------------------------------------------
// Writing

TEST(WriteObj, RoundTripIsExact) {
  Mesh mesh;
  mesh.positions.resize(4, 3);
  mesh.positions << 0.1, 1.0 / 3.0, std::numbers::pi, -1e-300, 2.5e17, 7.0 / 9.0, 1, -1, -1,
      std::sqrt(2.0), -1, 1e-5;
  mesh.triangles.resize(4, 3);
  mesh.triangles << 0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2;
  const std::string path = (io_tmp_dir() / "roundtrip.obj").string();
  write_obj(path, mesh);
  const ReadResult result = read_mesh(path, {.validate = false});
  EXPECT_EQ(result.mesh.positions, mesh.positions);  // shortest round trip: every double exactly
  EXPECT_EQ(result.mesh.triangles, mesh.triangles);

  std::ifstream in(path);
  std::string first_line;
  std::getline(in, first_line);
  // The shortest text that reads back as the same double (std::to_chars), not %.17g's padding.
  EXPECT_EQ(first_line, "v 0.1 0.3333333333333333 3.141592653589793");
}

/// The folder `name` in the test folder, emptied, then holding only `file` with "old content";
/// returns the file's path.
std::string folder_with_old_file(const std::string& name, const std::string& file) {
  const fs::path folder = io_tmp_dir() / name;
  fs::remove_all(folder);
  fs::create_directories(folder);
  return write_test_file(name + "/" + file, "old content");
}

TEST(WriteAtomically, ReplacesTheFileAndLeavesNoTemporary) {
  const fs::path folder = io_tmp_dir() / "atomic_ok";
  const std::string path = folder_with_old_file("atomic_ok", "out.txt");
  write_file_atomically(path, [](std::ostream& out) { out << "new content"; });
  EXPECT_EQ(testing::read_text_file(path), "new content");
  EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);
}

TEST(WriteAtomically, ThrowingWriterLeavesTheOldFileAndNoTemporary) {
  const fs::path folder = io_tmp_dir() / "atomic_fail";
  const std::string path = folder_with_old_file("atomic_fail", "keep.obj");
  const std::string message = message_of<IoError>([&] {
    write_file_atomically(path, [](std::ostream& out) {
      out << "half of the new content";
      throw std::runtime_error("writer gave up");
    });
  });
  expect_mentions(message, {"keep.obj", "writer gave up"});
  EXPECT_EQ(testing::read_text_file(path), "old content");
  EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);
}

TEST(WriteAtomically, UnwritableFolderIsAnIoError) {
  const std::string path = (io_tmp_dir() / "no_such_dir" / "x.obj").string();
  const std::string message =
      message_of<IoError>([&] { write_file_atomically(path, [](std::ostream&) {}); });
  expect_mentions(message, {"x.obj", "temporary"});
}

// ------------------------------------------------------------------------------------------
// Bad input: every class of defect has its row in bad_input_catalogue_test.cpp; here only the
// sweep over every truncation of a binary file.

TEST(BadInput, EveryTruncationOfABinaryFileIsAnIoError) {
  for (const bool big_endian : {false, true}) {
    const std::string full =
        tetrahedron_ply(big_endian ? "binary_big_endian" : "binary_little_endian", big_endian, true,
                        "vertex_index");
    for (std::size_t cut = 1; cut < full.size(); ++cut) {
      const std::string path = write_test_file("cut.ply", full.substr(0, cut));
      EXPECT_THROW(read_mesh(path), IoError) << "cut after " << cut << " bytes";
    }
  }
}

// ------------------------------------------------------------------------------------------
// The real meshes of ../shared/meshes

/// The number after `key` in the manifest notes, e.g. "edges=8784" or "min angle 10.2 deg".
std::optional<double> note_number(const std::string& notes, const std::string& key) {
  const std::size_t at = notes.find(key);
  if (at == std::string::npos) return std::nullopt;
  return std::stod(notes.substr(at + key.size()));
}

TEST(SharedMeshes, ReadAndSummariseLikeTheManifest) {
  RICCI_REQUIRE_SHARED_MESHES();
  const auto meshes = testing::shared_meshes();
  ASSERT_FALSE(meshes.empty());
  for (const testing::SharedMesh& m : meshes) {
    SCOPED_TRACE(m.file);
    // The defective ones have their rows in bad_input_catalogue_test.cpp.
    if (!m.manifold || !m.orientable || m.file == "degtri_sliding.off") continue;
    const ReadResult result = read_mesh(m.path);
    EXPECT_EQ(result.polygons_triangulated, 0);
    const MeshInfo info = mesh_info(result.mesh);
    // The manifest counts every vertex in the file; the reader drops unreferenced ones.
    EXPECT_EQ(info.vertices + static_cast<int>(result.dropped_vertices.size()), m.vertices);
    std::smatch unreferenced;
    const bool has_unreferenced =
        std::regex_search(m.notes, unreferenced, std::regex("([0-9]+) unreferenced vertices"));
    EXPECT_EQ(static_cast<int>(result.dropped_vertices.size()),
              has_unreferenced ? std::stoi(unreferenced[1]) : 0);
    EXPECT_EQ(info.unreferenced_vertices, 0);
    EXPECT_EQ(info.faces, m.faces);
    EXPECT_EQ(info.boundary_loops, m.boundary_loops);
    EXPECT_EQ(info.euler_characteristic, m.euler_characteristic);
    EXPECT_EQ(info.genus, m.genus);
    EXPECT_EQ(info.components, 1);
    if (const auto edges = note_number(m.notes, "edges=")) {
      EXPECT_EQ(info.edges, *edges);
    }
    if (const auto angle = note_number(m.notes, "min angle ")) {
      // The manifest rounds to three significant digits.
      EXPECT_NEAR(info.min_angle_degrees, *angle, 0.006 * *angle);
    }
  }
}

/// The count the manifest notes give before `what`, e.g. "2534 non-manifold edges"; 0 if none.
int noted_count(const std::string& notes, const std::string& what) {
  std::smatch match;
  if (!std::regex_search(notes, match, std::regex("([0-9]+) " + what))) return 0;
  return std::stoi(match[1]);
}

TEST(SharedMeshes, DefectCountsLikeTheManifest) {
  RICCI_REQUIRE_SHARED_MESHES();
  for (const testing::SharedMesh& m : testing::shared_meshes()) {
    SCOPED_TRACE(m.file);
    const ReadResult result = read_mesh(m.path, {.validate = false});
    const MeshInfo info = mesh_info(result.mesh);
    auto count = [&](DefectKind kind) {
      for (const auto& [k, c] : info.validation.counts) {
        if (k == kind) return c;
      }
      return 0;
    };
    EXPECT_EQ(count(DefectKind::NonManifoldEdge), noted_count(m.notes, "non-manifold edges"));
    EXPECT_EQ(count(DefectKind::NonManifoldVertex), noted_count(m.notes, "non-manifold vertices"));
    EXPECT_EQ(count(DefectKind::DuplicateFace), noted_count(m.notes, "duplicate faces"));
    EXPECT_EQ(count(DefectKind::ZeroAreaFace), noted_count(m.notes, "zero-area triangles"));
    EXPECT_EQ(static_cast<int>(result.dropped_vertices.size()),
              noted_count(m.notes, "unreferenced vertices"));
    EXPECT_EQ(info.faces, m.faces);
    if (m.orientable) {
      EXPECT_EQ(count(DefectKind::InconsistentOrientation),
                noted_count(m.notes, "inconsistently oriented edges"));
      EXPECT_EQ(count(DefectKind::NonOrientable), 0);
    } else {
      EXPECT_EQ(count(DefectKind::NonOrientable), 1);  // one strip, one defect
    }
    EXPECT_EQ(info.validation.ok(), m.manifold && m.file != "degtri_sliding.off");
    if (!info.validation.ok() && count(DefectKind::ZeroAreaFace) == 0) {
      EXPECT_EQ(info.genus, -1);  // topology undefined
    }
  }
}

}  // namespace
}  // namespace ricci
