// The catalogue of bad input: one row per class of defect, each read as the file comes, with
// ReadOptions::repair, and with ReadOptions::auto_repair (the front ends' default: as the file
// comes when it has no defect, else as with repair). A row says what each read must do: throw a
// given exception class with a message naming the file, the line (or byte) and the element (and,
// read as it comes, ReadOptions::repair as the fix where repair makes the mesh valid), or read
// with the warnings and the repair messages named and a mesh that passes the row's checks.
// docs/mesh-input.md shows the same catalogue as a table.
#include <gtest/gtest.h>

#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <typeinfo>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/mesh/info.hpp"
#include "ricci/mesh/io.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

namespace fs = std::filesystem;

/// What a read must throw; Nothing means it must succeed.
enum class Thrown { Nothing, Io, Invalid, Topology };

/// What one read of a row's file must do.
struct Expect {
  Thrown thrown = Thrown::Nothing;
  /// Pieces of the exception's message; on success, pieces of the warnings and repair messages.
  std::vector<std::string> words = {};
  /// On success: checks of the result (counts, topology).
  std::function<void(const ReadResult&)> check = {};
  /// On an InvalidInput: the fixes it names.
  std::vector<OptionFix> fixes = {};
};

/// One class of bad input.
struct Row {
  std::string defect;    ///< the test's name
  std::string file;      ///< file name in the test folder ("" for a missing file)
  std::string content;   ///< the bytes written there
  Expect plain = {};     ///< read_mesh(path)
  Expect repaired = {};  ///< read_mesh(path, {.repair = true}); empty: as plain
};

fs::path catalogue_dir() {
  return testing::suite_tmp_dir("bad_input_catalogue");
}

const char* thrown_name(Thrown thrown) {
  switch (thrown) {
    case Thrown::Nothing:
      return "nothing";
    case Thrown::Io:
      return "IoError";
    case Thrown::Invalid:
      return "InvalidInput";
    case Thrown::Topology:
      return "TopologyError";
  }
  return "?";
}

/// The class of a ricci exception, exactly (TopologyError is also an InvalidInput).
Thrown classify(const Error& e) {
  if (typeid(e) == typeid(TopologyError)) return Thrown::Topology;
  if (typeid(e) == typeid(InvalidInput)) return Thrown::Invalid;
  if (typeid(e) == typeid(IoError)) return Thrown::Io;
  return Thrown::Nothing;
}

void expect_words(const std::string& text, const std::vector<std::string>& pieces) {
  for (const std::string& piece : pieces) {
    EXPECT_NE(text.find(piece), std::string::npos) << "lacks \"" << piece << "\": " << text;
  }
}

/// Reads `path` with `options` and checks the outcome against `expect`.
void run_expectation(const std::string& path, const ReadOptions& options, const Expect& expect) {
  try {
    const ReadResult result = read_mesh(path, options);
    ASSERT_EQ(expect.thrown, Thrown::Nothing)
        << "read without error, expected " << thrown_name(expect.thrown);
    std::string said;
    for (const std::string& w : result.warnings) said += w + "\n";
    for (const std::string& m : result.repair.messages) said += m + "\n";
    expect_words(said, expect.words);
    if (expect.check) expect.check(result);
  } catch (const InvalidInput& e) {
    EXPECT_EQ(thrown_name(classify(e)), std::string(thrown_name(expect.thrown))) << e.what();
    expect_words(e.what(), expect.words);
    EXPECT_EQ(e.fixes(), expect.fixes) << e.what();
  } catch (const Error& e) {
    EXPECT_EQ(thrown_name(classify(e)), std::string(thrown_name(expect.thrown))) << e.what();
    expect_words(e.what(), expect.words);
  }
}

/// The fix a refusal names where repair makes the mesh valid.
std::vector<OptionFix> repair_fix() {
  return fixes_of({{"repair", "true"}});
}

ReadOptions with_auto_repair() {
  ReadOptions options;
  options.auto_repair = true;
  return options;
}

/// What the auto mode must do: read a file without defects as it comes, repair any other (the
/// warning naming the file's first defect beside the repair messages).
Expect automatic(const Expect& plain, const Expect& repaired) {
  if (plain.thrown != Thrown::Invalid && plain.thrown != Thrown::Topology) return plain;
  if (repaired.thrown != Thrown::Nothing) return repaired;
  Expect expect = repaired;
  expect.words.emplace_back("the mesh was repaired");
  return expect;
}

ReadOptions with_repair() {
  ReadOptions options;
  options.repair = true;
  return options;
}

/// Checks shared by the successful rows: the mesh validates, and its topology.
void expect_valid(const ReadResult& r, int vertices, int faces, int components, int chi,
                  int boundary_loops) {
  const MeshInfo info = mesh_info(r.mesh);
  EXPECT_TRUE(info.validation.ok());
  EXPECT_EQ(info.vertices, vertices);
  EXPECT_EQ(info.unreferenced_vertices, 0);
  EXPECT_EQ(info.faces, faces);
  EXPECT_EQ(info.components, components);
  EXPECT_EQ(info.euler_characteristic, chi);
  EXPECT_EQ(info.boundary_loops, boundary_loops);
}

// ---------------------------------------------------------------------------------------------
// Generated files

/// Little-endian binary values, for PLY and STL files.
class LittleEndian {
 public:
  LittleEndian& text(const std::string& s) {
    data_ += s;
    return *this;
  }
  LittleEndian& u8(std::uint8_t x) { return bytes(x, 1); }
  LittleEndian& u16(std::uint16_t x) { return bytes(x, 2); }
  LittleEndian& u32(std::uint32_t x) { return bytes(x, 4); }
  LittleEndian& i32(std::int32_t x) { return bytes(static_cast<std::uint32_t>(x), 4); }
  LittleEndian& f32(float x) { return bytes(std::bit_cast<std::uint32_t>(x), 4); }
  const std::string& data() const { return data_; }

 private:
  LittleEndian& bytes(std::uint64_t x, int n) {
    for (int i = 0; i < n; ++i) data_ += static_cast<char>((x >> (8 * i)) & 0xff);
    return *this;
  }
  std::string data_;
};

/// A binary little-endian PLY tetrahedron: 4 float vertices, 4 faces as uchar-counted int lists.
std::string tetrahedron_ply() {
  LittleEndian out;
  out.text(
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
      "property float y\nproperty float z\nelement face 4\n"
      "property list uchar int vertex_indices\nend_header\n");
  const float xyz[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  const int faces[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  for (const auto& p : xyz) out.f32(p[0]).f32(p[1]).f32(p[2]);
  for (const auto& f : faces) out.u8(3).i32(f[0]).i32(f[1]).i32(f[2]);
  return out.data();
}

/// A Moebius strip of 2n triangles as OBJ: rails a_i, b_i around a circle, the rung a_i b_i
/// turning by half a turn over the loop, so the last quad joins (a_{n-1}, b_{n-1}) to (b_0, a_0).
std::string moebius_obj(int n) {
  std::string text;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n;
    const double c = std::cos(t), s = std::sin(t), h = 0.3 * std::cos(t / 2);
    const double z = 0.3 * std::sin(t / 2);
    for (const double sign : {1.0, -1.0}) {
      text += "v " + std::to_string((1 + sign * h) * c) + " " + std::to_string((1 + sign * h) * s) +
              " " + std::to_string(sign * z) + "\n";
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

std::string ply_with_index(int index, std::size_t* where) {
  LittleEndian ply;
  ply.text(
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n");
  *where = ply.data().size() + 36;  // the face, after three vertices of 12 bytes
  for (int i = 0; i < 9; ++i) ply.f32(i == 3 || i == 7 ? 1.0f : 0.0f);
  ply.u8(3).i32(0).i32(index).i32(1);
  return ply.data();
}

std::string truncated_stl() {
  LittleEndian stl;
  stl.text(std::string(80, ' ')).u32(3);
  for (int i = 0; i < 12; ++i) stl.f32(0.5f);
  stl.u16(0);
  for (int i = 0; i < 5; ++i) stl.f32(0.5f);  // triangle 1 is cut off after 20 of its 50 bytes
  return stl.data();
}

std::vector<Row> generated_rows() {
  const std::string ply = tetrahedron_ply();
  // Cut inside the third face: the header, 4 vertices of 12 bytes, two faces of 13, 5 more.
  const std::string cut_ply = ply.substr(0, ply.find("end_header\n") + 11 + 48 + 26 + 5);
  std::size_t ply_index_byte = 0;
  const std::string ply_range = ply_with_index(-5, &ply_index_byte);

  std::vector<Row> rows = {
      // Files that cannot be read: repair never runs.
      {"MissingFile", "", "", {Thrown::Io, {"does_not_exist.obj", "no such file"}}, {}},
      {"ZeroByteFile", "empty.off", "", {Thrown::Io, {"empty.off", "empty file (0 bytes)"}}, {}},
      {"NoFaces",
       "nofaces.off",
       "OFF\n1 0 0\n0 0 0\n",
       {Thrown::Io, {"nofaces.off", "line 2", "no faces"}},
       {}},
      {"UnknownFormat",
       "mesh.xyz",
       "v 0 0 0\n",
       {Thrown::Io, {"mesh.xyz", "unknown mesh format", ".xyz"}},
       {}},
      {"BinaryPlyCutInTheMiddle",
       "cut.ply",
       cut_ply,
       {Thrown::Io, {"cut.ply", "byte ", "truncated", "face 2 of 4"}},
       {}},
      {"TruncatedOff",
       "truncated.off",
       "OFF\n4 6 0\n1 1 1\n1 -1 -1\n-1 1 -1\n-1 -1 1\n3 0 1 2\n3 0 2 3\n",
       {Thrown::Io, {"truncated.off", "truncated", "declares 6 faces", "ends after 2"}},
       {}},
      {"TruncatedBinaryStl",
       "truncated.stl",
       truncated_stl(),
       {Thrown::Io, {"truncated.stl", "declares 3 triangles", "triangle 1 at byte 134 is cut off"}},
       {}},
      {"MalformedNumberObj",
       "malformed.obj",
       "v 0 0 0\nv 1 0 0\nv 0 1.5x 0\n",
       {Thrown::Io, {"malformed.obj", "line 3", "malformed number", "'1.5x'", "vertex 2"}},
       {}},
      {"MalformedNumberPly",
       "malformed.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 0\n0 1 zero\n3 0 1 2\n",
       {Thrown::Io, {"malformed.ply", "line 12", "'zero'", "vertex 2"}},
       {}},
      {"ListLengthBeyondItsTypePly",
       "long_list.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 0\n0 1 0\n" +
           std::string(120, '5') + " 0 1 2\n",
       {Thrown::Io,
        {"long_list.ply", "line 13", "list length beyond 2^63", "face 0", "largest value", "255"}},
       {}},
      {"FaceWithTwoCorners",
       "short.obj",
       "v 0 0 0\nv 1 0 0\nf 1 2\n",
       {Thrown::Io, {"short.obj", "line 3", "face 0", "2 corners"}},
       {}},
      {"UnknownObjStatement",
       "unknown.obj",
       "v 0 0 0\nvx 1 0 0\n",
       {Thrown::Io, {"unknown.obj", "line 2", "'vx'"}},
       {}},
      {"MisspelledPlyHeader",
       "header.ply",
       "ply\nformat ascii 1.0\nelemnt x\n",
       {Thrown::Io, {"header.ply", "line 3", "'elemnt'"}},
       {}},
      {"MoreOffFacesThanDeclared",
       "extra.off",
       "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n",
       {Thrown::Io, {"extra.off", "line 7", "after the last of the 1 declared faces"}},
       {}},
      {"MisspelledStlKeyword",
       "bad.stl",
       "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertx 1 0 0\n",
       {Thrown::Io, {"bad.stl", "line 5", "'vertx'"}},
       {}},
      // Face indices out of range: the reader refuses them before repair could run.
      {"FaceIndexTenToTheNine",
       "range.obj",
       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n# faces\nf 1 2 3\nf 2 4 1000000000\n",
       {Thrown::Invalid,
        {"range.obj", "line 7", "face 1 uses vertex index 1000000000",
         "the file has only 4 vertices"}},
       {}},
      {"FaceIndexZeroInObj",
       "zero.obj",
       "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
       {Thrown::Invalid, {"zero.obj", "line 4", "face 0", "index 0"}},
       {}},
      {"FaceIndexPastTheEndInOff",
       "range.off",
       "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
       {Thrown::Invalid, {"range.off", "line 6", "face 0", "index 3"}},
       {}},
      {"NegativeFaceIndexInBinaryPly",
       "range.ply",
       ply_range,
       {Thrown::Invalid,
        {"range.ply", "byte " + std::to_string(ply_index_byte), "face 0", "index -5"}},
       {}},
      // Defects repair does not touch.
      {"NanCoordinate",
       "nan.obj",
       "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\n\nv -1 nan 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n",
       {Thrown::Invalid, {"nan.obj", "line 5", "vertex 3 has a non-finite coordinate", "nan"}},
       {Thrown::Invalid,
        {"nan.obj", "line 5: after repair", "vertex 3", "non-finite",
         "repair does not change coordinates"}}},
      {"InfiniteCoordinate",
       "inf.off",
       "OFF\n3 1 0\n0 0 0\n1 0 inf\n0 1 0\n3 0 1 2\n",
       {Thrown::Invalid, {"inf.off", "line 4", "vertex 1", "inf"}},
       {Thrown::Invalid, {"inf.off", "line 4: after repair", "inf"}}},
      // A disk whose centre is two vertices 1e-14 apart, joined by two needles.
      {"ZeroAreaFaceNeedle",
       "needle.obj",
       "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nv 1 1 0\nv 1.00000000000001 1 0\n"
       "f 1 2 6\nf 2 3 6\nf 3 4 5\nf 4 1 5\nf 1 6 5\nf 3 5 6\n",
       {Thrown::Invalid, {"needle.obj", "line 11", "face 4 (0, 5, 4) has zero area"}},
       {Thrown::Invalid,
        {"needle.obj", "after repair", "zero area",
         "repair removes zero-area faces only where it can without changing the surface"}}},
      {"MoebiusStrip",
       "moebius.obj",
       moebius_obj(8),
       {Thrown::Topology, {"moebius.obj", "line 17", "non-orientable", "16 faces", "face 0"}},
       {Thrown::Topology,
        {"moebius.obj", "line 17: after repair", "non-orientable",
         "repair cannot orient a non-orientable surface"}}},
      // Defects repair fixes.
      {"FaceUsesAVertexTwice",
       "repeated.obj",
       "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 3\n",
       {Thrown::Invalid,
        {"repeated.obj", "line 5", "face 1 uses vertex 2 more than once"},
        {},
        repair_fix()},
       {Thrown::Nothing,
        {"removed 1 faces that use a vertex twice (e.g. face 1)"},
        [](const ReadResult& r) { expect_valid(r, 3, 1, 1, 1, 1); }}},
      {"DuplicateFace",
       "duplicate.obj",
       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\nf 3 1 2\n",
       {Thrown::Invalid,
        {"duplicate.obj", "line 7", "face 2", "same vertices as face 0"},
        {},
        repair_fix()},
       {Thrown::Nothing,
        {"removed 1 duplicate faces (e.g. face 2, the same vertices as face 0)"},
        [](const ReadResult& r) {
          expect_valid(r, 4, 2, 1, 1, 1);
          EXPECT_EQ(r.repair.duplicate_faces_removed.examples, std::vector<int>{2});
        }}},
      {"NonManifoldEdge",
       "fin.obj",
       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0.5 0.5 1\nf 1 2 3\nf 2 4 3\nf 2 5 3\n",
       {Thrown::Topology,
        {"fin.obj", "line 6", "non-manifold edge (1, 2) is shared by 3 faces (0, 1, 2)"},
        {},
        repair_fix()},
       {Thrown::Nothing,
        {"split 1 non-manifold edges", "(e.g. edge (1, 2))",
         "split 2 non-manifold vertices into one copy per fan of faces (2 copies added)"},
        [](const ReadResult& r) {
          // The flat square (faces 0 and 1) stays whole; the fin (face 2) is detached.
          expect_valid(r, 7, 3, 2, 2, 2);
          EXPECT_EQ(r.vertex_map, (std::vector<int>{0, 1, 2, 3, 4, 1, 2}));
          EXPECT_EQ(r.mesh.triangles.row(2), Eigen::RowVector3i(5, 4, 6));
        }}},
      {"NonManifoldBowTieVertex",
       "bowtie.off",
       "OFF\n5 2 0\n0 0 0\n1 0 0\n0.5 1 0\n0 2 0\n1 2 0\n3 0 1 2\n3 2 4 3\n",
       {Thrown::Topology,
        {"bowtie.off", "line 5", "non-manifold vertex 2", "2 fans"},
        {},
        repair_fix()},
       {Thrown::Nothing,
        {"split 1 non-manifold vertices", "(e.g. vertex 2)"},
        [](const ReadResult& r) {
          expect_valid(r, 6, 2, 2, 2, 2);
          EXPECT_EQ(r.vertex_map, (std::vector<int>{0, 1, 2, 3, 4, 2}));
        }}},
      {"InconsistentOrientation",
       "flipped.obj",
       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 4 2 3\n",
       {Thrown::Topology,
        {"flipped.obj", "line 6", "inconsistent orientation", "faces 1 and 0", "edge (1, 2)",
         "the surface is orientable"},
        {},
        repair_fix()},
       {Thrown::Nothing,
        {"reversed 1 faces to orient their components consistently (e.g. face 1)"},
        [](const ReadResult& r) {
          expect_valid(r, 4, 2, 1, 1, 1);
          EXPECT_EQ(r.mesh.triangles.row(1), Eigen::RowVector3i(3, 2, 1));
        }}},
      {"ZeroAreaFaceOnTheBoundary",
       "collinear.obj",
       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 4 2\n",
       {Thrown::Invalid,
        {"collinear.obj", "line 6", "face 1 (0, 3, 1) has zero area"},
        {},
        repair_fix()},
       {Thrown::Nothing,
        {"removed 1 zero-area faces with a vertex on their longest edge (slivers) (e.g. face 1)",
         "1 on the boundary (they cover nothing)", "dropped 1 unreferenced vertices"},
        [](const ReadResult& r) { expect_valid(r, 3, 1, 1, 1, 1); }}},
      {"ZeroAreaFaceInside",
       "sliver.obj",
       "v 0 0 0\nv 2 0 0\nv 1 0 0\nv 1 -1 0\nv 1 1 0\n"
       "f 1 4 2\nf 1 3 5\nf 3 2 5\nf 1 2 3\n",
       {Thrown::Invalid,
        {"sliver.obj", "line 9", "face 3 (0, 1, 2) has zero area"},
        {},
        repair_fix()},
       {Thrown::Nothing,
        {"removed 1 zero-area faces with a vertex on their longest edge (slivers) (e.g. face 3): "
         "1 by splitting the face across that edge at the vertex (1 faces split (e.g. face 0); "
         "the surface is unchanged)"},
        [](const ReadResult& r) { expect_valid(r, 5, 4, 1, 1, 1); }}},
      // Repaired by the reader itself, with a warning (and left alone by repair).
      {"Polygons",
       "cube.obj",
       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
       "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
       {Thrown::Nothing,
        {"cube.obj: 6 polygons with more than 3 corners triangulated"},
        [](const ReadResult& r) {
          EXPECT_EQ(r.polygons_triangulated, 6);
          expect_valid(r, 8, 12, 1, 2, 0);
          EXPECT_EQ(r.mesh.triangles.row(0), Eigen::RowVector3i(0, 3, 2));  // fan from corner 0
          EXPECT_EQ(r.mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 1));
        }},
       {Thrown::Nothing,
        {"6 polygons"},
        [](const ReadResult& r) {
          EXPECT_FALSE(r.repair.changed());
          expect_valid(r, 8, 12, 1, 2, 0);
        }}},
      {"UnreferencedVertices",
       "unreferenced.obj",
       "v 1 1 1\nv 1 -1 -1\nv 5 5 5\nv -1 1 -1\nv -1 -1 1\nv 7 7 7\n"
       "f 1 2 4\nf 1 4 5\nf 1 5 2\nf 2 5 4\n",
       {Thrown::Nothing,
        {"unreferenced.obj: 2 unreferenced vertices dropped (the first is vertex 2 at line 3)"},
        [](const ReadResult& r) {
          EXPECT_EQ(r.dropped_vertices, (std::vector<int>{2, 5}));
          EXPECT_EQ(r.vertex_map, (std::vector<int>{0, 1, 3, 4}));
          EXPECT_EQ(r.mesh.positions.row(2), Eigen::RowVector3d(-1, 1, -1));
          EXPECT_EQ(r.mesh.triangles.row(3), Eigen::RowVector3i(1, 3, 2));
          ASSERT_EQ(r.validation.counts.size(), 1u);
          EXPECT_EQ(r.validation.counts[0], std::make_pair(DefectKind::UnreferencedVertex, 2));
          expect_valid(r, 4, 4, 1, 2, 0);
        }},
       {Thrown::Nothing,
        {"dropped 2 unreferenced vertices (e.g. vertices 2, 5)"},
        [](const ReadResult& r) {
          EXPECT_EQ(r.dropped_vertices, (std::vector<int>{2, 5}));
          EXPECT_EQ(r.vertex_map, (std::vector<int>{0, 1, 3, 4}));
          expect_valid(r, 4, 4, 1, 2, 0);
        }}},
      // Read as they are (a seam may be meant), with a warning; repair welds them.
      {"DuplicateVertices",
       "unwelded.obj",
       "v 1 1 1\nv 1 -1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 1 1\n"
       "f 1 2 3\nf 1 3 4\nf 5 4 2\nf 2 4 3\n",
       {Thrown::Nothing,
        {"unwelded.obj: 1 vertices repeat the position of another vertex and are kept apart "
         "(e.g. vertex 4 at line 5 and vertex 0); repair welds them"},
        [](const ReadResult& r) { expect_valid(r, 5, 4, 1, 1, 1); }},  // a slit: one boundary
       {Thrown::Nothing,
        {"welded 1 vertices onto earlier vertices at the same position (e.g. vertex 4 onto "
         "vertex 0)"},
        [](const ReadResult& r) {
          expect_valid(r, 4, 4, 1, 2, 0);  // the closed tetrahedron
          EXPECT_EQ(r.repair.welded_vertices.examples, std::vector<int>{4});
          EXPECT_TRUE(r.dropped_vertices.empty());  // welded, not dropped
        }}},
  };
  // Where repair never gets to run, it must fail the same way.
  for (Row& row : rows) {
    if (row.repaired.thrown == Thrown::Nothing && row.repaired.words.empty() &&
        !row.repaired.check) {
      row.repaired = row.plain;
    }
  }
  return rows;
}

class BadInputCatalogue : public ::testing::TestWithParam<Row> {};

TEST_P(BadInputCatalogue, PlainAndRepaired) {
  const Row& row = GetParam();
  std::string path = (catalogue_dir() / "does_not_exist.obj").string();
  if (!row.file.empty()) {
    path = (catalogue_dir() / row.file).string();
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(row.content.data(), static_cast<std::streamsize>(row.content.size()));
  }
  {
    SCOPED_TRACE("plain read");
    run_expectation(path, ReadOptions{}, row.plain);
  }
  {
    SCOPED_TRACE("read with repair");
    run_expectation(path, with_repair(), row.repaired);
  }
  {
    SCOPED_TRACE("read with auto repair");
    run_expectation(path, with_auto_repair(), automatic(row.plain, row.repaired));
  }
}

INSTANTIATE_TEST_SUITE_P(Generated, BadInputCatalogue, ::testing::ValuesIn(generated_rows()),
                         [](const ::testing::TestParamInfo<Row>& param) {
                           return param.param.defect;
                         });

// ---------------------------------------------------------------------------------------------
// The defective meshes of ../shared/meshes (skipped where the folder is missing)

struct SharedRow {
  std::string file;
  Expect plain = {};
  Expect repaired = {};
};

std::vector<SharedRow> shared_rows() {
  return {
      // Unwelded patch seams: non-manifold where patches meet at a point.
      {"teapot.obj",
       {Thrown::Topology, {"teapot.obj", "line ", "non-manifold vertex", "fans"}, {}, repair_fix()},
       {Thrown::Nothing,
        {"welded 403 vertices", "split 1 non-manifold vertices"},
        [](const ReadResult& r) {
          EXPECT_EQ(r.repair.welded_vertices.count, 403);
          expect_valid(r, 3242, 6320, 4, 2, 6);
        }}},
      // Three sheets meeting along edges.
      {"triple_vierbein.obj",
       {Thrown::Topology,
        {"triple_vierbein.obj", "line ", "non-manifold edge", "faces"},
        {},
        repair_fix()},
       {Thrown::Nothing,
        {"split 20 non-manifold edges", "non-manifold vertices", "reversed"},
        [](const ReadResult& r) {
          EXPECT_EQ(r.repair.non_manifold_edges_split, 20);
          expect_valid(r, 97, 108, 2, 2, 2);
        }}},
      // Decimated with broken topology: the first defect in check order is a duplicate face.
      {"dragon_vrip_res2.ply",
       {Thrown::Invalid,
        {"dragon_vrip_res2.ply", "line ", "face 582", "same vertices as face 581",
         "more duplicate-face defects"},
        {},
        repair_fix()},
       {Thrown::Nothing,
        {"removed 1489 duplicate faces", "non-manifold edges", "dropped 43 unreferenced"},
        [](const ReadResult& r) {
          const RepairReport& report = r.repair;
          EXPECT_EQ(report.duplicate_faces_removed.count, 1489);
          EXPECT_EQ(report.unreferenced_vertices_dropped.count, 43);
          EXPECT_EQ(report.non_orientable_components.count, 0);
          // Every edge with more than two faces once duplicates are gone (2534 with them).
          EXPECT_EQ(report.non_manifold_edges_split, 2260);
          EXPECT_GT(report.non_manifold_vertices_split.count, 0);
          EXPECT_EQ(r.mesh.num_faces(), 202520 - 1489);
          const MeshInfo info = mesh_info(r.mesh);
          EXPECT_TRUE(info.validation.ok());
          EXPECT_GE(info.components, 7);
          EXPECT_EQ(info.unreferenced_vertices, 0);
        }}},
      // Four slivers in a chain along one line between two fans: split until none is left.
      {"degtri_sliding.off",
       {Thrown::Invalid,
        {"degtri_sliding.off", "line 13", "face 2 (3, 2, 4) has zero area"},
        {},
        repair_fix()},
       {Thrown::Nothing,
        {"removed 4 zero-area faces with a vertex on their longest edge"},
        [](const ReadResult& r) {
          EXPECT_EQ(r.repair.slivers_removed.count, 4);
          expect_valid(r, 8, 8, 1, 1, 1);
        }}},
      {"moebius_big.ply",
       {Thrown::Topology, {"moebius_big.ply", "byte 6717", "non-orientable", "480 faces"}},
       {Thrown::Topology,
        {"moebius_big.ply", "byte 6717: after repair", "non-orientable",
         "repair cannot orient a non-orientable surface"}}},
      // Duplicate positions where holes touch: welding makes pinch vertices, which are split
      // again, so the repaired mesh is the input.
      {"elephant-with-holes.off",
       {Thrown::Nothing,
        {"65 vertices repeat the position of another vertex"},
        [](const ReadResult& r) { expect_valid(r, 2798, 4463, 1, -110, 106); }},
       {Thrown::Nothing,
        {"welded 65 vertices", "split 65 non-manifold vertices"},
        [](const ReadResult& r) { expect_valid(r, 2798, 4463, 1, -110, 106); }}},
      {"stanford-bunny.obj",
       {Thrown::Nothing,
        {"1113 unreferenced vertices dropped"},
        [](const ReadResult& r) {
          EXPECT_EQ(r.dropped_vertices.size(), 1113u);
          EXPECT_EQ(r.validation.count(DefectKind::UnreferencedVertex), 1113);
        }},
       {Thrown::Nothing,
        {"dropped 1113 unreferenced vertices"},
        [](const ReadResult& r) {
          EXPECT_EQ(r.dropped_vertices.size(), 1113u);
          expect_valid(r, 34834, 69451, 1, -3, 5);
        }}},
  };
}

class SharedMeshCatalogue : public ::testing::TestWithParam<SharedRow> {};

TEST_P(SharedMeshCatalogue, PlainAndRepaired) {
  RICCI_REQUIRE_SHARED_MESHES();
  const SharedRow& row = GetParam();
  const fs::path path = fs::path(*testing::shared_meshes_dir()) / row.file;
  if (!fs::exists(path)) GTEST_SKIP() << path << " is missing";
  {
    SCOPED_TRACE("plain read");
    run_expectation(path.string(), ReadOptions{}, row.plain);
  }
  {
    SCOPED_TRACE("read with repair");
    run_expectation(path.string(), with_repair(), row.repaired);
  }
  {
    SCOPED_TRACE("read with auto repair");
    run_expectation(path.string(), with_auto_repair(), automatic(row.plain, row.repaired));
  }
}

INSTANTIATE_TEST_SUITE_P(Shared, SharedMeshCatalogue, ::testing::ValuesIn(shared_rows()),
                         [](const ::testing::TestParamInfo<SharedRow>& param) {
                           std::string name;
                           for (const char c : param.param.file) {
                             name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace ricci
