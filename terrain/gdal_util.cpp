#include "nestwalk/terrain/gdal_util.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/dem_reader.h"

#include <cpl_error.h>

#include <cstdio>

namespace nestwalk::terrain {

BandNoData bandNoData(GDALRasterBandH band) {
  BandNoData nd;
  int hasNoData = 0;
  nd.value = GDALGetRasterNoDataValue(band, &hasNoData);
  nd.has = hasNoData != 0;
  nd.isNan = nd.has && std::isnan(nd.value);
  return nd;
}

void readRowsFloat64(GDALRasterBandH band, int r0, int cols, int n, std::vector<double>& strip,
                     const std::string& name) {
  strip.resize(std::size_t(n) * std::size_t(cols));
  CPLErrorReset();
  if (GDALRasterIO(band, GF_Read, 0, r0, cols, n, strip.data(), cols, n, GDT_Float64, 0, 0) != CE_None)
    throw InputError(name + ": cannot read the samples (truncated or corrupt file?): " + lastGdalError());
}

std::string gdalNumber(double v) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

}  // namespace nestwalk::terrain
