"""Node graphs of the libbrdf materials as plain data (no bpy): blender_nodes.py instantiates them,
tests interpret them (tests/blender/graph_interpreter.py) without Blender.

A Graph is a list of Node(id, type, props, inputs) and links (from node, output) -> (to node,
input); sockets are named by index (Math nodes have three inputs called "Value") or by name.
Group sockets: node ids "GROUP_INPUT" / "GROUP_OUTPUT", sockets by name.

LUT graph, factored form (the ASF models mbk, mbk-fg, bk, bk-modified; exporters/include/exporters/
blender.h, kernel): f = K(theta_i) F(theta_d) P~(theta_h, theta_d, phi_d) C (pi l_c^2/lambda^2) Sigma(g, c)
  g = g_scale (N.L + N.V)^2, c = c_scale |N x (L + V)|^2 per channel (dot products, no angles);
  Sigma from the universal Sigma image S(x = ln g, z = sqrt(c/(g+1))), bilinear from 4 Closest
  fetches: ln Sigma = S + x - ln(1 + g^2) - z^2; P~ trilinear in its atlas (theta_h uniform),
  K(theta_i), F(theta_d), R_spec(theta_v) linear in the side rows; C = 1, F_bk^2 or 1/S.
LUT graph, rusinkiewicz atlas (the other models): the lookup of blender.h in shader nodes:
  theta_h = atan2(|N x H|, N.H), theta_d = atan2(|L x H|, L.H)       (atan2: exact near 0)
  cos phi_d = (cos theta_h cos theta_d - N.L) / (sin theta_h sin theta_d), clamped to [-1, 1]
  u0 = sqrt(theta_h / (pi/2)) (N0-1),  u1 = theta_d / (pi/2) (N1-1),  u2 = phi_d / pi (N2-1)
  trilinear between the 8 nodes around (u0, u1, u2), each fetched with Closest interpolation at
  its texel centre ((x + 0.5)/W, (y + 0.5)/H): no filtering or mip level can mix tiles (EEVEE).
Both: N = shading normal, V = Incoming (towards the viewer), L = group input "Light Direction";
  Radiance = f_r cos(theta_i) E_sun C_sun for N.L > 0 and N.V > 0, emitted; plus a sharp Glossy
  weighted by R_spec(theta_v), theta_v = atan2(|N x V|, N.V), linear between the R_spec nodes.
  One group instance per Sun lamp (blender_nodes.attach_extra_suns): their radiances add.
"""

import dataclasses
import math
import os

GROUP_INPUT = "GROUP_INPUT"
GROUP_OUTPUT = "GROUP_OUTPUT"

# Group interface of every libbrdf node group: (name, socket type, default).
LIGHT_INPUTS = (
    ("Light Direction", "NodeSocketVector", (0.0, 0.0, 1.0)),
    ("Sun Strength", "NodeSocketFloat", 1.0),
    ("Sun Color", "NodeSocketColor", (1.0, 1.0, 1.0, 1.0)),
)
SHADER_OUTPUT = ("Shader", "NodeSocketShader")
# The specular spike's mirror lobe: GGX at roughness 1e-3 (alpha^2 = 1e-12). Cycles takes any
# alpha^2 <= 1e-7 as a perfect mirror; EEVEE gives NaN pixels at exactly 0 (Blender 3.4, seen in
# tests/blender/test_blender_render.py --engine BLENDER_EEVEE), not at 1e-3.
MIRROR_ROUGHNESS = 1e-3
# EEVEE's FIT output: at 1e-3 a sun of Blender's default size gave one NaN pixel at the mirror
# direction (tests/blender/test_blender_fit.py); 0.02 is still a mirror at EEVEE's resolution.
EEVEE_MIRROR_ROUGHNESS = 0.02


@dataclasses.dataclass
class Node:
    id: str
    type: str                    # bl_idname, e.g. "ShaderNodeMath"
    props: dict = dataclasses.field(default_factory=dict)    # e.g. {"operation": "ADD"}
    inputs: dict = dataclasses.field(default_factory=dict)   # socket -> constant default
    label: str = ""


@dataclasses.dataclass(frozen=True)
class Out:
    """An output socket: node id and output (index or name)."""
    node: str
    socket: object = 0


@dataclasses.dataclass
class Graph:
    name: str
    inputs: list = dataclasses.field(default_factory=list)    # (name, socket type, default)
    outputs: list = dataclasses.field(default_factory=list)   # (name, socket type)
    nodes: list = dataclasses.field(default_factory=list)
    links: list = dataclasses.field(default_factory=list)     # (Out, to node id, to socket)
    images: dict = dataclasses.field(default_factory=dict)    # image key -> absolute file path
    notes: dict = dataclasses.field(default_factory=dict)

    def node(self, node_id):
        for n in self.nodes:
            if n.id == node_id:
                return n
        raise KeyError(node_id)


class _Builder:
    """Adds nodes and links; arguments are constants or Out sockets. `filtered`: table lookups
    through the renderer's own bilinear filtering (Linear interpolation, one fetch per 2 x 2 nodes:
    Cycles, which filters in float precision); else Closest fetches of each node and the
    interpolation in nodes (EEVEE, whose GPU filtering has 8-bit weights and mip levels)."""

    def __init__(self, graph, filtered=False):
        self.g = graph
        self.count = 0
        self.filtered = filtered

    def add(self, type_, props=None, label=""):
        self.count += 1
        node = Node(f"{type_.replace('ShaderNode', '')}.{self.count:03d}", type_, dict(props or {}), {}, label)
        self.g.nodes.append(node)
        return node

    def connect(self, node, socket, value):
        if isinstance(value, Out):
            self.g.links.append((value, node.id, socket))
        elif value is not None:
            node.inputs[socket] = value

    def math(self, op, a, b=None, c=None, label=""):
        n = self.add("ShaderNodeMath", {"operation": op}, label)
        for i, v in enumerate((a, b, c)):
            self.connect(n, i, v)
        return Out(n.id, 0)

    def vmath(self, op, a, b=None, c=None, scale=None, label="", out=0):
        n = self.add("ShaderNodeVectorMath", {"operation": op}, label)
        for i, v in enumerate((a, b, c, scale)):
            self.connect(n, i, v)
        return Out(n.id, out)

    def dot(self, a, b, label=""):
        return self.vmath("DOT_PRODUCT", a, b, label=label, out=1)

    def length(self, a):
        return self.vmath("LENGTH", a, out=1)

    def clamp(self, x, lo, hi):
        return self.math("MINIMUM", self.math("MAXIMUM", x, lo), hi)

    def combine(self, x, y, z=0.0):
        n = self.add("ShaderNodeCombineXYZ")
        for i, v in enumerate((x, y, z)):
            self.connect(n, i, v)
        return Out(n.id, 0)

    def lerp(self, a, b, t):
        """a + t (b - a) on colours/vectors (t a float: broadcast by Blender's implicit conversion)."""
        return self.vmath("MULTIPLY_ADD", self.vmath("SUBTRACT", b, a), t, a)

    def split(self, u, nodes):
        """Cell index i = clamp(floor(u), 0, nodes - 2) and fraction t = clamp(u - i, 0, 1)."""
        i = self.clamp(self.math("FLOOR", u), 0.0, float(nodes - 2))
        t = self.clamp(self.math("SUBTRACT", u, i), 0.0, 1.0)
        return i, t

    def angle(self, a, b):
        """Angle between unit vectors a, b: atan2(|a x b|, a.b)."""
        return self.math("ARCTAN2", self.length(self.vmath("CROSS_PRODUCT", a, b)), self.dot(a, b))

    def texel(self, image_key, uv, label="", interpolation="Closest"):
        n = self.add("ShaderNodeTexImage", {"image": image_key, "interpolation": interpolation,
                                            "extension": "EXTEND"}, label)
        self.connect(n, 0, uv)
        return Out(n.id, 0)

    def bilinear(self, image_key, x, y, width, height, label=""):
        """The image bilinear at texel position (x, y) (node index units, texel centres at integers),
        one Linear fetch at ((x + 0.5)/W, (y + 0.5)/H). Callers keep x, y inside one tile."""
        uv = self.combine(self.math("DIVIDE", self.math("ADD", x, 0.5), float(width)),
                          self.math("DIVIDE", self.math("ADD", y, 0.5), float(height)))
        return self.texel(image_key, uv, label=label, interpolation="Linear")


def _group(name):
    return Graph(name=name, inputs=list(LIGHT_INPUTS),
                 outputs=[SHADER_OUTPUT, ("Radiance", "NodeSocketColor"), ("Specular Weight", "NodeSocketColor")])


def _half_difference(b, n_vec, l_vec, v_vec):
    """The dot products and half/difference angles of (N, L, V) (blender.h): H = normalize(L + V),
    theta_h = atan2(|N x H|, N.H), theta_d = atan2(|L x H|, L.H) (exact near 0, where acos of a
    float loses the peak); cos phi_d by spherical trigonometry in the triangle (N, H, L), any phi_d
    where H = N or L = H (the denominator vanishes and the tables do not depend on phi_d)."""
    h_vec = b.vmath("NORMALIZE", b.vmath("ADD", l_vec, v_vec), label="H")
    a = {"H": h_vec, "cos_i": b.dot(n_vec, l_vec, label="cos theta_i"), "cos_s": b.dot(n_vec, v_vec, label="cos theta_s")}
    a["cos_h"], a["cos_d"] = b.dot(n_vec, h_vec, label="cos theta_h"), b.dot(l_vec, h_vec, label="cos theta_d")
    sin_h = b.length(b.vmath("CROSS_PRODUCT", n_vec, h_vec))
    sin_d = b.length(b.vmath("CROSS_PRODUCT", l_vec, h_vec))
    a["theta_h"] = b.math("ARCTAN2", sin_h, a["cos_h"], label="theta_h")
    a["theta_d"] = b.math("ARCTAN2", sin_d, a["cos_d"], label="theta_d")
    numerator = b.math("SUBTRACT", b.math("MULTIPLY", a["cos_h"], a["cos_d"]), a["cos_i"])
    denominator = b.math("MAXIMUM", b.math("MULTIPLY", sin_h, sin_d), 1e-7)
    a["phi_d"] = b.math("ARCCOSINE", b.clamp(b.math("DIVIDE", numerator, denominator), -1.0, 1.0), label="phi_d")
    return a


def _atlas_trilinear(b, image_key, atlas, u0, u1, u2):
    """Trilinear interpolation between the 8 atlas nodes around (u0, u1, u2) (node index units),
    each fetched with Closest interpolation at its texel centre (blender.h: tile k at column k % C,
    tile row k / C; texel x = column N0 + i0, y = tile row N1 + i1 from the bottom)."""
    n0, n1, n2 = atlas["theta_h"]["nodes"], atlas["theta_d"]["nodes"], atlas["phi_d"]["nodes"]
    columns, width, height = atlas["columns"], atlas["width"], atlas["height"]
    i0, t0 = b.split(u0, n0)
    i1, t1 = b.split(u1, n1)
    i2, t2 = b.split(u2, n2)
    inv_size = (1.0 / width, 1.0 / height, 0.0)
    tiles = []
    for dk in (0.0, 1.0):
        k = b.math("ADD", i2, dk) if dk else i2
        tile_row = b.math("FLOOR", b.math("DIVIDE", b.math("ADD", k, 0.5), float(columns)))
        tile_column = b.math("SUBTRACT", k, b.math("MULTIPLY", tile_row, float(columns)))
        if b.filtered:  # i + t stays in [i, i + 1] inside the tile: the filter never reaches the next tile
            x = b.math("MULTIPLY_ADD", tile_column, float(n0), b.math("ADD", i0, t0))
            y = b.math("MULTIPLY_ADD", tile_row, float(n1), b.math("ADD", i1, t1))
            tiles.append(b.bilinear(image_key, x, y, width, height, label=f"nodes i0, i1 bilinear, k+{int(dk)}"))
            continue
        x = b.math("MULTIPLY_ADD", tile_column, float(n0), b.math("ADD", i0, 0.5))
        y = b.math("MULTIPLY_ADD", tile_row, float(n1), b.math("ADD", i1, 0.5))
        base = b.vmath("MULTIPLY", b.combine(x, y), inv_size)
        corner = {}
        for da in (0, 1):
            for db in (0, 1):
                uv = b.vmath("ADD", base, (da / width, db / height, 0.0)) if (da or db) else base
                corner[da, db] = b.texel(image_key, uv, label=f"node i0+{da} i1+{db} k+{int(dk)}")
        along_h0 = b.lerp(corner[0, 0], corner[1, 0], t0)
        along_h1 = b.lerp(corner[0, 1], corner[1, 1], t0)
        tiles.append(b.lerp(along_h0, along_h1, t1))
    return b.lerp(tiles[0], tiles[1], t2)


def _row(b, image_key, theta, nodes, row, width, height, label):
    """A table row over theta = (pi/2) j/(nodes-1) (texels x = j, y = row from the bottom), linear."""
    j, tj = b.split(b.math("MULTIPLY", theta, (nodes - 1) / (math.pi / 2)), nodes)
    if b.filtered:
        return b.bilinear(image_key, b.math("ADD", j, tj), float(row), width, height, label=f"{label} linear")
    uv0 = b.combine(b.math("DIVIDE", b.math("ADD", j, 0.5), float(width)), (row + 0.5) / height)
    uv1 = b.vmath("ADD", uv0, (1.0 / width, 0.0, 0.0))
    return b.lerp(b.texel(image_key, uv0, label=f"{label} j"), b.texel(image_key, uv1, label=f"{label} j+1"), tj)


def _geometry_vectors(b):
    geometry = b.add("ShaderNodeNewGeometry")
    n_vec = b.vmath("NORMALIZE", Out(geometry.id, "Normal"), label="N")
    v_vec = b.vmath("NORMALIZE", Out(geometry.id, "Incoming"), label="V")
    l_vec = b.vmath("NORMALIZE", Out(GROUP_INPUT, "Light Direction"), label="L")
    return n_vec, l_vec, v_vec


def _atlas_graph(description, images, layout, image_key, atlas, filtered):
    """A LUT group's start: the geometry, the half/difference angles and the atlas' trilinear
    value at them (theta_h square-mapped for rusinkiewicz, uniform for the kernel's P~)."""
    n0, n1, n2 = atlas["theta_h"]["nodes"], atlas["theta_d"]["nodes"], atlas["phi_d"]["nodes"]
    g = _group(f"libbrdf {description['name']}")
    g.images.update(images)
    g.notes.update(mode="LUT", layout=layout, shape=(n0, n1, n2))
    b = _Builder(g, filtered=filtered)
    vectors = _geometry_vectors(b)
    a = _half_difference(b, *vectors)
    fraction = b.math("DIVIDE", a["theta_h"], math.pi / 2)
    u0 = b.math("MULTIPLY", b.math("SQRT", fraction) if layout == "rusinkiewicz" else fraction, float(n0 - 1), label="u theta_h")
    u1 = b.math("MULTIPLY", a["theta_d"], (n1 - 1) / (math.pi / 2), label="u theta_d")
    u2 = b.math("MULTIPLY", a["phi_d"], (n2 - 1) / math.pi, label="u phi_d")
    return g, b, vectors, a, _atlas_trilinear(b, image_key, atlas, u0, u1, u2)


def _lit_radiance(b, brdf, a):
    """Radiance = f_r cos(theta_i) E_sun C_sun where N.L > 0 and N.V > 0, else 0."""
    lit = b.math("MULTIPLY", b.math("GREATER_THAN", a["cos_i"], 0.0), b.math("GREATER_THAN", a["cos_s"], 0.0))
    scale = b.math("MULTIPLY", b.math("MULTIPLY", a["cos_i"], lit), Out(GROUP_INPUT, "Sun Strength"))
    return b.vmath("MULTIPLY", b.vmath("SCALE", brdf, scale=scale), Out(GROUP_INPUT, "Sun Color"), label="Radiance")


def lut_graph(description, images):
    """The LUT-mode node group for a description (dict from core.load_description); `images` maps
    the image keys of the description's layout to absolute paths (graph_images).
    Two evaluations of the same tables in one group: "Shader" / "Radiance" / "Specular Weight"
    through Linear (bilinear) fetches for Cycles, which filters in float precision: 8 fetches in
    place of 26 and half the render time per sample (tools/bench/renderer_cost.py); "EEVEE Shader" /
    "EEVEE Radiance" through Closest fetches interpolated in nodes, for EEVEE, whose GPU filter has
    8-bit weights and mip levels. Each engine compiles only the nodes its own output reaches
    (blender_nodes.attach_group gives each its Material Output)."""
    cycles = _lut_graph_one(description, images, filtered=True)
    eevee = _lut_graph_one(description, images, filtered=False)
    cycles.outputs += [EEVEE_SHADER_OUTPUT, EEVEE_RADIANCE_OUTPUT]
    renamed = {"Shader": EEVEE_SHADER_OUTPUT[0], "Radiance": EEVEE_RADIANCE_OUTPUT[0]}
    prefix = "EEVEE."
    for node in eevee.nodes:
        node.id = prefix + node.id
        cycles.nodes.append(node)
    for source, to_node, to_socket in eevee.links:
        if to_node == GROUP_OUTPUT and to_socket not in renamed:
            continue  # one Specular Weight output (the same rows in both)
        source = source if source.node == GROUP_INPUT else Out(prefix + source.node, source.socket)
        if to_node == GROUP_OUTPUT:
            cycles.links.append((source, GROUP_OUTPUT, renamed[to_socket]))
        else:
            cycles.links.append((source, prefix + to_node, to_socket))
    return cycles


def _lut_graph_one(description, images, filtered):
    """One LUT evaluation (lut_graph): filtered (Linear fetches) or not (Closest)."""
    if description["lut"].get("layout") == "kernel":
        return _kernel_lut_graph(description, images, filtered)
    lut = description["lut"]
    width, height = lut["width"], lut["height"]
    spec_nodes, spec_row = lut["specular"]["nodes"], lut["specular"]["row"]

    g, b, (n_vec, l_vec, v_vec), a, brdf = _atlas_graph(description, images, "rusinkiewicz", "atlas", lut, filtered)
    radiance = _lit_radiance(b, brdf, a)

    # R_spec(theta_v) of the specular spike (row spec_row, nodes over [0, 90] deg).
    spec = _row(b, "atlas", b.angle(n_vec, v_vec), spec_nodes, spec_row, width, height, "R_spec")
    spec = b.vmath("SCALE", spec, scale=b.math("GREATER_THAN", a["cos_s"], 0.0), label="R_spec")  # none from behind
    _finish(b, g, radiance, spec)
    return g


def _kernel_sigma(b, image_key, sigma, g_value, c_value, channel):
    """Sigma(g, c) of eq. 11 from the Sigma image (blender.h): S bilinear at x = ln g, z = sqrt(c/(g+1))
    (4 Closest fetches), then Sigma = exp(S + x - ln(1 + g^2) - z^2)."""
    width, height, x_min, dx, dz = sigma["width"], sigma["height"], sigma["x_min"], sigma["dx"], sigma["dz"]
    x_max, z_max = x_min + (width - 1) * dx, (height - 1) * dz
    x = b.math("LOGARITHM", b.math("MAXIMUM", g_value, 1e-30), math.e, label=f"x = ln g ({channel})")
    z2 = b.math("DIVIDE", c_value, b.math("ADD", g_value, 1.0), label=f"z^2 = c/(g+1) ({channel})")
    ux = b.math("DIVIDE", b.math("SUBTRACT", b.clamp(x, x_min, x_max), x_min), dx)
    uz = b.math("DIVIDE", b.math("MINIMUM", b.math("SQRT", z2), z_max), dz)
    i, tx = b.split(ux, width)
    j, tz = b.split(uz, height)
    if b.filtered:
        s = b.bilinear(image_key, b.math("ADD", i, tx), b.math("ADD", j, tz), width, height, label=f"S bilinear ({channel})")
        return _ln_sigma_to_sigma(b, s, x, g_value, z2, channel)
    base = b.combine(b.math("DIVIDE", b.math("ADD", i, 0.5), float(width)), b.math("DIVIDE", b.math("ADD", j, 0.5), float(height)))
    corner = {}
    for da in (0, 1):
        for db in (0, 1):
            uv = b.vmath("ADD", base, (da / width, db / height, 0.0)) if (da or db) else base
            corner[da, db] = b.texel(image_key, uv, label=f"S i+{da} j+{db} ({channel})")
    s = b.lerp(b.lerp(corner[0, 0], corner[1, 0], tx), b.lerp(corner[0, 1], corner[1, 1], tx), tz)
    return _ln_sigma_to_sigma(b, s, x, g_value, z2, channel)


def _ln_sigma_to_sigma(b, s, x, g_value, z2, channel):
    """Sigma = exp(S + x - ln(1 + g^2) - z^2) from the image's S (R = G = B)."""
    s = b.dot(s, (1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0))
    log_one_g2 = b.math("LOGARITHM", b.math("MULTIPLY_ADD", g_value, g_value, 1.0), math.e)
    ln_sigma = b.math("SUBTRACT", b.math("SUBTRACT", b.math("ADD", s, x), log_one_g2), z2, label=f"ln Sigma ({channel})")
    return b.math("EXPONENT", ln_sigma, label=f"Sigma ({channel})")


def _kernel_lut_graph(description, images, filtered):
    """LUT mode of the ASF models: the factored form (exporters/include/exporters/blender.h, kernel)
      f = K(theta_i) F(theta_d) P~(theta_h, theta_d, phi_d) C (pi l_c^2/lambda^2) Sigma(g, c),
      g = g_scale (N.L + N.V)^2 (eq. 12), c = c_scale |N x (L + V)|^2 (eq. 10), per channel;
    P~ trilinear in its atlas (theta_h uniform), K, F and R_spec linear in the side rows, Sigma from
    the universal Sigma image; C = 1, F_bk^2 (eq. 27) or 1/S (eq. 28) from dot products."""
    lut = description["lut"]
    side, sigma = lut["side"], lut["sigma"]
    g, b, (n_vec, l_vec, v_vec), a, angular_factor = _atlas_graph(description, images, "kernel", "angular", lut["angular"], filtered)

    nodes, width, height = side["width"], side["width"], side["height"]
    rows = side["rows"]
    theta_i = b.angle(n_vec, l_vec)
    k = _row(b, "side", theta_i, nodes, rows["k"], width, height, "K")
    fresnel = _row(b, "side", a["theta_d"], nodes, rows["fresnel"], width, height, "F")

    total = b.math("ADD", a["cos_i"], a["cos_s"], label="N.L + N.V")
    total2 = b.math("MULTIPLY", total, total)
    tangential = b.vmath("CROSS_PRODUCT", n_vec, b.vmath("ADD", l_vec, v_vec))
    eta2 = b.dot(tangential, tangential, label="eta_r^2")
    channels = lut["kernel_channels"]
    sigma_rgb = []
    for c, name in enumerate("RGB"):
        g_value = b.math("MULTIPLY", total2, channels[c]["g_scale"], label=f"g ({name})")
        c_value = b.math("MULTIPLY", eta2, channels[c]["c_scale"], label=f"c ({name})")
        sigma_rgb.append(b.math("MULTIPLY", _kernel_sigma(b, "sigma", sigma, g_value, c_value, name),
                                channels[c]["prefactor"]))
    brdf = b.vmath("MULTIPLY", b.vmath("MULTIPLY", k, fresnel), b.vmath("MULTIPLY", angular_factor, b.combine(*sigma_rgb)))
    closed = lut.get("closed_form", "none")
    if closed != "none":
        # F_bk^2 = (L.H)^2 / ((N.L)^2 (N.H)^2) (eq. 27) or 1/S = (L.H)^2 / ((N.L)(N.V)(N.H)^2) (eq. 28).
        cos_d2 = b.math("MULTIPLY", a["cos_d"], a["cos_d"])
        cos_h2 = b.math("MULTIPLY", a["cos_h"], a["cos_h"])
        other = a["cos_i"] if closed == "bk_eq27" else a["cos_s"]
        denominator = b.math("MAXIMUM", b.math("MULTIPLY", b.math("MULTIPLY", a["cos_i"], other), cos_h2), 1e-30)
        brdf = b.vmath("SCALE", brdf, scale=b.math("DIVIDE", cos_d2, denominator), label=closed)
    radiance = _lit_radiance(b, brdf, a)
    spec = _row(b, "side", b.angle(n_vec, v_vec), nodes, rows["r_spec"], width, height, "R_spec")
    spec = b.vmath("SCALE", spec, scale=b.math("GREATER_THAN", a["cos_s"], 0.0), label="R_spec")  # none from behind
    _finish(b, g, radiance, spec)
    return g


def graph_images(description, description_path):
    """{image key: absolute path} of a LUT/OSL description's images (beside the description)."""
    directory = os.path.dirname(os.path.abspath(description_path))
    lut = description["lut"]
    if lut.get("layout") == "kernel":
        return {"side": os.path.join(directory, lut["side"]["file"]),
                "angular": os.path.join(directory, lut["angular"]["file"]),
                "sigma": os.path.join(directory, lut["sigma"]["file"])}
    return {"atlas": os.path.join(directory, lut["file"])}


def _finish(b, g, radiance, spec_weight):
    """Emission(radiance) + sharp Glossy(spec_weight) -> Shader; also the colour outputs."""
    emission = b.add("ShaderNodeEmission")
    b.connect(emission, "Color", radiance)
    b.connect(emission, "Strength", 1.0)
    mirror = b.add("ShaderNodeBsdfGlossy", {"distribution": "GGX"}, label="specular spike")
    b.connect(mirror, "Color", spec_weight)
    b.connect(mirror, "Roughness", MIRROR_ROUGHNESS)
    total = b.add("ShaderNodeAddShader")
    g.links.append((Out(emission.id, 0), total.id, 0))
    g.links.append((Out(mirror.id, 0), total.id, 1))
    g.links.append((Out(total.id, 0), GROUP_OUTPUT, "Shader"))
    g.links.append((radiance, GROUP_OUTPUT, "Radiance"))
    g.links.append((spec_weight, GROUP_OUTPUT, "Specular Weight"))


EEVEE_SHADER_OUTPUT = ("EEVEE Shader", "NodeSocketShader")
EEVEE_RADIANCE_OUTPUT = ("EEVEE Radiance", "NodeSocketColor")  # LUT mode: what extra suns add in EEVEE


def fit_graph(description):
    """FIT mode: the lobes fitted by `brdf export blender --mode fit` (exporters/fit.h), one Glossy
    BSDF each, added; lobe colour per channel sum_k c_k B_k(N.V) (Bernstein basis: the colour follows
    the angle as the model's does); the spike as a sharp Glossy weighted by
    R_spec ~ Schlick(F0, theta_v) exp(-g0 cos^2 theta_v). Output "Shader": the Beckmann lobes, for
    Cycles; "EEVEE Shader": GGX lobes fitted for EEVEE, which renders every distribution as GGX
    (blender_nodes.attach_group gives each its own Material Output target)."""
    fit = description["fit"]
    f0 = _rgb(fit["f0"])
    g0 = _rgb(fit["g0"])
    eevee = fit.get("eevee", {})
    outputs = [SHADER_OUTPUT, ("Specular Weight", "NodeSocketColor")]
    if eevee:
        outputs.append(EEVEE_SHADER_OUTPUT)
    g = Graph(name=f"libbrdf {description['name']} (fit)", inputs=list(LIGHT_INPUTS), outputs=outputs)
    g.notes.update(mode="FIT", lobes=len(fit.get("lobes", [])), error=fit.get("error", {}))
    b = _Builder(g)
    geometry = b.add("ShaderNodeNewGeometry")
    n_vec = b.vmath("NORMALIZE", Out(geometry.id, "Normal"))
    v_vec = b.vmath("NORMALIZE", Out(geometry.id, "Incoming"))
    cos_v = b.clamp(b.dot(n_vec, v_vec), 0.0, 1.0)

    shared, eevee_shared = [], []
    rho_d = float(fit.get("rho_d", 0.0))
    if rho_d > 0.0:
        diffuse = b.add("ShaderNodeBsdfDiffuse")
        b.connect(diffuse, "Color", (rho_d, rho_d, rho_d, 1.0))
        shared.append(Out(diffuse.id, 0))
        eevee_shared.append(Out(diffuse.id, 0))
    if fit.get("has_spike", False):
        schlick_w = b.math("POWER", b.math("SUBTRACT", 1.0, cos_v), 5.0)
        fresnel = b.vmath("MULTIPLY_ADD", tuple(1.0 - f for f in f0), schlick_w, f0, label="Schlick F")
        cos2 = b.math("MULTIPLY", cos_v, cos_v)
        damping = b.combine(*[b.math("EXPONENT", b.math("MULTIPLY", cos2, -g0[c])) for c in range(3)])
        spec = b.vmath("MULTIPLY", fresnel, damping, label="R_spec")
        mirror = b.add("ShaderNodeBsdfGlossy", {"distribution": "GGX"}, label="specular spike")
        b.connect(mirror, "Color", spec)
        b.connect(mirror, "Roughness", MIRROR_ROUGHNESS)
        shared.append(Out(mirror.id, 0))
        g.links.append((spec, GROUP_OUTPUT, "Specular Weight"))
        if eevee:
            eevee_mirror = b.add("ShaderNodeBsdfGlossy", {"distribution": "GGX"}, label="EEVEE specular spike")
            b.connect(eevee_mirror, "Color", spec)
            b.connect(eevee_mirror, "Roughness", EEVEE_MIRROR_ROUGHNESS)
            eevee_shared.append(Out(eevee_mirror.id, 0))
    basis_cache = {}
    cycles = _lobe_shaders(b, fit.get("lobes", []), fit.get("distribution", "beckmann"), cos_v, basis_cache, "",
                           float(fit.get("min_view_cosine", 0.05)))
    g.links.append((_sum_shaders(b, g, cycles + shared), GROUP_OUTPUT, "Shader"))
    if eevee:
        if eevee.get("signed", False):
            lobes = _signed_lobes_emission(b, eevee.get("lobes", []), cos_v, basis_cache)
        else:
            lobes = _lobe_shaders(b, eevee.get("lobes", []), eevee.get("distribution", "ggx"), cos_v, basis_cache, "EEVEE ")
        g.links.append((_sum_shaders(b, g, lobes + eevee_shared), GROUP_OUTPUT, EEVEE_SHADER_OUTPUT[0]))
    return g


def _colour(b, lobe, basis):
    """sum_k c_k B_k(N.V) as a colour (None when every coefficient is 0)."""
    colour = None
    for k in range(len(basis)):
        coefficient = tuple(float(lobe["colour"][c][k]) for c in range(3))
        if not any(coefficient):
            continue
        term = b.vmath("SCALE", coefficient, scale=basis[k])
        colour = term if colour is None else b.vmath("ADD", colour, term)
    return colour


def _basis(b, cos_v, degree, basis_cache):
    if degree not in basis_cache:
        one_minus = b.math("SUBTRACT", 1.0, cos_v)
        basis = []
        for k in range(degree + 1):
            term = b.math("MULTIPLY", b.math("POWER", cos_v, float(k)), b.math("POWER", one_minus, float(degree - k)))
            basis.append(b.math("MULTIPLY", term, float(math.comb(degree, k)), label=f"B{k}(N.V)"))
        basis_cache[degree] = basis
    return basis_cache[degree]


def _signed_lobes_emission(b, lobes, cos_v, basis_cache):
    """EEVEE's lobes: coefficients of either sign (a difference of GGX lobes falls off like MBK's
    Gaussian lobe; fit.h). Blender clamps a negative BSDF colour to 0, so each white GGX lobe is lit
    by EEVEE (every light and probe) and turned into a colour by Shader to RGB, weighted by its
    signed colour, summed, clamped at 0 and emitted."""
    total = None
    for index, lobe in enumerate(lobes):
        basis = _basis(b, cos_v, len(lobe["colour"][0]) - 1, basis_cache)
        colour = _colour(b, lobe, basis)
        if colour is None:
            continue
        glossy = b.add("ShaderNodeBsdfGlossy", {"distribution": "GGX"}, label=f"EEVEE lobe {index + 1}")
        b.connect(glossy, "Color", (1.0, 1.0, 1.0, 1.0))
        b.connect(glossy, "Roughness", float(lobe["roughness"]))
        lit = b.add("ShaderNodeShaderToRGB", label=f"EEVEE lobe {index + 1} lit")
        b.g.links.append((Out(glossy.id, 0), lit.id, "Shader"))
        term = b.vmath("MULTIPLY", Out(lit.id, "Color"), colour)
        total = term if total is None else b.vmath("ADD", total, term)
    if total is None:
        return []
    emission = b.add("ShaderNodeEmission", label="EEVEE lobes")
    b.connect(emission, "Color", b.vmath("MAXIMUM", total, (0.0, 0.0, 0.0), label="clamped at 0"))
    b.connect(emission, "Strength", 1.0)
    return [Out(emission.id, 0)]


def _lobe_shaders(b, lobes, distribution, cos_v, basis_cache, label, min_view_cosine=0.05):
    """One Glossy BSDF per fitted lobe (non-negative colours), colour sum_k c_k B_k(N.V); roughness
    sqrt(alpha(N.V)), alpha(N.V) = min(alpha max(N.V, min_view_cosine)^-alpha_slope, 1) (fit.h,
    lobe_alpha: a polished MBK lobe's width in theta_h goes as 1/cos(theta_d), and N.V = cos(theta_d)
    at its peak), a constant where alpha_slope is 0."""
    shaders = []
    for index, lobe in enumerate(lobes):
        colour = _colour(b, lobe, _basis(b, cos_v, len(lobe["colour"][0]) - 1, basis_cache))
        if colour is None:
            continue
        glossy = b.add("ShaderNodeBsdfGlossy", {"distribution": distribution.upper()}, label=f"{label}lobe {index + 1}")
        b.connect(glossy, "Color", colour)
        slope = float(lobe.get("alpha_slope", 0.0))
        roughness = float(lobe["roughness"])
        if slope != 0.0:
            # sqrt(alpha mu^-slope) = sqrt(alpha) mu^(-slope/2), at most 1.
            follow = b.math("POWER", b.math("MAXIMUM", cos_v, min_view_cosine), -0.5 * slope)
            roughness = b.math("MINIMUM", b.math("MULTIPLY", follow, roughness), 1.0,
                               label=f"{label}lobe {index + 1} roughness(N.V)")
        b.connect(glossy, "Roughness", roughness)
        shaders.append(Out(glossy.id, 0))
    return shaders


def _sum_shaders(b, g, shaders):
    if not shaders:
        black = b.add("ShaderNodeEmission")
        b.connect(black, "Strength", 0.0)
        return Out(black.id, 0)
    total = shaders[0]
    for s in shaders[1:]:
        add = b.add("ShaderNodeAddShader")
        g.links.append((total, add.id, 0))
        g.links.append((s, add.id, 1))
        total = Out(add.id, 0)
    return total


def osl_graph(description, osl_path):
    """OSL mode: one Script node (external file); its sockets appear once Blender compiled it."""
    g = Graph(name=f"libbrdf {description['name']} (osl)", inputs=list(LIGHT_INPUTS),
              outputs=[SHADER_OUTPUT, ("Radiance", "NodeSocketColor"), ("Specular Weight", "NodeSocketColor")])
    g.notes.update(mode="OSL", shader=description["osl"]["shader"])
    b = _Builder(g)
    script = b.add("ShaderNodeScript", {"mode": "EXTERNAL", "filepath": osl_path}, label="libbrdf OSL")
    # The view direction from Blender's own definition (Geometry > Incoming, towards the viewer):
    # the I that Cycles 4.5 and 5.0 give OSL points the other way from OSL's spec.
    geometry = b.add("ShaderNodeNewGeometry")
    # Links to sockets of the compiled script (same names as the shader's parameters).
    g.notes["script_links"] = [
        ((geometry.id, "Incoming"), (script.id, "Incoming")),
        ((GROUP_INPUT, "Light Direction"), (script.id, "LightDirection")),
        ((GROUP_INPUT, "Sun Strength"), (script.id, "SunStrength")),
        ((GROUP_INPUT, "Sun Color"), (script.id, "SunColor")),
        ((script.id, "BSDF"), (GROUP_OUTPUT, "Shader")),
        ((script.id, "Radiance"), (GROUP_OUTPUT, "Radiance")),
        ((script.id, "SpecularWeight"), (GROUP_OUTPUT, "Specular Weight")),
    ]
    g.notes["script_node"] = script.id
    return g


def _rgb(values):
    values = [float(v) for v in values]
    return tuple(values * 3) if len(values) == 1 else tuple(values[:3])


def graph_for(description, description_path):
    """The graph of a description's mode (paths resolved beside the description)."""
    directory = os.path.dirname(os.path.abspath(description_path))
    mode = description["mode"]
    if mode == "lut":
        return lut_graph(description, graph_images(description, description_path))
    if mode == "fit":
        return fit_graph(description)
    if mode == "osl":
        return osl_graph(description, os.path.join(directory, description["osl"]["file"]))
    raise ValueError(f"mode: unknown mode {mode!r} in the description")
