"""The operator uv.ricci_unwrap: ricci's parameterization on every selected mesh object.

Invoked from a menu it runs as a modal operator: the work (ricci releases Python's lock while it
computes) goes on in a thread, the status bar shows the object and the flow's progress, Esc
cancels, and the results are written on the main thread once all objects are done (one undo
step). Called from a script or the redo panel it runs at once (execute).
"""

import re
import threading
import time

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from . import unwrap


def _ricci():
    """The ricci module shipped in this add-on (imported on first use: a module that cannot
    load is reported as an error, not a failed add-on)."""
    from . import ricci
    return ricci


# ricci's fixes name the Python module's keywords (`try: cones="auto"`); here they name the
# operator's options, as the redo panel shows them.
_FIXES = ((re.compile(r'cones="auto"'), "Cones: Automatic"),
          (re.compile(r'cones="needed"'), "Cones: Needed"),
          (re.compile(r"cones=(\d+)"), r"Cones: Count, Cone Count \1"),
          (re.compile(r'seams="free"'), "Seams: Free"),
          (re.compile(r'seams="rigid"'), "Seams: Rigid"),
          (re.compile(r"quantize=False"), "Quantize off"),
          (re.compile(r"polish=False"), "Polish off"))


def blender_message(message):
    """ricci's message on one line, its `try:` fixes phrased as this operator's options."""
    lines = []
    for line in str(message).splitlines():
        if line.lstrip().startswith("try:"):
            for pattern, option in _FIXES:
                line = pattern.sub(option, line)
        lines.append(line.strip())
    return "; ".join(line for line in lines if line)


def _mesh_objects(context):
    objects = context.objects_in_mode if context.mode == "EDIT_MESH" else context.selected_objects
    return [o for o in objects if o.type == "MESH"]


class _Work:
    """The state a run shares between its thread and the operator."""

    def __init__(self, jobs):
        self.jobs = jobs          # [(object name, unwrap.MeshJob)]
        self.results = {}         # object name -> ricci result
        self.errors = []          # (object name, message)
        self.current = 0
        self.iteration = 0
        self.max_error = float("nan")
        self.cancel = False
        self.done = False

    def progress(self, record):
        self.iteration = record.iteration
        self.max_error = record.max_error
        return not self.cancel


class UV_OT_ricci_unwrap(bpy.types.Operator):
    """Unwrap the selected meshes with ricci: conformal, with cones and seams chosen for low
    distortion, on the meshes' own faces"""

    bl_idname = "uv.ricci_unwrap"
    bl_label = "ricci Unwrap"
    bl_options = {"REGISTER", "UNDO"}

    cone_mode: EnumProperty(
        name="Cones",
        items=[("AUTO", "Automatic", "as many cones as keep the scale within its bound"),
               ("COUNT", "Count", "exactly this many cones"),
               ("NEEDED", "Needed", "none where the topology allows (a disk, a torus), else "
                "automatic")],
        default="AUTO")
    cone_count: IntProperty(name="Cone Count", default=8, min=1, max=10000,
                            description="number of cones (Cones: Count)")
    seams: EnumProperty(
        name="Seams",
        items=[("RIGID", "Rigid", "the flat metric with cones: each seam's two sides congruent"),
               ("FREE", "Free", "both sides of every seam equally long, free to bend: lower "
                "distortion with few cones")],
        default="RIGID")
    polish: BoolProperty(name="Polish", default=True,
                         description="lower the faces' angle distortion, seams and cones kept")
    quantize: BoolProperty(name="Quantize", default=False,
                           description="cone angles multiples of 90 degrees")
    margin: FloatProperty(name="Margin", default=0.002, min=0.0, max=0.2, precision=4,
                          description="space between charts in uv units")
    summary: StringProperty(name="Result", default="", options={"HIDDEN", "SKIP_SAVE"})

    @classmethod
    def poll(cls, context):
        return bool(_mesh_objects(context))

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "cone_mode")
        row = layout.row()
        row.enabled = self.cone_mode == "COUNT"
        row.prop(self, "cone_count")
        layout.prop(self, "seams")
        layout.prop(self, "polish")
        layout.prop(self, "quantize")
        layout.prop(self, "margin")
        if self.summary:
            box = layout.box()
            for line in self.summary.split("\n"):
                box.label(text=line)

    # --- the work -------------------------------------------------------------------------
    def _options(self):
        cones = {"AUTO": "auto", "NEEDED": "needed"}.get(self.cone_mode, int(self.cone_count))
        return dict(cones=cones, seams=self.seams.lower(), polish=self.polish,
                    quantize=self.quantize, gutter=self.margin)

    def _prepare(self, context):
        """The meshes as jobs (object mode while reading); errors as (name, message)."""
        ricci = _ricci()
        jobs, errors = [], []
        for obj in _mesh_objects(context):
            try:
                jobs.append((obj.name, unwrap.read_mesh(ricci, obj.name, obj.data)))
            except unwrap.UnwrapError as e:
                errors.append((obj.name, str(e)))
        return jobs, errors

    @staticmethod
    def _run(work, options):
        """ricci on every job (in the modal run: in a thread, so it touches no Blender data:
        the options were read on the main thread)."""
        ricci = _ricci()
        for i, (name, job) in enumerate(work.jobs):
            work.current = i
            if work.cancel:
                break
            try:
                work.results[name] = ricci.parameterize(job.V, job.F, polygons=job.polygons,
                                                        progress=work.progress, **options)
            except ricci.Error as e:
                work.errors.append((name, blender_message(e)))
            except Exception as e:  # reported in Blender, never a crash
                work.errors.append((name, f"{type(e).__name__}: {e}"))
        work.done = True

    def _write(self, context, work):
        lines, cones_total = [], 0
        for name, job in work.jobs:
            result = work.results.get(name)
            if result is None:
                continue
            obj = bpy.data.objects.get(name)
            if obj is None:
                continue
            if not job.matches(obj.data):
                work.errors.append((name, "the mesh was edited while ricci ran: run it again"))
                continue
            try:
                seams = unwrap.write_uv(obj.data, job, result)
            except unwrap.UnwrapError as e:
                work.errors.append((name, str(e)))
                continue
            cones = unwrap.cone_vertices(job, result)
            unwrap.set_cone_group(obj, cones)
            cones_total += len(cones)
            d = result.distortion
            obj["ricci_area_distortion"] = float(d.area_distortion_energy)
            obj["ricci_angle_distortion"] = float(d.angle_distortion_mean)
            obj["ricci_cones"] = len(cones)
            line = (f"{name}: {len(cones)} cones, {seams} seam edges, area distortion "
                    f"{d.area_distortion_energy:.3f}, angle {d.angle_distortion_mean:.3f}")
            if d.flipped_faces:
                line += f", {d.flipped_faces} flipped"
            if not result.converged:
                line += " (" + result.message + ")"
                self.report({"WARNING"}, f"ricci: {name}: {blender_message(result.message)}")
            lines.append(line)
            obj.data.update()
        for name, message in work.errors:
            self.report({"ERROR"}, f"ricci: {name}: {message}")
        self.summary = "\n".join(lines)
        if lines:
            head = lines[0] if len(lines) == 1 else f"{len(lines)} objects, {cones_total} cones"
            self.report({"INFO"}, "ricci: " + head)
        return bool(lines)

    def _in_object_mode(self, context, action):
        """Runs action() in object mode (mesh data current), back in edit mode afterwards."""
        was_edit = context.mode == "EDIT_MESH"
        if was_edit:
            bpy.ops.object.mode_set(mode="OBJECT")
        try:
            return action()
        finally:
            if was_edit:
                bpy.ops.object.mode_set(mode="EDIT")

    # --- entry points ---------------------------------------------------------------------
    def execute(self, context):
        try:
            _ricci()
        except ImportError as e:
            self.report({"ERROR"}, f"ricci: the module does not load here: {e}")
            return {"CANCELLED"}

        def action():
            jobs, errors = self._prepare(context)
            work = _Work(jobs)
            work.errors.extend(errors)
            self._run(work, self._options())
            return self._write(context, work)

        return {"FINISHED"} if self._in_object_mode(context, action) else {"CANCELLED"}

    def invoke(self, context, event):
        try:
            _ricci()
        except ImportError as e:
            self.report({"ERROR"}, f"ricci: the module does not load here: {e}")
            return {"CANCELLED"}
        self._was_edit = context.mode == "EDIT_MESH"
        if self._was_edit:
            bpy.ops.object.mode_set(mode="OBJECT")
        jobs, errors = self._prepare(context)
        self._work = _Work(jobs)
        self._work.errors.extend(errors)
        self._faces = [len(job.F) for _, job in jobs]
        self._thread = threading.Thread(target=self._run, args=(self._work, self._options()),
                                        daemon=True)
        self._started = time.monotonic()
        self._thread.start()
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.progress_begin(0, max(1, len(jobs)))
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        work = self._work
        if event.type == "ESC":
            work.cancel = True
            return {"RUNNING_MODAL"}
        if event.type != "TIMER":
            # The view can be turned and zoomed while ricci runs; an edit of the mesh meanwhile
            # is caught before writing (MeshJob.matches).
            return {"PASS_THROUGH"}
        wm = context.window_manager
        if not work.done:
            i = min(work.current, max(0, len(work.jobs) - 1))
            name = work.jobs[i][0] if work.jobs else ""
            faces = self._faces[i] if self._faces else 0
            wm.progress_update(i)
            context.workspace.status_text_set(
                f"ricci: {name} ({i + 1}/{len(work.jobs)}, {faces} triangles): flow iteration "
                f"{work.iteration}, max error {work.max_error:.1e}, "
                f"{time.monotonic() - self._started:.0f} s  (Esc cancels)")
            return {"RUNNING_MODAL"}
        self._thread.join()
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        # Edit mode entered during the run: its edits flushed to the mesh (object mode) before
        # writing, so that MeshJob.matches sees them and nothing written is lost on leaving it.
        back_to_edit = self._was_edit or context.mode == "EDIT_MESH"
        if context.mode == "EDIT_MESH":
            bpy.ops.object.mode_set(mode="OBJECT")
        try:
            # Cancelled: nothing written (the flow stopped short on the object it was on).
            written = not work.cancel and self._write(context, work)
        finally:
            if back_to_edit:
                bpy.ops.object.mode_set(mode="EDIT")
        if work.cancel:
            self.report({"WARNING"}, "ricci: cancelled, nothing written")
            return {"CANCELLED"}
        return {"FINISHED"} if written else {"CANCELLED"}


def menu_entry(self, context):
    self.layout.separator()
    self.layout.operator(UV_OT_ricci_unwrap.bl_idname)
