"""Mesh repair: read_mesh's repair modes and ricci.repair."""

import numpy as np
import pytest

import ricci

# The keys of the "repair" object of `ricci info --repair --json` (apps/ricci/json_output.cpp).
REPORT_KEYS = {
    "changed", "input_vertices", "input_faces", "output_vertices", "output_faces",
    "welded_vertices", "repeated_vertex_faces_removed", "duplicate_faces_removed",
    "slivers_removed", "boundary_slivers_removed", "faces_split", "zero_area_faces_left",
    "non_manifold_edges_split", "non_manifold_vertices_split", "vertex_copies_added",
    "faces_flipped", "unreferenced_vertices_dropped", "smaller_components_removed",
    "smaller_component_faces_removed", "non_orientable_components", "messages",
}

# Three triangles on the edge (1, 2): a flat square and a fin standing on its diagonal.
FIN_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0.5 0.5 1\nf 1 2 3\nf 2 4 3\nf 2 5 3\n"


def test_read_mesh_repair_returns_the_report_as_a_dict(tmp_path):
    path = tmp_path / "fin.obj"
    path.write_text(FIN_OBJ)
    for never in ("never", False):
        with pytest.raises(ricci.TopologyError,
                           match=r"fin.obj: line 6: non-manifold edge \(1, 2\)") as refused:
            ricci.read_mesh(path, repair=never)
        assert str(refused.value).endswith("try: repair=True")
        assert refused.value.fixes == [("repair", "true")]
    V, F, info = ricci.read_mesh(path, repair=True)
    assert info.repaired
    report = info.repair
    assert isinstance(report, dict)
    assert set(report) == REPORT_KEYS
    assert report["changed"] is True
    assert report["non_manifold_edges_split"] == {"count": 1, "examples": [[1, 2]]}
    assert report["non_manifold_vertices_split"] == {"count": 2, "examples": [1, 2]}
    assert report["vertex_copies_added"] == 2
    assert (report["input_vertices"], report["output_vertices"]) == (5, 7)
    assert any("split 1 non-manifold edges" in m for m in report["messages"])
    # The square stays whole, the fin gets its own copies of the edge's ends.
    assert V.shape == (7, 3) and F.shape == (3, 3)
    assert info.vertex_map == [0, 1, 2, 3, 4, 1, 2]
    np.testing.assert_array_equal(F[2], [5, 4, 6])
    mesh_info = ricci.info(V, F)
    assert mesh_info.validation.ok
    assert (mesh_info.components, mesh_info.euler_characteristic) == (2, 2)


def test_read_mesh_repairs_a_defective_file_by_default(tmp_path):
    path = tmp_path / "fin.obj"
    path.write_text(FIN_OBJ)
    V, F, info = ricci.read_mesh(path)
    assert info.repaired and info.repair["non_manifold_edges_split"]["count"] == 1
    assert any("fin.obj: line 6: non-manifold edge (1, 2)" in w and "repaired" in w
               for w in info.warnings)
    assert V.shape == (7, 3) and F.shape == (3, 3)
    with pytest.raises(ValueError, match="repair='sometimes'"):
        ricci.read_mesh(path, repair="sometimes")


def test_read_mesh_removes_a_sliver(tmp_path):
    # Face 0 below the segment (0, 1), faces 1 and 2 above it meeting at its midpoint 2, and
    # face 3, the zero-area sliver (0, 1, 2) between them: face 0 is split at vertex 2.
    path = tmp_path / "sliver.obj"
    path.write_text("v 0 0 0\nv 2 0 0\nv 1 0 0\nv 1 -1 0\nv 1 1 0\n"
                    "f 1 4 2\nf 1 3 5\nf 3 2 5\nf 1 2 3\n")
    with pytest.raises(ricci.InvalidInput, match="line 9: face 3 .* has zero area"):
        ricci.read_mesh(path, repair="never")
    V, F, info = ricci.read_mesh(path)
    assert info.repair["slivers_removed"] == {"count": 1, "examples": [3]}
    assert info.repair["faces_split"] == {"count": 1, "examples": [0]}
    assert F.shape == (4, 3)
    assert ricci.info(V, F).validation.ok


def test_read_mesh_without_repair_has_no_report(tmp_path, tetrahedron):
    path = tmp_path / "tetra.obj"
    ricci.write_obj(path, *tetrahedron)
    _, _, info = ricci.read_mesh(path)
    assert info.repair is None and not info.repaired
    _, _, info = ricci.read_mesh(path, repair=True)
    assert info.repair["changed"] is False and info.repair["messages"] == []


def test_read_mesh_repair_options_weld_within_a_tolerance(tmp_path):
    # Two unit squares whose shared side is 1e-9 apart.
    path = tmp_path / "gap.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                    "v 1.000000001 0 0\nv 2 0 0\nv 2 1 0\nv 1.000000001 1 0\n"
                    "f 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\n")
    _, _, exact = ricci.read_mesh(path, repair=True)
    assert exact.repair["welded_vertices"]["count"] == 0
    V, _, loose = ricci.read_mesh(path, repair=True, repair_options={"weld_tolerance": 1e-6})
    assert loose.repair["welded_vertices"] == {"count": 2, "examples": [4, 7]}
    assert V.shape == (6, 3)
    options = ricci.RepairOptions(weld_tolerance=1e-6, max_examples=1)
    _, _, one = ricci.read_mesh(path, repair=True, repair_options=options)
    assert one.repair["welded_vertices"] == {"count": 2, "examples": [4]}


def test_read_mesh_repair_cannot_fix_a_moebius_strip(tmp_path):
    n = 8
    lines = []
    for i in range(n):
        t = 2 * np.pi * i / n
        for s in (0.3, -0.3):
            r = 1 + s * np.cos(t / 2)
            lines.append(f"v {r * np.cos(t)} {r * np.sin(t)} {s * np.sin(t / 2)}")
    for i in range(n):
        a, b = 2 * i + 1, 2 * i + 2
        na, nb = (a + 2, b + 2) if i + 1 < n else (2, 1)
        lines += [f"f {a} {b} {nb}", f"f {a} {nb} {na}"]
    path = tmp_path / "moebius.obj"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ricci.TopologyError,
                       match="after repair.*non-orientable.*repair cannot orient"):
        ricci.read_mesh(path, repair=True)
    _, _, info = ricci.read_mesh(path, validate=False, repair=True)
    assert info.repair["non_orientable_components"] == {"count": 1, "examples": [0]}


def test_repair_arrays(tetrahedron):
    V, F = tetrahedron
    V = np.asarray(V)
    F = np.asarray(F)
    # A copy of face 0 and a reversed face 3: removed and flipped back.
    soup = np.vstack([F, F[:1], F[3:4, ::-1]])
    soup = np.delete(soup, 3, axis=0)
    V2, F2, result = ricci.repair(V, soup)
    report = result.report
    assert report["duplicate_faces_removed"] == {"count": 1, "examples": [3]}
    assert report["faces_flipped"] == {"count": 1, "examples": [4]}
    assert result.face_map == [0, 1, 2, 4]
    assert result.face_flipped.tolist() == [False, False, False, True]
    assert result.weld_map == [0, 1, 2, 3]
    np.testing.assert_array_equal(V2, V)
    assert ricci.info(V2, F2).validation.ok
    with pytest.raises(TypeError):
        ricci.repair(V, F, no_such_option=1)
    with pytest.raises(ricci.InvalidInput, match="weld_tolerance"):
        ricci.repair(V, F, weld_tolerance=-1.0)
