// plan_scene_bake(): the smallest table a scene needs, from a small JSON description
// (format in docs/scene.md).
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "libbrdf/error.h"
#include "libbrdf/lut.h"

namespace libbrdf {
namespace {

using nlohmann::json;

struct SceneReader {
  std::string path;

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InvalidArgument("scene", path + ": " + where + (where.empty() ? "" : ": ") + what);
  }

  void only_keys(const json& object, const std::string& where, std::initializer_list<const char*> allowed) const {
    if (!object.is_object()) fail(where, "expected a JSON object");
    const std::set<std::string> known(allowed.begin(), allowed.end());
    for (const auto& item : object.items())
      if (!known.count(item.key())) fail(where, "unknown key '" + item.key() + "'");
  }

  Direction direction(const json& object, const std::string& where, const char* key) const {
    if (!object.contains(key)) fail(where, std::string("missing '") + key + "' (X,Y,Z array)");
    const json& v = object.at(key);
    const std::string at = where + "." + key;
    if (!v.is_array() || v.size() != 3) fail(at, "expected an array of 3 numbers");
    double xyz[3];
    for (int k = 0; k < 3; ++k) {
      if (!v[k].is_number()) fail(at, "expected an array of 3 numbers");
      xyz[k] = v[k].get<double>();
    }
    const double length2 = xyz[0] * xyz[0] + xyz[1] * xyz[1] + xyz[2] * xyz[2];
    if (!(std::isfinite(length2) && length2 > 0.0)) fail(at, "must be a finite nonzero vector");
    return {xyz[0], xyz[1], xyz[2]};
  }

  std::string type(const json& object, const std::string& where, std::initializer_list<const char*> allowed) const {
    if (!object.contains("type") || !object.at("type").is_string()) fail(where, "missing 'type' (string)");
    const std::string t = object.at("type").get<std::string>();
    std::string names;
    for (const char* a : allowed) {
      if (t == a) return t;
      names += (names.empty() ? "" : "|") + std::string(a);
    }
    fail(where + ".type", "must be one of " + names + " (got '" + t + "')");
  }
};

}  // namespace

ScenePlan plan_scene_bake(const std::string& path) {
  SceneReader reader{path};
  std::ifstream in(path);
  if (!in) reader.fail("", "cannot open the scene file");
  json scene;
  try {
    scene = json::parse(in);
  } catch (const json::exception& e) {
    std::string what = e.what();
    reader.fail("", "not valid JSON (" + what.substr(0, what.find('\n')) + ")");
  }
  reader.only_keys(scene, "scene", {"lights", "camera", "wavelengths_um", "comment"});

  if (!scene.contains("lights") || !scene.at("lights").is_array() || scene.at("lights").empty())
    reader.fail("lights", "expected a non-empty array of lights");
  int suns = 0, local_lights = 0;
  Direction sun;
  for (std::size_t k = 0; k < scene.at("lights").size(); ++k) {
    const json& light = scene.at("lights")[k];
    const std::string where = "lights[" + std::to_string(k) + "]";
    reader.only_keys(light, where, {"type", "direction", "position", "comment"});
    if (reader.type(light, where, {"sun", "point", "spot", "area"}) == "sun") {
      sun = reader.direction(light, where, "direction");
      ++suns;
    } else {
      reader.direction(light, where, "position");
      ++local_lights;
    }
  }

  if (!scene.contains("camera")) reader.fail("camera", "missing (an object with type orthographic|perspective)");
  const json& camera = scene.at("camera");
  reader.only_keys(camera, "camera", {"type", "direction", "position", "comment"});
  const bool orthographic = reader.type(camera, "camera", {"orthographic", "perspective"}) == "orthographic";
  Direction view;
  if (orthographic) {
    view = reader.direction(camera, "camera", "direction");
  } else {
    reader.direction(camera, "camera", "position");
  }

  ScenePlan plan;
  if (scene.contains("wavelengths_um")) {
    const json& w = scene.at("wavelengths_um");
    if (!w.is_array() || w.empty() || w.size() > 64) reader.fail("wavelengths_um", "expected an array of 1 to 64 numbers (um)");
    for (const json& value : w) {
      if (!value.is_number() || !(value.get<double>() > 0.0) || !std::isfinite(value.get<double>()))
        reader.fail("wavelengths_um", "every wavelength must be a finite number > 0 um");
      plan.wavelengths_um.push_back(value.get<double>());
    }
  }

  if (suns == 1 && local_lights == 0 && orthographic) {
    plan.layout = LutLayout::slice;
    plan.light = sun;
    plan.view = view;
    plan.reason = "one sun and an orthographic camera: the light and view directions are fixed in the world, so a 2D "
                  "slice over (N.L, N.V) holds every geometry the scene can ask for";
  } else {
    plan.layout = LutLayout::rusinkiewicz;
    std::ostringstream why;
    why << "the scene has " << (suns + local_lights) << " light(s) (" << suns << " sun, " << local_lights
        << " local) and a" << (orthographic ? "n orthographic" : " perspective")
        << " camera: the light or view direction varies over the surface, so the full isotropic 3D table is needed";
    plan.reason = why.str();
  }
  return plan;
}

}  // namespace libbrdf
