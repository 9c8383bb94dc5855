"""Run inside Blender with a window (tests/blender/addon_test.sh starts it under xvfb-run): the
operator as a menu runs it (INVOKE_DEFAULT: modal, the work in a thread while the interface goes
on drawing), then Blender's own undo.

  xvfb-run blender --factory-startup -P modal_check.py -- ZIP MESH.obj

Prints one line per check and exits 1 when any fails (os._exit: Blender's event loop is running).
"""

import os
import sys
import time

import bpy

zip_path, mesh_path = sys.argv[sys.argv.index("--") + 1:][:2]
failures = []
state = {"phase": "start", "started": 0.0, "ticks": 0}


def check(name, condition, detail=""):
    print(("ok   " if condition else "FAIL ") + name + ("" if condition else f": {detail}"),
          flush=True)
    if not condition:
        failures.append(name)


def done():
    print(f"{len(failures)} failed", flush=True)
    os._exit(1 if failures else 0)


def window_context():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    return dict(window=window, area=area, region=region)


def step():
    """A timer: one phase per call, so that Blender's event loop (and the modal operator's
    timer) runs in between."""
    try:
        return advance()
    except Exception as e:  # noqa: BLE001 (the test must end, not hang)
        check("no exception", False, repr(e))
        done()


def advance():
    obj = bpy.data.objects.get("genus2")
    if state["phase"] == "start":
        bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
        bpy.ops.preferences.addon_enable(module="ricci_uv")
        for o in list(bpy.data.objects):
            bpy.data.objects.remove(o, do_unlink=True)
        with bpy.context.temp_override(**window_context()):
            bpy.ops.wm.obj_import(filepath=mesh_path)
            bpy.ops.ed.undo_push(message="imported")
        obj = bpy.data.objects.get("genus2")
        check("mesh imported", obj is not None)
        if obj is None:
            done()
        bpy.context.view_layer.objects.active = obj
        obj.select_set(True)
        with bpy.context.temp_override(**window_context()):
            result = bpy.ops.uv.ricci_unwrap("INVOKE_DEFAULT", cone_mode="COUNT", cone_count=8)
        check("invoke runs modal", result == {"RUNNING_MODAL"}, result)
        state.update(phase="running", started=time.monotonic())
        return 0.05
    if state["phase"] == "running":
        state["ticks"] += 1
        if "ricci_cones" not in obj:
            if time.monotonic() - state["started"] > 120:
                check("modal run ends", False, "still running after 120 s")
                done()
            return 0.05
        check(f"the interface went on while it ran ({state['ticks']} timer ticks)",
              state["ticks"] >= 1, state["ticks"])
        check("8 cones written", obj["ricci_cones"] == 8, obj.get("ricci_cones"))
        check("seams marked", sum(e.use_seam for e in obj.data.edges) > 0)
        state["phase"] = "undo"
        return 0.2
    if state["phase"] == "undo":
        with bpy.context.temp_override(**window_context()):
            bpy.ops.ed.undo()
        obj = bpy.data.objects.get("genus2")
        check("undo: the unwrap undone in one step",
              obj is not None and "ricci_cones" not in obj and
              not any(e.use_seam for e in obj.data.edges),
              "still unwrapped" if obj is not None else "object gone")
        done()
    return None


bpy.app.timers.register(step, first_interval=0.5)
