// Polygon meshes: read_mesh keeps the file's faces as Polygons over its triangles (through the
// triangulation, the dropping of unreferenced vertices and repair), the helpers of
// ricci/mesh/polygons.hpp, and write_mesh writing the polygons back.
#include "ricci/mesh/polygons.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"
#include "support/polygon_meshes.hpp"
#include "support/shared_meshes.hpp"

namespace ricci {
namespace {

using Faces = std::vector<std::vector<int>>;
using testing::PolygonSoup;
using testing::read_soup;

/// The faces the polygons describe, as vertex indices of the file (through vertex_map).
Faces faces_of(const Polygons& polygons, const Triangles& triangles,
               const std::vector<int>& vertex_map) {
  Faces faces;
  for (int p = 0; p < polygons.num_polygons(); ++p) {
    std::vector<int>& face = faces.emplace_back();
    for (int i = polygons.corner_start[p]; i < polygons.corner_start[p + 1]; ++i) {
      const int c = polygons.corners[i];
      face.push_back(vertex_map[triangles(c / 3, c % 3)]);
    }
  }
  return faces;
}

TEST(ReadPolygons, KeepsTheQuadsOfATorusInFileOrder) {
  const PolygonSoup soup = testing::quad_torus(6, 4);
  const ReadResult r = read_soup(soup, "quad_torus.obj");
  EXPECT_EQ(r.polygons_triangulated, 24);
  ASSERT_EQ(r.polygons.num_polygons(), 24);
  ASSERT_EQ(r.mesh.num_faces(), 48);
  EXPECT_NO_THROW(check_polygons(r.polygons, r.mesh.triangles, "test"));
  EXPECT_EQ(faces_of(r.polygons, r.mesh.triangles, r.vertex_map), soup.faces);
  for (int t = 0; t < 48; ++t) EXPECT_EQ(r.polygons.triangle_polygon[t], t / 2) << t;
  // One diagonal per quad, none of them an edge of the file.
  const Topology topology = build_topology(r.mesh.triangles, r.mesh.num_vertices());
  const std::vector<char> diagonals = polygon_diagonals(topology, r.polygons);
  EXPECT_EQ(std::count(diagonals.begin(), diagonals.end(), 1), 24);
  for (int e = 0; e < topology.num_edges; ++e) {
    if (!diagonals[e]) continue;
    const int a = topology.edge_vertices(e, 0), b = topology.edge_vertices(e, 1);
    for (const auto& face : soup.faces) {
      for (std::size_t i = 0; i < face.size(); ++i) {
        const int u = face[i], w = face[(i + 1) % face.size()];
        EXPECT_FALSE((u == a && w == b) || (u == b && w == a)) << "diagonal " << a << "-" << b;
      }
    }
  }
}

TEST(ReadPolygons, KeepsANonConvexOctagonThatEarClippingSplit) {
  const PolygonSoup soup = testing::l_octagon_grid(true);
  const ReadResult r = read_soup(soup, "l_octagon.obj");
  ASSERT_EQ(r.polygons.num_polygons(), 7);
  EXPECT_EQ(r.polygons.size(0), 8);
  EXPECT_EQ(r.mesh.num_faces(), 6 + 6 * 2);
  EXPECT_NO_THROW(check_polygons(r.polygons, r.mesh.triangles, "test"));
  EXPECT_EQ(faces_of(r.polygons, r.mesh.triangles, r.vertex_map), soup.faces);
  bool ear_clipped = false;
  for (const std::string& w : r.warnings)
    ear_clipped |= w.find("ear clipping") != std::string::npos;
  EXPECT_TRUE(ear_clipped);
}

TEST(ReadPolygons, TrianglesAndPolygonsMixedInFileOrderThroughUnreferencedVertices) {
  // Vertex 0 is unreferenced (dropped); a triangle and two quads.
  const std::string clean = testing::write_text_file(
      testing::suite_tmp_dir("polygons") / "mixed.off",
      "OFF\n8 3 0\n9 9 9\n0 0 0\n1 0 0\n2 0.5 0\n1 1 0\n0 1 0\n-1 0.5 0\n-1 -1 0\n"
      "3 1 2 5\n4 2 3 4 5\n4 1 5 6 7\n");
  const ReadResult r = read_mesh(clean);
  EXPECT_EQ(r.dropped_vertices, std::vector<int>{0});
  ASSERT_EQ(r.polygons.num_polygons(), 3);
  EXPECT_EQ(faces_of(r.polygons, r.mesh.triangles, r.vertex_map),
            (Faces{{1, 2, 5}, {2, 3, 4, 5}, {1, 5, 6, 7}}));
}

TEST(ReadPolygons, ATriangleMeshHasNoPolygons) {
  PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  soup.faces = {{0, 1, 2}, {1, 3, 2}};
  const ReadResult r = read_soup(soup, "triangles.obj");
  EXPECT_TRUE(r.polygons.empty());
  EXPECT_EQ(r.polygons.num_polygons(), 0);
}

TEST(ReadPolygons, RepairWeldsAndTurnsPolygonsOverWhole) {
  // A 3 by 2 grid of quads whose right column repeats the vertices it shares with the left
  // ones (unwelded), and whose middle-bottom quad is written clockwise.
  PolygonSoup soup = testing::quad_grid(3, 2);
  const int w = 3;  // vertices per column (m + 1)
  std::vector<int> copy(soup.positions.size(), -1);
  for (int j = 0; j < w; ++j) {  // column i = 2 shared by the middle and right quads
    copy[2 * w + j] = static_cast<int>(soup.positions.size());
    soup.positions.push_back(soup.positions[2 * w + j]);
  }
  for (auto& face : soup.faces) {
    const bool right = face[0] / w == 2;  // quads (2, j) start in column 2
    if (!right) continue;
    for (int& v : face) {
      if (copy[v] >= 0) v = copy[v];
    }
  }
  const std::vector<int> reversed = {soup.faces[2][0], soup.faces[2][3], soup.faces[2][2],
                                     soup.faces[2][1]};
  soup.faces[2] = reversed;  // quad (1, 0) clockwise
  ReadOptions options;
  options.repair = true;
  const ReadResult r = read_soup(soup, "grid_unwelded.obj", options);
  EXPECT_EQ(r.repair.welded_vertices.count, 3);
  ASSERT_EQ(r.polygons.num_polygons(), 6);
  EXPECT_NO_THROW(check_polygons(r.polygons, r.mesh.triangles, "test"));
  // Welded corners name the vertex they were welded onto; the reversed quad comes back turned
  // over (the orientation of the majority), its corners listed from the same first corner.
  const Faces expected = testing::quad_grid(3, 2).faces;
  const Faces got = faces_of(r.polygons, r.mesh.triangles, r.vertex_map);
  for (int p = 0; p < 6; ++p) {
    if (p == 2) {
      EXPECT_EQ(got[p], (std::vector<int>{reversed[0], reversed[3], reversed[2], reversed[1]}));
    } else {
      EXPECT_EQ(got[p], expected[p]) << "polygon " << p;
    }
  }
}

TEST(ReadPolygons, APolygonThatRepairCutsIsWrittenAsItsTrianglesLeft) {
  // A triangle, then a quad whose fan repeats that triangle (removed by repair as a duplicate),
  // then a quad that stays whole.
  PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
  soup.faces = {{0, 1, 2}, {0, 1, 2, 3}, {1, 4, 5, 2}};
  ReadOptions options;
  options.repair = true;
  const ReadResult r = read_soup(soup, "cut_quad.obj", options);
  EXPECT_EQ(r.repair.duplicate_faces_removed.count, 1);
  ASSERT_EQ(r.mesh.num_faces(), 4);
  ASSERT_EQ(r.polygons.num_polygons(), 3);
  EXPECT_NO_THROW(check_polygons(r.polygons, r.mesh.triangles, "test"));
  EXPECT_EQ(faces_of(r.polygons, r.mesh.triangles, r.vertex_map),
            (Faces{{0, 1, 2}, {0, 2, 3}, {1, 4, 5, 2}}));
}

TEST(Polygons, CheckNamesWhatIsWrong) {
  const ReadResult r = read_soup(testing::quad_grid(2, 1), "grid_2x1.obj");
  ASSERT_EQ(r.polygons.num_polygons(), 2);
  auto message = [&](const Polygons& p) {
    try {
      check_polygons(p, r.mesh.triangles, "ctx");
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Polygons p = r.polygons;
  p.triangle_polygon.pop_back();
  EXPECT_NE(message(p).find("ctx: polygons.triangle_polygon has 3 entries for 4 triangles"),
            std::string::npos)
      << message(p);
  p = r.polygons;
  p.corners[0] = p.corners[4];  // a corner of the other polygon's triangle
  EXPECT_NE(message(p).find("corner 0 of polygon 0"), std::string::npos) << message(p);
  p = r.polygons;
  p.triangle_polygon[1] = 1;  // polygon 0 with one triangle, polygon 1 with three
  EXPECT_NE(message(p).find("polygon 0 has 4 corners and 1 triangles"), std::string::npos)
      << message(p);
  EXPECT_EQ(message(Polygons{}), "no error");
}

TEST(Polygons, FansSubsetsAndDiagonals) {
  const ReadResult r = read_soup(testing::quad_grid(2, 2), "grid_2x2.obj");
  // The fan of a quad from its first corner: (c0, c1, c2), (c0, c2, c3).
  const Triangles fans = polygon_fans(r.polygons, r.mesh.triangles);
  ASSERT_EQ(fans.rows(), 8);
  const auto& c = r.polygons.corners;
  auto vertex = [&](int corner) { return r.mesh.triangles(corner / 3, corner % 3); };
  EXPECT_EQ(fans.row(0), Eigen::RowVector3i(vertex(c[0]), vertex(c[1]), vertex(c[2])));
  EXPECT_EQ(fans.row(1), Eigen::RowVector3i(vertex(c[0]), vertex(c[2]), vertex(c[3])));
  // The triangles of polygons 1 and 3, and one triangle of polygon 2.
  const Polygons sub = polygons_of_faces(r.polygons, {2, 3, 4, 6, 7});
  ASSERT_EQ(sub.num_polygons(), 3);
  EXPECT_EQ(sub.size(0), 4);
  EXPECT_EQ(sub.size(1), 3);
  EXPECT_EQ(sub.size(2), 4);
  EXPECT_EQ(sub.triangle_polygon, (std::vector<int>{0, 0, 1, 2, 2}));
  Triangles sub_triangles(5, 3);
  const std::vector<int> picked = {2, 3, 4, 6, 7};
  for (int i = 0; i < 5; ++i) sub_triangles.row(i) = r.mesh.triangles.row(picked[i]);
  EXPECT_NO_THROW(check_polygons(sub, sub_triangles, "sub"));
  EXPECT_TRUE(polygons_of_faces(r.polygons, {4}).empty());  // one triangle: no polygon left
}

TEST(WritePolygons, ObjOffAndPlyWriteThePolygonsBack) {
  const PolygonSoup soup = testing::l_octagon_grid(true);
  const ReadResult r = read_soup(soup, "l_octagon_write.obj");
  TexturedMesh textured;
  textured.mesh = r.mesh;
  textured.polygons = r.polygons;
  for (const char* extension : {"obj", "off", "ply"}) {
    const std::string path =
        (testing::suite_tmp_dir("polygons") / (std::string("written.") + extension)).string();
    write_mesh(path, textured);
    const ReadResult back = read_mesh(path);
    EXPECT_EQ(faces_of(back.polygons, back.mesh.triangles, back.vertex_map), soup.faces)
        << extension;
  }
  // With texture coordinates: one `f v/vt ...` per polygon, uv rows from the triangle corners.
  textured.uv_triangles = textured.mesh.triangles;
  textured.uv = textured.mesh.positions.leftCols<2>();
  const std::string path = (testing::suite_tmp_dir("polygons") / "written_uv.obj").string();
  write_mesh(path, textured);
  const std::string text = testing::read_text_file(path);
  EXPECT_NE(text.find("\nf 1/1 2/2 3/3 7/7 6/6 10/10 9/9 5/5\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nf 3/3 4/4 8/8 7/7\n"), std::string::npos) << text;
  const TexturedMesh read_back = read_textured_obj(path);
  ASSERT_EQ(read_back.polygons.num_polygons(), 7);
  EXPECT_NO_THROW(check_polygons(read_back.polygons, read_back.mesh.triangles, "back"));
  // read_textured_obj keeps the polygons too: writing what it read gives the same file.
  const std::string again = (testing::suite_tmp_dir("polygons") / "written_uv_again.obj").string();
  write_mesh(again, read_back);
  EXPECT_EQ(testing::read_text_file(again), text);
}

TEST(WritePolygons, RefusesPolygonsThatDoNotFitTheTriangles) {
  const ReadResult r = read_soup(testing::quad_grid(1, 1), "one_quad.obj");
  TexturedMesh textured;
  textured.mesh = r.mesh;
  textured.polygons = r.polygons;
  textured.polygons.corners[3] = textured.polygons.corners[0];  // the vertex twice, one missing
  const std::string path = (testing::suite_tmp_dir("polygons") / "bad_polygons.obj").string();
  try {
    write_mesh(path, textured);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("write_mesh: " + path), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace ricci
