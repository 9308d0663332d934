#include "nestwalk/gis/scene_builder.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/geometry/convex_hull.h"
#include "nestwalk/gis/fence_layout.h"
#include "nestwalk/scene/model_catalog.h"
#include "nestwalk/scene/model_geometry.h"
#include "nestwalk/scene/placement.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/imagery_import.h"
#include "nestwalk/terrain/terrain_imagery.h"
#include "nestwalk/terrain/paged_heightfield.h"
#include "nestwalk/terrain/terrain_import.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <tuple>
#include <filesystem>
#include <map>
#include <set>

namespace nestwalk::gis {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

/// A type of the catalog, loaded: its model's hull (file frame) and transform.
struct LoadedType {
  const ModelType* type = nullptr;
  std::vector<Vec3<double>> hull;
  Similarity<double> transform;
};

/// One instance to write.
struct Placed {
  std::string name, type, group;
  Eigen::Vector2d position;
  double headingDeg = 0;
  double scale = 1;
};

/// What a feature became, before the bad ones are dropped.
struct Built {
  const MapFeature* feature;
  std::vector<Placed> instances;
  std::vector<std::string> problems;
  std::vector<double> rises;  // metres of ground under each instance's footprint
  bool fence = false;
};

std::string metres(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", v);
  return text;
}

/// Whether `inner` lies inside the folder `outer` (both made absolute and normal).
bool isInside(const fs::path& inner, const fs::path& outer) {
  const fs::path a = fs::absolute(inner).lexically_normal(), b = fs::absolute(outer).lexically_normal();
  const auto mismatch = std::mismatch(b.begin(), b.end(), a.begin(), a.end());
  return mismatch.first == b.end();
}

class Builder {
 public:
  Builder(const BuildSceneOptions& o, const ModelCatalog& catalog, const terrain::Heightfield& hf)
      : o_(o), catalog_(catalog), hf_(hf) {}

  Built build(const MapFeature& f) {
    Built b{&f, {}, {}, {}, f.shape != FeatureShape::Point};
    const LoadedType* t = typeOf(f.type);
    if (!t) {
      std::string known;
      for (const auto& [name, type] : catalog_.types) known += (known.empty() ? "" : ", ") + name;
      b.problems.push_back("unknown type '" + f.type + "' (the catalog has: " + known + ")");
      return b;
    }
    const double scale = f.scale.value_or(t->type->scale);
    const std::string name = f.name.empty() ? f.layer + "/" + f.type + "#" + std::to_string(f.fid) : f.name;
    if (f.shape == FeatureShape::Point) {
      b.instances.push_back({name, f.type, f.group.empty() ? f.layer : f.group, f.points[0], f.headingDeg, scale});
    } else {
      const double piece = pieceLength(*t->type, t->hull) * (f.scale ? *f.scale / t->type->scale : 1.0);
      if (!(piece > 0)) {
        b.problems.push_back("type '" + f.type + "' has no length along its forward axis: give it a piece_length");
        return b;
      }
      const FenceLayout layout = layoutFence(f.points, f.shape == FeatureShape::Ring, piece, maxGap(*t->type, piece),
                                             maxOverlap(*t->type, piece));
      for (const std::string& p : layout.problems) b.problems.push_back(p);
      for (std::size_t k = 0; k < layout.pieces.size(); ++k)
        b.instances.push_back({name + "/" + std::to_string(k), f.type, name, layout.pieces[k].centre,
                               layout.pieces[k].headingDeg, scale});
    }
    for (const Placed& p : b.instances) checkGround(*t, p, b);
    return b;
  }

  /// The warning of a feature whose instances stand on more rising ground than allowed ("": none).
  std::string riseWarning(const Built& b) const {
    std::size_t over = 0;
    double most = 0;
    for (double r : b.rises) {
      over += r > o_.maxFootprintRise;
      most = std::max(most, r);
    }
    if (over == 0) return {};
    const std::string limit = " m of rising ground (more than --max-footprint-rise " + metres(o_.maxFootprintRise) +
                              " m): the uphill side sinks into the ground by that much";
    if (!b.fence) return "stands on " + metres(most) + limit;
    return std::to_string(over) + " of its " + std::to_string(b.rises.size()) + " pieces stand on up to " + metres(most) + limit;
  }

 private:
  /// The type, its model read and its transform computed on first use; null when unknown.
  const LoadedType* typeOf(const std::string& name) {
    if (const auto it = loaded_.find(name); it != loaded_.end()) return &it->second;
    const auto t = catalog_.types.find(name);
    if (t == catalog_.types.end()) return nullptr;
    LoadedType lt;
    lt.type = &t->second;
    try {
      lt.hull = convexHull(loadModelGeometry(t->second.model).vertices).vertices;
    } catch (const InputError& e) {
      throw InputError(catalog_.path + ": types." + name + ".model: " + e.what());
    }
    lt.transform = modelTypeTransform(t->second, lt.hull);
    return &loaded_.emplace(name, std::move(lt)).first->second;
  }

  /// As the scene loader will place it (scene_loader.h): on ground everywhere under its footprint.
  void checkGround(const LoadedType& t, const Placed& p, Built& b) {
    Similarity<double> placed;
    placed.rotation = attitudeRotation(p.headingDeg, 0, 0);
    placed.scale = p.scale;
    placed.translation = Eigen::Vector3d(p.position.x(), p.position.y(), 0.0);
    const terrain::GroundSpan ground =
        groundUnderFootprint(hf_, Eigen::Vector3d::Zero(), placed * t.transform, t.hull);
    const std::string who = b.fence ? "piece " + p.name + " " : "";
    if (!ground.complete())
      b.problems.push_back(who + (ground.points == 0 ? "has no ground under it" : "has no ground under part of it") +
                           " (outside the terrain, or over nodata) at (" + metres(p.position.x()) + ", " +
                           metres(p.position.y()) + ")");
    b.rises.push_back(ground.rise());
  }

  const BuildSceneOptions& o_;
  const ModelCatalog& catalog_;
  const terrain::Heightfield& hf_;
  std::map<std::string, LoadedType> loaded_;
};

/// The path written in scene.json for `p`: relative to the scene's folder.
std::string relativeTo(const fs::path& p, const fs::path& folder) {
  return fs::relative(fs::absolute(p), fs::absolute(folder)).generic_string();
}

}  // namespace

BuildSceneSummary buildScene(const BuildSceneOptions& o) {
  const fs::path out = fs::path(o.out).lexically_normal();
  if (out.empty()) throw InputError("--out: give the scene's folder");
  std::error_code ec;
  if (fs::exists(out, ec) && !o.overwrite) throw InputError(out.string() + ": already exists (use --overwrite to replace it)");
  if (!(o.maxFootprintRise >= 0)) throw InputError("--max-footprint-rise: must be >= 0 metres");
  const ModelCatalog catalog = readModelCatalog(o.catalog);
  for (const auto& [name, type] : catalog.types)
    if (isInside(type.model, out))
      throw InputError(catalog.path + ": types." + name + ".model: " + type.model +
                       " lies inside the output folder, which build-scene replaces");
  if (!fs::exists(o.terrain, ec)) throw InputError(o.terrain + ": file not found");
  fs::create_directories(out.has_parent_path() ? out.parent_path() : fs::path("."), ec);

  OutputFolder folder(out.string());
  BuildSceneSummary summary;
  // The terrain: used where it is when it is already the engine's format (and not inside the
  // folder about to be replaced), else imported into the scene's folder.
  std::string terrainInScene;
  std::string terrainPath;
  if (terrain::isTerrainCog(o.terrain) && !isInside(o.terrain, out)) {
    terrainPath = o.terrain;
    terrainInScene = relativeTo(o.terrain, out);
  } else {
    terrainPath = (fs::path(folder.tempPath()) / "terrain.tif").string();
    terrain::importTerrain(o.terrain, terrainPath, {});
    terrainInScene = "terrain.tif";
    summary.terrainImported = true;
  }
  const terrain::Heightfield hf = terrain::openTerrainHeightfield(terrainPath);  // paged when it has a pyramid
  if (hf.crsWkt().empty())
    throw InputError(o.terrain + ": has no CRS, so the layers cannot be placed on it (import it with --crs first)");
  summary.terrainCrs = terrain::crsName(hf.crsWkt());
  // The orthophoto: named where it is when it can be draped as it is (and is not inside the folder
  // about to be replaced), else imported beside the terrain; either way it must overlap it.
  std::string imageryInScene;
  if (!o.imagery.empty()) {
    std::string imageryPath;
    if (terrain::imageryReadyToDrape(o.imagery, hf.crsWkt()) && !isInside(o.imagery, out)) {
      imageryPath = o.imagery;
      imageryInScene = relativeTo(o.imagery, out);
    } else {
      imageryPath = (fs::path(folder.tempPath()) / "imagery.tif").string();
      terrain::importImagery(o.imagery, imageryPath, hf.crsWkt());
      imageryInScene = "imagery.tif";
      summary.imageryImported = true;
    }
    const Eigen::Vector2d first = hf.samplePosition(0, 0), last = hf.samplePosition(hf.cols() - 1, hf.rows() - 1);
    try {
      terrain::requireImageryOverlap(terrain::TerrainImagery(imageryPath, hf.crsWkt()), first.x(), first.y(), last.x(),
                                     last.y());
    } catch (const InputError& e) {
      throw InputError(o.imagery + std::string(e.what()).substr(imageryPath.size()));
    }
  }

  const LayerFeatures features = readLayerFeatures(o.layers, hf.crsWkt());
  summary.layers = features.layers;

  // Every feature built; its problems, and those of reading it, by feature.
  Builder builder(o, catalog, hf);
  std::vector<Built> built;
  built.reserve(features.features.size());
  for (const MapFeature& f : features.features) built.push_back(builder.build(f));
  std::map<std::string, std::string> nameOwner;  // instance name -> the feature that has it
  for (Built& b : built)
    for (const Placed& p : b.instances) {
      const auto [it, added] = nameOwner.emplace(p.name, b.feature->where);
      if (!added) b.problems.push_back("name '" + p.name + "' is already the name of " + it->second);
    }
  std::vector<FeatureProblem> bad = features.problems;
  for (const Built& b : built)
    for (const std::string& p : b.problems)
      bad.push_back({b.feature->where, p, b.feature->source, b.feature->layer, b.feature->fid});
  std::stable_sort(bad.begin(), bad.end(), [](const FeatureProblem& a, const FeatureProblem& b) {
    return std::tie(a.source, a.layer, a.fid) < std::tie(b.source, b.layer, b.fid);
  });
  if (!bad.empty() && !o.skipBad) {
    std::string list;
    for (const FeatureProblem& p : bad) list += (list.empty() ? "" : "; ") + p.where + ": " + p.problem;
    throw InputError(std::to_string(bad.size()) + " bad feature" + (bad.size() == 1 ? "" : "s") +
                     " (fix them, or leave them out with --skip-bad): " + list);
  }
  summary.skipped = bad;

  // The scene file: the types used, then every instance of the good features.
  Json equipment = Json::array();
  std::set<std::string> used;
  for (const Built& b : built) {
    if (!b.problems.empty()) continue;
    if (const std::string w = builder.riseWarning(b); !w.empty()) summary.warnings.push_back(b.feature->where + ": " + w);
    if (b.fence) {
      ++summary.fences;
      summary.fencePieces += b.instances.size();
    } else {
      summary.pointInstances += b.instances.size();
    }
    for (const Placed& p : b.instances) {
      used.insert(p.type);
      Json e;
      e["name"] = p.name;
      e["type"] = p.type;
      e["position"] = {p.position.x(), p.position.y()};
      e["heading"] = p.headingDeg;
      if (p.scale != catalog.types.at(p.type).scale) e["scale"] = p.scale;
      e["group"] = p.group;
      equipment.push_back(e);
    }
  }
  if (equipment.empty()) throw InputError("no equipment to place: every feature was left out");
  Json types = Json::object();
  for (const std::string& t : used) {
    const ModelType& type = catalog.types.at(t);
    types[t] = modelTypeJson(type, relativeTo(type.model, out));
  }
  Json source;
  source["built_by"] = "nestwalk build-scene";
  source["terrain"] = o.terrain;
  source["terrain_imported"] = summary.terrainImported;
  if (!o.imagery.empty()) {
    source["imagery"] = o.imagery;
    source["imagery_imported"] = summary.imageryImported;
  }
  source["catalog"] = o.catalog;
  Json layers = Json::array();
  for (const LayerRead& l : summary.layers)
    layers.push_back({{"source", l.source}, {"layer", l.layer}, {"crs", l.crs}, {"features", l.features}});
  source["layers"] = layers;
  if (!o.layers.where.empty()) source["where"] = o.layers.where;
  Json skipped = Json::array();
  for (const FeatureProblem& p : summary.skipped) skipped.push_back({{"feature", p.where}, {"problem", p.problem}});
  source["skipped"] = skipped;
  source["warnings"] = summary.warnings;
  Json scene;
  scene["terrain"] = terrainInScene;
  if (!imageryInScene.empty()) scene["imagery"] = imageryInScene;
  scene["types"] = types;
  scene["equipment"] = equipment;
  scene["source"] = source;

  const fs::path sceneFile = fs::path(folder.tempPath()) / "scene.json";
  writeFileAtomically(sceneFile.string(), scene.dump(2) + "\n");
  // The scene loads as `nestwalk run` will load it (paths are relative to OUT, a sibling of the
  // temporary folder, so they resolve the same from both).
  try {
    loadScene(sceneFile.string());
  } catch (const InputError& e) {
    throw InputError(out.string() + ": the scene written does not load: " + e.what());
  }
  folder.commit();
  summary.sceneFile = (out / "scene.json").string();
  return summary;
}

}  // namespace nestwalk::gis
