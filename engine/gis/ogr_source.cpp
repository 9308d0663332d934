#include "nestwalk/gis/ogr_source.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/dem_reader.h"

#include <cpl_error.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>

namespace nestwalk::gis {
namespace {

/// Metres either side of a feature along its heading whose images give the heading in the target
/// CRS: far above the rounding of map coordinates (1e-9 m at UTM magnitudes: 1e-9 rad of angle),
/// far below the distance over which the grid's convergence changes (1e-7 degrees per metre).
constexpr double kHeadingProbe = 1.0;

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

}  // namespace

Srs traditionalAxes(OGRSpatialReferenceH s) {
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

Srs layerSrs(OGRLayerH layer, const std::string& assumedCrs, const std::string& what) {
  if (OGRSpatialReferenceH own = OGR_L_GetSpatialRef(layer)) return traditionalAxes(own);
  if (!assumedCrs.empty()) return srsFrom(assumedCrs, what + ": --layer-crs");
  throw InputError(what + ": has no CRS; give the CRS its coordinates are in with --layer-crs (e.g. EPSG:4326)");
}

Dataset openVectorSource(const std::string& source) {
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

LayerTransform::LayerTransform(OGRSpatialReferenceH layer, OGRSpatialReferenceH target, const std::string& what)
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

bool LayerTransform::point(double x, double y, Eigen::Vector2d& out) const {
  double z = 0;
  int ok = 0;
  if (!OCTTransformEx(transform_.get(), 1, &x, &y, &z, &ok) || !ok || !std::isfinite(x) || !std::isfinite(y))
    return false;
  out = {x, y};
  return true;
}

std::optional<double> LayerTransform::heading(double x, double y, double headingDeg) const {
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

}  // namespace nestwalk::gis
