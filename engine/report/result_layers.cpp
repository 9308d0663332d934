#include "nestwalk/report/result_layers.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/report/frame_csv.h"
#include "nestwalk/terrain/dem_reader.h"

#include <cpl_error.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <type_traits>

namespace nestwalk {
namespace {

/// Metres: the GeoJSON's path is simplified within this of the walked one (its coordinates are
/// written to 1e-7 degrees, about 1 cm, as RFC 7946's GDAL writer does by default).
constexpr double kWebPathTolerance = 0.01;

/// An OGR dataset being written to a temporary file beside its target: close() closes it (GDAL
/// flushes on close), commit() renames it onto the target. The handles are owned, so a throw at
/// any point (the constructor's too) closes the dataset before the temporary is removed.
class LayerFile {
 public:
  LayerFile(const std::string& target, const char* driver, const std::string& crsWkt)
      : target_(target), file_(target, std::filesystem::path(target).extension().string()) {
    terrain::initGdal();
    CPLErrorReset();
    GDALDriverH d = GDALGetDriverByName(driver);
    ds_.reset(d ? GDALCreate(d, file_.tempPath().c_str(), 0, 0, 0, GDT_Unknown, nullptr) : nullptr);
    if (!ds_) fail("cannot be created");
    // One transaction for the whole file (GeoPackage: one SQLite commit instead of one per feature).
    GDALDatasetStartTransaction(ds_.get(), FALSE);
    if (!crsWkt.empty()) {
      srs_.reset(OSRNewSpatialReference(nullptr));
      if (OSRSetFromUserInput(srs_.get(), crsWkt.c_str()) != OGRERR_NONE) fail("the scene's CRS cannot be read");
      OSRSetAxisMappingStrategy(srs_.get(), OAMS_TRADITIONAL_GIS_ORDER);
    }
  }

  OGRLayerH layer(const char* name, OGRwkbGeometryType type, char** options = nullptr) {
    OGRLayerH l = GDALDatasetCreateLayer(ds_.get(), name, srs_.get(), type, options);
    if (!l) fail(std::string("cannot create the layer '") + name + "'");
    return l;
  }
  void field(OGRLayerH l, const char* name, OGRFieldType type, OGRFieldSubType subType = OFSTNone) {
    OGRFieldDefnH d = OGR_Fld_Create(name, type);
    OGR_Fld_SetSubType(d, subType);
    const OGRErr err = OGR_L_CreateField(l, d, TRUE);
    OGR_Fld_Destroy(d);
    if (err != OGRERR_NONE) fail(std::string("cannot add the field '") + name + "'");
  }
  /// Adds the feature (taking its geometry) and destroys it.
  void add(OGRLayerH l, OGRFeatureH f, OGRGeometryH g) {
    OGR_F_SetGeometryDirectly(f, g);
    const OGRErr err = OGR_L_CreateFeature(l, f);
    OGR_F_Destroy(f);
    if (err != OGRERR_NONE) fail(std::string("cannot write a feature of '") + OGR_L_GetName(l) + "'");
  }
  void close() {
    CPLErrorReset();
    if (GDALDatasetCommitTransaction(ds_.get()) == OGRERR_FAILURE) fail("cannot be written");
    ds_.reset();
    if (!terrain::lastGdalError().empty()) fail("cannot be written");
  }
  void commit() { file_.commit(); }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    const std::string gdal = terrain::lastGdalError();
    throw InputError(target_ + ": " + what + (gdal.empty() ? "" : ": " + gdal));
  }
  struct Close {
    void operator()(GDALDatasetH d) const { GDALClose(d); }
  };
  struct Release {
    void operator()(OGRSpatialReferenceH s) const { OSRRelease(s); }
  };

  std::string target_;
  OutputFile file_;
  std::unique_ptr<std::remove_pointer_t<GDALDatasetH>, Close> ds_;
  std::unique_ptr<std::remove_pointer_t<OGRSpatialReferenceH>, Release> srs_;
};

void setReal(OGRFeatureH f, const char* name, double v) {
  const int i = OGR_F_GetFieldIndex(f, name);
  if (std::isnan(v)) OGR_F_SetFieldNull(f, i);
  else OGR_F_SetFieldDouble(f, i, v);
}
void setInt(OGRFeatureH f, const char* name, std::int64_t v) { OGR_F_SetFieldInteger64(f, OGR_F_GetFieldIndex(f, name), v); }
void setText(OGRFeatureH f, const char* name, const std::string& v) {
  OGR_F_SetFieldString(f, OGR_F_GetFieldIndex(f, name), v.c_str());
}

OGRGeometryH pointZ(const Eigen::Vector3d& p) {
  OGRGeometryH g = OGR_G_CreateGeometry(wkbPoint25D);
  OGR_G_SetPoint(g, 0, p.x(), p.y(), p.z());
  return g;
}

double pathLength(const std::vector<FrameRecord>& records) {
  double length = 0;
  for (std::size_t i = 1; i < records.size(); ++i) length += (records[i].eye - records[i - 1].eye).norm();
  return length;
}

/// The path: one LineStringZM feature with the run's summary fields.
void writePath(LayerFile& file, OGRLayerH l, const RunSummaryInfo& info, const std::vector<FrameRecord>& records,
               const std::vector<ExpectationResult>& expectations, std::size_t contacts) {
  for (const char* name : {"scene", "script", "method"}) file.field(l, name, OFTString);
  for (const char* name : {"frames", "blocked_frames", "contacts", "expectations_met", "expectations_failed"})
    file.field(l, name, OFTInteger64);
  for (const char* name : {"seconds", "length_m"}) file.field(l, name, OFTReal);
  OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(l));
  setText(f, "scene", info.scene);
  setText(f, "script", info.script);
  setText(f, "method", info.method);
  std::int64_t blocked = 0, met = 0;
  for (const FrameRecord& r : records) blocked += r.blocked;
  for (const ExpectationResult& e : expectations) met += e.met;
  setInt(f, "frames", std::int64_t(records.size()));
  setInt(f, "blocked_frames", blocked);
  setInt(f, "contacts", std::int64_t(contacts));
  setInt(f, "expectations_met", met);
  setInt(f, "expectations_failed", std::int64_t(expectations.size()) - met);
  setReal(f, "seconds", records.empty() ? 0.0 : records.back().time);
  setReal(f, "length_m", pathLength(records));
  OGRGeometryH g = OGR_G_CreateGeometry(wkbLineStringZM);
  for (std::size_t i = 0; i < records.size(); ++i) {
    const FrameRecord& r = records[i];
    OGR_G_SetPointZM(g, int(i), r.eye.x(), r.eye.y(), r.eye.z(), r.time);
  }
  file.add(l, f, g);
}

void contactFields(LayerFile& file, OGRLayerH l) {
  file.field(l, "frame", OFTInteger64);
  file.field(l, "time_s", OFTReal);
  for (const char* name : {"unit", "kind", "group", "method"}) file.field(l, name, OFTString);
  for (const char* name : {"stop_gap_m", "approach_deg"}) file.field(l, name, OFTReal);
}

/// Fields some layers add: the GeoJSON's "feature" (its points then in plan), the methods report's
/// "script".
struct ContactLabels {
  const char* feature = nullptr;
  const std::string* script = nullptr;
};

void writeContact(LayerFile& file, OGRLayerH l, const RunContact& c, const std::string& method,
                  const ContactLabels& labels = {}) {
  OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(l));
  if (labels.feature) setText(f, "feature", labels.feature);
  if (labels.script) setText(f, "script", *labels.script);
  OGRGeometryH point = pointZ(c.eye);
  if (labels.feature) OGR_G_FlattenTo2D(point);
  setInt(f, "frame", std::int64_t(c.frame));
  setReal(f, "time_s", c.time);
  setText(f, "unit", c.unit);
  setText(f, "kind", c.kind);
  setText(f, "group", c.group);
  setText(f, "method", method);
  setReal(f, "stop_gap_m", c.stopGapM);
  setReal(f, "approach_deg", c.approachDeg);
  file.add(l, f, point);
}

void writeBlocked(LayerFile& file, OGRLayerH l, const std::vector<FrameRecord>& records, double dt) {
  file.field(l, "blocked_by", OFTString);
  for (const char* name : {"start_s", "end_s", "duration_s"}) file.field(l, name, OFTReal);
  file.field(l, "frames", OFTInteger64);
  for (std::size_t i = 0; i < records.size();) {
    if (!records[i].blocked) {
      ++i;
      continue;
    }
    std::size_t end = i + 1;
    while (end < records.size() && records[end].blocked && records[end].blockedBy == records[i].blockedBy) ++end;
    OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(l));
    setText(f, "blocked_by", records[i].blockedBy);
    setReal(f, "start_s", records[i].time - dt);
    setReal(f, "end_s", records[end - 1].time);
    setReal(f, "duration_s", double(end - i) * dt);
    setInt(f, "frames", std::int64_t(end - i));
    OGRGeometryH g = OGR_G_CreateGeometry(wkbLineString25D);
    for (std::size_t k = i; k < end; ++k) OGR_G_AddPoint(g, records[k].eye.x(), records[k].eye.y(), records[k].eye.z());
    if (end - i == 1) OGR_G_AddPoint(g, records[i].eye.x(), records[i].eye.y(), records[i].eye.z());
    file.add(l, f, g);
    i = end;
  }
}

void writeExpectations(LayerFile& file, OGRLayerH l, const std::vector<ExpectationResult>& expectations) {
  for (const char* name : {"script", "text", "detail"}) file.field(l, name, OFTString);
  file.field(l, "line", OFTInteger);
  file.field(l, "frame", OFTInteger64);
  file.field(l, "met", OFTInteger, OFSTBoolean);
  for (const ExpectationResult& e : expectations) {
    OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(l));
    setText(f, "script", e.script);
    setText(f, "text", e.text);
    setText(f, "detail", e.detail);
    setInt(f, "line", e.line);
    setInt(f, "frame", std::int64_t(e.frame));
    setInt(f, "met", e.met);
    file.add(l, f, pointZ(e.eye));
  }
}

void writeFrames(LayerFile& file, OGRLayerH l, const std::vector<FrameRecord>& records,
                 std::span<const RenderRecord> renders, std::size_t every) {
  const std::vector<std::string>& columns = frameCsvColumns();
  std::vector<FrameCell> cells;
  const RenderRecord notRendered;
  if (!records.empty()) {
    frameCells(records[0], notRendered, cells);
    for (std::size_t c = 0; c < columns.size(); ++c)
      file.field(l, columns[c].c_str(),
                 cells[c].kind == FrameCellKind::Text ? OFTString
                                                      : (cells[c].kind == FrameCellKind::Integer ? OFTInteger64 : OFTReal));
  }
  for (std::size_t i = 0; i < records.size(); ++i) {
    if (i % every != 0 && i + 1 != records.size()) continue;
    frameCells(records[i], renders.empty() ? notRendered : renders[i], cells);
    OGRFeatureH f = OGR_F_Create(OGR_L_GetLayerDefn(l));
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const int field = int(c);
      if (cells[c].kind == FrameCellKind::Text) OGR_F_SetFieldString(f, field, cells[c].text.c_str());
      else if (!cells[c].number) OGR_F_SetFieldNull(f, field);
      else if (cells[c].kind == FrameCellKind::Integer) OGR_F_SetFieldInteger64(f, field, GIntBig(*cells[c].number));
      else OGR_F_SetFieldDouble(f, field, *cells[c].number);
    }
    file.add(l, f, pointZ(records[i].eye));
  }
}

}  // namespace

ResultLayerFiles writeResultLayers(const std::string& base, const std::string& crsWkt, const RunSummaryInfo& info,
                                   const std::vector<FrameRecord>& records,
                                   const std::vector<ExpectationResult>& expectations,
                                   const std::vector<RunContact>& contacts, std::span<const RenderRecord> renders,
                                   std::size_t frameEvery) {
  ResultLayerFiles out;
  out.gpkg = base + ".gpkg";
  LayerFile gpkg(out.gpkg, "GPKG", crsWkt);
  writePath(gpkg, gpkg.layer("path", wkbLineStringZM), info, records, expectations, contacts.size());
  OGRLayerH c = gpkg.layer("contacts", wkbPoint25D);
  contactFields(gpkg, c);
  for (const RunContact& contact : contacts) writeContact(gpkg, c, contact, info.method);
  writeBlocked(gpkg, gpkg.layer("blocked", wkbLineString25D), records, info.dt);
  writeExpectations(gpkg, gpkg.layer("expectations", wkbPoint25D), expectations);
  writeFrames(gpkg, gpkg.layer("frames", wkbPoint25D), records, renders, std::max<std::size_t>(1, frameEvery));
  gpkg.close();
  if (crsWkt.empty()) {
    gpkg.commit();
    return out;
  }
  // GeoJSON (RFC 7946): one collection, the path and the contacts, told apart by "feature".
  out.geojson = base + ".geojson";
  LayerFile json(out.geojson, "GeoJSON", crsWkt);
  char rfc7946[] = "RFC7946=YES";
  char* options[] = {rfc7946, nullptr};
  OGRLayerH l = json.layer("results", wkbUnknown, options);
  json.field(l, "feature", OFTString);
  contactFields(json, l);
  OGRFeatureH path = OGR_F_Create(OGR_L_GetLayerDefn(l));
  setText(path, "feature", "path");
  setText(path, "method", info.method);
  OGRGeometryH line = OGR_G_CreateGeometry(wkbLineString);
  for (const FrameRecord& r : records) OGR_G_AddPoint_2D(line, r.eye.x(), r.eye.y());
  // A web map needs no point per step: the line (in plan) simplified within kWebPathTolerance
  // (GEOS's Douglas-Peucker through OGR), a few points per straight leg instead of 60 a second.
  OGRGeometryH simple = OGR_G_Simplify(line, kWebPathTolerance);
  if (simple) {
    OGR_G_DestroyGeometry(line);
    line = simple;
  }
  json.add(l, path, line);
  for (const RunContact& contact : contacts) writeContact(json, l, contact, info.method, {"contact"});
  json.close();
  // Both written: renamed together, so a failure leaves neither new file beside an old one.
  gpkg.commit();
  json.commit();
  return out;
}

void writeContactsLayer(const std::string& path, const std::string& crsWkt, const std::vector<ContactSet>& sets) {
  LayerFile gpkg(path, "GPKG", crsWkt);
  OGRLayerH l = gpkg.layer("contacts", wkbPoint25D);
  contactFields(gpkg, l);
  gpkg.field(l, "script", OFTString);
  for (const ContactSet& set : sets)
    for (const RunContact& c : *set.contacts) writeContact(gpkg, l, c, set.method, {nullptr, &set.script});
  gpkg.close();
  gpkg.commit();
}

}  // namespace nestwalk
