"""Reading, writing and describing meshes."""

import os

import numpy as np

from . import _arrays, _ricci


_REPAIR_MODES = {"auto": "auto", "always": "always", "never": "never",
                 True: "always", False: "never"}


def read_mesh(path, *, validate=True, repair="auto", repair_options=None):
    """Reads an OBJ, OFF, PLY (ASCII or binary) or STL (ASCII or binary) file.

    Returns ``(V, F, info)``: V float64 (n, 3) positions, F int32 (m, 3) counter-clockwise
    triangles (polygons triangulated, unreferenced vertices dropped), and the C++ ``ReadResult``
    with ``warnings``, ``dropped_vertices``, ``vertex_map`` (file index of each vertex),
    ``polygons_triangulated``, ``polygons``, ``format`` and ``validation``.

    ``info.polygons`` (a ``Polygons``, empty when every face is a triangle) says which triangles
    make up each face of the file: ``polygon_faces(F, info.polygons)`` lists the faces' vertices,
    ``parameterize(V, F, polygons=info.polygons)`` never cuts inside a face and returns the
    faces to write, ``write_mesh(..., polygons=...)`` writes them.

    ``repair`` says what to do with a file that has defects, as the command line's
    ``--repair=MODE``: ``"auto"`` (the default) runs ``repair_mesh`` on a file with defects
    (duplicate faces and vertices, faces using a vertex twice, zero-area slivers, non-manifold
    edges and vertices, inconsistent orientation) and adds a warning naming the first defect and
    its line to ``info.warnings``, and reads a file without defects as it is; ``"always"`` (or
    True) repairs every file (duplicate positions welded too); ``"never"`` (or False) refuses a
    defective file, and the exception's message ends with ``try: repair=True`` when repair
    would make it valid. ``repair_options`` is a ``RepairOptions`` or a dict of its fields.
    After a repair ``info.repaired`` is True and ``info.repair`` is a dict of what changed: the
    same keys as the "repair" object of ``ricci info --repair --json`` (``welded_vertices``,
    ``non_manifold_edges_split``, ``slivers_removed``, ... each with ``count`` and ``examples``,
    and ``messages``); otherwise ``info.repair`` is None.

    Raises IoError for a missing or malformed file (naming file and line), InvalidInput or
    TopologyError for a defective mesh when ``validate`` is set (after repair: for what repair
    cannot fix, e.g. a Moebius strip or non-finite coordinates, saying so), ValueError for an
    unknown ``repair`` mode.
    """
    try:
        mode = _REPAIR_MODES[repair]
    except (KeyError, TypeError):
        raise ValueError(f"repair={repair!r}: expected 'auto', 'always' (True) or 'never' "
                         "(False)") from None
    options = _ricci.ReadOptions(validate=validate, repair=mode == "always",
                                 auto_repair=mode == "auto")
    if repair_options is not None:
        if isinstance(repair_options, dict):
            repair_options = _ricci.RepairOptions(**repair_options)
        options.repair_options = repair_options
    result = _ricci.read_mesh(os.fspath(path), options)
    V, F = _arrays.arrays(result.mesh)
    return V, F, result


def repair(V, F, **options):
    """Repairs a triangle soup (see ``read_mesh(..., repair=True)``); keyword arguments are the
    fields of ``RepairOptions`` (``weld_tolerance``, ``largest_component_only``, ...).

    Returns ``(V, F, result)``: the repaired arrays and the C++ ``RepairResult`` with
    ``vertex_map`` (input vertex of each output vertex), ``face_map``, ``face_flipped``,
    ``weld_map`` and ``report`` (the dict ``read_mesh`` gives as ``info.repair``).
    """
    result = _ricci.repair_mesh(_arrays.mesh(V, F), _ricci.RepairOptions(**options))
    V2, F2 = _arrays.arrays(result.mesh)
    return V2, F2, result


_WRITTEN_FORMATS = tuple(name for name in _ricci.MeshFormat.names if name != "glb")


def polygon_faces(F, polygons):
    """The faces of a polygon mesh as lists of vertex indices, in order: per polygon of
    ``polygons`` (a ``Polygons`` over the triangles F, e.g. ``info.polygons`` of ``read_mesh`` or
    ``result.polygons`` of ``parameterize``) its corners' vertices; the triangles of F themselves
    when ``polygons`` is empty. Returns a list of int arrays."""
    F = _arrays.triangles(F, "F")
    if polygons.empty():
        return [row.copy() for row in F]
    corners = np.asarray(polygons.corners, dtype=np.int64)
    vertices = F[corners // 3, corners % 3]
    return np.split(vertices, polygons.corner_start[1:-1])


def write_mesh(path, V, F, uv=None, uv_triangles=None, *, polygons=None, format=None,
               drop_uv=False):
    """Writes a mesh atomically (the target is untouched when anything fails), in ``format``
    ("obj", "off", "ply" or "stl") or, when it is None, the format of the path's extension.

    With ``polygons`` (a ``Polygons`` over the triangles F, e.g. ``result.polygons`` of
    ``parameterize``) OBJ, OFF and PLY write one face per polygon (OBJ with texture coordinates:
    ``f v/vt v/vt v/vt v/vt``, each corner's uv row taken from uv_triangles); STL writes the
    triangles.

    With ``uv`` (k, 2) and ``uv_triangles`` (m, 3, indices into uv per corner) also its texture
    coordinates: OBJ holds them (``vt`` and ``f v/vt``); OFF, PLY and STL cannot, and refuse
    them unless ``drop_uv=True``. OFF and PLY keep positions exactly; STL rounds them to float and
    writes no shared vertices (reading welds them again). glTF binary needs a texture and is
    written by ``ricci param -o x.glb``.
    """
    m = _arrays.mesh(V, F)
    if (uv is None) != (uv_triangles is None):
        raise ValueError("write_mesh needs both uv and uv_triangles, or neither")
    if format is not None and format not in _WRITTEN_FORMATS:
        raise ValueError(f"write_mesh: unknown format {format!r}; expected "
                         + ", ".join(_WRITTEN_FORMATS[:-1]) + f" or {_WRITTEN_FORMATS[-1]}")
    if uv is None:
        uv = np.zeros((0, 2))
        uv_triangles = np.zeros((0, 3), dtype=np.int32)
    else:
        uv = np.asarray(uv)
        if uv.ndim != 2 or uv.shape[1] != 2 or uv.dtype.kind not in "fiu":
            raise ValueError(f"uv must be a (k, 2) float array, got shape {uv.shape} "
                             f"and dtype {uv.dtype}")
        uv_triangles = _arrays.triangles(uv_triangles, "uv_triangles")
        if uv_triangles.shape[0] != m.num_faces:
            raise ValueError(f"uv_triangles must have one row per face ({m.num_faces}), "
                             f"got shape {uv_triangles.shape}")
    _ricci.write_mesh(os.fspath(path), m, uv_triangles,
                      np.ascontiguousarray(uv, dtype=np.float64), format or "", bool(drop_uv),
                      _ricci.Polygons() if polygons is None else polygons)


def write_obj(path, V, F, uv=None, uv_triangles=None):
    """Writes a mesh as OBJ atomically; with ``uv`` (k, 2) and ``uv_triangles`` (m, 3, indices
    into uv per corner) also its texture coordinates. The same as
    ``write_mesh(path, V, F, uv, uv_triangles, format="obj")``."""
    write_mesh(path, V, F, uv, uv_triangles, format="obj")


def info(V, F):
    """Summary of a mesh (``MeshInfo``): vertices, edges, faces, components, boundary_loops,
    euler_characteristic, genus, component_info, min/max_angle_degrees,
    bounding_box_diagonal, and ``defects`` (every defect found, each with kind, name, element
    and message). Topological fields are -1 when defects keep them from being defined. Never
    raises on a defective mesh (that is its purpose); only on arrays of the wrong shape."""
    return _ricci.mesh_info(_arrays.mesh(V, F))


def validate(V, F):
    """Raises TopologyError or InvalidInput on the first defect of the mesh."""
    _ricci.validate_mesh(_arrays.mesh(V, F), "validate")
