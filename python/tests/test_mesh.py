"""Reading, writing, info and the generators."""

import math

import numpy as np
import pytest

import ricci


def test_read_mesh_obj(tmp_path):
    # A unit square as one quad plus one triangle, and a vertex no face uses (dropped).
    path = tmp_path / "square.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 5 5 5\nv 2 0 0\n"
                    "f 1 2 3 4\nf 2 6 3\n")
    V, F, info = ricci.read_mesh(path)
    assert V.dtype == np.float64 and V.shape == (5, 3)
    assert F.dtype == np.int32 and F.shape == (3, 3)
    assert V.flags["C_CONTIGUOUS"] and F.flags["C_CONTIGUOUS"]
    assert info.dropped_vertices == [4]
    assert info.vertex_map == [0, 1, 2, 3, 5]
    assert info.polygons_triangulated == 1
    assert len(info.warnings) >= 1
    assert info.format == ricci.MeshFormat.Obj
    np.testing.assert_array_equal(V[4], [2, 0, 0])
    # The triangulated quad and the triangle cover area 1 + 0.5.
    a = V[F[:, 1]] - V[F[:, 0]]
    b = V[F[:, 2]] - V[F[:, 0]]
    assert np.linalg.norm(np.cross(a, b), axis=1).sum() / 2 == pytest.approx(1.5, abs=1e-15)


def test_read_mesh_missing_file(tmp_path):
    path = tmp_path / "missing.off"
    with pytest.raises(ricci.IoError) as caught:
        ricci.read_mesh(path)
    assert isinstance(caught.value, OSError)
    assert isinstance(caught.value, ricci.Error)
    assert "missing.off" in str(caught.value)


def test_read_mesh_malformed_names_line(tmp_path):
    path = tmp_path / "bad.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n")
    with pytest.raises(ricci.IoError, match="bad.obj"):
        ricci.read_mesh(path)


def test_write_obj_round_trip(tmp_path, torus):
    V, F = torus
    path = tmp_path / "torus.obj"
    ricci.write_obj(path, V, F)
    V2, F2, _ = ricci.read_mesh(path)
    np.testing.assert_allclose(V2, V, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(F2, F)


@pytest.mark.parametrize("extension", ["obj", "off", "ply", "stl"])
def test_write_mesh_round_trip_in_every_format(tmp_path, torus, extension):
    V, F = torus
    path = tmp_path / f"torus.{extension}"
    ricci.write_mesh(path, V, F)
    V2, F2, info = ricci.read_mesh(path)
    assert info.format.name.lower() == extension
    # STL rounds positions to float and numbers vertices as the faces first use them; the others
    # keep positions and numbering exactly. Corner by corner, all four give the same faces.
    np.testing.assert_allclose(V2[F2], V[F], rtol=0, atol=2e-7 if extension == "stl" else 0)
    if extension != "stl":
        np.testing.assert_array_equal(F2, F)


def test_write_mesh_format_overrides_the_extension_and_uv_needs_obj(tmp_path, torus):
    V, F = torus
    path = tmp_path / "torus.dat"
    ricci.write_mesh(path, V, F, format="ply")
    assert path.read_bytes().startswith(b"ply\n")
    uv = V[:, :2]
    with pytest.raises(ValueError, match="texture coordinates") as refused:
        ricci.write_mesh(tmp_path / "t.off", V, F, uv, F)
    assert "try: drop_uv=True" in str(refused.value)
    assert refused.value.fixes == [("drop_uv", "true")]
    assert not (tmp_path / "t.off").exists()  # nothing written
    ricci.write_mesh(tmp_path / "t.off", V, F, uv, F, drop_uv=True)
    with pytest.raises(ValueError, match="expected obj, off, ply or stl"):
        ricci.write_mesh(tmp_path / "t.x", V, F, format="vrml")
    ricci.write_mesh(tmp_path / "t.obj", V, F, uv, F)
    assert b"\nvt " in (tmp_path / "t.obj").read_bytes()


def test_info_tetrahedron(tetrahedron):
    info = ricci.info(*tetrahedron)
    assert (info.vertices, info.edges, info.faces) == (4, 6, 4)
    assert (info.components, info.boundary_loops) == (1, 0)
    assert (info.euler_characteristic, info.genus) == (2, 0)
    assert info.min_angle_degrees == pytest.approx(60, abs=1e-12)
    assert info.max_angle_degrees == pytest.approx(60, abs=1e-12)
    assert info.defects == []
    assert info.validation.ok


def test_info_torus(torus):
    info = ricci.info(*torus)
    assert (info.vertices, info.edges, info.faces) == (512, 1536, 1024)
    assert (info.components, info.boundary_loops) == (1, 0)
    assert (info.euler_characteristic, info.genus) == (0, 1)
    assert len(info.component_info) == 1
    assert info.component_info[0].genus == 1
    assert 0 < info.min_angle_degrees < 60 < info.max_angle_degrees < 180


def test_info_reports_defects_without_raising(non_manifold):
    info = ricci.info(*non_manifold)
    names = [d.name for d in info.defects]
    assert "non-manifold-edge" in names
    assert info.genus == -1 and info.euler_characteristic == -1
    assert not info.validation.ok
    # The kind's name is a row of the table the enum carries (C++ EnumNames<DefectKind>).
    kinds = ricci.DefectKind.names
    assert len(kinds) == len(ricci.DefectKind.__members__) and "non-manifold-edge" in kinds
    assert all(d.name == ricci._ricci.defect_name(d.kind) for d in info.defects)
    assert ricci.ComponentMethod.names == ("flow", "untangled", "charts", "unfolded", "patches")


def test_generators_counts():
    V, F = ricci.generate.icosphere(2)
    assert V.shape == (10 * 4**2 + 2, 3) and F.shape == (20 * 4**2, 3)
    np.testing.assert_allclose(np.linalg.norm(V, axis=1), 1, atol=1e-15)
    V, F = ricci.generate.disk(3, 0.5)
    assert V.shape == (1 + 3 * 3 * 4, 3) and F.shape == (6 * 9, 3)
    assert ricci.info(V, F).boundary_loops == 1
    V, F = ricci.generate.closed_surface(2, 10)
    info = ricci.info(V, F)
    assert (info.genus, info.euler_characteristic) == (2, -2)
    V, F = ricci.generate.tetrahedron(2.0)
    assert np.linalg.norm(V[0] - V[1]) == pytest.approx(2.0, rel=1e-15)
    V, F = ricci.generate.torus(12, 6)
    assert V.shape == (72, 3) and F.shape == (144, 3)
    assert not math.isnan(V.sum())


def test_generator_errors_are_invalid_input():
    with pytest.raises(ricci.InvalidInput, match="minor"):
        ricci.generate.torus(12, 6, 1.0, 2.0)
