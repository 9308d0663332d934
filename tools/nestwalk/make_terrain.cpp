// nestwalk make-terrain OUT [--seed N] [--size METRES] [--cell METRES] [--fine-relief] [--ortho FILE]
//                          [--ortho-pixel METRES]
// [--overwrite]: generates the bundled mining-dump DEM (terrain/mining_dump.h) and writes it as the
// engine's terrain format (the same Cloud-Optimized GeoTIFF as import-terrain, with its pyramid), in
// UTM zone 51N (EPSG:32651); with --ortho, also its synthetic orthophoto on the DEM's grid
// (terrain/mining_dump_ortho.h). The DEM is generated and written stripe by stripe (any size up to
// 65,536 cells a side, in bounded memory); the orthophoto needs the whole grid (4e8 samples at most).
#include "nestwalk/core/input_error.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/terrain/mining_dump.h"
#include "nestwalk/terrain/mining_dump_ortho.h"
#include "nestwalk/terrain/terrain_import.h"
#include "tools/nestwalk/commands.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>

namespace nestwalk::tools {
namespace {

struct MakeTerrainArgs {
  std::string out;
  std::string ortho;  // the orthophoto's file; empty: none
  double orthoPixel = 0;  // its pixel, metres; 0: the DEM's cell
  terrain::MiningDumpParams params;
  bool overwrite = false;
};

void runMakeTerrain(const MakeTerrainArgs& args) {
  if (!(args.params.size >= 16 * args.params.cell && args.params.cell > 0))
    throw InputError("--size must be at least 16 cells and --cell positive");
  const double cells = std::round(args.params.size / args.params.cell);
  const bool fineOrtho = args.orthoPixel > 0 && args.orthoPixel != args.params.cell;
  if (args.orthoPixel > args.params.cell)
    throw InputError("--ortho-pixel must not be coarser than --cell (the orthophoto is at least the DEM's resolution)");
  if (fineOrtho && std::round(args.params.size / args.orthoPixel) > terrain::kMaxMiningDumpCellsPerSide)
    throw InputError("--ortho-pixel: more than 65536 pixels a side over --size");
  if (cells > terrain::kMaxMiningDumpCellsPerSide ||
      (!args.ortho.empty() && !fineOrtho && cells * cells > terrain::kMaxHeldMiningDumpSamples)) {
    char text[200];
    std::snprintf(text, sizeof text, "--size %g at --cell %g is %.0f cells a side: more than the generator's %s",
                  args.params.size, args.params.cell, cells,
                  cells > terrain::kMaxMiningDumpCellsPerSide ? "65536 a side" : "4e8 samples with --ortho (it holds them in memory)");
    throw InputError(text);
  }
  if (!args.ortho.empty()) {
    // Refused before anything is written, so that a refusal leaves OUT as it was too.
    std::error_code ec, ecOrtho, ecOut;
    const auto ortho = std::filesystem::weakly_canonical(args.ortho, ecOrtho);
    const auto out = std::filesystem::weakly_canonical(args.out, ecOut);
    if (!ecOrtho && !ecOut && ortho == out)
      throw InputError(args.ortho + ": --ortho names the terrain file OUT; choose another file");
    if (std::filesystem::exists(args.ortho, ec) && !args.overwrite)
      throw InputError(args.ortho + ": already exists (use --overwrite to replace it)");
  }
  const terrain::MiningDumpGenerator generator(args.params);
  float lo = INFINITY, hi = -INFINITY;
  terrain::writeTerrainCog(
      args.out, generator.cols(), generator.rows(),
      [&](int r0, int count, float* heights) {
        generator.generateRows(r0, count, heights);
        for (std::size_t k = 0; k < std::size_t(count) * std::size_t(generator.cols()); ++k)
          lo = std::min(lo, heights[k]), hi = std::max(hi, heights[k]);
      },
      generator.originX(), generator.originY(), args.params.cell, args.params.cell, terrain::kMiningDumpCrs,
      args.overwrite);
  if (!args.ortho.empty() && fineOrtho)
    terrain::writeFineMiningDumpOrtho(args.ortho, args.params, args.orthoPixel, terrain::kMiningDumpCrs, args.overwrite);
  else if (!args.ortho.empty())
    terrain::writeMiningDumpOrtho(args.ortho, terrain::generateMiningDump(args.params), args.params.seed,
                                  terrain::kMiningDumpCrs, args.overwrite);
  const auto& L = generator.layout();
  std::printf("generated %s (seed %llu)\n", args.out.c_str(), static_cast<unsigned long long>(args.params.seed));
  std::printf("  size:         %d x %d samples\n", generator.cols(), generator.rows());
  std::printf("  cell size:    %.10g x %.10g (CRS units)\n", args.params.cell, args.params.cell);
  std::printf("  CRS:          WGS 84 / UTM zone 51N (EPSG:32651)\n");
  std::printf("  height range: %.3f .. %.3f m\n", double(lo), double(hi));
  std::printf("  nodata:       0.0000 %%\n");
  std::printf("  dump:         centre %.3f %.3f, long axis azimuth %.6f deg, ramp on the azimuth %.6f deg side\n",
              L.centreE, L.centreN, L.azimuthDeg, std::fmod(L.azimuthDeg + 270.0, 360.0));
  std::printf("  benches:      toe at %.3f m, top at %.3f m, bench height %.3f m, face slope %.3f deg\n",
              L.baseHeight, L.topHeight, args.params.benchHeight, args.params.faceSlopeDeg);
  if (!args.ortho.empty() && fineOrtho)
    std::printf("  ortho:        %s, RGB JPEG at %.10g m a pixel (materials%s)\n", args.ortho.c_str(), args.orthoPixel,
                args.orthoPixel < terrain::kOrthoTextureBelowPixelM ? ", gravel, stones and vegetation patches" : "");
  else if (!args.ortho.empty())
    std::printf("  ortho:        %s, RGB on the DEM's grid (materials of the top, berms, faces, ramp, ditch and "
                "ground)\n",
                args.ortho.c_str());
}

}  // namespace

void registerMakeTerrain(CLI::App& app) {
  auto args = std::make_shared<MakeTerrainArgs>();
  CLI::App* cmd = app.add_subcommand(
      "make-terrain",
      "Generate the bundled mining-dump DEM (terraced benches, haul ramp, pits, ditches) in UTM 51N as a terrain COG");
  cmd->add_option("OUT", args->out, "Output terrain file (.tif); replaced only with --overwrite")->required();
  cmd->add_option("--seed", args->params.seed, "Random seed (same seed, same heights)")->default_val(1);
  cmd->add_option("--size", args->params.size, "Side of the square area, metres")->default_val(1000.0);
  cmd->add_option("--cell", args->params.cell, "Cell size, metres")->default_val(1.0);
  cmd->add_flag("--fine-relief", args->params.fineRelief,
                "Relief down to the cell (stones, ruts: noise octaves from 2 m down to two cells), as a drone survey has");
  cmd->add_option("--ortho", args->ortho,
                  "Also write a synthetic orthophoto of the dump (RGB GeoTIFF on the DEM's grid) to this file");
  cmd->add_option("--ortho-pixel", args->orthoPixel,
                  "The orthophoto's pixel, metres (default: --cell): finer, as a drone's is, written as a JPEG COG row by "
                  "row in bounded memory, with gravel, stones and vegetation below 0.5 m")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--overwrite", args->overwrite, "Replace an existing OUT (and --ortho FILE)");
  cmd->callback([args] { runMakeTerrain(*args); });
}

}  // namespace nestwalk::tools
