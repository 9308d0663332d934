// Small GDAL helpers shared by the DEM reader, the terrain import and the imagery import.
// Thread safety: a band belongs to a dataset that must not be used by another thread meanwhile
// (GDAL datasets are not thread-safe); the error text comes from lastGdalError(), which is per
// thread.
#pragma once

#include <gdal.h>

#include <cmath>
#include <string>
#include <vector>

namespace nestwalk::terrain {

/// A band's nodata value; a NaN nodata value marks every NaN sample as a hole.
struct BandNoData {
  bool has = false;
  double value = 0;
  bool isNan = false;
  /// Whether sample `v` is a hole (nodata).
  bool hole(double v) const { return has && (v == value || (isNan && std::isnan(v))); }
};

BandNoData bandNoData(GDALRasterBandH band);

/// Reads rows r0 .. r0 + n - 1 (all `cols` columns) of `band` as doubles into `strip` (resized to
/// n * cols). InputError naming `name` when GDAL cannot read them.
void readRowsFloat64(GDALRasterBandH band, int r0, int cols, int n, std::vector<double>& strip,
                     const std::string& name);

/// A NULL-terminated argv for GDAL's utility option parsers (GDALTranslateOptionsNew, ...).
struct GdalArgv {
  std::vector<std::string> args;
  std::vector<char*> ptrs;
  char** get() {
    ptrs.clear();
    for (auto& a : args) ptrs.push_back(a.data());
    ptrs.push_back(nullptr);
    return ptrs.data();
  }
};

/// A number as a GDAL utility argument: the shortest %.17g text that reads back to `v`.
std::string gdalNumber(double v);

}  // namespace nestwalk::terrain
