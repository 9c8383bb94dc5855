"""Run inside Blender (tests/blender/addon_test.sh): installs and enables the add-on zip,
unwraps generated meshes with bpy.ops.uv.ricci_unwrap, writes each object's UV map as Blender
stores it (float32 values written exactly) on the triangles Blender draws its polygons with to an
OBJ, and checks them with ../shared/tools/checkuv.py (an independent reader).

  blender -b --factory-startup --python-exit-code 1 -P addon_check.py -- ZIP WORK CHECKUV \
      TORUS.obj GENUS2.obj

Prints one line per check (ok / FAIL) and exits 1 when any fails.
"""

import json
import math
import subprocess
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
zip_path, work, checkuv, torus_obj, genus2_obj = args
failures = []


def check(name, condition, detail=""):
    print(("ok   " if condition else "FAIL ") + name + ("" if condition else f": {detail}"))
    if not condition:
        failures.append(name)


def fresh_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for mesh in list(bpy.data.meshes):
        bpy.data.meshes.remove(mesh)


def select_only(objects):
    bpy.ops.object.select_all(action="DESELECT")
    for obj in objects:
        obj.select_set(True)
    bpy.context.view_layer.objects.active = objects[0]


def import_obj(path):
    bpy.ops.wm.obj_import(filepath=path)
    return bpy.context.selected_objects[0]


def write_obj(obj, path):
    """The object's polygons with its active UV map as stored (float32 values written exactly);
    corners of one vertex with bitwise equal uv share a vt, so that a seam is where they do not.
    Returns the largest absolute difference in uv length between an edge's two copies."""
    # (On the triangles Blender draws the polygons with: a fan from each polygon's first
    # corner, as OBJ readers make, is another reading of an n-gon; Blender's own exporter is
    # checked on the quad torus below.)
    from ricci_uv import unwrap as addon_unwrap
    mesh = obj.data
    uv = mesh.uv_layers.active.data
    addon_unwrap.write_drawn_obj(mesh, mesh.uv_layers.active, path)
    # Each edge's uv length on each side.
    lengths = {}
    for p in mesh.polygons:
        loops = list(p.loop_indices)
        for i, l in enumerate(loops):
            m = loops[(i + 1) % len(loops)]
            a, b = uv[l].uv, uv[m].uv
            edge = mesh.loops[l].edge_index
            lengths.setdefault(edge, []).append(math.hypot(a[0] - b[0], a[1] - b[1]))
    return max((max(x) - min(x) for x in lengths.values() if len(x) == 2), default=0.0)


def checkuv_of(obj, name):
    path = f"{work}/{name}.obj"
    mismatch = write_obj(obj, path)
    out = subprocess.run(["/usr/bin/python3", checkuv, path], capture_output=True, text=True)
    c = json.loads(out.stdout)
    c["seam_absolute_mismatch"] = mismatch
    return c


def check_unwrapped(obj, name, *, expect_cones=None):
    mesh = obj.data
    triangles = sum(len(p.vertices) - 2 for p in mesh.polygons)
    c = checkuv_of(obj, name)
    check(f"{name}: checkuv reads it", "error" not in c, c)
    if "error" in c:
        return c
    check(f"{name}: 0 flipped", c["flipped"] == 0, c["flipped"])
    check(f"{name}: 0 degenerate", c["degenerate"] == 0, c["degenerate"])
    # uv in [0, 1] as float32: each end of an edge is rounded by up to 6e-8, so an edge's two
    # copies may differ by about 1.7e-7 in length (relatively more on short edges: checkuv's
    # relative figure is printed, and held to 1e-4).
    check(f"{name}: seams exact to 1e-6 in uv units after float32 storage",
          c["seam_absolute_mismatch"] <= 1e-6, c["seam_absolute_mismatch"])
    check(f"{name}: checkuv's relative seam mismatch {c['seam_length_mismatch']:.1e} <= 1e-4",
          c["seam_length_mismatch"] <= 1e-4, c["seam_length_mismatch"])
    check(f"{name}: the UV on the object's own {len(mesh.polygons)} polygons",
          c["faces"] == triangles, f"{c['faces']} triangles for {triangles}")
    inside = all(-1e-6 <= x <= 1 + 1e-6 for loop in mesh.uv_layers.active.data for x in loop.uv)
    check(f"{name}: uv in the unit square", inside)
    seams = sum(e.use_seam for e in mesh.edges)
    check(f"{name}: the cut marked as seams ({seams} edges, checkuv {c['seam_edges']})",
          seams == c["seam_edges"], f"{seams} against {c['seam_edges']}")
    group = obj.vertex_groups.get("ricci_cones")
    in_group = [v.index for v in mesh.vertices if any(g.group == group.index for g in v.groups)] \
        if group else []
    check(f"{name}: cones in the vertex group ricci_cones", group is not None and
          len(in_group) == obj["ricci_cones"], f"{len(in_group)} against {obj.get('ricci_cones')}")
    if expect_cones is not None:
        check(f"{name}: {expect_cones} cones", obj["ricci_cones"] == expect_cones,
              obj["ricci_cones"])
    print(f"     {name}: E {c['area_distortion_energy']:.4f}, angle "
          f"{c['angle_distortion_mean']:.4f}, {obj['ricci_cones']} cones, {seams} seam edges")
    return c


# --- install and enable, the usual way --------------------------------------------------------
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
bpy.ops.preferences.addon_enable(module="ricci_uv")
check("add-on enabled", "ricci_uv" in bpy.context.preferences.addons)
check("operator registered", hasattr(bpy.types, "UV_OT_ricci_unwrap"))
menus = [m for m in ("VIEW3D_MT_uv_map", "IMAGE_MT_uvs")
         if any(getattr(f, "__module__", "").startswith("ricci_uv")
                for f in getattr(bpy.types, m).draw._draw_funcs)]
check("in the UV menus of the 3D view and the UV editor", len(menus) == 2, menus)

# --- a torus (triangles) ---------------------------------------------------------------------
fresh_scene()
torus = import_obj(torus_obj)
select_only([torus])
result = bpy.ops.uv.ricci_unwrap(cone_mode="NEEDED")
check("torus: FINISHED", result == {"FINISHED"}, result)
check_unwrapped(torus, "torus", expect_cones=0)

# --- genus 2 with 8 cones, then free seams -----------------------------------------------------
fresh_scene()
genus2 = import_obj(genus2_obj)
select_only([genus2])
result = bpy.ops.uv.ricci_unwrap(cone_mode="COUNT", cone_count=8)
check("genus 2: FINISHED", result == {"FINISHED"}, result)
check_unwrapped(genus2, "genus2", expect_cones=8)
result = bpy.ops.uv.ricci_unwrap(cone_mode="COUNT", cone_count=4, seams="FREE")
check("genus 2 free seams: FINISHED", result == {"FINISHED"}, result)
free = checkuv_of(genus2, "genus2_free")
check("genus 2 free seams: 0 flipped", free.get("flipped") == 0, free.get("flipped"))
check("genus 2 free seams: seams equally long to 1e-6 in uv units",
      free.get("seam_absolute_mismatch", 1) <= 1e-6, free.get("seam_absolute_mismatch"))
print(f"     genus2 free seams: E {free['area_distortion_energy']:.4f}, angle "
      f"{free['angle_distortion_mean']:.4f}")

# --- a quad mesh (Blender's own torus), in edit mode -------------------------------------------
fresh_scene()
bpy.ops.mesh.primitive_torus_add(major_segments=48, minor_segments=24)
quads = bpy.context.active_object
check("quad torus: all quads", all(len(p.vertices) == 4 for p in quads.data.polygons))
bpy.ops.object.mode_set(mode="EDIT")
result = bpy.ops.uv.ricci_unwrap()
check("quad torus: FINISHED from edit mode", result == {"FINISHED"}, result)
check("quad torus: back in edit mode", bpy.context.mode == "EDIT_MESH", bpy.context.mode)
bpy.ops.object.mode_set(mode="OBJECT")
check("quad torus: still quads", all(len(p.vertices) == 4 for p in quads.data.polygons))
check_unwrapped(quads, "quad_torus")

# Blender's own OBJ exporter (6 decimals) on the same map: what a user exports reads back with
# the same faces, none flipped (its rounding, not the map, sets the seams' mismatch there).
select_only([quads])
bpy.ops.wm.obj_export(filepath=f"{work}/quad_torus_blender.obj", export_selected_objects=True,
                      export_uv=True, export_normals=False, export_materials=False,
                      export_triangulated_mesh=False)
run = subprocess.run(["/usr/bin/python3", checkuv, f"{work}/quad_torus_blender.obj"],
                     capture_output=True, text=True)
exported = json.loads(run.stdout)
check("Blender's OBJ export: 0 flipped, the same triangles", exported.get("flipped") == 0 and
      exported.get("faces") == sum(len(p.vertices) - 2 for p in quads.data.polygons), exported)


# --- two objects at once: a UV sphere (quads and triangles) and a grid (a disk) ------------------
fresh_scene()
bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, location=(3, 0, 0))
sphere = bpy.context.active_object
bpy.ops.mesh.primitive_grid_add(x_subdivisions=20, y_subdivisions=12, size=2)
grid = bpy.context.active_object
select_only([sphere, grid])
result = bpy.ops.uv.ricci_unwrap(margin=0.01)
check("two objects: FINISHED", result == {"FINISHED"}, result)
check_unwrapped(sphere, "uv_sphere")
check_unwrapped(grid, "grid", expect_cones=0)

# --- n-gons: a cylinder with 24-gon caps -------------------------------------------------------
fresh_scene()
bpy.ops.mesh.primitive_cylinder_add(vertices=24, depth=2, end_fill_type="NGON")
cylinder = bpy.context.active_object
sizes = sorted({len(p.vertices) for p in cylinder.data.polygons})
select_only([cylinder])
result = bpy.ops.uv.ricci_unwrap()
check(f"n-gon cylinder ({sizes}-gons): FINISHED", result == {"FINISHED"}, result)
check("n-gon cylinder: still its polygons",
      sorted({len(p.vertices) for p in cylinder.data.polygons}) == sizes)
check_unwrapped(cylinder, "ngon_cylinder")

# --- polygons with vertices along their edges (every edge cut in 8): a fan from any corner has
# zero-area triangles, which ricci refuses; the add-on triangulates them clear of those. The map is
# checked on that triangulation (a fan of such a polygon is not a sound reading of it).
fresh_scene()
bpy.ops.mesh.primitive_cylinder_add(vertices=12, depth=2, end_fill_type="NGON")
cut = bpy.context.active_object
bpy.ops.object.mode_set(mode="EDIT")
bpy.ops.mesh.select_all(action="SELECT")
bpy.ops.mesh.subdivide(number_cuts=7)
bpy.ops.object.mode_set(mode="OBJECT")
sizes = sorted({len(p.vertices) for p in cut.data.polygons})
select_only([cut])
result = bpy.ops.uv.ricci_unwrap()
check(f"polygons with vertices along their edges ({sizes}-gons): FINISHED",
      result == {"FINISHED"}, result)
from ricci_uv import unwrap as addon_unwrap  # noqa: E402
triangles, polygon = addon_unwrap.triangulate(cut.data)
uv = cut.data.uv_layers.active.data
loop_of = {}
for p in cut.data.polygons:
    for l in p.loop_indices:
        loop_of[(p.index, cut.data.loops[l].vertex_index)] = l
with open(f"{work}/cut_cylinder_triangles.obj", "w") as f:
    for v in cut.data.vertices:
        f.write("v %r %r %r\n" % tuple(float(x) for x in v.co))
    for l in range(len(cut.data.loops)):
        f.write("vt %r %r\n" % (float(uv[l].uv[0]), float(uv[l].uv[1])))
    for t, p in zip(triangles, polygon):
        f.write("f " + " ".join(f"{v + 1}/{loop_of[(int(p), int(v))] + 1}" for v in t) + "\n")
run = subprocess.run(["/usr/bin/python3", checkuv, f"{work}/cut_cylinder_triangles.obj"],
                     capture_output=True, text=True)
on_triangles = json.loads(run.stdout)
check("polygons with vertices along their edges: 0 flipped on the add-on's triangles",
      on_triangles.get("flipped") == 0, on_triangles.get("flipped"))

# --- undo: one undo step. Blender's undo needs a window, which a headless Blender has not: the
# operator's flags are checked here (REGISTER and UNDO: one undo step, and the redo panel).
flags = bpy.types.UV_OT_ricci_unwrap.bl_options
check("undo: the operator registers an undo step", {"REGISTER", "UNDO"} <= set(flags), flags)

# --- bad meshes: Blender's error report with ricci's message, never a crash ---------------------
fresh_scene()
mesh = bpy.data.meshes.new("fin")
# Three triangles on one edge: not a manifold.
mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1)], [],
                 [(0, 1, 2), (1, 0, 3), (0, 1, 4)])
fin = bpy.data.objects.new("fin", mesh)
bpy.context.scene.collection.objects.link(fin)
select_only([fin])
try:
    bpy.ops.uv.ricci_unwrap()
    check("non-manifold: refused", False, "no error")
except RuntimeError as e:
    message = str(e)
    check("non-manifold: an error report naming the problem",
          "ricci: fin:" in message and "manifold" in message, message)

# An option that cannot work: ricci's fix, phrased as the operator's options.
fresh_scene()
bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16)
select_only([bpy.context.active_object])
try:
    bpy.ops.uv.ricci_unwrap(cone_mode="COUNT", cone_count=1)
    check("one cone on a sphere: refused", False, "no error")
except RuntimeError as e:
    message = str(e)
    check("one cone on a sphere: the fix as the operator's options",
          "try: Cones: Count, Cone Count 4, or Cones: Automatic" in message, message)

# The flow's progress callback cancels: the work object of the operator, driven directly.
from ricci_uv import operator as addon_operator, unwrap  # noqa: E402
import ricci_uv.ricci as ricci  # noqa: E402

fresh_scene()
bpy.ops.mesh.primitive_torus_add(major_segments=48, minor_segments=24)
job = unwrap.read_mesh(ricci, "torus", bpy.context.active_object.data)
work = addon_operator._Work([("torus", job)])
work.cancel = True
result = ricci.parameterize(job.V, job.F, polygons=job.polygons, progress=work.progress)
check("cancel: the flow stops", not result.converged and "ancel" in result.message,
      result.message)

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
