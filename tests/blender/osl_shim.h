// The part of OSL the generated libbrdf shaders use, as C++ (tests/blender/test_osl_shader.py):
// types color/vector/normal/point (one float triple), string, closures (emission, reflection as
// tagged weights), the builtins, the shader globals N and I, and texture() on images held in
// memory (by file name), with OSL's conventions: s from the left, t from the TOP of the image, "interp"
// "closest" picks texel floor(s W), floor(t H) ("wrap" "clamp" clamps it to the image).
// Everything is float, as in OSL. The generated source is included inside namespace osl, so
// that these names win over <cmath>'s.
#pragma once
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace osl {

struct Triple {
  float x = 0.0f, y = 0.0f, z = 0.0f;
  Triple() = default;
  Triple(float v) : x(v), y(v), z(v) {}  // NOLINT: OSL's implicit float -> triple
  Triple(float a, float b, float c) : x(a), y(b), z(c) {}
  float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};
using color = Triple;
using vector = Triple;
using normal = Triple;
using point = Triple;
using string = std::string;

inline Triple operator+(Triple a, Triple b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Triple operator-(Triple a, Triple b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Triple operator-(Triple a) { return {-a.x, -a.y, -a.z}; }
inline Triple operator*(Triple a, Triple b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline Triple operator*(Triple a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Triple operator*(float s, Triple a) { return a * s; }
inline Triple& operator+=(Triple& a, Triple b) { return a = a + b; }
inline bool operator==(Triple a, Triple b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
inline bool operator!=(Triple a, Triple b) { return !(a == b); }

inline float floor(float x) { return std::floor(x); }
inline float sqrt(float x) { return std::sqrt(x); }
inline float log(float x) { return std::log(x); }
inline float exp(float x) { return std::exp(x); }
inline float acos(float x) { return std::acos(x); }
inline float atan2(float y, float x) { return std::atan2(y, x); }
inline float max(float a, float b) { return a > b ? a : b; }
inline float min(float a, float b) { return a < b ? a : b; }
inline float clamp(float x, float lo, float hi) { return min(max(x, lo), hi); }
inline Triple mix(Triple a, Triple b, float t) { return a * (1.0f - t) + b * t; }
inline float mix(float a, float b, float t) { return a * (1.0f - t) + b * t; }
inline float dot(Triple a, Triple b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Triple cross(Triple a, Triple b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline float length(Triple a) { return std::sqrt(dot(a, a)); }
inline Triple normalize(Triple a) {
  const float l = length(a);
  return l > 0.0f ? a * (1.0f / l) : Triple(0.0f);
}

// Closures: weights of the two closures the shader may use.
struct Closure {
  Triple emission, reflection;
};
inline Closure emission() { return {Triple(1.0f), Triple(0.0f)}; }
inline Closure reflection(Triple) { return {Triple(0.0f), Triple(1.0f)}; }
inline Closure operator*(Triple w, Closure c) { return {w * c.emission, w * c.reflection}; }
inline Closure operator+(Closure a, Closure b) { return {a.emission + b.emission, a.reflection + b.reflection}; }

// Shader globals.
inline Triple N, I;

// The images: RGB floats, rows from the top (as stored in the EXR and as OSL's t counts), by path.
struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;
};
inline std::map<std::string, Image> images;
inline long texture_calls = 0;

inline Triple texture(const string& file, float s, float t, float dsdx, float dtdx, float dsdy, float dtdy,
                      const char* k1, const char* v1, const char* k2, const char* v2) {
  const auto found = images.find(file);
  if (found == images.end() || std::strcmp(k1, "interp") || std::strcmp(v1, "closest") || std::strcmp(k2, "wrap") ||
      std::strcmp(v2, "clamp") || dsdx != 0.0f || dtdx != 0.0f || dsdy != 0.0f || dtdy != 0.0f) {
    std::fprintf(stderr, "texture(): unexpected call (file %s, %s %s, %s %s)\n", file.c_str(), k1, v1, k2, v2);
    std::exit(3);
  }
  const Image& image = found->second;
  ++texture_calls;
  int x = static_cast<int>(std::floor(s * static_cast<float>(image.width)));
  int y = static_cast<int>(std::floor(t * static_cast<float>(image.height)));
  x = x < 0 ? 0 : (x >= image.width ? image.width - 1 : x);
  y = y < 0 ? 0 : (y >= image.height ? image.height - 1 : y);
  const float* p = &image.rgb[(static_cast<std::size_t>(y) * image.width + x) * 3];
  return {p[0], p[1], p[2]};
}

}  // namespace osl
