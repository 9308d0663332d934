// Reading a scene file (scene_file.h): JSON through nlohmann_json, then every field checked by hand
// so that each error names the file and the field path ("equipment[12].scale").
#include "nestwalk/scene/scene_file.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/scene/json_fields.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <set>
#include <sstream>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

/// Branching factors the broad phase supports (box_tree.h).
constexpr int kAllowedDegrees[] = {2, 4, 8};

/// A group path: '/'-separated names, none empty (so no leading, trailing or doubled '/').
void checkGroup(const JsonFieldReader& r, const std::string& group, const std::string& field) {
  if (group.empty()) return;
  std::size_t start = 0;
  while (true) {
    const std::size_t slash = group.find('/', start);
    const std::size_t end = slash == std::string::npos ? group.size() : slash;
    if (end == start)
      r.fail(field, "'" + group + "' has an empty component (no leading, trailing or doubled '/')");
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
}

EquipmentSpec readEquipment(const JsonFieldReader& r, const Json& e, const std::string& field,
                            const std::map<std::string, ModelType>& types) {
  r.checkObject(e, field);
  r.checkKeys(e, field,
              {"name", "model", "type", "position", "heading", "pitch", "roll", "scale", "group", "use_only", "kind"});
  EquipmentSpec s;
  if (e.contains("type")) {
    if (e.contains("model")) r.fail(joinField(field, "model"), "give either a model or a type, not both");
    s.type = r.nonEmptyString(e["type"], joinField(field, "type"));
    const auto t = types.find(s.type);
    if (t == types.end()) r.fail(joinField(field, "type"), "'" + s.type + "' is not one of the scene's types");
    s.model = t->second.model;
    s.kind = t->second.kind;
    s.useOnly = t->second.useOnly;
    s.scale = t->second.scale;
  } else {
    if (!e.contains("model")) r.fail(joinField(field, "model"), "missing (a model file or a type is required)");
    s.model = r.nonEmptyString(e["model"], joinField(field, "model"));
  }
  if (!e.contains("position")) r.fail(joinField(field, "position"), "missing (map coordinates [x, y] or [x, y, z])");
  const std::vector<double> p = r.numbers(e["position"], joinField(field, "position"), 2, 3);
  s.position = {p[0], p[1], p.size() == 3 ? p[2] : 0.0};
  s.hasZ = p.size() == 3;
  if (e.contains("heading")) s.headingDeg = r.number(e["heading"], joinField(field, "heading"));
  if (e.contains("pitch")) s.pitchDeg = r.number(e["pitch"], joinField(field, "pitch"));
  if (e.contains("roll")) s.rollDeg = r.number(e["roll"], joinField(field, "roll"));
  if (e.contains("scale")) s.scale = r.positive(e["scale"], joinField(field, "scale"));
  if (e.contains("group")) {
    s.group = r.string(e["group"], joinField(field, "group"));
    checkGroup(r, s.group, joinField(field, "group"));
  }
  if (e.contains("use_only")) s.useOnly = r.boolean(e["use_only"], joinField(field, "use_only"));
  if (s.useOnly && s.group.empty())
    r.fail(joinField(field, "use_only"), "a use_only instance needs a group (its volume is its group's)");
  if (e.contains("kind")) s.kind = r.string(e["kind"], joinField(field, "kind"));
  if (e.contains("name")) s.name = r.nonEmptyString(e["name"], joinField(field, "name"));
  return s;
}

ViewerSpec readViewer(const JsonFieldReader& r, const Json& v) {
  const std::string field = "viewer";
  r.checkObject(v, field);
  r.checkKeys(v, field, {"eye_height", "body_half_extents", "max_step", "max_slope_deg", "speed", "fly_clearance"});
  ViewerSpec s;
  if (v.contains("eye_height")) s.eyeHeight = r.positive(v["eye_height"], "viewer.eye_height");
  if (v.contains("body_half_extents")) {
    const std::vector<double> h = r.numbers(v["body_half_extents"], "viewer.body_half_extents", 3, 3);
    for (std::size_t i = 0; i < 3; ++i)
      if (!(h[i] > 0)) r.fail(indexField("viewer.body_half_extents", i), "must be > 0");
    s.bodyHalfExtents = {h[0], h[1], h[2]};
  }
  if (v.contains("max_step")) s.maxStep = r.nonNegative(v["max_step"], "viewer.max_step");
  if (v.contains("max_slope_deg")) {
    s.maxSlopeDeg = r.number(v["max_slope_deg"], "viewer.max_slope_deg");
    if (!(s.maxSlopeDeg > 0 && s.maxSlopeDeg < 90)) r.fail("viewer.max_slope_deg", "must be > 0 and < 90 degrees");
  }
  if (v.contains("speed")) s.speed = r.positive(v["speed"], "viewer.speed");
  if (v.contains("fly_clearance")) s.flyClearance = r.nonNegative(v["fly_clearance"], "viewer.fly_clearance");
  return s;
}

MethodSpec readMethod(const JsonFieldReader& r, const Json& m) {
  const std::string field = "method";
  r.checkObject(m, field);
  r.checkKeys(m, field, {"volumes", "hierarchy", "degree", "split_axis", "split_point", "fitter"});
  MethodSpec s;
  if (m.contains("volumes")) {
    const std::string v = r.string(m["volumes"], "method.volumes");
    if (!parseVolumeMethod(v, s.volumes))
      r.fail("method.volumes", "expected nested, aabb, obb, nested+mesh, kdop18 or auto, got '" + v + "'");
  }
  if (m.contains("hierarchy")) {
    const std::string h = r.string(m["hierarchy"], "method.hierarchy");
    if (h == "auto") s.templateHierarchy = false;
    else if (h == "template") s.templateHierarchy = true;
    else r.fail("method.hierarchy", "expected auto or template, got '" + h + "'");
  }
  if (m.contains("degree")) {
    const double d = r.number(m["degree"], "method.degree");
    if (std::find(std::begin(kAllowedDegrees), std::end(kAllowedDegrees), d) == std::end(kAllowedDegrees))
      r.fail("method.degree", "expected 2, 4 or 8, got " + m["degree"].dump());
    s.autoTree.degree = int(d);
  }
  // The names are the ones splitAxisName / splitPointName print (box_tree.h).
  if (m.contains("split_axis")) {
    const std::string a = r.string(m["split_axis"], "method.split_axis");
    if (a == "longest") s.autoTree.axis = SplitAxis::LongestSide;
    else if (a == "splatter") s.autoTree.axis = SplitAxis::Splatter;
    else r.fail("method.split_axis", "expected longest or splatter, got '" + a + "'");
  }
  if (m.contains("split_point")) {
    const std::string p = r.string(m["split_point"], "method.split_point");
    if (p == "mean") s.autoTree.point = SplitPoint::Mean;
    else if (p == "median") s.autoTree.point = SplitPoint::Median;
    else r.fail("method.split_point", "expected mean or median, got '" + p + "'");
  }
  if (m.contains("fitter")) {
    const std::string f = r.string(m["fitter"], "method.fitter");
    const std::optional<ObbFitter> fitter = parseFitter(f);
    if (!fitter) r.fail("method.fitter", "expected hull-search or covariance, got '" + f + "'");
    s.fitter = *fitter;
  }
  return s;
}

/// Default instance name: "<group>/<model stem or type>#<index>" ("<...>#<index>" at the root).
std::string defaultName(const EquipmentSpec& e, std::size_t index) {
  const std::string stem = e.type.empty() ? fs::path(e.model).stem().string() : e.type;
  return (e.group.empty() ? "" : e.group + "/") + stem + "#" + std::to_string(index);
}

/// Names must be unique among instances and must not equal a use_only group's unit name.
void checkNames(const JsonFieldReader& r, std::vector<EquipmentSpec>& equipment, const std::vector<bool>& named) {
  std::map<std::string, std::size_t> seen;
  for (std::size_t i = 0; i < equipment.size(); ++i) {
    const std::string field = indexField("equipment", i);
    auto [it, inserted] = seen.emplace(equipment[i].name, i);
    if (!inserted)
      r.fail(named[i] ? joinField(field, "name") : field,
             std::string(named[i] ? "" : "default ") + "name '" + equipment[i].name + "' is already the name of " +
                 indexField("equipment", it->second));
  }
  for (std::size_t i = 0; i < equipment.size(); ++i) {
    if (!equipment[i].useOnly) continue;
    auto it = seen.find(equipment[i].group);
    if (it != seen.end() && !equipment[it->second].useOnly)
      r.fail(joinField(indexField("equipment", it->second), "name"),
             "'" + equipment[i].group + "' is also the name of the unit formed by group '" + equipment[i].group +
                 "''s use_only members (e.g. " + indexField("equipment", i) + ")");
  }
}

}  // namespace

SceneSpec parseSceneJson(const std::string& text, const std::string& path) {
  const JsonFieldReader r(path, fs::path(path).parent_path());
  const Json root = parseJsonStrictly(text, path);
  r.checkObject(root, "");
  r.checkKeys(root, "", {"terrain", "imagery", "shading", "origin", "types", "equipment", "viewer", "method", "source"});

  SceneSpec s;
  s.path = path;
  if (!root.contains("terrain")) r.fail("terrain", "missing (the terrain file is required)");
  s.terrain = r.resolve(r.nonEmptyString(root["terrain"], "terrain"));
  if (root.contains("imagery")) s.imagery = r.resolve(r.nonEmptyString(root["imagery"], "imagery"));
  if (root.contains("shading")) {
    const std::string shading = r.nonEmptyString(root["shading"], "shading");
    if (shading != "hillshade" && shading != "none")
      r.fail("shading", "expected hillshade or none, got '" + shading + "'");
    s.hillshade = shading == "hillshade";
  }
  if (root.contains("origin")) {
    const std::vector<double> o = r.numbers(root["origin"], "origin", 3, 3);
    s.origin = Eigen::Vector3d(o[0], o[1], o[2]);
  }
  if (root.contains("types"))
    s.types = parseModelTypes(root["types"], path, fs::path(path).parent_path().string(), "types");
  if (root.contains("source")) r.checkObject(root["source"], "source");
  std::vector<bool> named;
  if (root.contains("equipment")) {
    const Json& list = root["equipment"];
    if (!list.is_array()) r.fail("equipment", std::string("expected an array, got ") + list.type_name());
    for (std::size_t i = 0; i < list.size(); ++i) {
      EquipmentSpec e = readEquipment(r, list[i], indexField("equipment", i), s.types);
      named.push_back(!e.name.empty());
      if (e.name.empty()) e.name = defaultName(e, i);
      s.equipment.push_back(std::move(e));
    }
  }
  checkNames(r, s.equipment, named);
  if (root.contains("viewer")) s.viewer = readViewer(r, root["viewer"]);
  if (root.contains("method")) s.method = readMethod(r, root["method"]);

  // Files: the terrain, the imagery, then every model (all missing ones in one error).
  if (!fs::is_regular_file(s.terrain)) r.fail("terrain", "file not found: " + s.terrain);
  if (s.imagery && !fs::is_regular_file(*s.imagery)) r.fail("imagery", "file not found: " + *s.imagery);
  std::set<std::string> checked;
  std::vector<std::string> missing;
  for (std::size_t i = 0; i < s.equipment.size(); ++i) {
    EquipmentSpec& e = s.equipment[i];
    if (e.type.empty()) e.model = r.resolve(e.model);  // a type's path is resolved already
    if (!checked.insert(e.model).second) continue;
    const std::string field = e.type.empty() ? joinField(indexField("equipment", i), "model") : "types." + e.type + ".model";
    if (!fs::is_regular_file(e.model)) missing.push_back(field + ": " + e.model);
  }
  failOnMissingModels(path, missing);
  return s;
}

SceneSpec readSceneFile(const std::string& path) { return parseSceneJson(readJsonFile(path, "scene file"), path); }

}  // namespace nestwalk
