/// \file
/// Bindings of the mesh module: Mesh, reading and writing, validation, info, topology and the
/// generated meshes.

#include "bindings.hpp"
#include "ricci/mesh/generate.hpp"
#include "ricci/mesh/info.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/mesh/mesh.hpp"
#include "ricci/mesh/polygons.hpp"
#include "ricci/mesh/repair.hpp"
#include "ricci/mesh/topology.hpp"
#include "ricci/mesh/validate.hpp"

namespace ricci::python {
namespace {

/// The repair report as a dict, with the keys of the "repair" object of `ricci ... --json`.
py::dict repair_dict(const RepairReport& r) {
  auto count = [](const RepairCount& c) {
    py::dict d;
    d["count"] = c.count;
    d["examples"] = c.examples;
    return d;
  };
  py::dict d;
  d["changed"] = r.changed();
  d["input_vertices"] = r.input_vertices;
  d["input_faces"] = r.input_faces;
  d["output_vertices"] = r.output_vertices;
  d["output_faces"] = r.output_faces;
  d["welded_vertices"] = count(r.welded_vertices);
  d["repeated_vertex_faces_removed"] = count(r.repeated_vertex_faces_removed);
  d["duplicate_faces_removed"] = count(r.duplicate_faces_removed);
  d["slivers_removed"] = count(r.slivers_removed);
  d["boundary_slivers_removed"] = r.boundary_slivers_removed;
  d["faces_split"] = count(r.faces_split);
  py::dict edges;
  edges["count"] = r.non_manifold_edges_split;
  edges["examples"] = r.non_manifold_edge_examples;
  d["non_manifold_edges_split"] = edges;
  d["non_manifold_vertices_split"] = count(r.non_manifold_vertices_split);
  d["vertex_copies_added"] = r.vertex_copies_added;
  d["faces_flipped"] = count(r.faces_flipped);
  d["unreferenced_vertices_dropped"] = count(r.unreferenced_vertices_dropped);
  d["smaller_components_removed"] = count(r.smaller_components_removed);
  d["smaller_component_faces_removed"] = r.smaller_component_faces_removed;
  d["non_orientable_components"] = count(r.non_orientable_components);
  d["zero_area_faces_left"] = count(r.zero_area_faces_left);
  d["messages"] = r.messages;
  return d;
}

}  // namespace

void bind_mesh(py::module_& m) {
  StructBinding<Mesh>(m, "Mesh", "A triangle mesh: positions (#V, 3) and triangles (#F, 3).")
      .field("positions", &Mesh::positions, "#V by 3 vertex positions")
      .field("triangles", &Mesh::triangles,
             "#F by 3 vertex indices, counter-clockwise seen from outside")
      .keyword_constructor()
      .repr()
      .cls()
      .def(py::init([](Positions positions, Triangles triangles) {
             return Mesh{std::move(positions), std::move(triangles)};
           }),
           py::arg("positions"), py::arg("triangles"))
      .def_property_readonly("num_vertices", &Mesh::num_vertices)
      .def_property_readonly("num_faces", &Mesh::num_faces);

  py::enum_<MeshFormat> mesh_format(
      m, "MeshFormat",
      "Mesh file formats: read_mesh reads and write_mesh writes Obj, Off, Ply and Stl; Glb (glTF "
      "binary) is written by `ricci param -o x.glb`.");
  mesh_format.value("Obj", MeshFormat::Obj)
      .value("Off", MeshFormat::Off)
      .value("Ply", MeshFormat::Ply)
      .value("Stl", MeshFormat::Stl)
      .value("Glb", MeshFormat::Glb);
  bind_enum_names(mesh_format);

  py::enum_<DefectKind> defect_kind(m, "DefectKind", "The kinds of mesh defect.");
  defect_kind.value("NonFiniteCoordinate", DefectKind::NonFiniteCoordinate)
      .value("IndexOutOfRange", DefectKind::IndexOutOfRange)
      .value("RepeatedVertex", DefectKind::RepeatedVertex)
      .value("ZeroAreaFace", DefectKind::ZeroAreaFace)
      .value("DuplicateFace", DefectKind::DuplicateFace)
      .value("NonManifoldEdge", DefectKind::NonManifoldEdge)
      .value("NonManifoldVertex", DefectKind::NonManifoldVertex)
      .value("InconsistentOrientation", DefectKind::InconsistentOrientation)
      .value("NonOrientable", DefectKind::NonOrientable)
      .value("UnreferencedVertex", DefectKind::UnreferencedVertex);
  bind_enum_names(defect_kind);
  m.def("defect_name", &defect_name, py::arg("kind"),
        "Short stable name of a defect kind, e.g. 'non-manifold-edge'.");

  StructBinding<Defect>(m, "Defect", "One mesh defect.")
      .readonly("kind", &Defect::kind, "DefectKind")
      .readonly("element", &Defect::element, "vertex or face index, as the kind says")
      .readonly("message", &Defect::message, "e.g. 'vertex 17 has coordinate nan'")
      .computed(
          "name", [](const Defect& d) { return std::string(defect_name(d.kind)); },
          "short name of the kind, e.g. 'non-manifold-edge'")
      .repr();

  StructBinding<ValidationReport>(m, "ValidationReport", "All defects found in a mesh.")
      .readonly("defects", &ValidationReport::defects, "at most max_defects_per_kind of each kind")
      .readonly("counts", &ValidationReport::counts, "(kind, total count) of every kind found")
      .computed("ok", &ValidationReport::ok, "no defect other than UnreferencedVertex")
      .repr();

  StructBinding<RepairOptions>(m, "RepairOptions", "Options of repair_mesh.")
      .field("weld_vertices", &RepairOptions::weld_vertices,
             "weld vertices at the same position into one (the smallest index)")
      .field("weld_tolerance", &RepairOptions::weld_tolerance,
             "weld vertices closer than this times the bounding-box diagonal; 0: exact positions")
      .field("remove_slivers", &RepairOptions::remove_slivers,
             "remove zero-area faces with a vertex on their longest edge without changing the "
             "surface (split the face across that edge at the vertex)")
      .field("zero_area_tolerance", &RepairOptions::zero_area_tolerance,
             "zero area as validation sees it: twice the area at most this times the longest "
             "edge squared")
      .field("split_non_manifold", &RepairOptions::split_non_manifold,
             "split non-manifold edges and vertices")
      .field("orient", &RepairOptions::orient,
             "reverse faces so that each orientable component is consistently oriented")
      .field("largest_component_only", &RepairOptions::largest_component_only,
             "keep only the connected component with the most faces")
      .field("max_examples", &RepairOptions::max_examples, "examples kept per kind of change")
      .keyword_constructor()
      .repr();

  StructBinding<ReadOptions>(m, "ReadOptions", "Options of read_mesh.")
      .field("validate", &ReadOptions::validate,
             "run validate_mesh on the result and throw on the first defect")
      .field("repair", &ReadOptions::repair,
             "run repair_mesh on the file's triangles before validating")
      .field("auto_repair", &ReadOptions::auto_repair,
             "run repair_mesh only when the file has a defect (the default of read_mesh in "
             "Python and of the command line)")
      .field("repair_options", &ReadOptions::repair_options, "RepairOptions of that repair")
      .keyword_constructor()
      .repr();

  StructBinding<Polygons>(m, "Polygons",
                          "A polygon mesh's faces over its triangles (empty: every triangle a "
                          "face); ricci.polygon_faces lists each face's vertices.")
      .field("triangle_polygon", &Polygons::triangle_polygon,
             "#F: the polygon each triangle belongs to")
      .field("corner_start", &Polygons::corner_start,
             "#P + 1 offsets into corners (empty: no polygon)")
      .field("corners", &Polygons::corners,
             "each polygon's corners in order, as triangle corners 3 t + k: vertex F[t, k], uv "
             "row uv_triangles[t, k]")
      .keyword_constructor()
      .repr()
      .cls()
      .def_property_readonly("num_polygons", &Polygons::num_polygons)
      .def("empty", &Polygons::empty);

  StructBinding<ReadResult>(m, "ReadResult", "What read_mesh returns.")
      .readonly("mesh", &ReadResult::mesh, "the triangles, unreferenced vertices removed")
      .readonly("format", &ReadResult::format, "MeshFormat of the file")
      .readonly("warnings", &ReadResult::warnings, "e.g. 'bunny.obj: 12 polygons triangulated'")
      .readonly("polygons_triangulated", &ReadResult::polygons_triangulated,
                "faces with more than three corners in the file")
      .readonly("polygons", &ReadResult::polygons,
                "Polygons: the file's faces over the triangles (empty when all are triangles)")
      .readonly("dropped_vertices", &ReadResult::dropped_vertices,
                "file indices (0-based) of unreferenced vertices dropped")
      .readonly("vertex_map", &ReadResult::vertex_map,
                "#V: file index (0-based) of each output vertex")
      .readonly("validation", &ReadResult::validation,
                "defects found when validating (warnings only, since errors raise)")
      .readonly("file_vertices", &ReadResult::file_vertices, "vertices in the file")
      .readonly("repaired", &ReadResult::repaired,
                "repair_mesh ran (options.repair, or options.auto_repair on a file with defects)")
      .computed(
          "repair",
          [](const ReadResult& r) -> py::object {
            if (!r.repaired) return py::none();
            return repair_dict(r.repair);
          },
          "what repair changed, as a dict (the 'repair' object of the command line's --json), "
          "or None without repair")
      .repr();

  StructBinding<RepairResult>(m, "RepairResult", "What repair_mesh returns.")
      .readonly("mesh", &RepairResult::mesh, "the repaired mesh")
      .readonly("vertex_map", &RepairResult::vertex_map, "#V: input vertex of each output vertex")
      .readonly("face_map", &RepairResult::face_map, "#F: input face of each output face")
      .flags("face_flipped", &RepairResult::face_flipped, "#F: the face was reversed")
      .flags("face_split", &RepairResult::face_split,
             "#F: the face is a piece of its input face, split at a sliver's vertex")
      .readonly("weld_map", &RepairResult::weld_map,
                "input #V: the vertex each input vertex was welded onto (itself if not)")
      .computed(
          "report", [](const RepairResult& r) { return repair_dict(r.report); },
          "what changed, as a dict")
      .repr();
  m.def("repair_mesh", &repair_mesh, py::arg("mesh"), py::arg("options") = RepairOptions{},
        "Welds duplicate vertices, removes duplicate and collapsed faces and slivers (zero-area "
        "faces with a vertex on their longest edge), splits non-manifold edges and vertices, "
        "orients components and drops unreferenced vertices. Raises "
        "InvalidInput on an index out of range.",
        py::call_guard<py::gil_scoped_release>());

  StructBinding<ValidationOptions>(m, "ValidationOptions", "Options of find_defects.")
      .field("zero_area_tolerance", &ValidationOptions::zero_area_tolerance,
             "a face is degenerate when twice its area is at most this times its longest edge "
             "squared")
      .field("max_defects_per_kind", &ValidationOptions::max_defects_per_kind,
             "stop listing a kind after this many (the count goes on)")
      .keyword_constructor()
      .repr();
  m.def("read_mesh", &read_mesh, py::arg("path"), py::arg("options") = ReadOptions{},
        "Reads an OBJ, OFF, PLY or STL file. Raises IoError (file), InvalidInput or "
        "TopologyError (defects, when options.validate).",
        py::call_guard<py::gil_scoped_release>());
  m.def(
      "write_mesh",
      [](const std::string& path, const Mesh& mesh, const Triangles& uv_triangles,
         const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv, const std::string& format,
         bool drop_uv, const Polygons& polygons) {
        TexturedMesh textured;
        textured.mesh = mesh;
        textured.uv_triangles = uv_triangles;
        textured.uv = uv;
        textured.polygons = polygons;
        WriteOptions options;
        if (!format.empty()) options.format = parse_enum<MeshFormat>(format, "write_mesh");
        options.drop_uv = drop_uv;
        write_mesh(path, textured, options);
      },
      py::arg("path"), py::arg("mesh"), py::arg("uv_triangles"), py::arg("uv"),
      py::arg("format") = "", py::arg("drop_uv") = false, py::arg("polygons") = Polygons{},
      "Writes a mesh (empty uv_triangles and uv: without texture coordinates; non-empty "
      "polygons: one face per polygon) in the format of `format` or of the path's extension, "
      "atomically (C++ write_mesh).");
  m.def("validate_mesh", &validate_mesh, py::arg("mesh"), py::arg("context"),
        py::arg("options") = ValidationOptions{},
        "Raises on the first defect other than an unreferenced vertex (TopologyError for "
        "non-manifold and orientation defects, InvalidInput for the others).");
  m.def("find_defects", &find_defects, py::arg("mesh"), py::arg("options") = ValidationOptions{},
        "Lists every defect of the mesh.");

  StructBinding<ComponentInfo>(m, "ComponentInfo", "Topology of one connected component.")
      .readonly("vertices", &ComponentInfo::vertices, "")
      .readonly("edges", &ComponentInfo::edges, "")
      .readonly("faces", &ComponentInfo::faces, "")
      .readonly("boundary_loops", &ComponentInfo::boundary_loops, "")
      .readonly("euler_characteristic", &ComponentInfo::euler_characteristic, "")
      .readonly("genus", &ComponentInfo::genus, "")
      .repr();

  StructBinding<MeshInfo>(m, "MeshInfo",
                          "Summary of a mesh. Topological fields are -1 when defects keep them "
                          "from being defined.")
      .readonly("vertices", &MeshInfo::vertices, "referenced vertices")
      .readonly("unreferenced_vertices", &MeshInfo::unreferenced_vertices, "vertices no face uses")
      .readonly("edges", &MeshInfo::edges, "")
      .readonly("faces", &MeshInfo::faces, "")
      .readonly("components", &MeshInfo::components, "")
      .readonly("boundary_loops", &MeshInfo::boundary_loops, "")
      .readonly("euler_characteristic", &MeshInfo::euler_characteristic,
                "V - E + F over referenced vertices, when manifold")
      .readonly("genus", &MeshInfo::genus, "total over components, when manifold")
      .readonly("component_info", &MeshInfo::component_info, "ComponentInfo of each component")
      .readonly("min_angle_degrees", &MeshInfo::min_angle_degrees,
                "smallest corner angle over all faces")
      .readonly("max_angle_degrees", &MeshInfo::max_angle_degrees,
                "largest corner angle over all faces")
      .readonly("bounding_box_diagonal", &MeshInfo::bounding_box_diagonal, "")
      .readonly("validation", &MeshInfo::validation, "every defect found")
      .computed(
          "defects", [](const MeshInfo& info) { return info.validation.defects; },
          "validation.defects: the Defect list")
      .repr();
  m.def("mesh_info", &mesh_info, py::arg("mesh"),
        "Summary of a mesh; never raises on defective meshes.");

  StructBinding<Component>(m, "Component", "One connected component of a mesh.")
      .readonly("vertices", &Component::vertices, "vertex indices, ascending")
      .readonly("faces", &Component::faces, "face indices, ascending")
      .readonly("num_edges", &Component::num_edges, "")
      .readonly("num_boundary_loops", &Component::num_boundary_loops, "")
      .readonly("euler_characteristic", &Component::euler_characteristic, "")
      .readonly("genus", &Component::genus, "")
      .repr();

  StructBinding<Topology>(m, "Topology",
                          "Connectivity of a manifold mesh as flat arrays (halfedge h = 3 f + k "
                          "lies in face f opposite its corner k).")
      .readonly("num_vertices", &Topology::num_vertices, "")
      .readonly("num_edges", &Topology::num_edges, "")
      .readonly("num_faces", &Topology::num_faces, "")
      .readonly("triangles", &Topology::triangles, "#F by 3")
      .readonly("edge_vertices", &Topology::edge_vertices, "#E by 2, smaller index first")
      .readonly("face_edges", &Topology::face_edges, "#F by 3: edge opposite corner k of face f")
      .readonly("edge_halfedges", &Topology::edge_halfedges, "#E by 2, -1 if none")
      .readonly("halfedge_twin", &Topology::halfedge_twin,
                "3#F: opposite halfedge, -1 on the boundary")
      .flags("is_boundary_vertex", &Topology::is_boundary_vertex, "#V bools")
      .flags("is_boundary_edge", &Topology::is_boundary_edge, "#E bools")
      .readonly("vertex_degree", &Topology::vertex_degree, "#V incident edge counts")
      .readonly("boundary_loops", &Topology::boundary_loops, "vertices of each loop")
      .readonly("vertex_component", &Topology::vertex_component, "#V, -1 when unreferenced")
      .readonly("face_component", &Topology::face_component, "#F")
      .readonly("components", &Topology::components, "Component list")
      .repr();
  m.def("build_topology", py::overload_cast<const Triangles&, int>(&build_topology),
        py::arg("triangles"), py::arg("num_vertices"),
        "Connectivity of a triangle mesh; raises TopologyError on non-manifold input.");

  m.def("make_tetrahedron", &make_tetrahedron, py::arg("edge_length") = 1.0,
        "Regular tetrahedron centred at the origin.");
  m.def("make_icosphere", &make_icosphere, py::arg("subdivisions"), py::arg("radius") = 1.0,
        "Icosahedron subdivided `subdivisions` times, on the sphere of `radius`.");
  m.def("make_disk", &make_disk, py::arg("rings"), py::arg("bulge") = 0.0,
        "Unit disk of `rings` rings, lifted to the cap z = bulge (1 - x^2 - y^2).");
  m.def("make_torus", &make_torus, py::arg("major_segments"), py::arg("minor_segments"),
        py::arg("major_radius") = 1.0, py::arg("minor_radius") = 0.4,
        "Torus of revolution, vertex (i, j) at index i * minor_segments + j.");
  m.def("make_closed_surface", &make_closed_surface, py::arg("genus"), py::arg("resolution") = 12,
        "A closed orientable surface of the given genus.");
  m.def("make_surface_with_holes", &make_surface_with_holes, py::arg("genus"), py::arg("holes"),
        py::arg("resolution") = 12, "A surface of the given genus with `holes` boundary loops.");
  m.def("make_grid", &make_grid, py::arg("nx"), py::arg("ny"), py::arg("width") = 1.0,
        py::arg("height") = 1.0, "Flat rectangular grid of nx by ny quads split in triangles.");
}

}  // namespace ricci::python
