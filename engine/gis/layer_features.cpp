#include "nestwalk/gis/layer_features.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/gis/ogr_source.h"
#include "nestwalk/terrain/dem_reader.h"

#include <cpl_error.h>

#include <algorithm>
#include <memory>

namespace nestwalk::gis {
namespace {

/// Whether a layer's declared geometry can hold points or lines (unknown counts: the features tell).
bool pointOrLineLayer(OGRLayerH layer) {
  switch (wkbFlatten(OGR_L_GetGeomType(layer))) {
    case wkbNone: return false;
    default: return true;
  }
}

class LayerReader {
 public:
  LayerReader(const std::string& source, OGRLayerH layer, const LayerSelection& sel, OGRSpatialReferenceH target,
              LayerFeatures& out)
      : source_(source), layer_(layer), sel_(sel), out_(out), layerName_(OGR_L_GetName(layer)) {
    what_ = source + ": layer '" + layerName_ + "'";
    const Srs srs = layerSrs(layer, sel.assumedCrs, what_);
    crs_ = srsName(srs.get());
    transform_ = std::make_unique<LayerTransform>(srs.get(), target, what_);
  }

  void read() {
    if (!sel_.where.empty()) {
      CPLErrorReset();
      if (OGR_L_SetAttributeFilter(layer_, sel_.where.c_str()) != OGRERR_NONE)
        throw InputError(what_ + ": --where '" + sel_.where + "': " + terrain::lastGdalError());
    }
    if (OGR_L_GetFeatureCount(layer_, TRUE) == 0)
      throw InputError(what_ + (sel_.where.empty() ? ": has no features" : ": --where '" + sel_.where + "' matches no feature"));
    OGRFeatureDefnH defn = OGR_L_GetLayerDefn(layer_);
    typeField_ = OGR_FD_GetFieldIndex(defn, sel_.fields.type.c_str());
    nameField_ = OGR_FD_GetFieldIndex(defn, sel_.fields.name.c_str());
    headingField_ = OGR_FD_GetFieldIndex(defn, sel_.fields.heading.c_str());
    scaleField_ = OGR_FD_GetFieldIndex(defn, sel_.fields.scale.c_str());
    groupField_ = OGR_FD_GetFieldIndex(defn, sel_.fields.group.c_str());
    if (typeField_ < 0 && sel_.defaultType.empty())
      throw InputError(what_ + ": has no field '" + sel_.fields.type +
                       "' for the equipment type (name the field with --type-field, or give --default-type)");
    OGR_L_ResetReading(layer_);
    std::size_t count = 0;
    for (Feature f(OGR_L_GetNextFeature(layer_)); f; f.reset(OGR_L_GetNextFeature(layer_))) {
      ++count;
      readFeature(f.get());
    }
    out_.layers.push_back({source_, layerName_, crs_, count});
  }

 private:
  void problem(const MapFeature& f, const std::string& what) { out_.problems.push_back({f.where, what, f.source, f.layer, f.fid}); }

  void readFeature(OGRFeatureH f) {
    MapFeature base;
    base.source = source_;
    base.layer = layerName_;
    base.fid = OGR_F_GetFID(f);
    base.where = what_ + " feature " + std::to_string(base.fid);
    base.type = typeField_ >= 0 ? textField(f, typeField_) : std::string();
    if (base.type.empty()) base.type = sel_.defaultType;
    if (base.type.empty()) return problem(base, "no type (the field '" + sel_.fields.type + "' is empty)");
    base.name = textField(f, nameField_);
    base.group = textField(f, groupField_);
    bool ok = true;
    const std::optional<double> heading = numberField(f, headingField_, ok);
    if (!ok) return problem(base, "heading '" + textField(f, headingField_) + "' is not a number (degrees)");
    const std::optional<double> scale = numberField(f, scaleField_, ok);
    if (!ok || (scale && !(*scale > 0)))
      return problem(base, "scale '" + textField(f, scaleField_) + "' is not a number > 0");
    base.scale = scale;

    OGRGeometryH g = OGR_F_GetGeometryRef(f);
    if (!g || OGR_G_IsEmpty(g)) return problem(base, "has no geometry");
    std::vector<std::pair<OGRGeometryH, FeatureShape>> parts;
    const OGRwkbGeometryType t = wkbFlatten(OGR_G_GetGeometryType(g));
    auto addPolygon = [&](OGRGeometryH polygon) {
      if (OGR_G_GetGeometryCount(polygon) > 0) parts.push_back({OGR_G_GetGeometryRef(polygon, 0), FeatureShape::Ring});
    };
    switch (t) {
      case wkbPoint: parts.push_back({g, FeatureShape::Point}); break;
      case wkbLineString: parts.push_back({g, FeatureShape::Line}); break;
      case wkbPolygon: addPolygon(g); break;
      case wkbMultiPoint:
      case wkbMultiLineString:
      case wkbMultiPolygon:
        for (int i = 0; i < OGR_G_GetGeometryCount(g); ++i) {
          OGRGeometryH part = OGR_G_GetGeometryRef(g, i);
          if (t == wkbMultiPolygon) addPolygon(part);
          else parts.push_back({part, t == wkbMultiPoint ? FeatureShape::Point : FeatureShape::Line});
        }
        break;
      default:
        return problem(base, std::string("has an unsupported geometry (") + OGRGeometryTypeToName(t) +
                                       "): give points, lines or polygons");
    }
    for (std::size_t k = 0; k < parts.size(); ++k) {
      MapFeature m = base;
      m.shape = parts[k].second;
      if (parts.size() > 1) {
        m.where += " part " + std::to_string(k);
        if (!m.name.empty()) m.name += "#" + std::to_string(k);
      }
      OGRGeometryH part = parts[k].first;
      const int n = OGR_G_GetPointCount(part);
      for (int i = 0; i < n; ++i) {
        Eigen::Vector2d p;
        if (!transform_->point(OGR_G_GetX(part, i), OGR_G_GetY(part, i), p)) {
          problem(m, "cannot be transformed to the terrain's CRS (from " + crs_ + ")");
          m.points.clear();
          break;
        }
        if (m.points.empty() || p != m.points.back()) m.points.push_back(p);  // repeated vertices dropped
      }
      if (m.points.empty()) continue;
      if (m.shape == FeatureShape::Ring && m.points.size() > 1 && m.points.front() == m.points.back()) m.points.pop_back();
      if (m.shape != FeatureShape::Point && m.points.size() < 2) {
        problem(m, "a line with fewer than two distinct points");
        continue;
      }
      if (m.shape == FeatureShape::Point) {
        const std::optional<double> h =
            transform_->heading(OGR_G_GetX(part, 0), OGR_G_GetY(part, 0), heading.value_or(0.0));
        if (!h) {
          problem(m, "its heading cannot be transformed to the terrain's CRS");
          continue;
        }
        m.headingDeg = *h;
      }
      out_.features.push_back(std::move(m));
    }
  }

  std::string source_;
  OGRLayerH layer_;
  const LayerSelection& sel_;
  LayerFeatures& out_;
  std::string layerName_, what_, crs_;
  std::unique_ptr<LayerTransform> transform_;
  int typeField_ = -1, nameField_ = -1, headingField_ = -1, scaleField_ = -1, groupField_ = -1;
};

}  // namespace

LayerFeatures readLayerFeatures(const LayerSelection& selection, const std::string& targetCrs) {
  terrain::initGdal();
  if (selection.sources.empty()) throw InputError("--equipment: give at least one layer source");
  const Srs target = srsFrom(targetCrs, "the terrain");
  LayerFeatures out;
  std::vector<bool> layerFound(selection.layers.size(), false);
  for (const std::string& source : selection.sources) {
    const Dataset ds = openVectorSource(source);
    std::size_t read = 0;
    for (int i = 0; i < GDALDatasetGetLayerCount(ds.get()); ++i) {
      OGRLayerH layer = GDALDatasetGetLayer(ds.get(), i);
      const std::string name = OGR_L_GetName(layer);
      if (!selection.layers.empty()) {
        const auto it = std::find(selection.layers.begin(), selection.layers.end(), name);
        if (it == selection.layers.end()) continue;
        layerFound[std::size_t(it - selection.layers.begin())] = true;
      } else if (!pointOrLineLayer(layer)) {
        continue;  // an attribute table
      }
      LayerReader(source, layer, selection, target.get(), out).read();
      ++read;
    }
    if (read == 0 && selection.layers.empty()) throw InputError(source + ": has no point or line layer");
  }
  for (std::size_t k = 0; k < selection.layers.size(); ++k)
    if (!layerFound[k]) throw InputError("--layer " + selection.layers[k] + ": no such layer in the sources given");
  return out;
}

}  // namespace nestwalk::gis
