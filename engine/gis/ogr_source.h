// What the GIS readers share of OGR (private to gis, not installed): owning handles for OGR's
// objects, opening a vector source (CSV files with the open options that find their geometry),
// spatial references in the traditional GIS axis order (east first, whatever the CRS's official
// order), a transformation from a layer's CRS to the terrain's that also carries headings, and
// attribute fields read as text or numbers.
//
// Errors: InputError naming the source (and layer, through `what`) and GDAL's last message.
// Thread safety: every object here is the caller's; GDAL's last-error text is per thread.
#pragma once

#include <Eigen/Core>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <memory>
#include <optional>
#include <string>
#include <type_traits>

namespace nestwalk::gis {

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
struct DatasetClose {
  void operator()(GDALDatasetH d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<std::remove_pointer_t<GDALDatasetH>, DatasetClose>;

/// A copy of `s` set to the traditional GIS axis order.
Srs traditionalAxes(OGRSpatialReferenceH s);
/// The CRS named by `text` (WKT, "EPSG:n", anything OSRSetFromUserInput takes), traditional axis
/// order; InputError "WHAT: cannot read the CRS ..." when it cannot be read.
Srs srsFrom(const std::string& text, const std::string& what);
/// The CRS's name as OGR gives it ("unnamed CRS" without one).
std::string srsName(OGRSpatialReferenceH s);
/// A layer's CRS (traditional axis order): its own, else `assumedCrs` (--layer-crs), else
/// InputError "WHAT: has no CRS; give ... --layer-crs".
Srs layerSrs(OGRLayerH layer, const std::string& assumedCrs, const std::string& what);

/// Opens a vector source read-only (runs initGdal first). InputError when a file path does not
/// exist or OGR cannot open it.
Dataset openVectorSource(const std::string& source);

/// Carries points and headings from a layer's CRS into the target's.
class LayerTransform {
 public:
  /// InputError "WHAT: cannot transform from its CRS (...) to the terrain's (...)".
  LayerTransform(OGRSpatialReferenceH layer, OGRSpatialReferenceH target, const std::string& what);

  /// The point in the target CRS; false when the transformation fails.
  bool point(double x, double y, Eigen::Vector2d& out) const;

  /// The target's grid azimuth of the layer-CRS azimuth `headingDeg` (degrees clockwise from the
  /// layer CRS's north) at (x, y): two points kHeadingProbe metres either side along the heading
  /// (on the ellipsoid for a geographic layer) carried through; nullopt on failure.
  std::optional<double> heading(double x, double y, double headingDeg) const;

 private:
  Transform transform_;
  bool geographic_;
  double semiMajor_ = 0, eccentricity2_ = 0, radiansPerUnit_ = 1, metresPerUnit_ = 1;
};

/// The field as text, blanks trimmed ("" when unset or field < 0).
std::string textField(OGRFeatureH f, int field);
/// The field as a number: nullopt when unset; `ok` false when set but not a finite number (read
/// with a point as the decimal mark whatever the locale).
std::optional<double> numberField(OGRFeatureH f, int field, bool& ok);

}  // namespace nestwalk::gis
