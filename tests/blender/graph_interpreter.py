"""Evaluates a libbrdf node graph (blender_addon/libbrdf_materials/nodegraph.py) with numpy, for
many shading points at once, with Blender's semantics for the node types the graphs use: Math and
Vector Math (safe division, logarithm and normalisation as in Cycles), Combine XYZ, Image Texture with
Closest interpolation and EXTEND, Geometry (Normal, Incoming), and Emission / Glossy / Add Shader
as tagged closures. Not physics: it runs the graph the add-on builds, so that tests can check the
graph against `brdf eval` without Blender.
"""

import numpy as np
import OpenImageIO as oiio


def load_image(path):
    """Float RGB texels [row from the BOTTOM][x][3], as Blender indexes images (v = 0 bottom)."""
    buf = oiio.ImageBuf(path)
    spec = buf.spec()
    pixels = buf.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)[:, :, :3]
    return pixels[::-1].astype(np.float32)


def _vec(x, m):
    x = np.asarray(x, dtype=np.float32)
    if x.ndim == 0:
        return np.repeat(np.full((1, 3), x, np.float32), m, axis=0)
    if x.ndim == 1 and x.shape[0] in (3, 4) and m != x.shape[0]:
        return np.repeat(x[None, :3], m, axis=0)
    if x.ndim == 1:
        return np.repeat(x[:, None], 3, axis=1)  # float -> vector broadcast
    return x[:, :3]


def _flt(x, m):
    x = np.asarray(x, dtype=np.float32)
    if x.ndim == 0:
        return np.full(m, x, np.float32)
    if x.ndim == 2:
        return x.mean(axis=1)  # Blender: vector -> float is the average
    return x


def _safe_div(a, b):
    return np.where(b != 0, a / np.where(b != 0, b, 1), 0).astype(np.float32)


MATH = {
    "ADD": lambda a, b, c: a + b,
    "SUBTRACT": lambda a, b, c: a - b,
    "MULTIPLY": lambda a, b, c: a * b,
    "DIVIDE": lambda a, b, c: _safe_div(a, b),
    "MULTIPLY_ADD": lambda a, b, c: a * b + c,
    "MINIMUM": lambda a, b, c: np.minimum(a, b),
    "MAXIMUM": lambda a, b, c: np.maximum(a, b),
    "SQRT": lambda a, b, c: np.where(a > 0, np.sqrt(np.maximum(a, 0)), 0),
    "FLOOR": lambda a, b, c: np.floor(a),
    "ARCCOSINE": lambda a, b, c: np.arccos(np.clip(a, -1, 1)),
    "ARCTAN2": lambda a, b, c: np.arctan2(a, b),
    "GREATER_THAN": lambda a, b, c: (a > b).astype(np.float32),
    "POWER": lambda a, b, c: np.where(a >= 0, np.power(np.maximum(a, 0), b), 0),
    "EXPONENT": lambda a, b, c: np.exp(a),
    # Cycles' safe_logf: 0 unless both the value and the base are positive.
    "LOGARITHM": lambda a, b, c: np.where((a > 0) & (b > 0), np.log(np.maximum(a, 1e-38)) / np.log(np.where(b > 0, b, 2.0)), 0),
}


def _normalize(v):
    n = np.linalg.norm(v, axis=1, keepdims=True)
    return np.where(n > 0, v / np.where(n > 0, n, 1), 0).astype(np.float32)


VMATH = {
    "ADD": lambda a, b, c, s: (a + b, None),
    "SUBTRACT": lambda a, b, c, s: (a - b, None),
    "MULTIPLY": lambda a, b, c, s: (a * b, None),
    "MULTIPLY_ADD": lambda a, b, c, s: (a * b + c, None),
    "SCALE": lambda a, b, c, s: (a * s[:, None], None),
    "MAXIMUM": lambda a, b, c, s: (np.maximum(a, b), None),
    "NORMALIZE": lambda a, b, c, s: (_normalize(a), None),
    "CROSS_PRODUCT": lambda a, b, c, s: (np.cross(a, b).astype(np.float32), None),
    "DOT_PRODUCT": lambda a, b, c, s: (None, np.sum(a * b, axis=1)),
    "LENGTH": lambda a, b, c, s: (None, np.linalg.norm(a, axis=1)),
}


def evaluate(graph, normal, incoming, inputs, images):
    """Group outputs {name: array} for M shading points.

    normal, incoming: (M, 3) unit vectors (Geometry node's Normal and Incoming);
    inputs: {group input name: constant}; images: {image key: texels from load_image}.
    Closures come back as dicts {"emission": (M,3), "glossy_ggx": (M,3), ...} of weights."""
    m = normal.shape[0]
    nodes = {n.id: n for n in graph.nodes}
    links = {(to, sock): src for src, to, sock in graph.links}
    cache = {}

    def input_value(node, socket, default=0.0):
        src = links.get((node.id, socket))
        if src is not None:
            return output_value(src.node, src.socket)
        return node.inputs.get(socket, default)

    def output_value(node_id, socket):
        key = (node_id, socket)
        if key in cache:
            return cache[key]
        if node_id == "GROUP_INPUT":
            value = np.asarray(inputs[socket], dtype=np.float32)
        else:
            value = compute(nodes[node_id], socket)
        cache[key] = value
        return value

    def compute(node, socket):
        t = node.type
        if t == "ShaderNodeNewGeometry":
            return {"Normal": normal, "Incoming": incoming}[socket].astype(np.float32)
        if t == "ShaderNodeMath":
            a, b, c = (_flt(input_value(node, i), m) for i in range(3))
            return MATH[node.props["operation"]](a, b, c).astype(np.float32)
        if t == "ShaderNodeVectorMath":
            a, b, c = (_vec(input_value(node, i), m) for i in range(3))
            s = _flt(input_value(node, 3, 1.0), m)
            vector, value = VMATH[node.props["operation"]](a, b, c, s)
            return vector if socket == 0 else value
        if t == "ShaderNodeCombineXYZ":
            return np.stack([_flt(input_value(node, i), m) for i in range(3)], axis=1)
        if t == "ShaderNodeTexImage":
            assert node.props["interpolation"] in ("Closest", "Linear") and node.props["extension"] == "EXTEND"
            texels = images[node.props["image"]]
            h, w = texels.shape[:2]
            uv = _vec(input_value(node, 0), m)
            if node.props["interpolation"] == "Closest":
                x = np.clip(np.floor(uv[:, 0] * w).astype(int), 0, w - 1)
                y = np.clip(np.floor(uv[:, 1] * h).astype(int), 0, h - 1)
                return texels[y, x]
            # Linear as Cycles filters on the CPU: texel centres at (i + 0.5)/W, weights in float,
            # EXTEND repeating the edge texels.
            x, y = uv[:, 0] * np.float32(w) - np.float32(0.5), uv[:, 1] * np.float32(h) - np.float32(0.5)
            x0, y0 = np.floor(x), np.floor(y)
            tx, ty = (x - x0)[:, None], (y - y0)[:, None]
            xi = [np.clip(x0.astype(int) + d, 0, w - 1) for d in (0, 1)]
            yi = [np.clip(y0.astype(int) + d, 0, h - 1) for d in (0, 1)]
            bottom = texels[yi[0], xi[0]] * (1 - tx) + texels[yi[0], xi[1]] * tx
            top = texels[yi[1], xi[0]] * (1 - tx) + texels[yi[1], xi[1]] * tx
            return (bottom * (1 - ty) + top * ty).astype(np.float32)
        if t == "ShaderNodeEmission":
            colour = _vec(input_value(node, "Color"), m)
            return {"emission": colour * _flt(input_value(node, "Strength", 1.0), m)[:, None]}
        if t == "ShaderNodeBsdfGlossy":
            kind = f"glossy_{node.props['distribution'].lower()}"
            return {kind: _vec(input_value(node, "Color"), m),
                    kind + "_roughness": _flt(input_value(node, "Roughness"), m)}
        if t == "ShaderNodeShaderToRGB":
            # Lighting is the renderer's: without lights the lit colour is 0 (the graph around it
            # is still evaluated, so its nodes must be known).
            input_value(node, "Shader", {})
            return np.zeros((m, 3), dtype=np.float32)
        if t == "ShaderNodeAddShader":
            total = {}
            for part in (input_value(node, 0, {}), input_value(node, 1, {})):
                for k, v in part.items():
                    total[k] = total[k] + v if k in total and not k.endswith("roughness") else v
            return total
        raise NotImplementedError(t)

    return {name: output_value_for_group(links, name, output_value) for name, _ in graph.outputs}


def output_value_for_group(links, name, output_value):
    src = links.get(("GROUP_OUTPUT", name))
    return None if src is None else output_value(src.node, src.socket)
