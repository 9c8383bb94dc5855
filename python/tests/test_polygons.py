"""Polygon meshes: read_mesh keeps the faces, parameterize never cuts inside one, write_mesh
writes them back with a uv per corner."""

import math

import numpy as np

import ricci


def _quad_torus(path, n=12, m=6):
    lines = []
    for i in range(n):
        for j in range(m):
            u, v = 2 * math.pi * i / n, 2 * math.pi * j / m
            lines.append("v %.17g %.17g %.17g" % ((1 + 0.4 * math.cos(v)) * math.cos(u),
                                                  (1 + 0.4 * math.cos(v)) * math.sin(u),
                                                  0.4 * math.sin(v)))
    faces = [[i * m + j, (i + 1) % n * m + j, (i + 1) % n * m + (j + 1) % m, i * m + (j + 1) % m]
             for i in range(n) for j in range(m)]
    lines += ["f " + " ".join(str(k + 1) for k in f) for f in faces]
    path.write_text("\n".join(lines) + "\n")
    return faces


def _same_cycle(a, b):
    a, b = list(a), list(b)
    return len(a) == len(b) and any(a == b[s:] + b[:s] for s in range(len(b)))


def test_read_mesh_keeps_the_faces(tmp_path):
    faces = _quad_torus(tmp_path / "quads.obj")
    V, F, info = ricci.read_mesh(tmp_path / "quads.obj")
    assert F.shape == (2 * len(faces), 3)
    assert info.polygons.num_polygons == len(faces)
    assert len(info.polygons.triangle_polygon) == F.shape[0]
    got = ricci.polygon_faces(F, info.polygons)
    assert [list(f) for f in got] == faces
    # A triangle mesh: no polygons, its faces are its triangles.
    V2, F2 = ricci.generate.tetrahedron()
    empty = ricci.Polygons()
    assert empty.empty() and empty.num_polygons == 0
    assert [list(f) for f in ricci.polygon_faces(F2, empty)] == F2.tolist()


def test_parameterize_and_write_the_polygons(tmp_path):
    faces = _quad_torus(tmp_path / "quads.obj")
    V, F, info = ricci.read_mesh(tmp_path / "quads.obj")
    r = ricci.parameterize(V, F, polygons=info.polygons)
    assert r.converged, r.message
    assert r.distortion.flipped_faces == 0
    written = ricci.polygon_faces(F, r.polygons)
    assert all(_same_cycle(a, b) for a, b in zip(faces, written))
    # One uv per corner: the polygon's triangles agree at every vertex they share.
    for p in range(r.polygons.num_polygons):
        triangles = np.flatnonzero(np.asarray(r.polygons.triangle_polygon) == p)
        uv_of = {}
        for t in triangles:
            for k in range(3):
                assert uv_of.setdefault(F[t, k], r.uv_triangles[t, k]) == r.uv_triangles[t, k]
    out = tmp_path / "quads_uv.obj"
    ricci.write_mesh(out, V, F, r.uv, r.uv_triangles, polygons=r.polygons)
    lines = [line.split() for line in out.read_text().splitlines() if line.startswith("f ")]
    assert len(lines) == len(faces)
    assert all(len(f) == 5 and all("/" in c for c in f[1:]) for f in lines)
    back = [[int(c.split("/")[0]) - 1 for c in f[1:]] for f in lines]
    assert all(_same_cycle(a, b) for a, b in zip(faces, back))
    # Without polygons the triangles are written.
    ricci.write_mesh(tmp_path / "triangles.obj", V, F, r.uv, r.uv_triangles)
    assert sum(line.startswith("f ") for line in
               (tmp_path / "triangles.obj").read_text().splitlines()) == F.shape[0]
