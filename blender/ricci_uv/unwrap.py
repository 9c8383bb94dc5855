"""Blender meshes to ricci's arrays and back: no operator, no UI (the operator calls these).

read_mesh(mesh) takes the mesh's positions and the triangles Blender draws its polygons with
(see triangulate) and describes each polygon over those triangles as a ``ricci.Polygons``, so that
ricci's cut never runs inside a face. write_uv(mesh, job, result) puts the layout back on the
mesh's own loops (quads and n-gons kept), marks the cut as seams and the cones in a vertex group.
"""

import numpy as np

CONE_GROUP = "ricci_cones"


class UnwrapError(Exception):
    """A mesh this add-on cannot hand to ricci, or a result it cannot write back."""


class MeshJob:
    """One mesh as ricci sees it: V and F over the vertices that faces use (compacted), the
    polygons over F, and the maps back to the Blender mesh's vertices and loops."""

    def __init__(self, name, V, F, polygons, vertex_of, polygon_of_loop, vertex_of_loop):
        self.name = name
        self.V = V                              # (n, 3) float64, compacted vertices
        self.F = F                              # (m, 3) int64, Blender's loop triangles
        self.polygons = polygons                # ricci.Polygons over F
        self.vertex_of = vertex_of              # compacted vertex -> Blender vertex
        self.polygon_of_loop = polygon_of_loop  # Blender loop -> its polygon
        self.vertex_of_loop = vertex_of_loop    # Blender loop -> compacted vertex

    def matches(self, mesh):
        """Whether `mesh` still has the loops this job was read from (same count, same vertex
        at every loop): the layout can be written back."""
        if len(mesh.loops) != len(self.vertex_of_loop):
            return False
        loop_vertex = np.empty(len(mesh.loops), dtype=np.int64)
        mesh.loops.foreach_get("vertex_index", loop_vertex)
        return bool(np.array_equal(self.vertex_of[self.vertex_of_loop], loop_vertex))


# A triangle ricci refuses as of zero area: twice its area at most this times its longest edge
# squared (ricci's ValidationOptions::zero_area_tolerance is 1e-12; a margin above it).
ZERO_AREA = 1e-10


def triangulate(mesh, positions=None):
    """Each polygon of the mesh as triangles: (m, 3) vertex indices and the polygon of each.

    The triangles Blender draws the polygons with (the mesh's loop_triangles), so that the layout
    is fold-free on what Blender shows; but a polygon with vertices along its edges (a subdivided
    edge, a knife cut) gets zero-area triangles there, which ricci refuses: such polygons are
    triangulated again by bmesh's "beauty" method, which keeps clear of them."""
    mesh.calc_loop_triangles()
    nt = len(mesh.loop_triangles)
    triangles = np.empty(3 * nt, dtype=np.int64)
    polygon = np.empty(nt, dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", triangles)
    mesh.loop_triangles.foreach_get("polygon_index", polygon)
    triangles = triangles.reshape(nt, 3)
    if positions is None:  # (read_mesh passes the ones it has read)
        positions = np.empty(3 * len(mesh.vertices), dtype=np.float64)
        mesh.vertices.foreach_get("co", positions)
    p = positions.reshape(-1, 3)[triangles]
    twice_area = np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    longest = np.max([((p[:, (k + 1) % 3] - p[:, k]) ** 2).sum(axis=1) for k in range(3)], axis=0)
    flat = np.unique(polygon[twice_area <= ZERO_AREA * longest])
    if len(flat) == 0:
        return triangles, polygon

    import bmesh  # Blender's module, there only

    bm = bmesh.new()
    try:
        bm.from_mesh(mesh)
        bm.faces.ensure_lookup_table()
        origin = bm.faces.layers.int.new("ricci_polygon")
        for face in bm.faces:
            face[origin] = face.index
        bmesh.ops.triangulate(bm, faces=[bm.faces[i] for i in flat], quad_method="BEAUTY",
                              ngon_method="BEAUTY")
        redone = set(flat.tolist())
        new = [([v.index for v in f.verts], f[origin]) for f in bm.faces if f[origin] in redone]
    finally:
        bm.free()
    keep = ~np.isin(polygon, flat)
    triangles = np.concatenate([triangles[keep], np.array([t for t, _ in new], dtype=np.int64)])
    polygon = np.concatenate([polygon[keep], np.array([q for _, q in new], dtype=np.int64)])
    return triangles, polygon


def read_mesh(ricci, name, mesh):
    """The MeshJob of a bpy Mesh (object mode: its data up to date)."""
    nv, nl, np_ = len(mesh.vertices), len(mesh.loops), len(mesh.polygons)
    if np_ == 0:
        raise UnwrapError(f"{name}: the mesh has no faces")
    co = np.empty(3 * nv, dtype=np.float64)
    mesh.vertices.foreach_get("co", co)
    loop_vertex = np.empty(nl, dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    loop_start = np.empty(np_, dtype=np.int64)
    loop_total = np.empty(np_, dtype=np.int64)
    mesh.polygons.foreach_get("loop_start", loop_start)
    mesh.polygons.foreach_get("loop_total", loop_total)
    tri_vertex, tri_polygon = triangulate(mesh, co)
    nt = len(tri_vertex)

    # Each polygon's corners in loop order, each named by a corner 3 t + k of one of its
    # triangles (ricci.Polygons): looked up by (polygon, vertex).
    polygon_in_order = np.repeat(np.arange(np_), loop_total)
    first_in_order = np.repeat(np.cumsum(loop_total) - loop_total, loop_total)
    loops_in_order = np.repeat(loop_start, loop_total) + np.arange(nl) - first_in_order
    polygon_of_loop = np.empty(nl, dtype=np.int64)
    polygon_of_loop[loops_in_order] = polygon_in_order
    corner_keys = np.repeat(tri_polygon, 3) * nv + tri_vertex.ravel()
    order = np.argsort(corner_keys, kind="stable")
    wanted = polygon_of_loop[loops_in_order] * nv + loop_vertex[loops_in_order]
    at = np.minimum(np.searchsorted(corner_keys[order], wanted), 3 * nt - 1)
    found = corner_keys[order][at] == wanted
    if not found.all():
        bad = int(polygon_of_loop[loops_in_order[int(np.argmin(found))]])
        raise UnwrapError(f"{name}: polygon {bad} has a corner that Blender's triangulation "
                          "leaves out (a degenerate face: try Mesh > Clean Up > Merge by Distance)")
    corners = order[at]

    # Only the vertices that faces use (ricci refuses unreferenced ones).
    used = np.unique(loop_vertex)
    compact = np.full(nv, -1, dtype=np.int64)
    compact[used] = np.arange(len(used))
    V = co.reshape(nv, 3)[used]
    F = compact[tri_vertex]

    polygons = ricci.Polygons()
    polygons.triangle_polygon = tri_polygon.tolist()
    polygons.corner_start = np.concatenate([[0], np.cumsum(loop_total)]).tolist()
    polygons.corners = corners.tolist()
    return MeshJob(name, V, F, polygons, used, polygon_of_loop, compact[loop_vertex])


def loop_uv_rows(job, result):
    """Per Blender loop, the row of result.uv at that corner of its polygon."""
    tri = np.asarray(result.triangles, dtype=np.int64)
    uv_tri = np.asarray(result.uv_triangles, dtype=np.int64)
    if not result.polygons.empty():
        corners = np.asarray(result.polygons.corners, dtype=np.int64)
        start = np.asarray(result.polygons.corner_start, dtype=np.int64)
        polygon = np.repeat(np.arange(len(start) - 1), np.diff(start))
        vertex = tri.ravel()[corners]
        row = uv_tri.ravel()[corners]
    elif tri.shape == job.F.shape and np.array_equal(tri, job.F):
        polygon = np.asarray(job.polygons.triangle_polygon, dtype=np.int64).repeat(3)
        vertex = tri.ravel()
        row = uv_tri.ravel()
    else:
        raise UnwrapError(f"{job.name}: ricci changed the triangles (edge splits), so its layout "
                          "is not on the mesh's own faces: try another scheme")
    if (vertex >= len(job.V)).any():
        raise UnwrapError(f"{job.name}: the layout has vertices the mesh does not")
    # (polygon, vertex) -> row, looked up for every loop.
    n = len(job.V)
    keys = polygon * n + vertex
    order = np.argsort(keys, kind="stable")
    wanted = job.polygon_of_loop * n + job.vertex_of_loop
    at = np.searchsorted(keys[order], wanted)
    at = np.minimum(at, len(order) - 1)
    found = keys[order][at] == wanted
    if not found.all():
        raise UnwrapError(f"{job.name}: loop {int(np.argmin(found))} has no texture coordinate")
    return row[order][at]


def write_uv(mesh, job, result, uv_name=None):
    """Writes result's layout into the mesh's active UV map (created when there is none, or the
    map named uv_name), marks the seams (edges whose two sides have different uv rows) and puts
    the cones in the vertex group CONE_GROUP of obj. Returns (seam edges, cone vertices)."""
    rows = loop_uv_rows(job, result)
    uv = np.asarray(result.uv, dtype=np.float64)
    layer = None
    if uv_name:
        layer = mesh.uv_layers.get(uv_name) or mesh.uv_layers.new(name=uv_name)
    else:
        layer = mesh.uv_layers.active or mesh.uv_layers.new(name="UVMap")
    mesh.uv_layers.active = layer
    layer.data.foreach_set("uv", uv[rows].astype(np.float32).ravel())

    # Seams: per loop, the uv rows at its edge's two vertices (in the edge's own order).
    nl, ne = len(mesh.loops), len(mesh.edges)
    loop_edge = np.empty(nl, dtype=np.int64)
    mesh.loops.foreach_get("edge_index", loop_edge)
    loop_vertex = np.empty(nl, dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", loop_vertex)
    edge_vertices = np.empty(2 * ne, dtype=np.int64)
    mesh.edges.foreach_get("vertices", edge_vertices)
    edge_vertices = edge_vertices.reshape(ne, 2)
    loop_start = np.empty(len(mesh.polygons), dtype=np.int64)
    loop_total = np.empty(len(mesh.polygons), dtype=np.int64)
    mesh.polygons.foreach_get("loop_start", loop_start)
    mesh.polygons.foreach_get("loop_total", loop_total)
    polygon = job.polygon_of_loop
    position = np.arange(nl) - loop_start[polygon]
    next_loop = loop_start[polygon] + (position + 1) % loop_total[polygon]
    forward = loop_vertex == edge_vertices[loop_edge, 0]
    row0 = np.where(forward, rows, rows[next_loop])
    row1 = np.where(forward, rows[next_loop], rows)
    big = np.iinfo(np.int64).max
    lo0, hi0 = np.full(ne, big), np.full(ne, -1)
    lo1, hi1 = np.full(ne, big), np.full(ne, -1)
    np.minimum.at(lo0, loop_edge, row0)
    np.maximum.at(hi0, loop_edge, row0)
    np.minimum.at(lo1, loop_edge, row1)
    np.maximum.at(hi1, loop_edge, row1)
    seam = (lo0 != hi0) | (lo1 != hi1)
    seam &= hi0 >= 0  # loose edges: no loop, no seam
    mesh.edges.foreach_set("use_seam", seam)
    return int(seam.sum())


def cone_vertices(job, result):
    """The cones as (Blender vertex, curvature) pairs."""
    out = []
    for cone in result.cones:
        if 0 <= cone.vertex < len(job.vertex_of):
            out.append((int(job.vertex_of[cone.vertex]), float(cone.curvature)))
    return out


def set_cone_group(obj, cones):
    """The vertex group CONE_GROUP holds exactly the cone vertices (weight 1)."""
    group = obj.vertex_groups.get(CONE_GROUP)
    if group is not None:
        obj.vertex_groups.remove(group)
    group = obj.vertex_groups.new(name=CONE_GROUP)
    if cones:
        group.add([v for v, _ in cones], 1.0, "REPLACE")
    return group


def write_drawn_obj(mesh, layer, path):
    """The UV map `layer` as Blender stores it, on the triangles Blender draws the polygons with
    (loop_triangles), to an OBJ: float32 values written exactly, and the corners of one vertex
    with bitwise equal uv sharing a vt, so that a seam is where they do not (what checkers such as
    ../shared/tools/checkuv.py read). Returns per loop its vt index."""
    uv = layer.data
    vt, corner_vt = {}, []
    for loop, data in zip(mesh.loops, uv):
        key = (loop.vertex_index, float(data.uv[0]), float(data.uv[1]))
        corner_vt.append(vt.setdefault(key, len(vt)))
    mesh.calc_loop_triangles()
    with open(path, "w") as f:
        for v in mesh.vertices:
            f.write("v %r %r %r\n" % tuple(float(x) for x in v.co))
        for (_, u, w) in vt:
            f.write("vt %r %r\n" % (u, w))
        for t in mesh.loop_triangles:
            f.write("f " + " ".join(f"{mesh.loops[l].vertex_index + 1}/{corner_vt[l] + 1}"
                                    for l in t.loops) + "\n")
    return corner_vt
