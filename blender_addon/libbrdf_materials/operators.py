"""Operators: libbrdf.add_material (bake through `brdf`, build the node group, wire the sun) and
libbrdf.apply_preset (fill the panel's settings from a preset)."""

import bpy
from bpy.props import EnumProperty, FloatProperty, FloatVectorProperty, IntVectorProperty, StringProperty

from . import blender_nodes, core, nodegraph


def _preferences(context):
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon is not None else None


class LIBBRDF_OT_add_material(bpy.types.Operator):
    """Bake a libbrdf BRDF for the scene and put it on the active object's active material"""

    bl_idname = "libbrdf.add_material"
    bl_label = "Add libbrdf Material"
    bl_options = {"REGISTER", "UNDO"}

    model: EnumProperty(name="Model", items=[(m, label, d) for m, label, d in core.MODELS], default="mbk")
    sigma_s: FloatProperty(name="sigma_s (um)", description="RMS surface height, >= 0 um", default=0.1, min=0.0,
                           precision=4)
    lc: FloatProperty(name="l_c (um)", description="Surface correlation length, > 0 um", default=2.0, min=1e-6,
                      precision=3)
    n: FloatProperty(name="n", description="Real part of the complex index (when no material is given)", default=1.5,
                     min=1e-6)
    k: FloatProperty(name="kappa", description="Imaginary part of the complex index, >= 0", default=0.0, min=0.0)
    material: StringProperty(name="Material", default="",
                             description="Built-in optical constants (" + ", ".join(core.MATERIALS) + "); empty: n, kappa")
    wavelengths: FloatVectorProperty(name="Wavelengths (um)", size=3, default=core.DEFAULT_WAVELENGTHS, min=1e-3,
                                     description="Wavelength of the R, G and B channels")
    mode: EnumProperty(name="Mode", items=[(m, label, d) for m, label, d in core.MODES], default="LUT")
    resolution: IntVectorProperty(name="Table nodes", size=3, default=(0, 0, 0), min=0, max=4096,
                                  description="theta_h, theta_d, phi_d nodes of the baked table (LUT, OSL); 0, 0, 0: "
                                              "the default (54^3 angular factor for MBK/BK, 128x64x48 otherwise)")
    name: StringProperty(name="Name", default="", description="Node group name (default: from the parameters)")
    target_error: FloatProperty(name="Target error", default=core.DEFAULT_TARGET_ERROR, min=0.001, max=1.0,
                                description="FIT: p95 per-pixel relative error the number of fitted lobes must meet")
    k_mode: EnumProperty(name="K", default="plane",
                         items=[("plane", "plane (eq. 13)", "The paper's renormalization; exceeds albedo 1 near grazing on rough surfaces"),
                                ("tis", "tis (conserves energy)", "K renormalized to the total integrated scatter")])

    @classmethod
    def poll(cls, context):
        return context.active_object is not None

    def execute(self, context):
        prefs = _preferences(context)
        request = core.MaterialRequest(model=self.model, sigma_s=self.sigma_s, lc=self.lc, n=self.n, k=self.k,
                                       material=self.material, wavelengths=tuple(self.wavelengths), mode=self.mode,
                                       resolution=tuple(self.resolution), name=self.name,
                                       target_error=self.target_error, k_mode=self.k_mode)
        try:
            request = request.validated()
            if request.mode in ("LUT", "OSL") and blender_nodes.first_sun(context.scene) is None:
                raise blender_nodes.SetupError("scene: LUT and OSL modes need a Sun lamp (add one, or use FIT mode)")
            executable = core.find_brdf_executable(prefs.brdf_executable if prefs else "")
            directory = blender_nodes.cache_directory(prefs.cache_directory if prefs else "")
            description_path = core.run_export(executable, request, directory)
            description = core.load_description(description_path)
            graph = nodegraph.graph_for(description, description_path)
            material, group, messages = blender_nodes.apply_graph(context.active_object, graph, context.scene,
                                                                      description_path)
        except (core.RequestError, core.ExportError, blender_nodes.SetupError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        for message in messages:
            self.report({"WARNING"}, message)
        error = description.get("lut", {}).get("error", {})
        detail = (f", table error rms {error['rms_relative']:.2%}, max {error['max_relative']:.2%} "
                  "(both polar angles <= 85 deg)" if error else "")
        albedo = core.albedo_text(description)
        if albedo:
            group.node_tree["libbrdf_albedo"] = albedo  # shown in the panel
            detail += ", " + albedo
        fit_text = core.fit_error_text(description)
        if fit_text:
            group.node_tree["libbrdf_fit_error"] = fit_text  # shown in the panel
            detail += ", " + fit_text
        self.report({"INFO"}, f"libbrdf: {group.node_tree.name} on {material.name} ({request.mode}{detail})")
        return {"FINISHED"}


class LIBBRDF_OT_apply_preset(bpy.types.Operator):
    """Fill the libbrdf panel with a preset surface"""

    bl_idname = "libbrdf.apply_preset"
    bl_label = "Apply libbrdf Preset"
    bl_options = {"REGISTER", "UNDO"}

    preset: EnumProperty(name="Preset", items=[(key, label, desc) for key, (label, desc, _) in core.PRESETS.items()])

    def execute(self, context):
        settings = context.scene.libbrdf
        values = core.PRESETS[self.preset][2]
        settings.model = values["model"]
        settings.material = values.get("material", "") or "CUSTOM"
        settings.sigma_s = values["sigma_s"]
        settings.lc = values["lc"]
        return {"FINISHED"}
