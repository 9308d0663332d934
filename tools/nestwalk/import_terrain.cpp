// nestwalk import-terrain IN OUT [--imagery ORTHO]: any raster GDAL reads becomes the engine's
// terrain format, a Cloud-Optimized GeoTIFF of Float32 heights in metres (see
// terrain/terrain_import.h); with --imagery, the orthophoto becomes OUT_imagery.tif beside it, an
// 8-bit JPEG COG with overviews in the terrain's CRS (terrain/imagery_import.h), or a copy of it
// when it already is a tiled GeoTIFF ready to drape. Prints a
// summary on stdout; a progress bar on stderr when it is a terminal.
#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/imagery_import.h"
#include "nestwalk/terrain/terrain_import.h"
#include "tools/nestwalk/commands.h"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <unistd.h>

namespace nestwalk::tools {
namespace {

struct ImportArgs {
  std::string in, out;
  terrain::ImportOptions options;
  std::vector<double> window;
  double resolution = 0.0;
  std::string nodata = "keep";
  std::string imagery;  // an orthophoto to import beside the terrain (imagery_import.h)
};

void runImportTerrain(ImportArgs& args) {
  terrain::ImportOptions& o = args.options;
  if (!args.window.empty()) o.window = std::array<double, 4>{args.window[0], args.window[1], args.window[2], args.window[3]};
  if (args.resolution != 0.0) o.resolution = args.resolution;
  o.fillNoData = args.nodata == "fill";
  o.progress = ::isatty(2) != 0;
  const std::string imageryOut = terrain::imageryPathOf(args.out);
  if (!args.imagery.empty() && std::filesystem::exists(imageryOut) && !o.overwrite)
    throw InputError(imageryOut + ": exists; pass --overwrite to replace it");
  const terrain::ImportSummary s = terrain::importTerrain(args.in, args.out, o);
  for (const auto& w : s.warnings) std::fprintf(stderr, "nestwalk: warning: %s\n", w.c_str());
  std::printf("imported %s -> %s\n", args.in.c_str(), args.out.c_str());
  std::printf("  size:         %d x %d samples\n", s.cols, s.rows);
  std::printf("  cell size:    %.10g x %.10g%s\n", s.dx, s.dy, s.georeferenced ? " (CRS units)" : " (pixel units)");
  std::printf("  CRS:          %s\n", s.crsName.c_str());
  std::printf("  height range: %.3f .. %.3f m\n", double(s.minHeight), double(s.maxHeight));
  std::printf("  nodata:       %.4f %%\n", 100.0 * s.noDataFraction);
  if (!s.pyramidPath.empty())
    std::printf("  pyramid:      %s (%d levels)\n", s.pyramidPath.c_str(), s.pyramidLevels);
  if (args.imagery.empty()) return;
  // The orthophoto, in the CRS the terrain was written in.
  const std::string terrainWkt = terrain::crsWkt(terrain::openRaster(args.out).get());
  const terrain::ImageryImportSummary im = terrain::importImagery(args.imagery, imageryOut, terrainWkt, o.overwrite, o.progress);
  for (const auto& w : im.warnings) std::fprintf(stderr, "nestwalk: warning: %s\n", w.c_str());
  std::printf("  imagery:      %s: %d x %d pixels of %.4g, %s%s, %s with %d overviews%s\n", imageryOut.c_str(), im.cols,
              im.rows, im.pixelSize, im.bands == 1 ? "grey" : "RGB", im.masked ? " with a mask" : "",
              im.copied ? "copied as it is (a tiled GeoTIFF ready to drape)" : "JPEG COG", im.overviews,
              im.reprojected ? ", warped to the terrain's CRS" : "");
}

}  // namespace

void registerImportTerrain(CLI::App& app) {
  auto args = std::make_shared<ImportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "import-terrain",
      "Import a DEM (any raster GDAL reads) as the engine's terrain: a Cloud-Optimized GeoTIFF of Float32 heights");
  cmd->add_option("IN", args->in, "Input raster (never modified)")->required();
  cmd->add_option("OUT", args->out, "Output terrain file (.tif); replaced only with --overwrite")->required();
  cmd->add_option("--band", args->options.band, "Band holding the heights (1-based)")->default_val(1);
  cmd->add_option("--window", args->window, "Crop window MINX MINY MAXX MAXY in map coordinates of the output CRS")
      ->expected(4);
  cmd->add_option("--resolution", args->resolution, "Output cell size (output CRS units; resampled bilinearly)");
  cmd->add_option("--crs", args->options.targetCrs, "Reproject to this CRS (e.g. EPSG:32651) through GDAL's warper");
  cmd->add_option("--nodata", args->nodata, "Nodata handling: keep (holes) or fill (GDALFillNodata interpolation)")
      ->check(CLI::IsMember({"keep", "fill"}))
      ->default_val("keep");
  cmd->add_option("--fill-distance", args->options.fillDistance, "Largest hole distance filled, in pixels")
      ->default_val(100.0);
  cmd->add_option("--vertical-scale", args->options.verticalScale, "Multiply heights by this (0.3048 for feet)")
      ->default_val(1.0);
  cmd->add_option("--imagery", args->imagery,
                  "An orthophoto to import beside OUT (as OUT_imagery.tif): an 8-bit JPEG COG with overviews in the "
                  "terrain's CRS");
  cmd->add_flag("--overwrite", args->options.overwrite, "Replace an existing OUT (and its imagery)");
  cmd->callback([args] { runImportTerrain(*args); });
}

}  // namespace nestwalk::tools
