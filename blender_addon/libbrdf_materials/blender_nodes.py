"""Blender glue: turns a nodegraph.Graph into a shader node group, puts it on a material and
drives its light inputs from the scene's first Sun lamp. Works with Blender 3.4 to 4.x."""

import os

import bpy

from . import nodegraph


class SetupError(RuntimeError):
    """Something in the scene keeps the material from being set up (one-line message)."""


def scene_suns(scene):
    """The scene's Sun lamps, by object name."""
    return sorted((o for o in scene.objects if o.type == "LIGHT" and o.data.type == "SUN"), key=lambda o: o.name)


def first_sun(scene):
    """The scene's first Sun lamp (by object name), or None."""
    suns = scene_suns(scene)
    return suns[0] if suns else None


def _new_interface_socket(tree, name, socket_type, in_out):
    if hasattr(tree, "interface"):  # Blender 4.0+
        return tree.interface.new_socket(name=name, in_out=in_out, socket_type=socket_type)
    collection = tree.inputs if in_out == "INPUT" else tree.outputs
    return collection.new(socket_type, name)


def _socket(sockets, key):
    if isinstance(key, int):
        return sockets[key]
    for s in sockets:  # first enabled socket of that name (Mix-like nodes repeat names)
        if s.name == key and getattr(s, "enabled", True):
            return s
    raise KeyError(key)


def _load_image(path):
    image = bpy.data.images.load(path, check_existing=True)
    image.colorspace_settings.name = "Non-Color"  # raw BRDF values, no view transform
    image.alpha_mode = "NONE"
    if hasattr(image, "use_half_precision"):
        image.use_half_precision = False          # EEVEE: keep 32-bit floats on the GPU
    return image


def build_node_group(graph):
    """A new ShaderNodeTree group from a nodegraph.Graph; returns the group."""
    tree = bpy.data.node_groups.new(graph.name, "ShaderNodeTree")
    for name, socket_type, default in graph.inputs:
        socket = _new_interface_socket(tree, name, socket_type, "INPUT")
        if default is not None and hasattr(socket, "default_value"):
            socket.default_value = default
    for name, socket_type in graph.outputs:
        _new_interface_socket(tree, name, socket_type, "OUTPUT")
    group_in = tree.nodes.new("NodeGroupInput")
    group_out = tree.nodes.new("NodeGroupOutput")
    group_in.location, group_out.location = (-1600, 0), (1600, 0)
    images = {key: _load_image(path) for key, path in graph.images.items()}

    made = {nodegraph.GROUP_INPUT: group_in, nodegraph.GROUP_OUTPUT: group_out}
    for index, spec in enumerate(graph.nodes):
        node = tree.nodes.new(spec.type)
        node.name = spec.id
        node.label = spec.label
        node.location = (-1400 + 160 * (index // 12), 250 - 60 * (index % 12) - 8 * (index // 12))
        for prop, value in spec.props.items():
            if prop == "image":
                node.image = images[value]
            else:
                setattr(node, prop, value)
        for socket, value in spec.inputs.items():
            _socket(node.inputs, socket).default_value = value
        made[spec.id] = node
    for source, to_node, to_socket in graph.links:
        tree.links.new(_socket(made[source.node].outputs, source.socket), _socket(made[to_node].inputs, to_socket))
    return tree


def connect_script_node(tree, graph):
    """OSL mode: compiles the Script node through Cycles (as its Script Node Update button does)
    and links its sockets; False when this Blender cannot compile OSL (no sockets appear)."""
    script = tree.nodes[graph.notes["script_node"]]
    if not script.outputs:
        try:
            import _cycles
            from cycles import osl
            if getattr(_cycles, "with_osl", False):
                _put_oslquery_on_path()
                osl.update_script_node(script, lambda kind, message: None)
        except Exception:  # noqa: BLE001 - any failure here means: not compiled
            pass
    if not script.outputs:
        return False
    group_in = _group_node(tree, "NodeGroupInput")
    group_out = _group_node(tree, "NodeGroupOutput")
    for (from_node, from_socket), (to_node, to_socket) in graph.notes["script_links"]:
        source = group_in if from_node == nodegraph.GROUP_INPUT else tree.nodes[from_node]
        target = group_out if to_node == nodegraph.GROUP_OUTPUT else tree.nodes[to_node]
        tree.links.new(_socket(source.outputs, from_socket), _socket(target.inputs, to_socket))
    return True


def _put_oslquery_on_path():
    """Cycles' Script Node Update imports `oslquery`, which Blender keeps in its bundled Python's
    site-packages. Blender as a Python module (bpy 4.5 / 5.0 from PyPI) runs in the caller's
    Python, where that folder is not on sys.path: add it (a no-op in the Blender program)."""
    import glob
    import sys
    pattern = os.path.join(bpy.utils.resource_path("LOCAL"), "python", "lib", "python3*", "site-packages")
    for folder in glob.glob(pattern):
        if folder not in sys.path and os.path.isdir(os.path.join(folder, "oslquery")):
            sys.path.append(folder)


def _group_node(tree, bl_idname):
    return next(n for n in tree.nodes if n.bl_idname == bl_idname)


def material_for(obj):
    """The object's active material (a new one if it has none), with nodes enabled."""
    if obj is None or not hasattr(obj.data, "materials"):
        raise SetupError("active object: select a mesh (or other object that takes materials)")
    material = obj.active_material
    if material is None:
        material = bpy.data.materials.new("libbrdf")
        if obj.material_slots:
            obj.material_slots[obj.active_material_index].material = material
        else:
            obj.data.materials.append(material)
    material.use_nodes = True
    return material


def attach_group(material, tree, node_name="libbrdf"):
    """Puts a Group node of `tree` into the material and links it to the output's Surface."""
    nodes = material.node_tree.nodes
    old = nodes.get(node_name)
    if old is not None:
        nodes.remove(old)
    group = nodes.new("ShaderNodeGroup")
    group.name = node_name
    group.label = tree.name
    group.node_tree = tree
    output = next((n for n in nodes if n.bl_idname == "ShaderNodeOutputMaterial" and n.is_active_output
                   and n.name != "libbrdf EEVEE output"), None)
    if output is None:
        output = nodes.new("ShaderNodeOutputMaterial")
    group.location = (output.location.x - 300, output.location.y)
    material.node_tree.links.new(group.outputs["Shader"], output.inputs["Surface"])
    # FIT mode's EEVEE lobes (nodegraph.fit_graph): their own output, the group's "Shader" for Cycles.
    eevee_name = nodegraph.EEVEE_SHADER_OUTPUT[0]
    old_eevee = nodes.get("libbrdf EEVEE output")
    if eevee_name in group.outputs:
        output.target = "CYCLES"
        if old_eevee is None:
            old_eevee = nodes.new("ShaderNodeOutputMaterial")
            old_eevee.name = "libbrdf EEVEE output"
        old_eevee.target = "EEVEE"
        old_eevee.location = (output.location.x, output.location.y - 200)
        material.node_tree.links.new(group.outputs[eevee_name], old_eevee.inputs["Surface"])
    else:
        output.target = "ALL"
        if old_eevee is not None:
            nodes.remove(old_eevee)
    return group


def drive_light_inputs(material, group_node, sun):
    """Drivers: Light Direction = the sun's world +Z axis (towards the sun), Sun Strength = its
    strength, Sun Color = its colour. They follow the lamp when it moves or is re-parented."""
    tree = material.node_tree
    base = f'nodes["{group_node.name}"].inputs'
    names = [s.name for s in group_node.inputs]

    def drive(input_name, index, id_type, target_id, data_path):
        path = f'{base}[{names.index(input_name)}].default_value'
        tree.driver_remove(path, index)
        fcurve = tree.driver_add(path, index)
        driver = fcurve.driver
        driver.type = "AVERAGE"  # one variable, no Python expression (works with auto-run off)
        for v in list(driver.variables):
            driver.variables.remove(v)
        var = driver.variables.new()
        var.name = "v"
        var.type = "SINGLE_PROP"
        var.targets[0].id_type = id_type
        var.targets[0].id = target_id
        var.targets[0].data_path = data_path

    for axis in range(3):
        # RNA paths index Blender's column-major storage: matrix_world[2] is the Z axis (column).
        drive("Light Direction", axis, "OBJECT", sun, f"matrix_world[2][{axis}]")
        drive("Sun Color", axis, "LIGHT", sun.data, f"color[{axis}]")
    drive("Sun Strength", -1, "LIGHT", sun.data, "energy")


def turn_off_unavailable_denoiser(scene):
    """Cycles denoises final renders by default; a Blender built without OpenImageDenoise (Debian's
    3.4) then fails every render ("Build without OpenImageDenoiser"). Turns denoising off in that
    case only and says so (None when nothing changed)."""
    try:
        import _cycles
    except ImportError:  # Cycles not loaded: nothing to render with it yet
        return None
    cycles = getattr(scene, "cycles", None)
    if cycles is None or getattr(_cycles, "with_openimagedenoise", True) or not cycles.use_denoising:
        return None
    cycles.use_denoising = False
    return "Cycles: render denoising turned off (this Blender has no OpenImageDenoise)"


def apply_graph(obj, graph, scene, description_path=""):
    """Builds the group, attaches it to the object's active material and wires the sun.
    Returns (material, group node, messages)."""
    messages = []
    sun = first_sun(scene)
    if graph.notes.get("mode") in ("LUT", "OSL") and sun is None:
        raise SetupError("scene: LUT and OSL modes need a Sun lamp (its direction and strength drive the material)")
    material = material_for(obj)
    message = turn_off_unavailable_denoiser(scene)
    if message:
        messages.append(message)
    tree = build_node_group(graph)
    tree["libbrdf_description"] = description_path  # where the table and its parameters are
    if graph.notes.get("mode") == "OSL":
        scene.render.engine = "CYCLES"
        scene.cycles.shading_system = True
        scene.cycles.device = "CPU"
        if not connect_script_node(tree, graph):
            messages.append("OSL: the Script node is set up but not compiled (this Blender has no OSL); "
                            "open the file in a Blender with OSL and press Script Node Update")
    group = attach_group(material, tree)
    if sun is not None:
        drive_light_inputs(material, group, sun)
    if graph.notes.get("mode") in ("LUT", "OSL"):
        attach_extra_suns(material, group, scene_suns(scene)[1:])
    return material, group, messages


EXTRA_SUN_PREFIX = "libbrdf sun "


def attach_extra_suns(material, group, suns):
    """Every Sun after the first lights the material too: one more instance of the same node group
    per sun (its own drivers: direction, strength, colour), whose Radiance is emitted and added to
    the first group's Shader (emission + mirror lobe), and its EEVEE Radiance to the EEVEE Shader
    where the group has one (LUT mode). The table is shared; only the few light nodes run once
    per sun. Suns added later need the material applied again."""
    nodes, links = material.node_tree.nodes, material.node_tree.links
    for node in [n for n in nodes if n.name.startswith(EXTRA_SUN_PREFIX)]:
        nodes.remove(node)
    if not suns:
        return
    extras = []
    for index, sun in enumerate(suns, start=2):
        extra = nodes.new("ShaderNodeGroup")
        extra.name = f"{EXTRA_SUN_PREFIX}{index}"
        extra.label = f"{group.node_tree.name} ({sun.name})"
        extra.node_tree = group.node_tree
        extra.location = (group.location.x, group.location.y - 220 * (index - 1))
        drive_light_inputs(material, extra, sun)
        extras.append(extra)
    outputs = [("Shader", "Radiance", "")]
    if nodegraph.EEVEE_SHADER_OUTPUT[0] in group.outputs and nodegraph.EEVEE_RADIANCE_OUTPUT[0] in group.outputs:
        outputs.append((nodegraph.EEVEE_SHADER_OUTPUT[0], nodegraph.EEVEE_RADIANCE_OUTPUT[0], " eevee"))
    for shader_name, radiance_name, tag in outputs:
        output = next(link.to_node for link in group.outputs[shader_name].links)
        total = group.outputs[shader_name]
        for extra in extras:
            emission = nodes.new("ShaderNodeEmission")
            emission.name = f"{extra.name}{tag} emission"
            emission.location = (extra.location.x + 180, extra.location.y - (90 if tag else 0))
            links.new(extra.outputs[radiance_name], emission.inputs["Color"])
            add = nodes.new("ShaderNodeAddShader")
            add.name = f"{extra.name}{tag} add"
            add.location = (emission.location.x + 160, emission.location.y)
            links.new(total, add.inputs[0])
            links.new(emission.outputs[0], add.inputs[1])
            total = add.outputs[0]
        links.new(total, output.inputs["Surface"])


def cache_directory(preferences_directory=""):
    """Where baked tables go: the preference, else libbrdf_tables beside the saved .blend, else the
    user's cache ($XDG_CACHE_HOME, default ~/.cache, /libbrdf/blender_tables): never a temporary
    folder, which a saved .blend would point into after a reboot."""
    if preferences_directory:
        return bpy.path.abspath(preferences_directory)
    if bpy.data.filepath:
        return os.path.join(os.path.dirname(bpy.data.filepath), "libbrdf_tables")
    cache_home = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(cache_home, "libbrdf", "blender_tables")
