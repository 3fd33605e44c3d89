// OSL shader for Blender's Script node (Cycles, OSL on): the same atlas lookup as the add-on's
// node group (blender.h), with texture() at texel centres and trilinear interpolation in code.
//
// The source is kept to the part of OSL that is also C++ with a small shim header (types color,
// vector, string; builtins dot, cross, length, normalize, acos, atan2, sqrt, floor, clamp, max, mix, texture,
// emission, reflection): tests/blender/test_osl_shader.py compiles the generated text as C++ and
// checks it against libbrdf at random angles, since Debian has no oslc. Hence: no output
// parameters in functions, no OSL-only syntax outside the shader's own parameter list.
#include <cstdio>
#include <sstream>

#include "exporters/blender.h"

namespace libbrdf::blender {

namespace {
std::string number(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  std::string text = buffer;
  if (text.find_first_of(".eEn") == std::string::npos) text += ".0";  // a float literal in both languages
  return text;
}

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char ch : text) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += ch;
  }
  return out + "\"";
}
}  // namespace

std::string osl_shader_source(const BlenderAtlas& a, const std::string& shader_name, const std::string& atlas_path,
                              const std::string& header_comment) {
  std::ostringstream o;
  std::istringstream comment(header_comment);
  for (std::string line; std::getline(comment, line);) o << "// " << line << "\n";
  o << "//\n"
       "// Inputs: LightDirection = unit vector towards the sun (world space), SunStrength (W/m^2) and\n"
       "// SunColor of the sun lamp. Outputs: BSDF = Radiance * emission() + SpecularWeight * reflection(N),\n"
       "// Radiance = f_r * cos(theta_i) * SunStrength * SunColor, SpecularWeight = R_spec(theta_v).\n"
       "// Atlas layout and axis mapping: libbrdf exporters/include/exporters/blender.h.\n\n";
  o << "#define LIBBRDF_PI 3.14159265358979323846\n"
       "#define LIBBRDF_HALF_PI 1.57079632679489661923\n";
  o << "#define LIBBRDF_N0 " << number(a.shape[0]) << "  // theta_h nodes (square map)\n";
  o << "#define LIBBRDF_N1 " << number(a.shape[1]) << "  // theta_d nodes\n";
  o << "#define LIBBRDF_N2 " << number(a.shape[2]) << "  // phi_d nodes (tiles)\n";
  o << "#define LIBBRDF_COLUMNS " << number(a.columns) << "  // tiles per atlas row\n";
  o << "#define LIBBRDF_WIDTH " << number(a.width) << "\n";
  o << "#define LIBBRDF_HEIGHT " << number(a.height) << "\n";
  o << "#define LIBBRDF_SPEC_NODES " << number(a.specular_nodes) << "  // R_spec nodes over [0, 90] deg\n";
  o << "#define LIBBRDF_SPEC_ROW " << number(a.specular_row) << "  // R_spec row, counted from the bottom\n\n";
  o << R"OSL(// Texel (x, y), y counted from the bottom row, sampled at its centre (OSL's t runs from the top).
color libbrdf_texel(string atlas, float x, float y)
{
    return (color) texture(atlas, (x + 0.5) / LIBBRDF_WIDTH, 1.0 - (y + 0.5) / LIBBRDF_HEIGHT,
                           0.0, 0.0, 0.0, 0.0, "interp", "closest", "wrap", "clamp");
}

// Table node (i0 theta_h, i1 theta_d, k phi_d).
color libbrdf_node(string atlas, float i0, float i1, float k)
{
    float tile_row = floor((k + 0.5) / LIBBRDF_COLUMNS);
    float tile_column = k - tile_row * LIBBRDF_COLUMNS;
    return libbrdf_texel(atlas, tile_column * LIBBRDF_N0 + i0, tile_row * LIBBRDF_N1 + i1);
}

// f_r (1/sr, per channel) for unit N, L (towards the light) and V (towards the viewer).
color libbrdf_brdf(string atlas, vector Nn, vector Ln, vector Vn)
{
    vector H = normalize(Ln + Vn);
    // Angles as atan2(|a x b|, a.b): exact near 0, where acos of a float loses the peak.
    float sin_h = length(cross(Nn, H));
    float sin_d = length(cross(Ln, H));
    float cos_h = dot(Nn, H);
    float cos_d = dot(Ln, H);
    float theta_h = atan2(sin_h, cos_h);
    float theta_d = atan2(sin_d, cos_d);
    // Spherical triangle (N, H, L) in MERL's half-vector frame; phi_d is arbitrary when H = N or L = H.
    float cos_phi = clamp((cos_h * cos_d - dot(Nn, Ln)) / max(sin_h * sin_d, 1e-7), -1.0, 1.0);
    float u0 = sqrt(theta_h / LIBBRDF_HALF_PI) * (LIBBRDF_N0 - 1.0);
    float u1 = theta_d / LIBBRDF_HALF_PI * (LIBBRDF_N1 - 1.0);
    float u2 = acos(cos_phi) / LIBBRDF_PI * (LIBBRDF_N2 - 1.0);
    float i0 = clamp(floor(u0), 0.0, LIBBRDF_N0 - 2.0);
    float i1 = clamp(floor(u1), 0.0, LIBBRDF_N1 - 2.0);
    float i2 = clamp(floor(u2), 0.0, LIBBRDF_N2 - 2.0);
    float t0 = clamp(u0 - i0, 0.0, 1.0);
    float t1 = clamp(u1 - i1, 0.0, 1.0);
    float t2 = clamp(u2 - i2, 0.0, 1.0);
    color c00 = mix(libbrdf_node(atlas, i0, i1, i2), libbrdf_node(atlas, i0 + 1.0, i1, i2), t0);
    color c10 = mix(libbrdf_node(atlas, i0, i1 + 1.0, i2), libbrdf_node(atlas, i0 + 1.0, i1 + 1.0, i2), t0);
    color c01 = mix(libbrdf_node(atlas, i0, i1, i2 + 1.0), libbrdf_node(atlas, i0 + 1.0, i1, i2 + 1.0), t0);
    color c11 = mix(libbrdf_node(atlas, i0, i1 + 1.0, i2 + 1.0), libbrdf_node(atlas, i0 + 1.0, i1 + 1.0, i2 + 1.0), t0);
    return mix(mix(c00, c10, t1), mix(c01, c11, t1), t2);
}

// R_spec(theta) of the specular spike (theta in radians), linear between its nodes.
color libbrdf_specular(string atlas, float theta)
{
    float position = theta / LIBBRDF_HALF_PI * (LIBBRDF_SPEC_NODES - 1.0);  // not u, v: OSL globals
    float j = clamp(floor(position), 0.0, LIBBRDF_SPEC_NODES - 2.0);
    float fraction = clamp(position - j, 0.0, 1.0);
    return mix(libbrdf_texel(atlas, j, LIBBRDF_SPEC_ROW), libbrdf_texel(atlas, j + 1.0, LIBBRDF_SPEC_ROW), fraction);
}

)OSL";
  o << "shader " << shader_name << "(\n"
    << "    string Atlas = " << quoted(atlas_path) << ",\n";
  o << R"OSL(    vector LightDirection = vector(0.0, 0.0, 1.0),
    float SunStrength = 1.0,
    color SunColor = color(1.0, 1.0, 1.0),
    output closure color BSDF = 0,
    output color Radiance = color(0.0, 0.0, 0.0),
    output color SpecularWeight = color(0.0, 0.0, 0.0))
{
    vector Nn = normalize(N);
    vector Vn = normalize(-I);
    vector Ln = normalize(LightDirection);
    float cos_i = dot(Nn, Ln);
    float cos_s = dot(Nn, Vn);
    Radiance = color(0.0, 0.0, 0.0);
    if (cos_i > 0.0 && cos_s > 0.0)
        Radiance = libbrdf_brdf(Atlas, Nn, Ln, Vn) * (cos_i * SunStrength) * SunColor;
    SpecularWeight = libbrdf_specular(Atlas, atan2(length(cross(Nn, Vn)), max(cos_s, 0.0)));
    BSDF = Radiance * emission() + SpecularWeight * reflection(Nn);
}
)OSL";
  return o.str();
}

}  // namespace libbrdf::blender
