"""A polished gold plate and a gold ball on a grey floor, built from an empty scene, lit by one sun, with
the libbrdf add-on's MBK material (Cycles). A template for your own scene.

    blender -b --python gold_plate.py -- OUT.png [WIDTH HEIGHT]

Needs the add-on installed and enabled (README, "Quickstart") and `brdf` on PATH (or set in the
add-on's preferences). Cycles' denoiser is off: Debian's Blender is built without one.
"""
import math
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if not args:
    sys.exit("usage: blender -b --python gold_plate.py -- OUT.png [WIDTH HEIGHT]")
output = bpy.path.abspath("//" + args[0]) if not args[0].startswith("/") else args[0]
width, height = (int(args[1]), int(args[2])) if len(args) >= 3 else (640, 400)

# An empty scene (the startup file's cube, light and camera go).
bpy.ops.object.select_all(action="SELECT")
bpy.ops.object.delete()
scene = bpy.context.scene

# Floor: a plain grey diffuse plane.
bpy.ops.mesh.primitive_plane_add(size=20)
floor_material = bpy.data.materials.new("Floor")
floor_material.use_nodes = True
floor_material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.3, 0.3, 0.3, 1)
bpy.context.active_object.data.materials.append(floor_material)

# The plate (a bevelled disc) and a ball on it, both smooth-shaded.
bpy.ops.mesh.primitive_cylinder_add(vertices=128, radius=1.6, depth=0.12, location=(0, 0, 0.06))
plate = bpy.context.active_object
plate.modifiers.new("Bevel", "BEVEL").width = 0.05
bpy.ops.object.shade_smooth()
bpy.ops.mesh.primitive_uv_sphere_add(segments=96, ring_count=48, radius=0.6, location=(0.3, 0.2, 0.72))
ball = bpy.context.active_object
bpy.ops.object.shade_smooth()

# One sun behind the plate, 45 deg from the zenith (LUT mode is lit by the Sun lamps of the scene),
# and a neutral grey sky, which the surface sees through its mirror lobe.
sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
sun.data.energy = 3.0
sun.rotation_euler = (math.radians(-45), 0, math.radians(-20))
scene.collection.objects.link(sun)
scene.world.use_nodes = True
scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.6, 0.6, 0.6, 1)

camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
camera.location = (0, -6.5, 3.6)
camera.rotation_euler = (math.radians(62), 0, 0)
scene.collection.objects.link(camera)
scene.camera = camera

# Gold by the libbrdf add-on: MBK, sigma_s = 0.05 um, l_c = 2 um (the add-on runs `brdf export
# blender` and builds the node group); the ball gets the same material.
bpy.context.view_layer.objects.active = plate
result = bpy.ops.libbrdf.add_material(model="mbk", material="Au", sigma_s=0.05, lc=2.0, mode="LUT")
if result != {"FINISHED"}:
    sys.exit(f"libbrdf.add_material: {result}")
ball.data.materials.append(plate.active_material)

scene.render.engine = "CYCLES"
scene.cycles.samples = 32
scene.cycles.use_denoising = False
scene.render.resolution_x, scene.render.resolution_y = width, height
scene.render.resolution_percentage = 100
scene.render.filepath = output
bpy.ops.render.render(write_still=True)
print(f"wrote {output}")
