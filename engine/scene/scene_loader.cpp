// Loading a scene (scene.h): terrain, models once per file, instance transforms and volumes, and
// the collision units.
#include "nestwalk/core/input_error.h"
#include "nestwalk/geometry/convex_hull.h"
#include "nestwalk/geometry/obb_fit.h"
#include "nestwalk/scene/model_file.h"
#include "nestwalk/scene/node_geometry.h"
#include "nestwalk/scene/placement.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/scene/terrain_cache.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/paged_heightfield.h"
#include "nestwalk/terrain/terrain_pyramid.h"


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

namespace nestwalk {
namespace {

/// The exact AABB of `local` = t.apply(model points), rounded outward as aabbOf (volumes.h) rounds:
/// by kOutwardRounding times the magnitudes involved in s * R * p + t (|t| + s * max |p| per axis),
/// which bounds the rounding of the computed points even where s * R * p and t nearly cancel.
Aabb<double> outwardBounds(const std::vector<Vec3<double>>& local, const std::vector<Vec3<double>>& model,
                           const Similarity<double>& t) {
  double radius = 0;
  for (const auto& p : model) radius = std::max(radius, p.norm());
  Aabb<double> b;
  for (const auto& p : local) b.extend(p);
  const Vec3<double> pad = kOutwardRounding<double> * (t.translation.cwiseAbs().array() + t.scale * radius).matrix();
  return {b.min - pad, b.max + pad};
}

std::vector<Vec3<double>> transformed(const Similarity<double>& t, const std::vector<Vec3<double>>& points) {
  std::vector<Vec3<double>> out;
  out.reserve(points.size());
  for (const auto& p : points) out.push_back(t.apply(p));
  return out;
}

/// The heightfield moved by `shift` (same samples; heights move by shift.z, rounded to float).
terrain::Heightfield shifted(const terrain::Heightfield& hf, const Eigen::Vector3d& shift) {
  std::vector<float> heights;
  heights.reserve(std::size_t(hf.cols()) * std::size_t(hf.rows()));
  for (int r = 0; r < hf.rows(); ++r)
    for (int c = 0; c < hf.cols(); ++c) heights.push_back(shift.z() == 0.0 ? hf.sample(c, r) : float(hf.sample(c, r) + shift.z()));
  std::optional<float> noData = hf.noData();
  if (noData && shift.z() != 0.0) {
    // Holes must stay holes: keep the sentinel where it was.
    for (std::size_t i = 0; i < heights.size(); ++i)
      if (hf.sample(int(i % std::size_t(hf.cols())), int(i / std::size_t(hf.cols()))) == *noData) heights[i] = *noData;
  }
  return terrain::Heightfield(hf.cols(), hf.rows(), std::move(heights), hf.origin().x() + shift.x(),
                              hf.origin().y() + shift.y(), hf.dx(), hf.dy(), noData, hf.crsWkt());
}

std::string quotedName(const EquipmentSpec& e) { return "'" + e.name + "'"; }

}  // namespace

void printSceneNote(const std::string& text) { std::fprintf(stderr, "nestwalk: note: %s\n", text.c_str()); }

Scene loadScene(const std::string& path, const SceneLoadOptions& options) {
  return loadScene(readSceneFile(path), options);
}

static_assert(kDefaultTerrainTileBudget == terrain::kDefaultHeightTileBudgetBytes);

Scene loadScene(const SceneSpec& spec, const SceneLoadOptions& options) {
  const std::string& file = spec.path;
  Scene scene;
  scene.spec = spec;

  // Terrain (map frame, moved by the shift): its pyramid (its own beside it, else the terrain
  // cache's), then the samples paged from the pyramid's terrain file or read whole.
  try {
    using Storage = SceneLoadOptions::TerrainStorage;
    scene.terrainHeightShift = options.mapShift.z();
    const auto [cols, rows] = terrain::rasterSize(spec.terrain);
    const std::uint64_t samples = std::uint64_t(cols) * std::uint64_t(rows);
    const bool wantPaged = options.terrainStorage == Storage::paged ||
                           (options.terrainStorage == Storage::automatic && samples > kResidentTerrainSamples);
    std::error_code ec;
    if (std::filesystem::exists(terrain::pyramidPathOf(spec.terrain), ec)) {
      try {
        scene.terrainPyramid = std::make_shared<const terrain::TerrainPyramid>(spec.terrain);
      } catch (const InputError& e) {
        scene.terrainPyramidRefused = e.what();
        if (options.note) options.note(scene.terrainPyramidRefused + " (not used)");
      }
    }
    if (wantPaged && !scene.terrainPyramid && (cols > 2 || rows > 2))
      scene.terrainPyramid = cachedTerrainPyramid(spec.terrain, nullptr, options.note);
    if (wantPaged && scene.terrainPyramid && std::max(cols, rows) > 9) {
      scene.terrain = std::make_shared<const terrain::Heightfield>(terrain::openPagedHeightfield(
          scene.terrainPyramid, {.budgetBytes = options.terrainTileBudget, .shift = options.mapShift}));
    } else {
      if (samples > terrain::kMaxDemSamples)
        throw InputError(spec.terrain + ": " + std::to_string(cols) + " x " + std::to_string(rows) +
                         " samples, too many to hold, and no terrain pyramid to page them from (nestwalk "
                         "import-terrain writes one; the terrain cache could not)");
      terrain::Heightfield hf = terrain::readDem(spec.terrain);
      if (!scene.terrainPyramid) scene.terrainPyramid = cachedTerrainPyramid(spec.terrain, &hf, options.note);
      const Eigen::Vector3d& s = options.mapShift;
      scene.terrain = std::make_shared<const terrain::Heightfield>(s.isZero() ? std::move(hf) : shifted(hf, s));
    }
  } catch (const InputError& e) {
    throw InputError(file + ": terrain: " + e.what());
  }
  const terrain::Heightfield& hf = *scene.terrain;
  if (spec.imagery) scene.drapedImagery = cachedImagery(*spec.imagery, hf.crsWkt(), options.note);
  if (spec.origin) {
    scene.origin = *spec.origin + options.mapShift;
  } else {
    // The centre of the samples' extent, z 0.
    const Eigen::Vector2d first = hf.samplePosition(0, 0), last = hf.samplePosition(hf.cols() - 1, hf.rows() - 1);
    scene.origin = {0.5 * (first.x() + last.x()), 0.5 * (first.y() + last.y()), 0.0};
  }

  // Models: each distinct file once, in order of first use.
  std::map<std::string, std::uint32_t> modelIndex;
  std::vector<std::string> unreadable;
  std::vector<ModelFile> read;
  for (const auto& e : spec.equipment) {
    if (modelIndex.count(e.model)) continue;
    modelIndex.emplace(e.model, std::uint32_t(scene.models.size()));
    SceneModel m;
    m.path = e.model;
    read.push_back(readModelFile(e.model));
    if (!read.back().node) unreadable.push_back(e.model + " (" + read.back().problem + ")");
    scene.models.push_back(std::move(m));
  }
  if (!unreadable.empty()) {
    std::string list;
    for (const auto& u : unreadable) list += (list.empty() ? "" : "; ") + u;
    throw InputError(file + ": " + std::to_string(unreadable.size()) + " model" + (unreadable.size() == 1 ? "" : "s") +
                     " could not be read: " + list);
  }
  for (std::size_t k = 0; k < scene.models.size(); ++k) {
    SceneModel& m = scene.models[k];
    try {
      m.mesh = collectModelGeometry(*read[k].node, m.path);
    } catch (const InputError& e) {
      throw InputError(file + ": model " + e.what());
    }
    m.drawing = std::move(read[k].osgb);
    m.hullPoints = convexHull(m.mesh.vertices).vertices;
    for (const auto& v : m.mesh.vertices) m.aabb.extend(v);
    m.obb = fitObb(m.hullPoints, spec.method.fitter);
  }

  // Types: each type's model-frame transform, from its model's hull points.
  for (const auto& [name, type] : spec.types) {
    const auto m = modelIndex.find(type.model);
    if (m != modelIndex.end()) scene.typeTransforms.emplace(name, modelTypeTransform(type, scene.models[m->second].hullPoints));
  }

  // Instances.
  std::vector<std::string> noGround;
  std::vector<std::vector<Vec3<double>>> points(spec.equipment.size());  // transformed hull points
  for (std::size_t i = 0; i < spec.equipment.size(); ++i) {
    const EquipmentSpec& e = spec.equipment[i];
    SceneInstance inst;
    inst.spec = std::uint32_t(i);
    inst.model = modelIndex.at(e.model);
    const SceneModel& model = scene.models[inst.model];
    Similarity<double> placed;
    placed.rotation = attitudeRotation(e.headingDeg, e.pitchDeg, e.rollDeg);
    placed.scale = e.scale;
    const Eigen::Vector3d position = e.position + options.mapShift;
    placed.translation = Eigen::Vector3d(position.x(), position.y(), e.hasZ ? position.z() : 0.0) - scene.origin;
    const Similarity<double> fromType = e.type.empty() ? Similarity<double>{} : scene.typeTransforms.at(e.type);
    inst.toLocal = placed * fromType;
    if (!e.hasZ) {
      const terrain::GroundSpan ground = groundUnderFootprint(hf, scene.origin, inst.toLocal, model.hullPoints);
      if (!ground.complete()) {
        char where[96];
        std::snprintf(where, sizeof where, " at (%.3f, %.3f)", e.position.x(), e.position.y());
        noGround.push_back("equipment[" + std::to_string(i) + "] " + quotedName(e) + where +
                           (ground.points == 0 ? "" : " (under part of its footprint)"));
        continue;
      }
      inst.toLocal.translation.z() += ground.lowest;  // it was -origin.z: now the ground's map z, local
      inst.footprintRise = ground.rise();
    }
    points[i] = transformed(inst.toLocal, model.hullPoints);
    inst.volume.outer = outwardBounds(points[i], model.hullPoints, inst.toLocal);
    inst.volume.inner = inst.toLocal.apply(model.obb);
    scene.instances.push_back(std::move(inst));
  }
  if (!noGround.empty()) {
    std::string list;
    for (const auto& n : noGround) list += (list.empty() ? "" : "; ") + n;
    throw InputError(file + ": no ground under " + list + " (give the position a z or move it onto the terrain)");
  }

  // Units: one per instance that is not use_only, one per group of use_only instances (placed where
  // its first member appears).
  std::map<std::string, std::uint32_t> groupUnit;
  for (auto& inst : scene.instances) {
    const EquipmentSpec& e = spec.equipment[inst.spec];
    if (!e.useOnly) {
      inst.unit = std::uint32_t(scene.units.size());
      scene.units.push_back({e.name, e.group, e.kind, inst.volume, {inst.spec}});
      continue;
    }
    auto [it, added] = groupUnit.emplace(e.group, std::uint32_t(scene.units.size()));
    if (added) scene.units.push_back({e.group, e.group, e.kind, {}, {}});
    CollisionUnit& unit = scene.units[it->second];
    if (unit.kind != e.kind) unit.kind.clear();  // mixed kinds: no label
    unit.instances.push_back(inst.spec);  // every spec entry is an instance: same index
    inst.unit = it->second;
  }
  for (const auto& [group, u] : groupUnit) {
    CollisionUnit& unit = scene.units[u];
    // The union of the members' outer boxes: the exact AABB of all their points, each rounded
    // outward by its own instance's magnitudes.
    std::vector<Vec3<double>> all;
    for (std::uint32_t k : unit.instances) {
      const auto& p = points[scene.instances[k].spec];
      all.insert(all.end(), p.begin(), p.end());
      unit.volume.outer.extend(scene.instances[k].volume.outer);
    }
    unit.volume.inner = fitObb(all, spec.method.fitter);
  }
  return scene;
}

}  // namespace nestwalk
