// The bundled GIS sample's files (gis_inputs.h).
#include "assets/generators/gis_inputs.h"

#include "assets/generators/generated_folder.h"
#include "assets/generators/to_lon_lat.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/core/input_error.h"

#include <gdal_priv.h>
#include <geodesic.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>
#include <nlohmann/json.hpp>
#include <osg/MatrixTransform>
#include <osgDB/WriteFile>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <stdexcept>

namespace nestwalk::assets {
namespace {

namespace fs = std::filesystem;

constexpr double kBarrierPiece = 3.0;     // metres: one jersey barrier, end to end (equipment_models.h)
constexpr float kNoData = -9999.0f;       // the DEM's nodata value (no cell uses it)
constexpr const char* kPickupCadFile = "pickup_mm_yup.osgt";

/// The catalog type of a model: its file stem ("weather_station").
std::string typeOf(ModelKind m) { return modelStem(m); }

struct GdalDataset {
  GDALDataset* ds = nullptr;
  ~GdalDataset() {
    if (ds) GDALClose(ds);
  }
};

/// The heights as a plain GeoTIFF: float32, deflate, strips (not the engine's tiled COG).
void writeDem(const GeneratedScene& scene, const fs::path& path) {
  const terrain::MiningDump& d = scene.dump;
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) throw InputError(path.string() + ": GDAL has no GTiff driver");
  char** options = CSLSetNameValue(nullptr, "COMPRESS", "DEFLATE");
  GdalDataset out{driver->Create(path.string().c_str(), d.cols, d.rows, 1, GDT_Float32, options)};
  CSLDestroy(options);
  if (!out.ds) throw InputError(path.string() + ": GDAL cannot create it");
  double transform[6] = {d.originX - 0.5 * d.cell, d.cell, 0, d.originY + 0.5 * d.cell, 0, -d.cell};
  OGRSpatialReference crs;
  if (out.ds->SetGeoTransform(transform) != CE_None || crs.SetFromUserInput(scene.site.crs) != OGRERR_NONE ||
      out.ds->SetSpatialRef(&crs) != CE_None)
    throw InputError(path.string() + ": cannot set its georeferencing");
  GDALRasterBand* band = out.ds->GetRasterBand(1);
  band->SetNoDataValue(kNoData);
  std::vector<float> heights = d.heights;
  if (band->RasterIO(GF_Write, 0, 0, d.cols, d.rows, heights.data(), d.cols, d.rows, GDT_Float32, 0, 0) != CE_None)
    throw InputError(path.string() + ": cannot write its heights");
}

OGRLayer* createLayer(GDALDataset& ds, const char* name, OGRSpatialReference crs, OGRwkbGeometryType type,
                      const std::vector<std::pair<const char*, OGRFieldType>>& fields, const fs::path& path) {
  OGRLayer* layer = ds.CreateLayer(name, &crs, type, nullptr);
  if (!layer) throw InputError(path.string() + ": cannot create layer " + name);
  for (const auto& [field, fieldType] : fields) {
    OGRFieldDefn defn(field, fieldType);
    if (layer->CreateField(&defn) != OGRERR_NONE)
      throw InputError(path.string() + ": layer " + name + ": cannot create field " + field);
  }
  return layer;
}

void addFeature(OGRLayer& layer, OGRGeometry& geometry, const std::map<std::string, std::string>& text,
                const std::map<std::string, double>& numbers, const fs::path& path) {
  OGRFeature* f = OGRFeature::CreateFeature(layer.GetLayerDefn());
  for (const auto& [k, v] : text) f->SetField(k.c_str(), v.c_str());
  for (const auto& [k, v] : numbers) f->SetField(k.c_str(), v);
  f->SetGeometry(&geometry);
  const OGRErr err = layer.CreateFeature(f);
  OGRFeature::DestroyFeature(f);
  if (err != OGRERR_NONE) throw InputError(path.string() + ": layer " + layer.GetName() + ": cannot write a feature");
}

/// The equipment points and the fence lines in EPSG:4326.
void writeLayers(const GeneratedScene& scene, const fs::path& path) {
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
  if (!driver) throw InputError(path.string() + ": GDAL has no GPKG driver");
  GdalDataset out{driver->Create(path.string().c_str(), 0, 0, 0, GDT_Unknown, nullptr)};
  if (!out.ds) throw InputError(path.string() + ": GDAL cannot create it");
  const ToLonLat toLonLat(scene.site.crs);
  OGRLayer* points = createLayer(*out.ds, "equipment", toLonLat.wgs84(), wkbPoint,
                                 {{"name", OFTString}, {"type", OFTString}, {"heading", OFTReal}, {"group", OFTString}},
                                 path);
  std::map<std::string, std::vector<const Placement*>> fences;  // group -> its barriers
  std::vector<std::string> fenceOrder;
  for (const Placement& p : scene.equipment) {
    if (p.model == ModelKind::JerseyBarrier) {
      if (fences[p.group].empty()) fenceOrder.push_back(p.group);
      fences[p.group].push_back(&p);
      continue;
    }
    const Eigen::Vector2d ll = toLonLat(p.position);
    OGRPoint point(ll.x(), ll.y());
    addFeature(*points, point, {{"name", p.name}, {"type", typeOf(p.model)}, {"group", p.group}},
               {{"heading", toLonLat.trueAzimuth(p.position, p.headingDeg)}}, path);
  }
  OGRLayer* lines = createLayer(*out.ds, "fences", toLonLat.wgs84(), wkbLineString,
                                {{"name", OFTString}, {"type", OFTString}}, path);
  for (const std::string& group : fenceOrder) {
    std::vector<const Placement*>& pieces = fences[group];
    const auto [s, c] = sinCosDegrees(pieces.front()->headingDeg);
    const Eigen::Vector2d along(s, c);
    std::sort(pieces.begin(), pieces.end(),
              [&](const Placement* a, const Placement* b) { return a->position.dot(along) < b->position.dot(along); });
    for (std::size_t i = 1; i < pieces.size(); ++i)  // the generator lays a fence's pieces end to end
      if (std::abs((pieces[i]->position - pieces[i - 1]->position).norm() - kBarrierPiece) > 0.01)
        throw std::logic_error("gis inputs: the pieces of " + group + " are not end to end");
    OGRLineString line;
    for (const Eigen::Vector2d& end : {Eigen::Vector2d(pieces.front()->position - 0.5 * kBarrierPiece * along),
                                       Eigen::Vector2d(pieces.back()->position + 0.5 * kBarrierPiece * along)}) {
      const Eigen::Vector2d ll = toLonLat(end);
      line.addPoint(ll.x(), ll.y());
    }
    addFeature(*lines, line, {{"name", group}, {"type", typeOf(ModelKind::JerseyBarrier)}}, {}, path);
  }
}

/// The pickup as a CAD export might have it: millimetres, y up, its origin at the middle of its
/// body.
void writePickupCad(const fs::path& path) {
  const Aabb<double> b = modelBounds(ModelKind::Pickup);
  const osg::Vec3d centre((b.min.x() + b.max.x()) / 2, (b.min.y() + b.max.y()) / 2, (b.min.z() + b.max.z()) / 2);
  // Engine frame (z up, +y forward) to the file's: about x by -90 degrees (z -> y, +y -> -z: the
  // catalog's "up": "y" turns it back), metres to millimetres, the box's centre to the origin.
  osg::ref_ptr<osg::MatrixTransform> cad = new osg::MatrixTransform(
      osg::Matrixd::translate(-centre) * osg::Matrixd::rotate(-std::numbers::pi / 2, osg::X_AXIS) *
      osg::Matrixd::scale(1000.0, 1000.0, 1000.0));
  cad->addChild(buildModel(ModelKind::Pickup));
  if (!osgDB::writeNodeFile(*cad, path.string()))
    throw InputError(path.string() + ": OpenSceneGraph could not write the model");
}

std::string catalogJson() {
  nlohmann::ordered_json types;
  for (ModelKind m : kAllModels) {
    nlohmann::ordered_json t;
    if (m == ModelKind::Pickup) {
      t["model"] = std::string("models/") + kPickupCadFile;
      t["units"] = "mm";
      t["up"] = "y";
    } else {
      t["model"] = "models/" + modelFileName(m);
      t["units"] = "m";
      t["up"] = "z";
    }
    t["origin"] = "base";
    t["kind"] = modelKindLabel(m);
    if (m == ModelKind::JerseyBarrier) {
      t["use_only"] = true;
      t["piece_length"] = kBarrierPiece;
    }
    types[typeOf(m)] = std::move(t);
  }
  return nlohmann::ordered_json{{"types", std::move(types)}}.dump(1) + "\n";
}

}  // namespace

void writeGisInputs(const GeneratedScene& scene, const std::string& dir, bool overwrite) {
  GDALAllRegister();
  writeGeneratedFolder(dir, overwrite, [&](const fs::path& tmp) {
    fs::create_directories(tmp / "models");
    fs::create_directories(tmp / "scripts");
    writeDem(scene, tmp / "dem.tif");
    writeLayers(scene, tmp / "equipment.gpkg");
    for (ModelKind m : kAllModels)
      if (m != ModelKind::Pickup) writeModel(m, (tmp / "models" / modelFileName(m)).string());
    writePickupCad(tmp / "models" / kPickupCadFile);
    writeTextFile(tmp / "catalog.json", catalogJson());
    for (const auto& [name, text] : scene.scripts) writeTextFile(tmp / "scripts" / name, text);
    if (!scene.routes.empty()) fs::create_directories(tmp / "routes");
    for (const auto& [name, text] : scene.routes) writeTextFile(tmp / "routes" / name, text);
  });
}

}  // namespace nestwalk::assets
