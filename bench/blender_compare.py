"""ricci's unwrap against Blender's own, run inside Blender (bench/blender_compare.sh runs it).

For every mesh: ricci Unwrap (the add-on ricci_uv, its defaults: automatic cones, rigid seams,
polish), then Blender's Unwrap along the seams ricci chose (Conformal, the LSCM, and Angle Based,
the ABF++ of Blender's default), then Smart UV Project (its defaults: 66 degrees, its own
islands), each into its own UV map. Each map is measured as Blender stores it, on the triangles
Blender draws the polygons with, by ../shared/tools/checkuv.py (area distortion E, mean angle distortion, flipped
triangles) and here (seam length in 3D, over the surface's total edge length; islands: faces
joined across edges whose two sides have the same uv; seconds: the operator's wall time).

  blender -b --factory-startup -P bench/blender_compare.py -- OUT_DIR CHECKUV \
      [--picture] MESH...

Prints a markdown table and writes OUT_DIR/blender_compare.md (and .json); with --picture also
renders Suzanne (subdivided once) with each map and a checker texture (Workbench) to
OUT_DIR/suzanne-<method>.png. Meshes are read with ricci's reader (any format ricci reads; a
polygon mesh keeps its polygons). The add-on must be installed and enabled (the .sh does it).
"""

import json
import math
import os
import subprocess
import sys
import time

import bpy
from mathutils import Vector

args = sys.argv[sys.argv.index("--") + 1:]
out_dir, checkuv = args[0], args[1]
picture = "--picture" in args
meshes = [a for a in args[2:] if a != "--picture"]
os.makedirs(out_dir, exist_ok=True)

import ricci_uv.ricci as ricci  # noqa: E402 (the add-on's own module: installed above)
from ricci_uv import unwrap  # noqa: E402

METHODS = ("ricci", "ricci_free", "conformal", "angle_based", "smart_uv")
LABELS = {"ricci": "ricci Unwrap", "ricci_free": "ricci Unwrap, free seams",
          "conformal": "Unwrap (Conformal) on ricci's seams",
          "angle_based": "Unwrap (Angle Based) on ricci's seams",
          "smart_uv": "Smart UV Project"}


def clear():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for mesh in list(bpy.data.meshes):
        bpy.data.meshes.remove(mesh)


def load(path):
    V, F, info = ricci.read_mesh(path)
    faces = ricci.polygon_faces(F, info.polygons)
    mesh = bpy.data.meshes.new(os.path.basename(path))
    mesh.from_pydata(V.tolist(), [], [list(map(int, f)) for f in faces])
    mesh.validate()
    obj = bpy.data.objects.new(mesh.name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def activate(obj):
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj


def uv_layer(obj, name):
    layer = obj.data.uv_layers.get(name) or obj.data.uv_layers.new(name=name)
    obj.data.uv_layers.active = layer
    return layer


def blender_unwrap(obj, method):
    """Blender's operator in edit mode on every face; returns its wall seconds."""
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    start = time.perf_counter()
    if method == "smart_uv":
        bpy.ops.uv.smart_project(angle_limit=math.radians(66), island_margin=0.002)
    else:
        bpy.ops.uv.unwrap(method="CONFORMAL" if method == "conformal" else "ANGLE_BASED",
                          margin=0.002)
    seconds = time.perf_counter() - start
    bpy.ops.object.mode_set(mode="OBJECT")
    return seconds


def measure(obj, layer, path):
    """checkuv's figures of the map, with seam length and islands measured here."""
    mesh = obj.data
    corner_vt = unwrap.write_drawn_obj(mesh, layer, path)
    run = subprocess.run(["/usr/bin/python3", checkuv, path], capture_output=True, text=True)
    c = json.loads(run.stdout)
    # Per edge, the vt pairs of its sides: a seam where they differ; islands by union-find.
    sides = {}
    for p in mesh.polygons:
        loops = list(p.loop_indices)
        for i, l in enumerate(loops):
            m = loops[(i + 1) % len(loops)]
            pair = tuple(sorted((corner_vt[l], corner_vt[m])))
            sides.setdefault(mesh.loops[l].edge_index, []).append((p.index, pair))
    parent = list(range(len(mesh.polygons)))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    seam_length = total_length = 0.0
    for e, s in sides.items():
        a, b = mesh.edges[e].vertices
        length = (mesh.vertices[a].co - mesh.vertices[b].co).length
        total_length += length
        if len(s) != 2:
            continue
        if s[0][1] == s[1][1]:
            parent[find(s[0][0])] = find(s[1][0])
        else:
            seam_length += length
    islands = len({find(p) for p in range(len(mesh.polygons))})
    return {"E": c.get("area_distortion_energy"), "angle": c.get("angle_distortion_mean"),
            "flipped": c.get("flipped"), "seam_share": seam_length / total_length,
            "islands": islands}


def run_mesh(path, obj=None):
    if obj is None:
        clear()
        obj = load(path)
    activate(obj)
    rows = {}
    uv_layer(obj, "ricci")
    start = time.perf_counter()
    try:
        result = bpy.ops.uv.ricci_unwrap()
    except RuntimeError as e:
        print(f"{path}: ricci refused: {e}", file=sys.stderr)
        return None, obj
    seconds = time.perf_counter() - start
    if result != {"FINISHED"}:
        return None, obj
    rows["ricci"] = dict(measure(obj, obj.data.uv_layers["ricci"], f"{out_dir}/m.obj"),
                         seconds=seconds, cones=obj.get("ricci_cones", 0))
    seams = [e.use_seam for e in obj.data.edges]
    # The same cones and cut, the seams free to bend (both sides equally long): a map of the
    # kind Blender's Unwrap makes along seams.
    uv_layer(obj, "ricci_free")
    start = time.perf_counter()
    bpy.ops.uv.ricci_unwrap(seams="FREE")
    rows["ricci_free"] = dict(measure(obj, obj.data.uv_layers["ricci_free"], f"{out_dir}/m.obj"),
                              seconds=time.perf_counter() - start,
                              cones=obj.get("ricci_cones", 0))
    obj.data.edges.foreach_set("use_seam", seams)  # Blender's Unwrap cuts where ricci Unwrap cut
    for method in METHODS[2:]:
        uv_layer(obj, method)
        seconds = blender_unwrap(obj, method)
        # (Edit mode rebuilds the layers: looked up again by name.)
        rows[method] = dict(measure(obj, obj.data.uv_layers[method], f"{out_dir}/m.obj"),
                            seconds=seconds)
    return rows, obj


def render(obj, name):
    """obj with each map and a checker texture, Workbench, one PNG per method."""
    scene = bpy.context.scene
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.shading.light = "STUDIO"
    scene.display.shading.color_type = "TEXTURE"
    scene.render.resolution_x = scene.render.resolution_y = 360
    scene.display.shading.show_backface_culling = False
    image = bpy.data.images.new("checker", 1024, 1024)
    image.generated_type = "UV_GRID"
    material = bpy.data.materials.new("checker")
    material.use_nodes = True
    texture = material.node_tree.nodes.new("ShaderNodeTexImage")
    texture.image = image
    material.node_tree.links.new(texture.outputs["Color"],
                                 material.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
    material.node_tree.nodes.active = texture
    obj.data.materials.clear()
    obj.data.materials.append(material)
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(camera)
    camera.location = (1.6, -3.4, 1.0)
    camera.rotation_euler = (Vector((0, 0, 0.1)) - camera.location).to_track_quat(
        "-Z", "Y").to_euler()
    scene.camera = camera
    for method in METHODS:
        layer = obj.data.uv_layers[method]
        obj.data.uv_layers.active = layer
        layer.active_render = True
        scene.render.filepath = f"{out_dir}/{name}-{method}.png"
        bpy.ops.render.render(write_still=True)


table, everything = [], {}
for path in meshes:
    rows, _ = run_mesh(path)
    if rows is None:
        table.append(f"| {os.path.basename(path)} | refused | | | | | |")
        continue
    everything[path] = rows
    name = os.path.basename(path)
    for method in METHODS:
        r = rows[method]
        cones = f" ({r['cones']} cones)" if method.startswith("ricci") else ""
        table.append(f"| {name} | {LABELS[method]}{cones} | {r['E']:.3f} | {r['angle']:.4f} | "
                     f"{r['flipped']} | {r['seam_share']:.3f} | {r['islands']} | "
                     f"{r['seconds']:.2f} |")
    print("\n".join(table[-len(METHODS):]), flush=True)

if picture:
    clear()
    bpy.ops.mesh.primitive_monkey_add()
    monkey = bpy.context.active_object
    modifier = monkey.modifiers.new("subdivision", "SUBSURF")
    modifier.levels = 1
    bpy.ops.object.modifier_apply(modifier=modifier.name)
    bpy.ops.object.shade_smooth()
    rows, monkey = run_mesh("suzanne", monkey)
    if rows:
        everything["suzanne"] = rows
        for method in METHODS:
            r = rows[method]
            table.append(f"| Suzanne (subdivided) | {LABELS[method]} | {r['E']:.3f} | "
                         f"{r['angle']:.4f} | {r['flipped']} | {r['seam_share']:.3f} | "
                         f"{r['islands']} | {r['seconds']:.2f} |")
        render(monkey, "suzanne")

header = ("| mesh | method | area distortion E | angle distortion | flipped | seam length / "
          "all edges | islands | seconds |\n|---|---|---|---|---|---|---|---|")
text = header + "\n" + "\n".join(table) + "\n"
print(text)
with open(f"{out_dir}/blender_compare.md", "w") as f:
    f.write(text)
with open(f"{out_dir}/blender_compare.json", "w") as f:
    json.dump(everything, f, indent=1)
