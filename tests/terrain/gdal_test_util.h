// Shared by the GDAL based terrain tests: writing sample values into a dataset's bands.
#pragma once

#include <gdal.h>
#include <gtest/gtest.h>

#include <optional>
#include <vector>

namespace nestwalk::test {

/// Writes `values` (cols x rows, row-major) into bands 1 .. bands of `ds`, band b offset by
/// 1000 * (b - 1), each with the nodata value `noData` when given.
inline void writeBands(GDALDatasetH ds, int cols, int rows, const std::vector<double>& values,
                       std::optional<double> noData, int bands) {
  for (int b = 1; b <= bands; ++b) {
    GDALRasterBandH band = GDALGetRasterBand(ds, b);
    if (noData) GDALSetRasterNoDataValue(band, *noData);
    std::vector<double> v = values;
    for (auto& x : v) x += 1000.0 * (b - 1);
    ASSERT_EQ(GDALRasterIO(band, GF_Write, 0, 0, cols, rows, v.data(), cols, rows, GDT_Float64, 0, 0), CE_None);
  }
}

}  // namespace nestwalk::test
