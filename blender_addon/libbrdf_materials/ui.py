"""User interface: add-on preferences, the scene's libbrdf settings and the Material Properties
panel (presets menu, custom parameters, Add button)."""

import bpy
from bpy.props import EnumProperty, FloatProperty, FloatVectorProperty, IntVectorProperty, StringProperty

from . import core


class LIBBRDF_AddonPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    brdf_executable: StringProperty(
        name="brdf executable", subtype="FILE_PATH", default="",
        description="Path of libbrdf's `brdf` program (empty: $LIBBRDF_BRDF_EXE, else `brdf` on PATH)")
    cache_directory: StringProperty(
        name="Table folder", subtype="DIR_PATH", default="",
        description="Where baked tables are kept (empty: libbrdf_tables beside the saved .blend, else ~/.cache/libbrdf/blender_tables)")

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "brdf_executable")
        layout.prop(self, "cache_directory")
        try:
            executable = core.find_brdf_executable(self.brdf_executable)
            layout.label(text=f"Using: {executable or 'the bundled libbrdf module (in process)'}", icon="CHECKMARK")
        except core.RequestError as e:
            layout.label(text=str(e), icon="ERROR")


class LIBBRDF_MaterialSettings(bpy.types.PropertyGroup):
    model: EnumProperty(name="Model", items=[(m, label, d) for m, label, d in core.MODELS], default="mbk")
    material: EnumProperty(name="Material",
                           items=[("CUSTOM", "Custom n, kappa", "Give the complex index yourself")] +
                                 [(m, m, f"libbrdf's built-in optical constants of {m}") for m in core.MATERIALS],
                           default="Au")
    sigma_s: FloatProperty(name="sigma_s (um)", default=0.1, min=0.0, precision=4, description="RMS height, um")
    lc: FloatProperty(name="l_c (um)", default=2.0, min=1e-6, precision=3, description="Correlation length, um")
    n: FloatProperty(name="n", default=1.5, min=1e-6)
    k: FloatProperty(name="kappa", default=0.0, min=0.0)
    wavelengths: FloatVectorProperty(name="Wavelengths (um)", size=3, default=core.DEFAULT_WAVELENGTHS, min=1e-3)
    mode: EnumProperty(name="Mode", items=[(m, label, d) for m, label, d in core.MODES], default="LUT")
    resolution: IntVectorProperty(name="Table nodes", size=3, default=(0, 0, 0), min=0, max=4096,
                                  description="0, 0, 0: the default (54^3 angular factor for MBK/BK, 128x64x48 otherwise)")
    target_error: FloatProperty(name="Target error", default=core.DEFAULT_TARGET_ERROR, min=0.001, max=1.0,
                                description="FIT: p95 per-pixel relative error the number of fitted lobes must meet")
    k_mode: EnumProperty(name="K", default="plane",
                         items=[("plane", "plane (eq. 13)", "The paper's renormalization; exceeds albedo 1 near grazing on rough surfaces"),
                                ("tis", "tis (conserves energy)", "K renormalized to the total integrated scatter")])


class LIBBRDF_MT_presets(bpy.types.Menu):
    bl_idname = "LIBBRDF_MT_presets"
    bl_label = "libbrdf Presets"

    def draw(self, context):
        for key, (label, description, _) in core.PRESETS.items():
            self.layout.operator("libbrdf.apply_preset", text=label).preset = key


class LIBBRDF_PT_material(bpy.types.Panel):
    bl_idname = "LIBBRDF_PT_material"
    bl_label = "libbrdf"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        return context.object is not None

    def draw(self, context):
        layout = self.layout
        s = context.scene.libbrdf
        layout.menu(LIBBRDF_MT_presets.bl_idname, text="Presets", icon="PRESET")
        col = layout.column(align=True)
        col.prop(s, "model")
        col.prop(s, "material")
        if s.material == "CUSTOM":
            row = col.row(align=True)
            row.prop(s, "n")
            row.prop(s, "k")
        col.prop(s, "sigma_s")
        col.prop(s, "lc")
        layout.prop(s, "wavelengths")
        layout.prop(s, "mode", expand=True)
        if s.mode != "FIT":
            layout.prop(s, "resolution")
        else:
            layout.prop(s, "target_error")
        layout.prop(s, "k_mode")
        op = layout.operator("libbrdf.add_material", icon="MATERIAL")
        op.model, op.sigma_s, op.lc, op.n, op.k = s.model, s.sigma_s, s.lc, s.n, s.k
        op.material = "" if s.material == "CUSTOM" else s.material
        op.wavelengths, op.mode, op.resolution = s.wavelengths, s.mode, s.resolution
        op.target_error = s.target_error
        op.k_mode = s.k_mode
        # The active material's libbrdf group: its fit's measured error (FIT mode).
        material = context.object.active_material
        group = material.node_tree.nodes.get("libbrdf") if material and material.node_tree else None
        if group is not None and group.node_tree is not None and group.node_tree.get("libbrdf_fit_error"):
            # core.fit_error_text: the overall error, then the error per light-camera angle per engine.
            for number, line in enumerate(group.node_tree["libbrdf_fit_error"].split("\n")):
                layout.label(text=("Fit: " if number == 0 else "  ") + line, icon="INFO" if number == 0 else "BLANK1")
        if group is not None and group.node_tree is not None and group.node_tree.get("libbrdf_albedo"):
            layout.label(text="Energy: " + group.node_tree["libbrdf_albedo"], icon="LIGHT_SUN")
