"""Runs inside Blender (tests/blender/test_blender_addon.py starts it): the add-on installs with
Blender's installer, registers and unregisters symmetrically, its preset operator fills the panel
settings, the operator refuses bad input and a scene without a sun with one-line errors, FIT mode
needs no sun, OSL mode sets up a Script node on the generated shader, and the sun's drivers update
the node group when the lamp turns. Exit status 1 on any failure; the last line of stdout is
"N passed, M failed" (tests/checks.py)."""

import os
import time
import sys

import bpy  # first: as a Python module (bpy from PyPI) it puts addon_utils on sys.path
import addon_utils  # noqa: E402
import mathutils  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import checks  # noqa: E402
from checks import check  # noqa: E402

MODULE = "libbrdf_materials"


def run_operator(**kwargs):
    """(result, [error messages]) of bpy.ops.libbrdf.add_material."""
    try:
        return bpy.ops.libbrdf.add_material(**kwargs), []
    except RuntimeError as e:  # operator reported an ERROR
        return {"CANCELLED"}, [line.strip().removeprefix("Error: ") for line in str(e).splitlines() if line.strip()]


def main():
    zip_path = sys.argv[sys.argv.index("--") + 1]
    bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
    addon_utils.enable(MODULE, default_set=True)
    check(MODULE in bpy.context.preferences.addons, "add-on installed and enabled")
    module = sys.modules[MODULE]
    check(os.environ["BLENDER_USER_SCRIPTS"] in module.__file__, f"loaded from the installed copy ({module.__file__})")
    check(hasattr(bpy.ops.libbrdf, "add_material") and hasattr(bpy.types.Scene, "libbrdf"),
          "operator and scene settings registered")
    check(hasattr(bpy.types, "LIBBRDF_PT_material") and bpy.types.LIBBRDF_PT_material.bl_context == "material",
          "panel in Material Properties")
    prefs = bpy.context.preferences.addons[MODULE].preferences
    check(prefs.brdf_executable == "", "preference: brdf executable empty by default (env, then PATH)")

    scene = bpy.context.scene
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    bpy.ops.libbrdf.apply_preset(preset="ROUGH_BK7")
    s = scene.libbrdf
    check((s.material, s.sigma_s, s.model) == ("BK7", 0.2, "mbk") or abs(s.sigma_s - 0.2) < 1e-6 and s.material == "BK7",
          f"preset fills the panel settings: {s.material} {s.sigma_s:g} {s.model}")

    bpy.ops.mesh.primitive_uv_sphere_add()
    obj = bpy.context.active_object
    result, errors = run_operator(model="mbk", material="Au", sigma_s=0.1, lc=2.0, mode="LUT")
    check(result == {"CANCELLED"} and any(e.startswith("scene:") for e in errors),
          f"LUT without a sun refused: {errors}")
    result, errors = run_operator(model="mbk", material="Xx", sigma_s=0.1, lc=2.0, mode="FIT")
    check(result == {"CANCELLED"} and any(e.startswith("material:") for e in errors), f"bad material refused: {errors}")
    result, errors = run_operator(model="mbk", material="Au", sigma_s=0.1, lc=2.0, wavelengths=(0.65, 0.55, 5.0),
                                  mode="FIT")
    check(result == {"CANCELLED"} and any(e.startswith("brdf: error: wavelength") for e in errors),
          f"brdf's error shown: {errors}")

    result, _ = run_operator(model="mbk", material="Al", sigma_s=0.2, lc=2.0, mode="FIT")
    mat = obj.active_material
    group = mat.node_tree.nodes.get("libbrdf") if mat else None
    check(result == {"FINISHED"} and group is not None, "FIT without a sun: material with a libbrdf group")
    if group:
        kinds = {n.bl_idname for n in group.node_tree.nodes}
        # Blender 4.0 merged Glossy into the Anisotropic BSDF: "ShaderNodeBsdfGlossy" makes one of those.
        glossy = [n for n in group.node_tree.nodes if n.bl_idname in ("ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic")]
        check("ShaderNodeTexImage" not in kinds and any(n.distribution == "BECKMANN" for n in glossy),
              "FIT group: Beckmann Glossy, no image")
        surface = next(n for n in mat.node_tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial").inputs["Surface"]
        check(surface.is_linked and surface.links[0].from_node == group, "group drives the material's Surface")

    light = bpy.data.lights.new("Sun", "SUN")
    sun = bpy.data.objects.new("Sun", light)
    scene.collection.objects.link(sun)
    sun.rotation_euler = (0.3, 0.2, 0.0)
    bpy.context.view_layer.objects.active = obj
    result, _ = run_operator(model="bk-modified", material="Cu", sigma_s=0.05, lc=2.0, mode="LUT",
                             resolution=(32, 16, 8))
    group = obj.active_material.node_tree.nodes["libbrdf"]
    images = [n.image for n in group.node_tree.nodes if n.bl_idname == "ShaderNodeTexImage"]
    # The factored form, twice: for EEVEE Closest fetches (P~ trilinear 8, K, F, R_spec rows 2 each,
    # Sigma bilinear per channel 12: 26), for Cycles Linear ones (P~ 2, rows 1 each, Sigma 1 per channel: 8).
    kinds = sorted(n.interpolation for n in group.node_tree.nodes if n.bl_idname == "ShaderNodeTexImage")
    check(result == {"FINISHED"} and kinds.count("Closest") == 26 and kinds.count("Linear") == 8
          and len({i.name for i in images}) == 3,
          f"LUT group: 26 Closest (EEVEE) and 8 Linear (Cycles) lookups of three images "
          f"({kinds.count('Closest')}, {kinds.count('Linear')}, {len({i.name for i in images})})")
    check(all(i.colorspace_settings.name == "Non-Color" and not i.use_half_precision and i.size[0] > 0 for i in images),
          f"images loaded as Non-Color float ({sorted({tuple(i.size) for i in images})})")
    # An unsaved .blend keeps its tables in the user's cache, not a temporary folder (test_blender_addon.py
    # points XDG_CACHE_HOME into its own folder).
    cache = os.path.join(os.environ["XDG_CACHE_HOME"], "libbrdf", "blender_tables")
    check(all(os.path.dirname(bpy.path.abspath(i.filepath)) == cache for i in images),
          f"tables in the user's cache {cache} ({sorted({os.path.dirname(i.filepath) for i in images})})")
    # The user's first render: Cycles denoises by default, which a Blender without OpenImageDenoise
    # (Debian's 3.4) cannot; the add-on turned it off there, so the render completes.
    import _cycles
    has_oidn = getattr(_cycles, "with_openimagedenoise", True)
    check(has_oidn or not scene.cycles.use_denoising,
          f"denoising {'left on (OpenImageDenoise present)' if has_oidn else 'turned off: no OpenImageDenoise'}")
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    camera.location = (0.0, -6.0, 0.0)
    camera.rotation_euler = (1.5708, 0.0, 0.0)
    scene.camera = camera
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 1
    scene.render.resolution_x = scene.render.resolution_y = 16
    try:
        rendered = bpy.ops.render.render()
    except RuntimeError as e:
        rendered = {str(e).strip()}
    check(rendered == {"FINISHED"}, f"a first Cycles render with the add-on's defaults completes ({rendered})")
    # A roughness change: the add-on exports again (only K and R_spec are re-baked) and rebuilds the group.
    start = time.perf_counter()
    result, _ = run_operator(model="bk-modified", material="Cu", sigma_s=0.07, lc=2.5, mode="LUT",
                             resolution=(32, 16, 8))
    took = time.perf_counter() - start
    group = obj.active_material.node_tree.nodes["libbrdf"]
    reused = {n.image.name for n in group.node_tree.nodes if n.bl_idname == "ShaderNodeTexImage"} & {i.name for i in images}
    check(result == {"FINISHED"} and len(reused) == 2,
          f"roughness change: Add Material again in {took:.2f} s (export and group), angular and Sigma images reused")
    check(all(n.interpolation in ("Closest", "Linear") and n.extension == "EXTEND"
              for n in group.node_tree.nodes if n.bl_idname == "ShaderNodeTexImage"), "Closest or Linear, Extend lookups")
    eevee_output = next((n for n in obj.active_material.node_tree.nodes if n.name == "libbrdf EEVEE output"), None)
    check(eevee_output is not None and eevee_output.target == "EEVEE" and eevee_output.inputs["Surface"].is_linked,
          "LUT mode: EEVEE's own Material Output (the Closest path), the group's Shader for Cycles")
    for rotation in ((0.3, 0.2, 0.0), (1.1, -0.4, 0.7)):
        sun.rotation_euler = rotation
        bpy.context.view_layer.update()
        evaluated = obj.active_material.evaluated_get(bpy.context.evaluated_depsgraph_get()).node_tree.nodes["libbrdf"]
        direction = mathutils.Vector(evaluated.inputs["Light Direction"].default_value)
        expected = sun.matrix_world.col[2].xyz.normalized()
        check((direction - expected).length < 1e-6, f"driver: Light Direction {tuple(round(v, 4) for v in direction)} "
                                                    f"follows the sun {tuple(round(v, 4) for v in expected)}")
    light.energy = 4.5
    bpy.context.view_layer.update()
    evaluated = obj.active_material.evaluated_get(bpy.context.evaluated_depsgraph_get()).node_tree.nodes["libbrdf"]
    check(abs(evaluated.inputs["Sun Strength"].default_value - 4.5) < 1e-6, "driver: Sun Strength follows the lamp")

    result, _ = run_operator(model="mbk", material="Au", sigma_s=0.1, lc=2.0, mode="OSL", resolution=(32, 16, 8))
    group = obj.active_material.node_tree.nodes["libbrdf"]
    script = next((n for n in group.node_tree.nodes if n.bl_idname == "ShaderNodeScript"), None)
    check(result == {"FINISHED"} and script is not None and script.mode == "EXTERNAL"
          and script.filepath.endswith(".osl") and os.path.isfile(script.filepath),
          f"OSL group: Script node on the generated shader ({script.filepath if script else None})")
    check(scene.cycles.shading_system, "OSL mode turns Cycles' Open Shading Language on")
    if getattr(_cycles, "with_osl", False):  # Blender 4.5 / 5.0 from PyPI: compiled, view from Incoming
        incoming = script.inputs.get("Incoming") if script else None
        check(script is not None and len(script.outputs) == 3 and incoming is not None and incoming.is_linked
              and incoming.links[0].from_socket.name == "Incoming",
              "OSL compiled by this Blender; its Incoming fed by Geometry > Incoming")
    with open(script.filepath, encoding="utf-8") as f:
        check("shader libbrdf_" in f.read(), "the Script node's file is a libbrdf shader")

    addon_utils.disable(MODULE, default_set=True)
    check(not hasattr(bpy.ops.libbrdf, "add_material") or "add_material" not in dir(bpy.ops.libbrdf),
          "operator gone after disable")
    check(not hasattr(bpy.types.Scene, "libbrdf") and not hasattr(bpy.types, "LIBBRDF_PT_material"),
          "scene settings and panel gone after disable")
    addon_utils.enable(MODULE, default_set=True)
    check(hasattr(bpy.types, "LIBBRDF_PT_material"), "re-enable registers again")
    checks.finish()


main()
