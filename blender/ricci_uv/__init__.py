"""ricci UV: ricci's conformal unwrap in Blender (UV menu of the 3D view and of the UV editor).

Built by `ricci blender-addon -o ricci_uv.zip`, which adds the compiled ricci module (the
package `ricci` beside these files) for Blender's Python.
"""

bl_info = {
    "name": "ricci UV",
    "author": "the ricci developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D View (Edit Mode) > UV > ricci Unwrap; UV Editor > UV > ricci Unwrap",
    "description": "Conformal unwrap by discrete Ricci flow: cones and seams chosen for low "
                   "distortion, on the mesh's own faces",
    "category": "UV",
}

import bpy  # noqa: E402 (after bl_info, which Blender reads without importing)

from . import operator  # noqa: E402

_MENUS = ("VIEW3D_MT_uv_map", "IMAGE_MT_uvs")


def register():
    bpy.utils.register_class(operator.UV_OT_ricci_unwrap)
    for menu in _MENUS:
        getattr(bpy.types, menu).append(operator.menu_entry)


def unregister():
    for menu in _MENUS:
        getattr(bpy.types, menu).remove(operator.menu_entry)
    bpy.utils.unregister_class(operator.UV_OT_ricci_unwrap)
