// The imagery import (imagery_import.h).
#include "nestwalk/terrain/imagery_import.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/gdal_util.h"
#include "nestwalk/terrain/terrain_imagery.h"

#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include <cstdio>
#include <filesystem>

namespace nestwalk::terrain {
namespace {

namespace fs = std::filesystem;

}  // namespace

bool imageryReadyToDrape(const std::string& path, const std::string& terrainCrsWkt) {
  try {
    GdalDataset owned = openRaster(path);
    auto* ds = static_cast<GDALDatasetH>(owned.get());
    const int cols = GDALGetRasterXSize(ds), rows = GDALGetRasterYSize(ds), bands = GDALGetRasterCount(ds);
    if (bands < 1) return false;
    for (int b = 1; b <= bands; ++b)
      if (GDALGetRasterDataType(GDALGetRasterBand(ds, b)) != GDT_Byte) return false;
    const char* wkt = GDALGetProjectionRef(ds);
    if (wkt && *wkt && !terrainCrsWkt.empty()) {
      OGRSpatialReferenceH a = OSRNewSpatialReference(wkt), b = OSRNewSpatialReference(terrainCrsWkt.c_str());
      const bool same = OSRIsSame(a, b);
      OSRDestroySpatialReference(a);
      OSRDestroySpatialReference(b);
      if (!same) return false;
    }
    if (cols <= kImageryReadySide && rows <= kImageryReadySide) return true;
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    int blockX = 0, blockY = 0;
    GDALGetBlockSize(band, &blockX, &blockY);
    return blockX < cols && blockY > 1 && GDALGetOverviewCount(band) > 0;
  } catch (const std::exception&) {
    return false;
  }
}

namespace {

/// Whether the opened orthophoto `ds` (at `path`) already is what importImagery writes: a GeoTIFF
/// in one file (no .ovr, .aux.xml, .tfw or .msk beside it that a copy of the file alone would
/// lose), ready to drape in the terrain's CRS, tiled with overviews.
bool alreadyImported(GDALDatasetH ds, const std::string& path, const std::string& terrainCrsWkt) {
  GDALDriverH driver = GDALGetDatasetDriver(ds);
  if (!driver || std::string(GDALGetDriverShortName(driver)) != "GTiff") return false;
  char** files = GDALGetFileList(ds);
  const bool alone = CSLCount(files) == 1;
  CSLDestroy(files);
  if (!alone) return false;
  GDALRasterBandH band = GDALGetRasterBand(ds, 1);
  int blockX = 0, blockY = 0;
  GDALGetBlockSize(band, &blockX, &blockY);
  return blockX < GDALGetRasterXSize(ds) && blockY > 1 && GDALGetOverviewCount(band) > 0 &&
         imageryReadyToDrape(path, terrainCrsWkt);
}

}  // namespace

std::string imageryPathOf(const std::string& terrainOut) {
  fs::path p(terrainOut);
  return (p.parent_path() / (p.stem().string() + "_imagery.tif")).string();
}

ImageryImportSummary importImagery(const std::string& in, const std::string& out, const std::string& terrainCrsWkt,
                                   bool overwrite, bool progress) {
  if (fs::exists(out) && !overwrite) throw InputError(out + ": exists; pass --overwrite to replace it");
  ImageryImportSummary s;
  // 1. Opened as a drape opens it: the same refusals, the same reprojection decision and pixel size.
  const TerrainImagery imagery(in, terrainCrsWkt);
  s.warnings = imagery.warnings();
  s.reprojected = imagery.reprojected();
  s.pixelSize = imagery.pixelSize();
  s.bands = imagery.colourBands();
  GdalDataset source = openRaster(in);
  GDALDatasetH chain = static_cast<GDALDatasetH>(source.get());
  if (!s.reprojected && alreadyImported(chain, in, terrainCrsWkt)) {
    OutputFile file(out, ".tif");
    std::error_code ec;
    fs::copy_file(in, file.tempPath(), fs::copy_options::overwrite_existing, ec);
    if (ec) throw InputError(out + ": the imagery could not be copied from " + in + ": " + ec.message());
    GDALRasterBandH band = GDALGetRasterBand(chain, 1);
    s.copied = true;
    s.cols = GDALGetRasterXSize(chain);
    s.rows = GDALGetRasterYSize(chain);
    s.overviews = GDALGetOverviewCount(band);
    s.masked = (GDALGetMaskFlags(band) & (GMF_PER_DATASET | GMF_ALPHA | GMF_NODATA)) != 0;
    const std::string wkt = crsWkt(chain);
    s.crsName = wkt.empty() ? "none" : crsName(wkt);
    source.reset();
    file.commit();
    return s;
  }

  // 2. The virtual chain: warped to the terrain's CRS where they differ, then 8-bit colour bands.
  GdalDataset warped, translated;
  int usageError = 0;
  if (s.reprojected) {
    GdalArgv w;
    w.args = {"-of",
              "VRT",
              "-t_srs",
              terrainCrsWkt,
              "-r",
              "bilinear",
              "-tr",
              gdalNumber(s.pixelSize),
              gdalNumber(s.pixelSize),
              "-dstalpha"};
    GDALWarpAppOptions* options = GDALWarpAppOptionsNew(w.get(), nullptr);
    GDALDatasetH sources[1] = {chain};
    CPLErrorReset();
    warped.reset(GDALWarp("", nullptr, 1, sources, options, &usageError));
    GDALWarpAppOptionsFree(options);
    if (!warped) throw InputError(in + ": cannot warp the imagery to the terrain's CRS: " + lastGdalError());
    chain = static_cast<GDALDatasetH>(warped.get());
  }
  const int bandCount = GDALGetRasterCount(chain);
  int alphaBand = 0;
  for (int b = 1; b <= bandCount; ++b)
    if (GDALGetRasterColorInterpretation(GDALGetRasterBand(chain, b)) == GCI_AlphaBand) alphaBand = b;
  GdalArgv t;
  t.args = {"-of", "VRT", "-ot", "Byte"};
  for (int b = 1; b <= s.bands; ++b) t.args.insert(t.args.end(), {"-b", std::to_string(b)});
  if (alphaBand) t.args.insert(t.args.end(), {"-b", std::to_string(alphaBand)});
  if (GDALGetRasterDataType(GDALGetRasterBand(chain, 1)) != GDT_Byte) {
    for (int b = 1; b <= s.bands; ++b) {  // each colour band from its own range to 0-255
      double range[2] = {0, 255};
      if (GDALComputeRasterMinMax(GDALGetRasterBand(chain, b), FALSE, range) != CE_None)
        throw InputError(in + ": band " + std::to_string(b) + " cannot be read: " + lastGdalError());
      t.args.insert(t.args.end(),
                    {"-scale_" + std::to_string(b), gdalNumber(range[0]), gdalNumber(range[1]), "0", "255"});
    }
  }
  if (alphaBand) t.args.insert(t.args.end(), {"-colorinterp_" + std::to_string(s.bands + 1), "alpha"});
  GDALTranslateOptions* options = GDALTranslateOptionsNew(t.get(), nullptr);
  CPLErrorReset();
  translated.reset(GDALTranslate("", chain, options, &usageError));
  GDALTranslateOptionsFree(options);
  if (!translated) throw InputError(in + ": cannot convert the imagery to 8-bit colour: " + lastGdalError());
  s.masked = alphaBand != 0;

  // 3. The COG, written beside OUT and renamed.
  GDALDriverH cog = GDALGetDriverByName("COG");
  if (!cog) throw InputError(out + ": this GDAL has no COG driver");
  OutputFile file(out, ".tif");
  CPLStringList co;
  co.SetNameValue("COMPRESS", "JPEG");
  co.SetNameValue("QUALITY", std::to_string(kImageryJpegQuality).c_str());
  co.SetNameValue("BLOCKSIZE", std::to_string(kImageryTileSize).c_str());
  co.SetNameValue("OVERVIEWS", "IGNORE_EXISTING");
  co.SetNameValue("OVERVIEW_RESAMPLING", "AVERAGE");
  CPLErrorReset();
  GdalDataset written(GDALCreateCopy(cog, file.tempPath().c_str(), static_cast<GDALDatasetH>(translated.get()), FALSE,
                                     co.List(), progress ? GDALTermProgress : nullptr, nullptr));
  if (!written) throw InputError(out + ": the imagery could not be written: " + lastGdalError());
  auto* w = static_cast<GDALDatasetH>(written.get());
  s.cols = GDALGetRasterXSize(w);
  s.rows = GDALGetRasterYSize(w);
  s.overviews = GDALGetOverviewCount(GDALGetRasterBand(w, 1));
  const std::string wkt = crsWkt(w);
  s.crsName = wkt.empty() ? "none" : crsName(wkt);
  written.reset();
  file.commit();
  return s;
}

}  // namespace nestwalk::terrain
