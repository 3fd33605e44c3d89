"""Renders a list of small libbrdf scenes inside Blender (run by Blender, not by plain Python):

    blender -b --factory-startup --python tools/blender_render_job.py -- JOB.json

JOB.json (written by tools/render_blender_comparison.py and tests/blender/test_blender_render.py):
  {"addon": {"zip": PATH} | {"extension": PATH} | {"path": DIR},  # legacy zip, 4.2+ extension, or import from DIR
   "results": PATH,                            # JSON written at the end (per render: what was set up)
   "renders": [{
      "output": PATH.exr,                      # multilayer EXR: Combined + requested passes
      "resolution": [W, H], "samples": 1, "engine": "CYCLES" | "BLENDER_EEVEE", "filter_width": 0.01,
      "camera": {"direction": [x, y, z], "ortho_scale": S,    # direction: from the target to the camera
                 "target": [x, y, z]},                        # (default: the origin)
      "sun": {"direction": [x, y, z], "strength": E, "color": [r, g, b], "angle_deg": 0, "shadow": true},
      "world": [r, g, b],                      # constant background radiance
      "extra_suns": [{same keys as "sun"}, ...],  # LUT/OSL materials sum every sun (optional)
      "passes": ["normal", "emit", ...],
      "keep_objects": false,                   # true: keep the previous render's objects and materials
      "objects": [{"shape": "sphere"|"torus"|"ellipsoid"|"monkey"|"cube"|"plane",
                   "segments": 96, "rings": 48,    # the spheres' tessellation
                   "diffuse": [r, g, b],           # instead of "material": a Lambertian surface
                   "principled": {"roughness": R, "color": [r, g, b]},  # or a metallic Principled BSDF
                   "location": [...], "scale": [...], "rotation_deg": [...], "visible_glossy": true,
                   "material": {operator arguments of bpy.ops.libbrdf.add_material}}]}]}

The sun lamp is rotated, never re-created, between renders, so `keep_objects` renders check that
the add-on's drivers follow it. Camera: orthographic, Standard view transform, Cycles on the CPU
with denoising and adaptive sampling off and a 0.01-pixel box filter (each pixel is the shading
point at its centre: the Normal pass and the colour come from the same point).
"""

import json
import math
import sys
import time

import bpy  # first: as a Python module (bpy from PyPI) it puts addon_utils on sys.path
import addon_utils  # noqa: E402
import mathutils  # noqa: E402

ADDON_MODULE = "libbrdf_materials"


def install_addon(spec):
    """Installs the add-on as the job says and returns its module name: a legacy zip
    (bpy.ops.preferences.addon_install), a Blender 4.2+ extension zip (Install from Disk:
    bpy.ops.extensions.package_install_files into the user repository), or a folder to import."""
    module = ADDON_MODULE
    if "extension" in spec:
        bpy.ops.extensions.package_install_files(filepath=spec["extension"], repo="user_default",
                                                 enable_on_install=True)
        module = f"bl_ext.user_default.{ADDON_MODULE}"
    elif "zip" in spec:
        bpy.ops.preferences.addon_install(filepath=spec["zip"], overwrite=True)
    else:
        sys.path.insert(0, spec["path"])
    if module not in bpy.context.preferences.addons:
        addon_utils.enable(module, default_set=True, handle_error=None)
    if module not in bpy.context.preferences.addons:
        raise SystemExit(f"{module}: add-on did not enable")
    return module


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for collection in (bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras):
        for block in list(collection):
            collection.remove(block)


def look_rotation(direction):
    """Rotation whose local +Z axis points along `direction` (lamps shine and cameras look along -Z)."""
    d = mathutils.Vector(direction).normalized()
    return d.to_track_quat("Z", "Y").to_euler()


def ensure_camera_and_sun(scene):
    cam = scene.objects.get("libbrdf camera")
    if cam is None:
        cam = bpy.data.objects.new("libbrdf camera", bpy.data.cameras.new("libbrdf camera"))
        scene.collection.objects.link(cam)
        cam.data.type = "ORTHO"
        scene.camera = cam
    sun = scene.objects.get("libbrdf sun")
    if sun is None:
        light = bpy.data.lights.new("libbrdf sun", "SUN")
        sun = bpy.data.objects.new("libbrdf sun", light)
        scene.collection.objects.link(sun)
    return cam, sun


def add_object(scene, spec):
    shape = spec["shape"]
    if shape == "sphere":  # Blender's own default UV sphere is 32 x 16: "segments", "rings" set it
        bpy.ops.mesh.primitive_uv_sphere_add(segments=spec.get("segments", 96), ring_count=spec.get("rings", 48), radius=1.0)
    elif shape == "ellipsoid":
        bpy.ops.mesh.primitive_uv_sphere_add(segments=96, ring_count=48, radius=1.0)
        bpy.context.active_object.scale = (1.0, 0.6, 0.8)
    elif shape == "torus":
        bpy.ops.mesh.primitive_torus_add(major_segments=96, minor_segments=48, major_radius=0.75, minor_radius=0.3)
    elif shape == "monkey":
        bpy.ops.mesh.primitive_monkey_add(size=1.6)
        modifier = bpy.context.active_object.modifiers.new("smooth", "SUBSURF")
        modifier.levels = modifier.render_levels = 2
    elif shape == "cube":
        bpy.ops.mesh.primitive_cube_add(size=1.4)
    elif shape == "plane":
        bpy.ops.mesh.primitive_plane_add(size=1.0)
    else:
        raise SystemExit(f"shape: unknown {shape!r}")
    obj = bpy.context.active_object
    if shape not in ("cube", "plane"):
        bpy.ops.object.shade_smooth()
    obj.location = spec.get("location", (0.0, 0.0, 0.0))
    if "scale" in spec:
        obj.scale = spec["scale"]
    obj.rotation_euler = [math.radians(a) for a in spec.get("rotation_deg", (0.0, 0.0, 0.0))]
    obj.visible_glossy = spec.get("visible_glossy", True)  # seen in other objects' glossy reflections
    bpy.context.view_layer.objects.active = obj
    if "principled" in spec:  # a stock Principled BSDF (the renderer-cost reference): metal of that roughness
        material = bpy.data.materials.new(f"principled {obj.name}")
        material.use_nodes = True
        principled = next(n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
        principled.inputs["Base Color"].default_value = (*spec["principled"].get("color", (0.8, 0.8, 0.8)), 1.0)
        principled.inputs["Metallic"].default_value = 1.0
        principled.inputs["Roughness"].default_value = spec["principled"]["roughness"]
        obj.data.materials.append(material)
        return obj
    if "diffuse" in spec:  # a plain Lambertian surface (ground, props), not a libbrdf material
        material = bpy.data.materials.new(f"diffuse {obj.name}")
        material.use_nodes = True
        nodes = material.node_tree.nodes
        for node in list(nodes):
            if node.bl_idname != "ShaderNodeOutputMaterial":
                nodes.remove(node)
        diffuse = nodes.new("ShaderNodeBsdfDiffuse")
        diffuse.inputs["Color"].default_value = (*spec["diffuse"], 1.0)
        output = next(n for n in nodes if n.bl_idname == "ShaderNodeOutputMaterial")
        material.node_tree.links.new(diffuse.outputs[0], output.inputs["Surface"])
        obj.data.materials.append(material)
        return obj
    result = bpy.ops.libbrdf.add_material(**spec["material"])
    if result != {"FINISHED"}:
        raise SystemExit(f"libbrdf.add_material failed for {spec}")
    return obj


def baked_in_process(core):
    """Whether the add-on bakes in Blender's process (no brdf program; the extension's libbrdf wheel)."""
    try:
        return core.find_brdf_executable("") is None
    except core.RequestError:  # neither: nothing baked (a scene of plain surfaces only)
        return False


def engine_name(engine):
    """The job's engine name in this Blender: EEVEE is BLENDER_EEVEE_NEXT in 4.2 - 4.5."""
    available = bpy.types.RenderSettings.bl_rna.properties["engine"].enum_items.keys()
    if engine == "BLENDER_EEVEE" and engine not in available and "BLENDER_EEVEE_NEXT" in available:
        return "BLENDER_EEVEE_NEXT"
    return engine


def configure_render(scene, r):
    scene.render.engine = engine_name(r.get("engine", "CYCLES"))
    scene.render.resolution_x, scene.render.resolution_y = r.get("resolution", (96, 96))
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    if scene.render.engine == "CYCLES":
        c = scene.cycles
        c.device = "CPU"
        c.samples = r.get("samples", 1)
        c.use_denoising = False
        c.use_adaptive_sampling = False
        # Default: each pixel is the shading point at its centre (Normal pass and colour agree);
        # "filter_width" >= 1 gives Blender's usual antialiased Blackman-Harris filter instead.
        width = r.get("filter_width", 0.01)
        c.pixel_filter_type = "BLACKMAN_HARRIS" if width >= 1.0 else "BOX"
        c.filter_width = width
        c.seed = 0
        c.max_bounces = r.get("max_bounces", 4)
        c.glossy_bounces = r.get("glossy_bounces", 4)
        c.caustics_reflective = r.get("caustics", True)
        c.blur_glossy = 0.0
        c.sample_clamp_direct = 0.0
        c.sample_clamp_indirect = r.get("clamp_indirect", 0.0)  # > 0: a scene render's firefly clamp
        # Cycles' default 0.01 terminates light samples below that contribution at random (0 or
        # 0.01 per pixel at 1 sample): off, so that dim pixels are exact too.
        c.light_sampling_threshold = 0.0
        if "threads" in r:  # a fixed thread count (renderer-cost benchmarks); default: all cores
            scene.render.threads_mode = "FIXED"
            scene.render.threads = r["threads"]
    else:
        scene.eevee.taa_render_samples = r.get("samples", 1)
    layer = scene.view_layers[0]
    passes = set(r.get("passes", ()))
    layer.use_pass_normal = "normal" in passes
    layer.use_pass_emit = "emit" in passes
    layer.use_pass_glossy_direct = layer.use_pass_glossy_indirect = "glossy" in passes
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):  # Blender 5.0+: the multilayer format needs its media type first
        settings.media_type = "MULTI_LAYER_IMAGE"
    settings.file_format = "OPEN_EXR_MULTILAYER"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"


def set_world(scene, rgb):
    world = scene.world or bpy.data.worlds.new("libbrdf world")
    scene.world = world
    world.use_nodes = True
    background = next(n for n in world.node_tree.nodes if n.bl_idname == "ShaderNodeBackground")
    background.inputs["Color"].default_value = (*rgb, 1.0)
    background.inputs["Strength"].default_value = 1.0


def main():
    job_path = sys.argv[sys.argv.index("--") + 1]
    with open(job_path, encoding="utf-8") as f:
        job = json.load(f)
    module = install_addon(job["addon"])
    scene = bpy.context.scene
    clear_scene()
    results = []
    for r in job["renders"]:
        cam, sun = ensure_camera_and_sun(scene)
        sun.rotation_euler = look_rotation(r["sun"]["direction"])
        sun.data.energy = r["sun"].get("strength", 1.0)
        sun.data.color = r["sun"].get("color", (1.0, 1.0, 1.0))
        sun.data.angle = math.radians(r["sun"].get("angle_deg", 0.0))
        sun.data.use_shadow = r["sun"].get("shadow", True)
        # Further suns ("extra_suns": same keys as "sun"), named after the first so that it stays first.
        wanted = {f"libbrdf sun {i}" for i in range(2, 2 + len(r.get("extra_suns", [])))}
        for stale in [o for o in scene.objects if o.name.startswith("libbrdf sun ") and o.name not in wanted]:
            bpy.data.objects.remove(stale, do_unlink=True)
        for index, spec in enumerate(r.get("extra_suns", []), start=2):
            extra = scene.objects.get(f"libbrdf sun {index}")
            if extra is None:
                extra = bpy.data.objects.new(f"libbrdf sun {index}", bpy.data.lights.new(f"libbrdf sun {index}", "SUN"))
                scene.collection.objects.link(extra)
            extra.rotation_euler = look_rotation(spec["direction"])
            extra.data.energy = spec.get("strength", 1.0)
            extra.data.color = spec.get("color", (1.0, 1.0, 1.0))
            extra.data.angle = math.radians(spec.get("angle_deg", 0.0))
            extra.data.use_shadow = spec.get("shadow", True)
        camera_direction = mathutils.Vector(r["camera"]["direction"]).normalized()
        cam.location = mathutils.Vector(r["camera"].get("target", (0.0, 0.0, 0.0))) + camera_direction * 10.0
        cam.rotation_euler = look_rotation(camera_direction)
        cam.data.ortho_scale = r["camera"].get("ortho_scale", 2.4)
        cam.data.clip_end = 100.0
        set_world(scene, r.get("world", (0.0, 0.0, 0.0)))
        configure_render(scene, r)
        if not r.get("keep_objects", False):
            for obj in [o for o in scene.objects if o.type == "MESH"]:
                bpy.data.objects.remove(obj, do_unlink=True)
            for spec in r["objects"]:
                add_object(scene, spec)
        bpy.context.view_layer.update()
        scene.render.filepath = r["output"]
        started = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        render_seconds = time.perf_counter() - started  # scene sync, kernels, samples and the file

        # What the materials saw (driver values after evaluation) and where their tables are.
        depsgraph = bpy.context.evaluated_depsgraph_get()
        materials = []
        for obj in [o for o in scene.objects if o.type == "MESH"]:
            mat = obj.active_material
            group = mat.node_tree.nodes.get("libbrdf") if mat else None
            if group is None:  # a plain surface ("diffuse")
                continue
            evaluated = mat.evaluated_get(depsgraph).node_tree.nodes.get("libbrdf")
            materials.append({
                "object": obj.name,
                "material": mat.name,
                "node_group": group.node_tree.name,
                "node_count": len(group.node_tree.nodes),
                "light_direction": list(evaluated.inputs["Light Direction"].default_value),
                "sun_strength": evaluated.inputs["Sun Strength"].default_value,
                "description": group.node_tree.get("libbrdf_description", ""),
            })
        extra_suns = [o for o in scene.objects if o.type == "LIGHT" and o.name.startswith("libbrdf sun ")]
        results.append({
            "output": r["output"],
            "extra_suns": [{"direction": list(o.matrix_world.col[2].xyz.normalized()), "strength": o.data.energy,
                            "color": list(o.data.color)} for o in sorted(extra_suns, key=lambda o: o.name)],
            "camera_direction": list(cam.matrix_world.col[2].xyz.normalized()),
            "sun_direction": list(sun.matrix_world.col[2].xyz.normalized()),
            "sun_strength": sun.data.energy,
            "render_seconds": render_seconds,
            "sun_color": list(sun.data.color),
            "materials": materials,
            "blender": bpy.app.version_string,
            "addon_file": sys.modules[module].__file__,
            # How the add-on baked: in Blender's process (the extension's bundled libbrdf wheel) or `brdf`.
            "baked_in_process": baked_in_process(sys.modules[module].core),
        })
    with open(job["results"], "w", encoding="utf-8") as f:
        json.dump(results, f, indent=2)


main()
