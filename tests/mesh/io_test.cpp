#include "ricci/mesh/io.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <typeinfo>

#include <Eigen/Geometry>

#include "ricci/errors.hpp"
#include "ricci/mesh/info.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;

/// This file's own folder under the shared test folder, so that names cannot clash with other
/// suites running at the same time.
fs::path io_tmp_dir() {
  const fs::path folder = fs::path(testing::test_tmp_dir()) / "mesh_io";
  fs::create_directories(folder);
  return folder;
}

/// Writes `content` to a fresh file of the given name in the test folder; returns its path.
std::string write_test_file(const std::string& name, const std::string& content) {
  const std::string path = (io_tmp_dir() / name).string();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  return path;
}

/// Runs `action`, which must throw exactly E (not a subclass), and returns the message.
template <class E>
std::string message_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(typeid(e).name()), std::string(typeid(E).name()))
        << "wrong exception class, message: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no exception thrown";
  return "";
}

/// Expects the message to contain every one of the given pieces.
void expect_mentions(const std::string& message, std::initializer_list<std::string> pieces) {
  for (const std::string& piece : pieces) {
    EXPECT_NE(message.find(piece), std::string::npos)
        << "message lacks \"" << piece << "\": " << message;
  }
}

/// Appends binary values in a chosen byte order, to build PLY and STL files in tests.
class ByteWriter {
 public:
  explicit ByteWriter(bool big_endian)
      : swap_(big_endian != (std::endian::native == std::endian::big)) {}
  template <class T>
  ByteWriter& put(T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (swap_) std::reverse(bytes, bytes + sizeof(T));
    data_.append(bytes, sizeof(T));
    return *this;
  }
  ByteWriter& text(const std::string& s) {
    data_ += s;
    return *this;
  }
  const std::string& data() const { return data_; }

 private:
  bool swap_;
  std::string data_;
};

const char* kTetrahedronObj =
    "# a regular tetrahedron\n"
    "v 1 1 1\n"
    "v 1 -1 -1\n"
    "v -1 1 -1\n"
    "v -1 -1 1\n"
    "f 1 2 3\n"
    "f 1 3 4\n"
    "f 1 4 2\n"
    "f 2 4 3\n";

// ------------------------------------------------------------------------------------------
// Reading good files

TEST(ReadObj, TetrahedronWithCommentsAndAttributes) {
  const std::string path = write_test_file(
      "attributes.obj",
      "mtllib tetra.mtl\r\no tetra\nv 1 1 1\nv 1 -1 -1\nv -1 1 -1 # trailing comment\n"
      "v -1 -1 1 1.0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\ng side\ns 1\nusemtl red\n"
      "f 1/1/1 2/2/1 3/3/1\nf 1//1 3//1 4//1\nf 1/1 4/2 2/3\nl 1 2\nf 2 4 3\n");
  const ReadResult result = read_mesh(path);
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
  const std::string path = write_test_file(
      "negative.obj",
      "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nf -3 -2 -1\nv -1 -1 1\nf -4 -2 -1\nf 1 -1 2\nf 2 4 3\n");
  const ReadResult result = read_mesh(path);
  ASSERT_EQ(result.mesh.num_faces(), 4);
  EXPECT_EQ(result.mesh.triangles.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(result.mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(result.mesh.triangles.row(2), Eigen::RowVector3i(0, 3, 1));
}

TEST(ReadObj, QuadsAreTriangulatedWithAWarning) {
  // A unit cube of six outward-facing quads.
  const std::string path =
      write_test_file("cube.obj",
                      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                      "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
  const ReadResult result = read_mesh(path);
  EXPECT_EQ(result.polygons_triangulated, 6);
  EXPECT_EQ(result.mesh.num_faces(), 12);
  ASSERT_EQ(result.warnings.size(), 1u);
  expect_mentions(result.warnings[0], {"cube.obj", "6 polygons", "triangulated"});
  // Convex quads are fanned from their first corner.
  EXPECT_EQ(result.mesh.triangles.row(0), Eigen::RowVector3i(0, 3, 2));
  EXPECT_EQ(result.mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 1));
  const MeshInfo info = mesh_info(result.mesh);
  EXPECT_EQ(info.euler_characteristic, 2);
  EXPECT_EQ(info.edges, 18);
}

TEST(ReadObj, NonConvexPolygonIsEarClipped) {
  // A dart with a reflex corner at its second vertex: the fan from the first corner would give
  // a clockwise triangle (0, 1, 2), so ear clipping takes over. Its area is 1.7.
  const std::string path =
      write_test_file("dart.obj", "v 0 0 0\nv 1 0.3 0\nv 2 0 0\nv 1 2 0\nf 1 2 3 4\n");
  const ReadResult result = read_mesh(path);
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

TEST(ReadObj, UnreferencedVerticesAreDroppedAndReported) {
  const std::string path =
      write_test_file("unreferenced.obj",
                      "v 1 1 1\nv 1 -1 -1\nv 5 5 5\nv -1 1 -1\nv -1 -1 1\nv 7 7 7\n"
                      "f 1 2 4\nf 1 4 5\nf 1 5 2\nf 2 5 4\n");
  const ReadResult result = read_mesh(path);
  EXPECT_EQ(result.dropped_vertices, (std::vector<int>{2, 5}));
  EXPECT_EQ(result.vertex_map, (std::vector<int>{0, 1, 3, 4}));
  ASSERT_EQ(result.mesh.num_vertices(), 4);
  EXPECT_EQ(result.mesh.positions.row(2), Eigen::RowVector3d(-1, 1, -1));
  EXPECT_EQ(result.mesh.triangles.row(3), Eigen::RowVector3i(1, 3, 2));
  ASSERT_EQ(result.warnings.size(), 1u);
  expect_mentions(result.warnings[0],
                  {"unreferenced.obj", "2 unreferenced vertices dropped", "vertex 2", "line 3"});
  ASSERT_EQ(result.validation.counts.size(), 1u);
  EXPECT_EQ(result.validation.counts[0].first, DefectKind::UnreferencedVertex);
  EXPECT_EQ(result.validation.counts[0].second, 2);
}

TEST(ReadOff, ColouredHeaderCommentsAndCountsOnTheHeaderLine) {
  const std::string path = write_test_file(
      "tetra.off",
      "COFF # coloured\n# counts next\n\n4 4 6\n1 1 1 255 0 0 255\n1 -1 -1 0 255 0 255\n"
      "-1 1 -1 0 0 255 255\n# a comment between vertices\n-1 -1 1 9 9 9 9\n"
      "3 0 1 2\n3 0 2 3 0.5 0.5 0.5\n3 0 3 1\n3 1 3 2\n\n");
  const ReadResult result = read_mesh(path);
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

/// The tetrahedron of kTetrahedronObj as a PLY: vertices with extra properties (a uchar colour,
/// a list of doubles), faces with an extra int, and an extra element, in the given encoding.
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
  const std::string path = write_test_file(
      "le_float.ply", tetrahedron_ply("binary_little_endian", false, false, "vertex_indices"));
  const ReadResult result = read_mesh(path);
  EXPECT_EQ(result.format, MeshFormat::Ply);
  expect_tetrahedron(result);
  ASSERT_EQ(result.warnings.size(), 1u);
  expect_mentions(result.warnings[0], {"le_float.ply", "edge"});
}

TEST(ReadPly, BinaryBigEndianDouble) {
  const std::string path = write_test_file(
      "be_double.ply", tetrahedron_ply("binary_big_endian", true, true, "vertex_index"));
  expect_tetrahedron(read_mesh(path));
}

TEST(ReadPly, BinaryBigEndianFloatAndLittleEndianDouble) {
  expect_tetrahedron(read_mesh(write_test_file(
      "be_float.ply", tetrahedron_ply("binary_big_endian", true, false, "vertex_indices"))));
  expect_tetrahedron(read_mesh(write_test_file(
      "le_double.ply", tetrahedron_ply("binary_little_endian", false, true, "vertex_indices"))));
}

TEST(ReadPly, Ascii) {
  const std::string path =
      write_test_file("ascii.ply", tetrahedron_ply("ascii", false, false, "vertex_indices"));
  expect_tetrahedron(read_mesh(path));
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
  const ReadResult result = read_mesh(write_test_file("square.stl", out.data()));
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
  const ReadResult result = read_mesh(write_test_file("square_ascii.stl", text));
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
  EXPECT_EQ(result.mesh.positions, mesh.positions);  // %.17g round-trips every double exactly
  EXPECT_EQ(result.mesh.triangles, mesh.triangles);

  std::ifstream in(path);
  std::string first_line;
  std::getline(in, first_line);
  EXPECT_EQ(first_line, "v 0.10000000000000001 0.33333333333333331 3.1415926535897931");
}

TEST(WriteAtomically, ReplacesTheFileAndLeavesNoTemporary) {
  const fs::path folder = io_tmp_dir() / "atomic_ok";
  fs::remove_all(folder);
  fs::create_directories(folder);
  const std::string path = (folder / "out.txt").string();
  write_test_file("atomic_ok/out.txt", "old content");
  write_file_atomically(path, [](std::ostream& out) { out << "new content"; });
  std::ifstream in(path);
  std::stringstream content;
  content << in.rdbuf();
  EXPECT_EQ(content.str(), "new content");
  EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);
}

TEST(WriteAtomically, ThrowingWriterLeavesTheOldFileAndNoTemporary) {
  const fs::path folder = io_tmp_dir() / "atomic_fail";
  fs::remove_all(folder);
  fs::create_directories(folder);
  const std::string path = (folder / "keep.obj").string();
  write_test_file("atomic_fail/keep.obj", "old content");
  const std::string message = message_of<IoError>([&] {
    write_file_atomically(path, [](std::ostream& out) {
      out << "half of the new content";
      throw std::runtime_error("writer gave up");
    });
  });
  expect_mentions(message, {"keep.obj", "writer gave up"});
  std::ifstream in(path);
  std::stringstream content;
  content << in.rdbuf();
  EXPECT_EQ(content.str(), "old content");
  EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);
}

TEST(WriteAtomically, UnwritableFolderIsAnIoError) {
  const std::string path = (io_tmp_dir() / "no_such_dir" / "x.obj").string();
  const std::string message =
      message_of<IoError>([&] { write_file_atomically(path, [](std::ostream&) {}); });
  expect_mentions(message, {"x.obj", "temporary"});
}

// ------------------------------------------------------------------------------------------
// One test per class of bad input: the exception class, the file name and the element.

TEST(BadInput, MissingFile) {
  const std::string path = (io_tmp_dir() / "does_not_exist.obj").string();
  const std::string message = message_of<IoError>([&] { read_mesh(path); });
  expect_mentions(message, {"does_not_exist.obj", "no such file"});
}

TEST(BadInput, EmptyFile) {
  const std::string empty = write_test_file("empty.off", "");
  expect_mentions(message_of<IoError>([&] { read_mesh(empty); }), {"empty.off", "0 bytes"});
  const std::string no_faces = write_test_file("nofaces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expect_mentions(message_of<IoError>([&] { read_mesh(no_faces); }), {"nofaces.obj", "no faces"});
  const std::string no_faces_off = write_test_file("nofaces.off", "OFF\n1 0 0\n0 0 0\n");
  expect_mentions(message_of<IoError>([&] { read_mesh(no_faces_off); }),
                  {"nofaces.off", "line 2", "no faces"});
}

TEST(BadInput, TruncatedBinaryPly) {
  const std::string full = tetrahedron_ply("binary_little_endian", false, false, "vertex_indices");
  // Cut inside the third face: the header, 4 vertices, two faces of 4 + 2 + 12 bytes, 5 more.
  const std::size_t header = full.find("end_header\n") + 11;
  const std::size_t vertices = 4 * (4 + 1 + 4 + 1 + 4) + 8 * (0 + 1 + 2 + 3);
  const std::size_t cut = header + vertices + 2 * 18 + 5;
  const std::string path = write_test_file("truncated.ply", full.substr(0, cut));
  const std::string message = message_of<IoError>([&] { read_mesh(path); });
  expect_mentions(message, {"truncated.ply", "truncated", "face 2 of 4", "byte "});
}

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

TEST(BadInput, TruncatedOffWithFewerFacesThanDeclared) {
  const std::string path = write_test_file(
      "truncated.off", "OFF\n4 6 0\n1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n3 0 1 2\n3 0 2 3\n");
  const std::string message = message_of<IoError>([&] { read_mesh(path); });
  expect_mentions(message, {"truncated.off", "truncated", "declares 6 faces", "ends after 2"});
}

TEST(BadInput, TruncatedBinaryStl) {
  ByteWriter out(false);
  out.text(std::string(80, ' ')).put<std::uint32_t>(3);
  for (int i = 0; i < 12; ++i) out.put(0.5f);
  out.put<std::uint16_t>(0);
  for (int i = 0; i < 5; ++i) out.put(0.5f);  // triangle 1 is cut off after 20 of its 50 bytes
  const std::string path = write_test_file("truncated.stl", out.data());
  const std::string message = message_of<IoError>([&] { read_mesh(path); });
  expect_mentions(message, {"truncated.stl", "truncated", "declares 3 triangles",
                            "triangle 1 at byte 134 is cut off"});
}

TEST(BadInput, UnknownFormat) {
  const std::string path = write_test_file("mesh.xyz", kTetrahedronObj);
  const std::string message = message_of<IoError>([&] { read_mesh(path); });
  expect_mentions(message, {"mesh.xyz", "unknown mesh format", ".xyz"});
}

TEST(BadInput, MalformedNumber) {
  const std::string obj = write_test_file("malformed.obj", "v 0 0 0\nv 1 0 0\nv 0 1.5x 0\n");
  expect_mentions(message_of<IoError>([&] { read_mesh(obj); }),
                  {"malformed.obj", "line 3", "malformed number", "'1.5x'", "vertex 2"});
  const std::string ply = write_test_file(
      "malformed.ply",
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 zero\n3 0 1 2\n");
  expect_mentions(message_of<IoError>([&] { read_mesh(ply); }),
                  {"malformed.ply", "line 12", "'zero'", "vertex 2"});
}

TEST(BadInput, NonFiniteCoordinate) {
  const std::string path = write_test_file(
      "nan.obj",
      "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\n\nv -1 nan 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n");
  const std::string message = message_of<InvalidInput>([&] { read_mesh(path); });
  expect_mentions(message, {"nan.obj", "line 5", "vertex 3", "non-finite", "nan"});
  const std::string inf =
      write_test_file("inf.off", "OFF\n3 1 0\n0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n");
  expect_mentions(message_of<InvalidInput>([&] { read_mesh(inf); }),
                  {"inf.off", "line 4", "vertex 1", "inf"});
}

TEST(BadInput, IndexOutOfRange) {
  const std::string obj = write_test_file(
      "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n# faces\nf 1 2 3\nf 2 4 1000000000\n");
  expect_mentions(message_of<InvalidInput>([&] { read_mesh(obj); }),
                  {"range.obj", "line 7", "face 1", "1000000000"});
  const std::string zero = write_test_file("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  expect_mentions(message_of<InvalidInput>([&] { read_mesh(zero); }),
                  {"zero.obj", "line 4", "face 0", "index 0"});
  const std::string off =
      write_test_file("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
  expect_mentions(message_of<InvalidInput>([&] { read_mesh(off); }),
                  {"range.off", "line 6", "face 0", "index 3"});
  ByteWriter ply(false);
  ply.text(
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n");
  const std::size_t header = ply.data().size();
  for (int i = 0; i < 9; ++i) ply.put(static_cast<float>(i == 3 || i == 7));
  ply.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(-5).put<std::int32_t>(1);
  const std::string ply_path = write_test_file("range.ply", ply.data());
  expect_mentions(message_of<InvalidInput>([&] { read_mesh(ply_path); }),
                  {"range.ply", "byte " + std::to_string(header + 36), "face 0", "index -5"});
}

TEST(BadInput, FaceUsesAVertexTwice) {
  const std::string path =
      write_test_file("repeated.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 3\n");
  const std::string message = message_of<InvalidInput>([&] { read_mesh(path); });
  expect_mentions(message, {"repeated.obj", "line 5", "face 1", "vertex 2 more than once"});
}

TEST(BadInput, DuplicateFace) {
  const std::string path = write_test_file(
      "duplicate.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\nf 3 1 2\n");
  const std::string message = message_of<InvalidInput>([&] { read_mesh(path); });
  expect_mentions(message, {"duplicate.obj", "line 7", "face 2", "same vertices as face 0"});
}

TEST(BadInput, NonManifoldEdge) {
  // Three triangles on the edge (1, 2).
  const std::string path = write_test_file(
      "fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0.5 0.5 1\nf 1 2 3\nf 2 4 3\nf 2 5 3\n");
  const std::string message = message_of<TopologyError>([&] { read_mesh(path); });
  expect_mentions(message,
                  {"fin.obj", "line 6", "non-manifold edge (1, 2)", "shared by 3 faces (0, 1, 2)"});
}

TEST(BadInput, NonManifoldVertex) {
  // Two triangles touching only at vertex 2 (a bow tie).
  const std::string path = write_test_file(
      "bowtie.off", "OFF\n5 2 0\n0 0 0\n1 0 0\n0.5 1 0\n0 2 0\n1 2 0\n3 0 1 2\n3 2 4 3\n");
  const std::string message = message_of<TopologyError>([&] { read_mesh(path); });
  expect_mentions(message, {"bowtie.off", "line 5", "non-manifold vertex 2", "2 fans"});
}

TEST(BadInput, InconsistentOrientation) {
  // Face 1 runs along edge 1 -> 2 like face 0 does: flipping it fixes the orientation.
  const std::string path =
      write_test_file("flipped.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 4 2 3\n");
  const std::string message = message_of<TopologyError>([&] { read_mesh(path); });
  expect_mentions(message, {"flipped.obj", "line 6", "inconsistent orientation", "faces 1 and 0",
                            "edge (1, 2)", "orientable"});
}

/// A Moebius strip of 2n triangles: rails a_i, b_i around a circle, the rung a_i b_i turning by
/// half a turn over the loop, so the last quad joins (a_{n-1}, b_{n-1}) to (b_0, a_0).
std::string moebius_obj(int n) {
  std::string text;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n;
    const Eigen::Vector3d centre(std::cos(t), std::sin(t), 0);
    const Eigen::Vector3d rung =
        0.3 * (std::cos(t / 2) * centre + std::sin(t / 2) * Eigen::Vector3d::UnitZ());
    for (const Eigen::Vector3d& p :
         {Eigen::Vector3d(centre + rung), Eigen::Vector3d(centre - rung)}) {
      text += "v " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " +
              std::to_string(p.z()) + "\n";
    }
  }
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i + 1, b = 2 * i + 2;  // 1-based
    const int next_a = i + 1 < n ? a + 2 : 2, next_b = i + 1 < n ? b + 2 : 1;
    text += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(next_b) +
            "\nf " + std::to_string(a) + " " + std::to_string(next_b) + " " +
            std::to_string(next_a) + "\n";
  }
  return text;
}

TEST(BadInput, NonOrientableSurface) {
  const std::string path = write_test_file("moebius.obj", moebius_obj(8));
  const std::string message = message_of<TopologyError>([&] { read_mesh(path); });
  expect_mentions(message, {"moebius.obj", "line 17", "non-orientable", "16 faces", "face 0"});
  // Without validation it reads, and mesh_info reports the defect instead of throwing.
  const MeshInfo info = mesh_info(read_mesh(path, {.validate = false}).mesh);
  EXPECT_EQ(info.genus, -1);
  ASSERT_FALSE(info.validation.defects.empty());
  EXPECT_EQ(info.validation.defects[0].kind, DefectKind::NonOrientable);
}

TEST(BadInput, ZeroAreaFace) {
  const std::string path =
      write_test_file("collinear.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 4 2\n");
  const std::string message = message_of<InvalidInput>([&] { read_mesh(path); });
  expect_mentions(message, {"collinear.obj", "line 6", "face 1", "zero area"});
}

TEST(BadInput, MalformedStructure) {
  const std::string short_face = write_test_file("short.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
  expect_mentions(message_of<IoError>([&] { read_mesh(short_face); }),
                  {"short.obj", "line 3", "face 0", "2 corners"});
  const std::string unknown = write_test_file("unknown.obj", "v 0 0 0\nvx 1 0 0\n");
  expect_mentions(message_of<IoError>([&] { read_mesh(unknown); }),
                  {"unknown.obj", "line 2", "'vx'"});
  const std::string bad_header = write_test_file("header.ply", "ply\nformat ascii 1.0\nelemnt x\n");
  expect_mentions(message_of<IoError>([&] { read_mesh(bad_header); }),
                  {"header.ply", "line 3", "'elemnt'"});
  const std::string extra =
      write_test_file("extra.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n");
  expect_mentions(message_of<IoError>([&] { read_mesh(extra); }),
                  {"extra.off", "line 7", "after the last of the 1 declared faces"});
  const std::string stl = write_test_file(
      "bad.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertx 1 0 0\n");
  expect_mentions(message_of<IoError>([&] { read_mesh(stl); }), {"bad.stl", "line 5", "'vertx'"});
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
    if (m.file == "degtri_sliding.off") {
      expect_mentions(message_of<InvalidInput>([&] { read_mesh(m.path); }),
                      {"degtri_sliding.off", "zero area", "line "});
      continue;
    }
    if (!m.orientable) {
      expect_mentions(message_of<TopologyError>([&] { read_mesh(m.path); }),
                      {m.file, "non-orientable"});
      continue;
    }
    if (!m.manifold) {
      try {
        read_mesh(m.path);
        ADD_FAILURE() << "non-manifold mesh read without error";
      } catch (const TopologyError& e) {
        expect_mentions(e.what(), {m.file, "non-manifold"});
      } catch (const InvalidInput& e) {
        expect_mentions(e.what(), {m.file, "same vertices as face"});  // a duplicate face
      }
      continue;
    }
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
