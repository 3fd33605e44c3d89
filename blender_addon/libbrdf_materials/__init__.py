"""libbrdf materials for Blender: physical-optics BRDFs (Butler, Nauyoks & Marciniak, Opt.
Express 23, 29100 (2015)) baked by libbrdf's `brdf` program and wired into a node group.

Layout (after glTF-Blender-IO): core.py and nodegraph.py hold the logic and need no `bpy`
(testable with plain Python); blender_nodes.py, operators.py and ui.py are the Blender glue.
"""

bl_info = {
    "name": "libbrdf materials",
    "author": "libbrdf",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Material > libbrdf",
    "description": "Physical-optics BRDFs (MBK, Beckmann-Kirchhoff, microfacet) baked by libbrdf",
    "category": "Material",
}

from . import core, nodegraph  # noqa: E402  (no bpy)

try:
    import bpy
except ImportError:  # imported outside Blender: only core and nodegraph are usable
    bpy = None

if bpy is not None:
    from . import blender_nodes, operators, ui

    if "_loaded_once" in globals():  # Reload Scripts: pick up edited submodules too
        import importlib
        for _module in (core, nodegraph, blender_nodes, operators, ui):
            importlib.reload(_module)
    _loaded_once = True

    classes = (
        ui.LIBBRDF_AddonPreferences,
        ui.LIBBRDF_MaterialSettings,
        ui.LIBBRDF_MT_presets,
        ui.LIBBRDF_PT_material,
        operators.LIBBRDF_OT_add_material,
        operators.LIBBRDF_OT_apply_preset,
    )

    def register():
        for cls in classes:
            bpy.utils.register_class(cls)
        bpy.types.Scene.libbrdf = bpy.props.PointerProperty(type=ui.LIBBRDF_MaterialSettings)

    def unregister():
        del bpy.types.Scene.libbrdf
        for cls in reversed(classes):
            bpy.utils.unregister_class(cls)
