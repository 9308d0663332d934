#include "nestwalk/scene/model_catalog.h"

#include "nestwalk/scene/gltf_model.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/scene/json_fields.h"

#include <cmath>
#include <filesystem>
#include <set>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

/// Metres per unit of the named units (exact conversions: the inch is 25.4 mm, the foot 0.3048 m).
struct NamedUnit {
  const char* name;
  double metres;
};
constexpr NamedUnit kUnits[] = {{"mm", 0.001}, {"cm", 0.01}, {"m", 1.0}, {"in", 0.0254}, {"ft", 0.3048}};

/// Defaults of the line fields, as fractions of the piece length: a joint may leave a tenth of a
/// piece open (a 3 m barrier: 0.3 m, less than the default walker body's 0.5 m width, so a row of
/// barriers stays closed) and two pieces may overlap by half of one (any stretch of at least half
/// a piece can then be covered: see gis/fence_layout.h).
constexpr double kDefaultGapFraction = 0.1;
constexpr double kDefaultOverlapFraction = 0.5;

const char* upName(ModelUp u) {
  switch (u) {
    case ModelUp::Z: return "z";
    case ModelUp::Y: return "y";
    case ModelUp::MinusY: return "-y";
    case ModelUp::MinusZ: return "-z";
  }
  return "z";
}

const char* forwardName(ModelForward f) {
  switch (f) {
    case ModelForward::PlusY: return "+y";
    case ModelForward::MinusY: return "-y";
    case ModelForward::PlusX: return "+x";
    case ModelForward::MinusX: return "-x";
  }
  return "+y";
}

const char* originName(ModelOrigin o) {
  switch (o) {
    case ModelOrigin::Base: return "base";
    case ModelOrigin::Centre: return "centre";
    case ModelOrigin::File: return "file";
  }
  return "base";
}

ModelType readType(const JsonFieldReader& r, const std::string& name, const Json& t, const std::string& field) {
  r.checkObject(t, field);
  r.checkKeys(t, field, {"model", "units", "up", "forward", "origin", "kind", "use_only", "scale", "piece_length",
                         "max_gap", "max_overlap"});
  ModelType type;
  type.name = name;
  if (!t.contains("model")) r.fail(joinField(field, "model"), "missing (the model file is required)");
  type.model = r.resolve(r.nonEmptyString(t["model"], joinField(field, "model")));
  if (isGltfPath(type.model)) {  // glTF's own frame (its specification, section 3.4): +y up, front towards +z
    type.up = ModelUp::Y;
    type.forward = ModelForward::MinusY;  // +z turned up to z becomes -y
  }
  if (t.contains("units")) {
    const Json& u = t["units"];
    const std::string f = joinField(field, "units");
    if (u.is_number()) {
      type.metresPerUnit = r.positive(u, f);
      type.unitsText = u.dump();
    } else {
      const std::string text = u.is_string() ? u.get<std::string>() : u.dump();
      bool known = false;
      for (const NamedUnit& k : kUnits)
        if (u.is_string() && text == k.name) {
          type.metresPerUnit = k.metres;
          known = true;
        }
      if (!known) r.fail(f, "expected mm, cm, m, in, ft or a number > 0, got '" + text + "'");
      type.unitsText = text;
    }
  }
  if (t.contains("up")) {
    const std::string up = r.string(t["up"], joinField(field, "up"));
    bool known = false;
    for (ModelUp u : {ModelUp::Z, ModelUp::Y, ModelUp::MinusY, ModelUp::MinusZ})
      if (up == upName(u)) {
        type.up = u;
        known = true;
      }
    if (!known) r.fail(joinField(field, "up"), "expected z, y, -y or -z, got '" + up + "'");
  }
  if (t.contains("forward")) {
    const std::string fw = r.string(t["forward"], joinField(field, "forward"));
    bool known = false;
    for (ModelForward f : {ModelForward::PlusY, ModelForward::MinusY, ModelForward::PlusX, ModelForward::MinusX})
      if (fw == forwardName(f)) {
        type.forward = f;
        known = true;
      }
    if (!known) r.fail(joinField(field, "forward"), "expected +y, -y, +x or -x, got '" + fw + "'");
  }
  if (t.contains("origin")) {
    const std::string o = r.string(t["origin"], joinField(field, "origin"));
    bool known = false;
    for (ModelOrigin m : {ModelOrigin::Base, ModelOrigin::Centre, ModelOrigin::File})
      if (o == originName(m)) {
        type.origin = m;
        known = true;
      }
    if (!known) r.fail(joinField(field, "origin"), "expected base, centre or file, got '" + o + "'");
  }
  if (t.contains("kind")) type.kind = r.string(t["kind"], joinField(field, "kind"));
  if (t.contains("use_only")) type.useOnly = r.boolean(t["use_only"], joinField(field, "use_only"));
  if (t.contains("scale")) type.scale = r.positive(t["scale"], joinField(field, "scale"));
  if (t.contains("piece_length")) type.pieceLength = r.positive(t["piece_length"], joinField(field, "piece_length"));
  if (t.contains("max_gap")) type.maxGap = r.nonNegative(t["max_gap"], joinField(field, "max_gap"));
  if (t.contains("max_overlap")) type.maxOverlap = r.nonNegative(t["max_overlap"], joinField(field, "max_overlap"));
  return type;
}

}  // namespace

std::map<std::string, ModelType> parseModelTypes(const Json& types, const std::string& file, const std::string& folder,
                                                 const std::string& field) {
  const JsonFieldReader r(file, folder);
  r.checkObject(types, field);
  std::map<std::string, ModelType> out;
  for (auto it = types.begin(); it != types.end(); ++it) {
    if (it.key().empty()) r.fail(field, "a type with an empty name");
    out.emplace(it.key(), readType(r, it.key(), it.value(), joinField(field, it.key())));
  }
  return out;
}

ModelCatalog readModelCatalog(const std::string& path) { return parseModelCatalog(readJsonFile(path, "catalog"), path); }

ModelCatalog parseModelCatalog(const std::string& text, const std::string& path) {
  const Json root = parseJsonStrictly(text, path);
  const JsonFieldReader r(path, fs::path(path).parent_path());
  r.checkObject(root, "");
  r.checkKeys(root, "", {"types"});
  if (!root.contains("types")) r.fail("types", "missing (the catalog's types are required)");
  ModelCatalog catalog;
  catalog.path = path;
  catalog.types = parseModelTypes(root["types"], path, fs::path(path).parent_path().string(), "types");
  if (catalog.types.empty()) r.fail("types", "no type: a catalog needs at least one");
  std::vector<std::string> missing;
  std::set<std::string> checked;
  for (const auto& [name, type] : catalog.types)
    if (checked.insert(type.model).second && !fs::is_regular_file(type.model))
      missing.push_back("types." + name + ".model: " + type.model);
  failOnMissingModels(path, missing);
  return catalog;
}

Json modelTypeJson(const ModelType& type, const std::string& modelPath) {
  Json j = Json::object();
  j["model"] = modelPath;
  bool named = false;
  for (const NamedUnit& k : kUnits)
    if (type.unitsText == k.name) named = true;
  if (named) j["units"] = type.unitsText;
  else j["units"] = type.metresPerUnit;
  j["up"] = upName(type.up);
  j["forward"] = forwardName(type.forward);
  j["origin"] = originName(type.origin);
  if (!type.kind.empty()) j["kind"] = type.kind;
  if (type.useOnly) j["use_only"] = true;
  if (type.scale != 1.0) j["scale"] = type.scale;
  if (type.pieceLength) j["piece_length"] = *type.pieceLength;
  if (type.maxGap) j["max_gap"] = *type.maxGap;
  if (type.maxOverlap) j["max_overlap"] = *type.maxOverlap;
  return j;
}

Mat3<double> modelTypeRotation(const ModelType& type) {
  Mat3<double> up = Mat3<double>::Identity();
  switch (type.up) {
    case ModelUp::Z: break;
    case ModelUp::Y: up << 1, 0, 0, 0, 0, -1, 0, 1, 0; break;        // Rx(+90): (x, y, z) -> (x, -z, y)
    case ModelUp::MinusY: up << 1, 0, 0, 0, 0, 1, 0, -1, 0; break;   // Rx(-90): (x, y, z) -> (x, z, -y)
    case ModelUp::MinusZ: up << 1, 0, 0, 0, -1, 0, 0, 0, -1; break;  // Rx(180): (x, y, z) -> (x, -y, -z)
  }
  Mat3<double> forward = Mat3<double>::Identity();               // turns the forward axis onto +y
  switch (type.forward) {
    case ModelForward::PlusY: break;
    case ModelForward::MinusY: forward << -1, 0, 0, 0, -1, 0, 0, 0, 1; break;  // Rz(180)
    case ModelForward::PlusX: forward << 0, -1, 0, 1, 0, 0, 0, 0, 1; break;    // Rz(+90): +x -> +y
    case ModelForward::MinusX: forward << 0, 1, 0, -1, 0, 0, 0, 0, 1; break;   // Rz(-90): -x -> +y
  }
  return forward * up;
}

Similarity<double> modelTypeTransform(const ModelType& type, const std::vector<Vec3<double>>& filePoints) {
  Similarity<double> t;
  t.rotation = modelTypeRotation(type);
  t.scale = type.metresPerUnit;
  if (type.origin == ModelOrigin::File || filePoints.empty()) return t;
  Aabb<double> box;
  for (const Vec3<double>& p : filePoints) box.extend(t.apply(p));
  const Vec3<double> centre = box.center();
  t.translation = -Vec3<double>(centre.x(), centre.y(), type.origin == ModelOrigin::Base ? box.min.z() : centre.z());
  return t;
}

double pieceLength(const ModelType& type, const std::vector<Vec3<double>>& filePoints) {
  if (type.pieceLength) return *type.pieceLength;
  const Similarity<double> t = modelTypeTransform(type, filePoints);
  double lo = INFINITY, hi = -INFINITY;
  for (const Vec3<double>& p : filePoints) {
    const double y = t.apply(p).y();
    lo = std::min(lo, y);
    hi = std::max(hi, y);
  }
  return hi > lo ? type.scale * (hi - lo) : 0.0;
}

double maxGap(const ModelType& type, double piece) { return type.maxGap.value_or(kDefaultGapFraction * piece); }
double maxOverlap(const ModelType& type, double piece) {
  return type.maxOverlap.value_or(kDefaultOverlapFraction * piece);
}

}  // namespace nestwalk
