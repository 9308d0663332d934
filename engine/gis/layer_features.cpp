#include "nestwalk/gis/layer_features.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/dem_reader.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <memory>

namespace nestwalk::gis {
namespace {

/// Metres either side of a feature along its heading whose images give the heading in the target
/// CRS: far above the rounding of map coordinates (1e-9 m at UTM magnitudes: 1e-9 rad of angle),
/// far below the distance over which the grid's convergence changes (1e-7 degrees per metre).
constexpr double kHeadingProbe = 1.0;

struct SrsRelease {
  void operator()(OGRSpatialReferenceH s) const { OSRRelease(s); }
};
using Srs = std::unique_ptr<std::remove_pointer_t<OGRSpatialReferenceH>, SrsRelease>;
struct TransformDestroy {
  void operator()(OGRCoordinateTransformationH t) const { OCTDestroyCoordinateTransformation(t); }
};
using Transform = std::unique_ptr<std::remove_pointer_t<OGRCoordinateTransformationH>, TransformDestroy>;
struct FeatureDestroy {
  void operator()(OGRFeatureH f) const { OGR_F_Destroy(f); }
};
using Feature = std::unique_ptr<std::remove_pointer_t<OGRFeatureH>, FeatureDestroy>;

Srs traditional(OGRSpatialReferenceH s) {
  Srs out(OSRClone(s));
  OSRSetAxisMappingStrategy(out.get(), OAMS_TRADITIONAL_GIS_ORDER);
  return out;
}

Srs srsFrom(const std::string& text, const std::string& what) {
  Srs s(OSRNewSpatialReference(nullptr));
  CPLErrorReset();
  if (OSRSetFromUserInput(s.get(), text.c_str()) != OGRERR_NONE)
    throw InputError(what + ": cannot read the CRS '" + text + "'" +
                     (terrain::lastGdalError().empty() ? "" : ": " + terrain::lastGdalError()));
  OSRSetAxisMappingStrategy(s.get(), OAMS_TRADITIONAL_GIS_ORDER);
  return s;
}

std::string srsName(OGRSpatialReferenceH s) {
  const char* name = OSRGetName(s);
  return name ? name : "unnamed CRS";
}

/// Carries points and headings from a layer's CRS into the target's.
class LayerTransform {
 public:
  LayerTransform(OGRSpatialReferenceH layer, OGRSpatialReferenceH target, const std::string& what)
      : geographic_(OSRIsGeographic(layer) != 0) {
    CPLErrorReset();
    transform_.reset(OCTNewCoordinateTransformation(layer, target));
    if (!transform_)
      throw InputError(what + ": cannot transform from its CRS (" + srsName(layer) + ") to the terrain's (" +
                       srsName(target) + ")" + (terrain::lastGdalError().empty() ? "" : ": " + terrain::lastGdalError()));
    if (geographic_) {
      OGRErr err = OGRERR_NONE;
      semiMajor_ = OSRGetSemiMajor(layer, &err);
      const double inverseFlattening = OSRGetInvFlattening(layer, &err);
      const double f = inverseFlattening > 0 ? 1.0 / inverseFlattening : 0.0;
      eccentricity2_ = f * (2.0 - f);
      char* unitName = nullptr;
      radiansPerUnit_ = OSRGetAngularUnits(layer, &unitName);
    } else {
      char* unitName = nullptr;
      metresPerUnit_ = OSRGetLinearUnits(layer, &unitName);
    }
  }

  /// The point in the target CRS; false when the transformation fails.
  bool point(double x, double y, Eigen::Vector2d& out) const {
    double z = 0;
    int ok = 0;
    if (!OCTTransformEx(transform_.get(), 1, &x, &y, &z, &ok) || !ok || !std::isfinite(x) || !std::isfinite(y))
      return false;
    out = {x, y};
    return true;
  }

  /// The target's grid azimuth of the layer-CRS azimuth `headingDeg` at (x, y); nullopt on failure.
  std::optional<double> heading(double x, double y, double headingDeg) const {
    const auto [sinH, cosH] = sinCosDegrees(headingDeg);
    double dx = 0, dy = 0;  // layer units per kHeadingProbe metres along the heading
    if (geographic_) {
      // Metres per radian of latitude (the meridian's radius of curvature M) and of longitude
      // (N cos(latitude), N the prime vertical's radius) on the layer's ellipsoid.
      const double latitude = y * radiansPerUnit_;
      const double w = std::sqrt(1.0 - eccentricity2_ * std::sin(latitude) * std::sin(latitude));
      const double m = semiMajor_ * (1.0 - eccentricity2_) / (w * w * w), n = semiMajor_ / w;
      dx = kHeadingProbe * sinH / (n * std::cos(latitude)) / radiansPerUnit_;
      dy = kHeadingProbe * cosH / m / radiansPerUnit_;
    } else {
      dx = kHeadingProbe * sinH / metresPerUnit_;
      dy = kHeadingProbe * cosH / metresPerUnit_;
    }
    Eigen::Vector2d ahead, behind;
    if (!point(x + dx, y + dy, ahead) || !point(x - dx, y - dy, behind)) return std::nullopt;
    const Eigen::Vector2d d = ahead - behind;
    return headingOf(d.x(), d.y());
  }

 private:
  Transform transform_;
  bool geographic_;
  double semiMajor_ = 0, eccentricity2_ = 0, radiansPerUnit_ = 1, metresPerUnit_ = 1;
};

/// Open options that let OGR's CSV driver find the geometry: X/Y columns by common names, or a WKT
/// column; attribute types detected so that numbers read as numbers.
const char* const kCsvOpenOptions[] = {
    "X_POSSIBLE_NAMES=x,easting,east,lon,long,longitude",
    "Y_POSSIBLE_NAMES=y,northing,north,lat,latitude",
    "GEOM_POSSIBLE_NAMES=wkt,geometry,geom",
    "KEEP_GEOM_COLUMNS=NO",
    "AUTODETECT_TYPE=YES",
    nullptr};

bool isCsv(const std::string& source) {
  std::string ext = std::filesystem::path(source).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".csv";
}

struct DatasetClose {
  void operator()(GDALDatasetH d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<std::remove_pointer_t<GDALDatasetH>, DatasetClose>;

Dataset openSource(const std::string& source) {
  terrain::initGdal();
  std::error_code ec;
  if (!source.empty() && std::filesystem::path(source).has_extension() && !std::filesystem::exists(source, ec))
    throw InputError(source + ": file not found");
  CPLErrorReset();
  Dataset ds(GDALOpenEx(source.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr,
                        isCsv(source) ? kCsvOpenOptions : nullptr, nullptr));
  if (!ds) {
    const std::string why = terrain::lastGdalError();
    throw InputError(source + ": cannot be read as a vector layer source" + (why.empty() ? "" : ": " + why));
  }
  return ds;
}

/// Whether a layer's declared geometry can hold points or lines (unknown counts: the features tell).
bool pointOrLineLayer(OGRLayerH layer) {
  switch (wkbFlatten(OGR_L_GetGeomType(layer))) {
    case wkbNone: return false;
    default: return true;
  }
}

/// The field as text ("" when unset), and as a number (nullopt unset; false in `ok` when not a number).
std::string textField(OGRFeatureH f, int field) {
  if (field < 0 || !OGR_F_IsFieldSetAndNotNull(f, field)) return {};
  const char* s = OGR_F_GetFieldAsString(f, field);
  std::string out = s ? s : "";
  const auto b = out.find_first_not_of(" \t"), e = out.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : out.substr(b, e - b + 1);
}

std::optional<double> numberField(OGRFeatureH f, int field, bool& ok) {
  ok = true;
  const std::string text = textField(f, field);
  if (text.empty()) return std::nullopt;
  // std::from_chars: a point as the decimal separator whatever locale the program set.
  const char* begin = text.data() + (text[0] == '+' ? 1 : 0);
  const char* end = text.data() + text.size();
  double v = 0;
  const auto r = std::from_chars(begin, end, v);
  if (r.ec != std::errc() || r.ptr != end || !std::isfinite(v)) {
    ok = false;
    return std::nullopt;
  }
  return v;
}

class LayerReader {
 public:
  LayerReader(const std::string& source, OGRLayerH layer, const LayerSelection& sel, OGRSpatialReferenceH target,
              LayerFeatures& out)
      : source_(source), layer_(layer), sel_(sel), out_(out), layerName_(OGR_L_GetName(layer)) {
    what_ = source + ": layer '" + layerName_ + "'";
    OGRSpatialReferenceH own = OGR_L_GetSpatialRef(layer);
    Srs layerSrs;
    if (own) {
      layerSrs = traditional(own);
    } else if (!sel.assumedCrs.empty()) {
      layerSrs = srsFrom(sel.assumedCrs, what_ + ": --layer-crs");
    } else {
      throw InputError(what_ + ": has no CRS; give the CRS its coordinates are in with --layer-crs (e.g. EPSG:4326)");
    }
    crs_ = srsName(layerSrs.get());
    transform_ = std::make_unique<LayerTransform>(layerSrs.get(), target, what_);
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
    const Dataset ds = openSource(source);
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
