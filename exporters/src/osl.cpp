// OSL shaders for Blender's Script node (Cycles, OSL on): the same lookups as the add-on's node
// groups (blender.h), with texture() at texel centres and the interpolation in code: the
// rusinkiewicz atlas (trilinear), and the kernel form (P~ tricubic, side rows linear, the Sigma
// image bilinear).
//
// The source is kept to the part of OSL that is also C++ with a small shim header (types color,
// vector, string; builtins dot, cross, length, normalize, acos, atan2, sqrt, log, exp, floor, clamp,
// min, max, mix, texture, emission, reflection): tests/blender/test_osl_shader.py compiles the generated text as C++ and
// checks it against libbrdf at random angles, since Debian has no oslc. Hence: no output
// parameters in functions, no OSL-only syntax outside the shader's own parameter list.
#include <cctype>
#include <cstdio>
#include <filesystem>
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
// The shader's light inputs, outputs and body after its image parameters (both forms).
constexpr const char* kShaderTail = R"OSL(    vector LightDirection = vector(0.0, 0.0, 1.0),
    vector Incoming = vector(0.0, 0.0, 0.0),
    float SunStrength = 1.0,
    color SunColor = color(1.0, 1.0, 1.0),
    output closure color BSDF = 0,
    output color Radiance = color(0.0, 0.0, 0.0),
    output color SpecularWeight = color(0.0, 0.0, 0.0))
{
    vector Nn = normalize(N);
    // Towards the viewer: Blender's Geometry > Incoming where linked (Cycles 4.5 and 5.0 hand OSL
    // an I that points towards the viewer, against OSL's spec), else -I (OSL's spec, testshade).
    vector Vn = Incoming != vector(0.0, 0.0, 0.0) ? normalize(Incoming) : normalize(-I);
    vector Ln = normalize(LightDirection);
    float cos_i = dot(Nn, Ln);
    float cos_s = dot(Nn, Vn);
    Radiance = color(0.0, 0.0, 0.0);
    if (cos_i > 0.0 && cos_s > 0.0)
        Radiance = LIBBRDF_BRDF(Nn, Ln, Vn) * (cos_i * SunStrength) * SunColor;
    SpecularWeight = LIBBRDF_SPECULAR(atan2(length(cross(Nn, Vn)), max(cos_s, 0.0)));
    BSDF = Radiance * emission() + SpecularWeight * reflection(Nn);
}
)OSL";

std::string comment_lines(const std::string& header_comment) {
  std::ostringstream o;
  std::istringstream comment(header_comment);
  for (std::string line; std::getline(comment, line);) o << "// " << line << "\n";
  o << "//\n"
       "// Inputs: LightDirection = unit vector towards the sun (world space), Incoming = towards the\n"
       "// viewer (Blender's Geometry > Incoming; zero: -I), SunStrength (W/m^2) and\n"
       "// SunColor of the sun lamp. Outputs: BSDF = Radiance * emission() + SpecularWeight * reflection(N),\n"
       "// Radiance = f_r * cos(theta_i) * SunStrength * SunColor, SpecularWeight = R_spec(theta_v).\n";
  return o.str();
}

// The half/difference angles of (N, L, V) as in the add-on's node group (blender.h): atan2 of
// |a x b| and a.b (exact near 0, where acos of a float loses the peak); phi_d by spherical
// trigonometry in the triangle (N, H, L), arbitrary where H = N or L = H.
constexpr const char* kAnglesOsl = R"OSL(    vector H = normalize(Ln + Vn);
    float sin_h = length(cross(Nn, H));
    float sin_d = length(cross(Ln, H));
    float cos_h = dot(Nn, H);
    float cos_d = dot(Ln, H);
    float theta_h = atan2(sin_h, cos_h);
    float theta_d = atan2(sin_d, cos_d);
    float cos_phi = clamp((cos_h * cos_d - dot(Nn, Ln)) / max(sin_h * sin_d, 1e-7), -1.0, 1.0);
    float phi_d = acos(cos_phi);
)OSL";

// Trilinear interpolation between the 8 atlas nodes around (u0, u1, u2) (node index units).
constexpr const char* kTrilinearOsl = R"OSL(    float i0 = clamp(floor(u0), 0.0, LIBBRDF_N0 - 2.0);
    float i1 = clamp(floor(u1), 0.0, LIBBRDF_N1 - 2.0);
    float i2 = clamp(floor(u2), 0.0, LIBBRDF_N2 - 2.0);
    float t0 = clamp(u0 - i0, 0.0, 1.0);
    float t1 = clamp(u1 - i1, 0.0, 1.0);
    float t2 = clamp(u2 - i2, 0.0, 1.0);
    color c00 = mix(libbrdf_node(atlas, i0, i1, i2), libbrdf_node(atlas, i0 + 1.0, i1, i2), t0);
    color c10 = mix(libbrdf_node(atlas, i0, i1 + 1.0, i2), libbrdf_node(atlas, i0 + 1.0, i1 + 1.0, i2), t0);
    color c01 = mix(libbrdf_node(atlas, i0, i1, i2 + 1.0), libbrdf_node(atlas, i0 + 1.0, i1, i2 + 1.0), t0);
    color c11 = mix(libbrdf_node(atlas, i0, i1 + 1.0, i2 + 1.0), libbrdf_node(atlas, i0 + 1.0, i1 + 1.0, i2 + 1.0), t0);
)OSL";

// Catmull-Rom (tricubic) interpolation of the kernel's P~ over the 4 x 4 x 4 atlas nodes around
// (u0, u1, u2), end nodes repeated at the edges: the interpolation of the C++ table form
// (libbrdf/src/kernel_angular_simd.cpp), which keeps P~ within ~1e-4 where trilinear leaves ~1e-3
// (Cycles OSL renders of rough mbk: median 1.0e-3 and 1.5e-3 trilinear). 64 fetches, for OSL mode,
// which has no speed target; the node graph (LUT mode) stays trilinear.
constexpr const char* kCatmullRomOsl = R"OSL(// Weight of tap a (0..3: nodes i-1, i, i+1, i+2) at fraction t of the cell (Catmull-Rom).
float libbrdf_catmull_rom(float t, float a)
{
    float t2 = t * t;
    float t3 = t2 * t;
    if (a < 0.5) return 0.5 * (-t3 + 2.0 * t2 - t);
    if (a < 1.5) return 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
    if (a < 2.5) return 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
    return 0.5 * (t3 - t2);
}

color libbrdf_angular_cubic(string atlas, float u0, float u1, float u2)
{
    float i0 = clamp(floor(u0), 0.0, LIBBRDF_N0 - 2.0);
    float i1 = clamp(floor(u1), 0.0, LIBBRDF_N1 - 2.0);
    float i2 = clamp(floor(u2), 0.0, LIBBRDF_N2 - 2.0);
    float t0 = clamp(u0 - i0, 0.0, 1.0);
    float t1 = clamp(u1 - i1, 0.0, 1.0);
    float t2 = clamp(u2 - i2, 0.0, 1.0);
    color sum = color(0.0, 0.0, 0.0);
    for (int c = 0; c < 4; ++c) {
        float k = clamp(i2 + c - 1.0, 0.0, LIBBRDF_N2 - 1.0);
        float wk = libbrdf_catmull_rom(t2, c);
        for (int b = 0; b < 4; ++b) {
            float j = clamp(i1 + b - 1.0, 0.0, LIBBRDF_N1 - 1.0);
            float wjk = wk * libbrdf_catmull_rom(t1, b);
            for (int a = 0; a < 4; ++a) {
                float i = clamp(i0 + a - 1.0, 0.0, LIBBRDF_N0 - 1.0);
                sum += (wjk * libbrdf_catmull_rom(t0, a)) * libbrdf_node(atlas, i, j, k);
            }
        }
    }
    return sum;
}

)OSL";

std::string atlas_defines(const BlenderAtlas& a) {
  std::ostringstream o;
  o << "#define LIBBRDF_N0 " << number(a.shape[0]) << "  // theta_h nodes\n";
  o << "#define LIBBRDF_N1 " << number(a.shape[1]) << "  // theta_d nodes\n";
  o << "#define LIBBRDF_N2 " << number(a.shape[2]) << "  // phi_d nodes (tiles)\n";
  o << "#define LIBBRDF_COLUMNS " << number(a.columns) << "  // tiles per atlas row\n";
  o << "#define LIBBRDF_WIDTH " << number(a.width) << "\n";
  o << "#define LIBBRDF_HEIGHT " << number(a.height) << "\n";
  return o.str();
}

// Texel (x, y) of an image of `width` x `height`, y counted from the bottom row, sampled at its
// centre (OSL's t runs from the top); table node (i0, i1, k) of the atlas.
constexpr const char* kTexelOsl = R"OSL(color libbrdf_texel(string file, float x, float y, float width, float height)
{
    return (color) texture(file, (x + 0.5) / width, 1.0 - (y + 0.5) / height,
                           0.0, 0.0, 0.0, 0.0, "interp", "closest", "wrap", "clamp");
}

color libbrdf_node(string atlas, float i0, float i1, float k)
{
    float tile_row = floor((k + 0.5) / LIBBRDF_COLUMNS);
    float tile_column = k - tile_row * LIBBRDF_COLUMNS;
    return libbrdf_texel(atlas, tile_column * LIBBRDF_N0 + i0, tile_row * LIBBRDF_N1 + i1, LIBBRDF_WIDTH, LIBBRDF_HEIGHT);
}

)OSL";

}  // namespace

std::string osl_shader_source(const BlenderAtlas& a, const std::string& shader_name, const std::string& atlas_path,
                              const std::string& header_comment) {
  std::ostringstream o;
  o << comment_lines(header_comment)
    << "// Atlas layout and axis mapping: libbrdf exporters/include/exporters/blender.h (rusinkiewicz).\n\n";
  o << "#define LIBBRDF_PI 3.14159265358979323846\n"
       "#define LIBBRDF_HALF_PI 1.57079632679489661923\n";
  o << atlas_defines(a);
  o << "#define LIBBRDF_SPEC_NODES " << number(a.specular_nodes) << "  // R_spec nodes over [0, 90] deg\n";
  o << "#define LIBBRDF_SPEC_ROW " << number(a.specular_row) << "  // R_spec row, counted from the bottom\n";
  o << "#define LIBBRDF_BRDF(Nn, Ln, Vn) libbrdf_brdf(Atlas, Nn, Ln, Vn)\n"
       "#define LIBBRDF_SPECULAR(theta) libbrdf_specular(Atlas, theta)\n\n";
  o << kTexelOsl;
  o << "// f_r (1/sr, per channel) for unit N, L (towards the light) and V (towards the viewer).\n"
       "color libbrdf_brdf(string atlas, vector Nn, vector Ln, vector Vn)\n{\n"
    << kAnglesOsl
    << "    float u0 = sqrt(theta_h / LIBBRDF_HALF_PI) * (LIBBRDF_N0 - 1.0);  // square map\n"
       "    float u1 = theta_d / LIBBRDF_HALF_PI * (LIBBRDF_N1 - 1.0);\n"
       "    float u2 = phi_d / LIBBRDF_PI * (LIBBRDF_N2 - 1.0);\n"
    << kTrilinearOsl << "    return mix(mix(c00, c10, t1), mix(c01, c11, t1), t2);\n}\n\n";
  o << R"OSL(// R_spec(theta) of the specular spike (theta in radians), linear between its nodes.
color libbrdf_specular(string atlas, float theta)
{
    float position = theta / LIBBRDF_HALF_PI * (LIBBRDF_SPEC_NODES - 1.0);  // not u, v: OSL globals
    float j = clamp(floor(position), 0.0, LIBBRDF_SPEC_NODES - 2.0);
    float fraction = clamp(position - j, 0.0, 1.0);
    return mix(libbrdf_texel(atlas, j, LIBBRDF_SPEC_ROW, LIBBRDF_WIDTH, LIBBRDF_HEIGHT),
               libbrdf_texel(atlas, j + 1.0, LIBBRDF_SPEC_ROW, LIBBRDF_WIDTH, LIBBRDF_HEIGHT), fraction);
}

)OSL";
  o << "shader " << shader_name << "(\n"
    << "    string Atlas = " << quoted(atlas_path) << ",\n"
    << kShaderTail;
  return o.str();
}

std::string osl_kernel_shader_source(const BlenderExport& e, const std::string& directory, const std::string& header_comment) {
  namespace fs = std::filesystem;
  const KernelFiles& k = *e.kernel;
  const SigmaImage& s = k.sigma;
  const std::array<KernelChannel, 3> channels = kernel_channels(e.channels);
  const auto path = [&](const std::string& file) { return quoted(fs::absolute(fs::path(directory) / file).lexically_normal().string()); };
  std::ostringstream o;
  o << comment_lines(header_comment)
    << "// The factored form f = K(theta_i) F(theta_d) P~(theta_h, theta_d, phi_d) C (pi l_c^2/lambda^2) Sigma(g, c):\n"
       "// images and formulas in libbrdf exporters/include/exporters/blender.h (kernel).\n\n";
  o << "#define LIBBRDF_PI 3.14159265358979323846\n"
       "#define LIBBRDF_HALF_PI 1.57079632679489661923\n";
  o << atlas_defines(k.angular);
  o << "#define LIBBRDF_SIDE_NODES " << number(kThetaINodes) << "  // side rows: R_spec, K, F over [0, 90] deg\n";
  o << "#define LIBBRDF_SIDE_ROWS " << number(kSideRows) << "\n";
  o << "#define LIBBRDF_SIGMA_WIDTH " << number(s.width) << "\n";
  o << "#define LIBBRDF_SIGMA_HEIGHT " << number(s.height) << "\n";
  o << "#define LIBBRDF_SIGMA_X_MIN " << number(s.x_min) << "  // ln g of column 0\n";
  o << "#define LIBBRDF_SIGMA_X_MAX " << number(s.x_max()) << "\n";
  o << "#define LIBBRDF_SIGMA_DX " << number(s.dx) << "\n";
  o << "#define LIBBRDF_SIGMA_DZ " << number(s.dz) << "\n";
  o << "#define LIBBRDF_SIGMA_Z_MAX " << number(s.z_max()) << "\n";
  const char* rgb = "RGB";
  for (int c = 0; c < 3; ++c) {
    o << "#define LIBBRDF_G_SCALE_" << rgb[c] << " " << number(channels[c].g_scale) << "  // (2 pi sigma_s/lambda)^2\n";
    o << "#define LIBBRDF_C_SCALE_" << rgb[c] << " " << number(channels[c].c_scale) << "  // pi^2 (l_c/lambda)^2\n";
  }
  o << "#define LIBBRDF_PREFACTOR color(" << number(channels[0].prefactor) << ", " << number(channels[1].prefactor) << ", "
    << number(channels[2].prefactor) << ")  // pi l_c^2/lambda^2\n";
  o << "#define LIBBRDF_CLOSED_FORM " << static_cast<int>(libbrdf::model_traits(e.model).closed_angular)
    << "  // 0: C = 1, 1: F_bk^2 (eq. 27), 2: 1/S (eq. 28)\n";
  o << "#define LIBBRDF_BRDF(Nn, Ln, Vn) libbrdf_brdf(Side, Angular, SigmaImage, Nn, Ln, Vn)\n"
       "#define LIBBRDF_SPECULAR(theta) libbrdf_row(Side, 0.0, theta)\n\n";
  o << kTexelOsl << kCatmullRomOsl;
  o << R"OSL(// Side row `row` (0 R_spec, 1 K, 2 F) at theta (radians), linear between its nodes.
color libbrdf_row(string side, float row, float theta)
{
    float position = theta / LIBBRDF_HALF_PI * (LIBBRDF_SIDE_NODES - 1.0);  // not u, v: OSL globals
    float j = clamp(floor(position), 0.0, LIBBRDF_SIDE_NODES - 2.0);
    float fraction = clamp(position - j, 0.0, 1.0);
    return mix(libbrdf_texel(side, j, row, LIBBRDF_SIDE_NODES, LIBBRDF_SIDE_ROWS),
               libbrdf_texel(side, j + 1.0, row, LIBBRDF_SIDE_NODES, LIBBRDF_SIDE_ROWS), fraction);
}

// Sigma(g, c) of eq. 11 from the Sigma image: S bilinear at (x = ln g, z = sqrt(c/(g+1))), then
// ln Sigma = S + x - ln(1 + g^2) - z^2 (the image's two ends continue beyond its edges).
float libbrdf_sigma(string image, float g, float c)
{
    float x = log(max(g, 1e-30));
    float z2 = c / (g + 1.0);
    float ux = (clamp(x, LIBBRDF_SIGMA_X_MIN, LIBBRDF_SIGMA_X_MAX) - LIBBRDF_SIGMA_X_MIN) / LIBBRDF_SIGMA_DX;
    float uz = min(sqrt(z2), LIBBRDF_SIGMA_Z_MAX) / LIBBRDF_SIGMA_DZ;
    float i = clamp(floor(ux), 0.0, LIBBRDF_SIGMA_WIDTH - 2.0);
    float j = clamp(floor(uz), 0.0, LIBBRDF_SIGMA_HEIGHT - 2.0);
    float tx = clamp(ux - i, 0.0, 1.0);
    float tz = clamp(uz - j, 0.0, 1.0);
    // R = G = B: one component of the bilinear colour.
    color s00 = libbrdf_texel(image, i, j, LIBBRDF_SIGMA_WIDTH, LIBBRDF_SIGMA_HEIGHT);
    color s10 = libbrdf_texel(image, i + 1.0, j, LIBBRDF_SIGMA_WIDTH, LIBBRDF_SIGMA_HEIGHT);
    color s01 = libbrdf_texel(image, i, j + 1.0, LIBBRDF_SIGMA_WIDTH, LIBBRDF_SIGMA_HEIGHT);
    color s11 = libbrdf_texel(image, i + 1.0, j + 1.0, LIBBRDF_SIGMA_WIDTH, LIBBRDF_SIGMA_HEIGHT);
    color s = mix(mix(s00, s10, tx), mix(s01, s11, tx), tz);
    return exp(s[0] + x - log(1.0 + g * g) - z2);
}

// f_r (1/sr, per channel) for unit N, L (towards the light) and V (towards the viewer).
color libbrdf_brdf(string side, string atlas, string sigma_image, vector Nn, vector Ln, vector Vn)
{
)OSL";
  o << kAnglesOsl
    << "    float u0 = theta_h / LIBBRDF_HALF_PI * (LIBBRDF_N0 - 1.0);  // uniform: the lobe is in Sigma\n"
       "    float u1 = theta_d / LIBBRDF_HALF_PI * (LIBBRDF_N1 - 1.0);\n"
       "    float u2 = phi_d / LIBBRDF_PI * (LIBBRDF_N2 - 1.0);\n";
  o << R"OSL(    color angular = libbrdf_angular_cubic(atlas, u0, u1, u2);
    float cos_i = dot(Nn, Ln);
    float cos_s = dot(Nn, Vn);
    float theta_i = atan2(length(cross(Nn, Ln)), cos_i);
    // g (eq. 12) and c = pi^2 (l_c/lambda)^2 eta_r^2, eta_r^2 = |N x (L + V)|^2 (eq. 10) per channel.
    float sum = cos_i + cos_s;
    vector tangential = cross(Nn, Ln + Vn);
    float eta2 = dot(tangential, tangential);
    color sigma = color(libbrdf_sigma(sigma_image, LIBBRDF_G_SCALE_R * sum * sum, LIBBRDF_C_SCALE_R * eta2),
                        libbrdf_sigma(sigma_image, LIBBRDF_G_SCALE_G * sum * sum, LIBBRDF_C_SCALE_G * eta2),
                        libbrdf_sigma(sigma_image, LIBBRDF_G_SCALE_B * sum * sum, LIBBRDF_C_SCALE_B * eta2));
    float closed = 1.0;
    if (LIBBRDF_CLOSED_FORM == 1)
        closed = cos_d * cos_d / max(cos_i * cos_i * cos_h * cos_h, 1e-30);
    if (LIBBRDF_CLOSED_FORM == 2)
        closed = cos_d * cos_d / max(cos_i * cos_s * cos_h * cos_h, 1e-30);
    return libbrdf_row(side, 1.0, theta_i) * libbrdf_row(side, 2.0, theta_d) * angular * sigma * LIBBRDF_PREFACTOR * closed;
}

)OSL";
  o << "shader " << e.osl_shader_name << "(\n"
    << "    string Side = " << path(k.side_file) << ",\n"
    << "    string Angular = " << path(k.angular_file) << ",\n"
    << "    string SigmaImage = " << path(k.sigma_file) << ",\n"
    << kShaderTail;
  return o.str();
}

std::string osl_identifier(const std::string& text) {
  std::string id = "libbrdf_";
  for (char ch : text) id += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  return id;
}

}  // namespace libbrdf::blender
