// nestwalk query ground TERRAIN --points POINTS.csv: the ground height under each point.
// Input: a CSV with columns x, y (map coordinates in TERRAIN's CRS; longitude, latitude in degrees
// for a geographic CRS, see terrain/dem_reader.h). Output on stdout: x,y,z with z empty where there
// is no ground (a hole, or outside the sample hull). TERRAIN is any raster GDAL reads; one with its
// terrain pyramid beside it (import-terrain's, band 1) is paged from it instead of read whole, so a
// survey of any size answers in time bounded by the points (the answers are the same, bit for bit).
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/map_points_csv.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/paged_heightfield.h"
#include "tools/nestwalk/commands.h"

#include <cstdio>
#include <fstream>
#include <memory>

namespace nestwalk::tools {
namespace {

struct QueryGroundArgs {
  std::string terrain, points;
  int band = 1;
};

void runQueryGround(const QueryGroundArgs& args) {
  std::vector<std::string> warnings;
  const terrain::Heightfield hf = args.band == 1 ? terrain::openTerrainHeightfield(args.terrain, &warnings)
                                                 : terrain::readDem(args.terrain, {args.band}, &warnings);
  for (const auto& w : warnings) std::fprintf(stderr, "nestwalk: warning: %s\n", w.c_str());

  std::ifstream file(args.points);
  if (!file) throw InputError(args.points + ": cannot open the file");
  std::string out = "x,y,z\n";
  char buf[64];
  for (const MapPoint& p : readMapPoints(file, args.points)) {
    out += p.xText + "," + p.yText + ",";
    if (const auto z = hf.groundHeight(p.x, p.y)) {
      std::snprintf(buf, sizeof buf, "%.17g", *z);
      out += buf;
    }
    out += "\n";
  }
  // Written only once every row has been read and checked: bad input produces no partial output.
  std::fwrite(out.data(), 1, out.size(), stdout);
}

}  // namespace

void registerQueryGround(CLI::App& query) {
  auto args = std::make_shared<QueryGroundArgs>();
  CLI::App* cmd = query.add_subcommand(
      "ground", "Ground height under points: reads x,y from a CSV, prints x,y,z (z empty where there is no ground)");
  cmd->add_option("TERRAIN", args->terrain, "Terrain raster (an imported COG or any DEM GDAL reads)")->required();
  cmd->add_option("--points", args->points, "CSV with header x,y (map coordinates in the terrain's CRS)")->required();
  cmd->add_option("--band", args->band, "Band holding the heights (1-based)")->default_val(1);
  cmd->callback([args] { runQueryGround(*args); });
}

}  // namespace nestwalk::tools
