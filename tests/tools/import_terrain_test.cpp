// `nestwalk import-terrain`: the summary, the COG it writes (read back through `query ground`),
// --overwrite, and every kind of bad input: its message names the file and the problem, the exit
// code is 1, OUT stays absent or byte-for-byte unchanged, and IN's bytes and mtime are untouched.
// The bad files are written by hand (ASCII grids, ENVI raw + header, VRT XML); GDAL's library
// only rewrites an orthophoto as a plain GeoTIFF for the imagery import.
#include "nestwalk/terrain/terrain_pyramid_format.h"
#include "tests/common/run_command.h"
#include "tests/common/test_data.h"

#include <cpl_error.h>
#include <gdal.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;

/// An Arc/Info ASCII grid (lower-left corner xll, yll; row 0 north); f(c, r) gives the value text.
template <class F>
void writeAsc(const fs::path& p, int cols, int rows, double xll, double yll, double cell, F f) {
  std::ofstream o(p);
  o << "ncols " << cols << "\nnrows " << rows << "\nxllcorner " << xll << "\nyllcorner " << yll << "\ncellsize " << cell
    << "\nNODATA_value -9999\n";
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) o << (c ? " " : "") << f(c, r);
    o << "\n";
  }
}

fs::path goodAsc(const fs::path& dir, int cols = 60, int rows = 40) {
  const fs::path p = dir / "good.asc";
  writeAsc(p, cols, rows, 550000.0, 4650000.0, 2.0, [](int c, int r) { return std::to_string(100 + c + 2 * r); });
  return p;
}

/// ENVI raw Float32, band after band (no map info: no georeferencing).
void writeEnvi(const fs::path& bin, int cols, int rows, const std::vector<float>& v, int bands = 1) {
  std::ofstream(bin, std::ios::binary).write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * 4));
  fs::path hdr = bin;
  hdr.replace_extension(".hdr");
  std::ofstream(hdr) << "ENVI\nsamples = " << cols << "\nlines = " << rows << "\nbands = " << bands
                     << "\nheader offset = 0\nfile type = ENVI Standard\ndata type = 4\ninterleave = "
                        "bsq\nbyte order = 0\n";
}

/// A VRT over `source` band 1 with the given geotransform (none when empty).
void writeVrt(const fs::path& p, const fs::path& source, int cols, int rows, const std::string& geoTransform) {
  std::ofstream o(p);
  o << "<VRTDataset rasterXSize=\"" << cols << "\" rasterYSize=\"" << rows << "\">\n";
  if (!geoTransform.empty()) o << "  <GeoTransform>" << geoTransform << "</GeoTransform>\n";
  o << "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n    <SimpleSource>\n      <SourceFilename "
       "relativeToVRT=\"0\">"
    << source.string() << "</SourceFilename>\n      <SourceBand>1</SourceBand>\n    </SimpleSource>\n"
    << "  </VRTRasterBand>\n</VRTDataset>\n";
}


struct Snapshot {
  std::string bytes;
  fs::file_time_type mtime;
};
Snapshot snapshot(const fs::path& p) { return {readText(p), fs::last_write_time(p)}; }

TEST(ImportTerrain, ImportsWithSummaryAndQueriesBack) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto in = goodAsc(dir);
  const auto before = snapshot(in);
  const fs::path out = dir / "terrain.tif";
  const auto r = runNestwalk("import-terrain " + quoted(in) + " " + quoted(out));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  for (const char* s : {"size:         60 x 40 samples", "cell size:    2 x 2", "CRS:          none",
                        "height range: 100.000 .. 237.000 m", "nodata:       0.0000 %"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s << "\n" << r.out;
  EXPECT_TRUE(r.err.empty()) << r.err;  // no progress bar: stderr is not a terminal
  EXPECT_EQ(snapshot(in).bytes, before.bytes);
  EXPECT_EQ(snapshot(in).mtime, before.mtime);
  EXPECT_FALSE(fs::exists(in.string() + ".aux.xml"));
  // Sample (3, 5) is at x = 550000 + 2 * 3.5, y = 4650000 + 80 - 2 * 5.5.
  writeText(dir / "p.csv", "x,y\n550007,4650069\n550008,4650069\n");
  const auto q = runNestwalk("query ground " + quoted(out) + " --points " + quoted(dir / "p.csv"));
  ASSERT_EQ(q.exitCode, 0) << q.err;
  EXPECT_EQ(q.out, "x,y,z\n550007,4650069,113\n550008,4650069,113.5\n");
}

TEST(ImportTerrain, QueryGroundPagesAnImportedSurveyFromItsPyramidWithTheSameAnswers) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const fs::path out = dir / "terrain.tif";
  ASSERT_EQ(runNestwalk("import-terrain " + quoted(goodAsc(dir)) + " " + quoted(out)).exitCode, 0);
  std::string points = "x,y\n";
  for (int k = 0; k < 400; ++k)
    points += std::to_string(549995.0 + 0.3137 * k) + "," + std::to_string(4650085.0 - 0.2291 * k) + "\n";
  writeText(dir / "p.csv", points);
  const std::string query = "query ground " + quoted(out) + " --points " + quoted(dir / "p.csv");
  const auto paged = runNestwalk(query);  // the pyramid beside it: paged
  ASSERT_EQ(paged.exitCode, 0) << paged.err;
  fs::rename(terrain::pyramidPathOf(out.string()), dir / "aside.tif");
  const auto whole = runNestwalk(query);  // none: read whole
  ASSERT_EQ(whole.exitCode, 0) << whole.err;
  EXPECT_EQ(paged.out, whole.out);
  EXPECT_GT(std::count(whole.out.begin(), whole.out.end(), '.'), 400);
  // A pyramid of another terrain is set aside with a warning naming it; the answers stay right.
  fs::copy_file(dir / "aside.tif", terrain::pyramidPathOf(out.string()));
  const auto again = runNestwalk("import-terrain " + quoted(goodAsc(dir)) + " " + quoted(dir / "other.tif") + " --resolution 3");
  ASSERT_EQ(again.exitCode, 0) << again.err;
  fs::copy_file(dir / "aside.tif", terrain::pyramidPathOf((dir / "other.tif").string()), fs::copy_options::overwrite_existing);
  const auto stale = runNestwalk("query ground " + quoted(dir / "other.tif") + " --points " + quoted(dir / "p.csv"));
  ASSERT_EQ(stale.exitCode, 0) << stale.err;
  EXPECT_NE(stale.err.find("changed since its pyramid was written"), std::string::npos) << stale.err;
}

TEST(ImportTerrain, BandOption) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  std::vector<float> v(2 * 3 * 2);
  for (int i = 0; i < 6; ++i) v[std::size_t(i)] = float(i), v[std::size_t(6 + i)] = 100.0f + float(i);
  writeEnvi(dir / "two.bin", 3, 2, v, 2);
  const auto r = runNestwalk("import-terrain " + quoted(dir / "two.bin") + " " + quoted(dir / "b2.tif") + " --band 2");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("height range: 100.000 .. 105.000 m"), std::string::npos) << r.out;
  writeText(dir / "p.csv", "x,y\n2.5,-1.5\n");
  for (const fs::path& t : {dir / "b2.tif", dir / "two.bin"}) {
    const auto q = runNestwalk("query ground " + quoted(t) + " --band " + (t.extension() == ".bin" ? "2" : "1") +
                               " --points " + quoted(dir / "p.csv"));
    EXPECT_EQ(q.out, "x,y,z\n2.5,-1.5,105\n") << q.err;
  }
  const auto bad = runNestwalk("import-terrain " + quoted(dir / "two.bin") + " " + quoted(dir / "b3.tif") + " --band 3");
  EXPECT_EQ(bad.exitCode, 1);
  EXPECT_NE(bad.err.find("band 3 does not exist (the raster has 2 bands)"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "b3.tif"));
}

TEST(ImportTerrain, OverwriteSemantics) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto in = goodAsc(dir);
  const fs::path out = dir / "terrain.tif";
  writeText(out, "an existing file");
  const auto r = runNestwalk("import-terrain " + quoted(in) + " " + quoted(out));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find(out.string() + ": already exists (use --overwrite"), std::string::npos) << r.err;
  EXPECT_EQ(readText(out), "an existing file");
  const auto o = runNestwalk("import-terrain " + quoted(in) + " " + quoted(out) + " --overwrite");
  ASSERT_EQ(o.exitCode, 0) << o.err;
  EXPECT_EQ(readText(out).substr(0, 2), "II");  // a little-endian TIFF now
  const auto same = runNestwalk("import-terrain " + quoted(in) + " " + quoted(in) + " --overwrite");
  EXPECT_EQ(same.exitCode, 1);
  EXPECT_NE(same.err.find("is the input file"), std::string::npos) << same.err;
  int hidden = 0;
  for (const auto& e : fs::directory_iterator(dir)) hidden += e.path().filename().string()[0] == '.';
  EXPECT_EQ(hidden, 0);  // no temporary file left behind
}

TEST(ImportTerrain, OptionsCropScaleCrs) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto in = goodAsc(dir);
  const fs::path out = dir / "crop.tif";
  const auto r = runNestwalk("import-terrain " + quoted(in) + " " + quoted(out) +
                             " --window 550010 4650010 550050 4650070 --vertical-scale 0.5");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("size:         20 x 30 samples"), std::string::npos) << r.out;
  // Top-left sample of the window is source (5, 5): 100 + 5 + 10 = 115, halved.
  writeText(dir / "p.csv", "x,y\n550011,4650069\n");
  const auto q = runNestwalk("query ground " + quoted(out) + " --points " + quoted(dir / "p.csv"));
  EXPECT_EQ(q.out, "x,y,z\n550011,4650069,57.5\n");
  const auto noCrs = runNestwalk("import-terrain " + quoted(in) + " " + quoted(dir / "x.tif") + " --crs EPSG:4326");
  EXPECT_EQ(noCrs.exitCode, 1);
  EXPECT_NE(noCrs.err.find("has no CRS"), std::string::npos) << noCrs.err;
  const auto res = runNestwalk("import-terrain " + quoted(in) + " " + quoted(dir / "r.tif") + " --resolution 4");
  ASSERT_EQ(res.exitCode, 0) << res.err;
  EXPECT_NE(res.out.find("size:         30 x 20 samples"), std::string::npos) << res.out;
  const auto fill = runNestwalk("import-terrain " + quoted(in) + " " + quoted(dir / "f.tif") + " --nodata fill");
  EXPECT_EQ(fill.exitCode, 0) << fill.err;
}

TEST(ImportTerrain, BadInputsAreRefusedAndLeaveOutAlone) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  writeText(dir / "text.tif", "not a raster at all\n");
  writeText(dir / "zero.tif", "");
  writeAsc(dir / "allnodata.asc", 8, 6, 0, 0, 1, [](int, int) { return std::string("-9999"); });
  std::vector<float> nan(12, 1.0f), inf(12, 1.0f);
  nan[5] = std::nanf("");
  inf[7] = INFINITY;
  writeEnvi(dir / "nan.bin", 4, 3, nan);
  writeEnvi(dir / "inf.bin", 4, 3, inf);
  {  // A truncated GeoTIFF: the first half of a valid terrain file.
    writeAsc(dir / "big.asc", 400, 300, 0, 0, 1, [](int c, int r) { return std::to_string((c * 7 + r * 13) % 1000); });
    ASSERT_EQ(runNestwalk("import-terrain " + quoted(dir / "big.asc") + " " + quoted(dir / "full.tif")).exitCode, 0);
    fs::copy_file(dir / "full.tif", dir / "truncated.tif");
    fs::resize_file(dir / "truncated.tif", fs::file_size(dir / "full.tif") / 2);
  }
  const struct {
    const char* in;
    const char* message;
  } cases[] = {
      {"missing.tif", "no such file"},
      {"text.tif", "not a raster GDAL can read"},
      {"zero.tif", "empty file"},
      {"allnodata.asc", "every sample is nodata"},
      {"nan.bin", "NaN or infinite sample at column 1, row 1"},
      {"inf.bin", "NaN or infinite sample at column 3, row 1"},
      {"truncated.tif", "truncated or corrupt"},
  };
  for (const auto& c : cases) {
    const fs::path in = dir / c.in;
    const bool exists = fs::exists(in);
    Snapshot before;
    if (exists) before = snapshot(in);
    // Absent OUT stays absent.
    const fs::path out = dir / "out.tif";
    const auto r = runNestwalk("import-terrain " + quoted(in) + " " + quoted(out));
    EXPECT_EQ(r.exitCode, 1) << c.in;
    EXPECT_NE(r.err.find(in.string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.in << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.in;
    // An existing OUT stays byte-for-byte unchanged, even with --overwrite.
    writeText(dir / "keep.tif", "keep me");
    const auto o = runNestwalk("import-terrain " + quoted(in) + " " + quoted(dir / "keep.tif") + " --overwrite");
    EXPECT_EQ(o.exitCode, 1) << c.in;
    EXPECT_EQ(readText(dir / "keep.tif"), "keep me") << c.in;
    if (exists) {
      EXPECT_EQ(readText(in), before.bytes) << c.in;
      EXPECT_EQ(fs::last_write_time(in), before.mtime) << c.in;
    }
  }
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();  // no temporary file left behind
    EXPECT_NE(e.path().extension(), ".xml") << e.path();           // no .aux.xml side-car
  }
}

TEST(ImportTerrain, RotatedIsWarpedNorthUpAndUngeoreferencedWarns) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto src = goodAsc(dir);
  writeVrt(dir / "rotated.vrt", src, 60, 40, "1000, 0.8, 0.6, 2000, 0.6, -0.8");
  const auto r = runNestwalk("import-terrain " + quoted(dir / "rotated.vrt") + " " + quoted(dir / "r.tif"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("rotated or sheared geotransform; warped north-up"), std::string::npos) << r.err;
  // The original cannot be queried as it is: refused clearly.
  writeText(dir / "p.csv", "x,y\n1000,2000\n");
  const auto q = runNestwalk("query ground " + quoted(dir / "rotated.vrt") + " --points " + quoted(dir / "p.csv"));
  EXPECT_EQ(q.exitCode, 1);
  EXPECT_NE(q.err.find("rotated or sheared"), std::string::npos) << q.err;

  writeVrt(dir / "plain.vrt", src, 60, 40, "");
  const auto p = runNestwalk("import-terrain " + quoted(dir / "plain.vrt") + " " + quoted(dir / "p.tif"));
  ASSERT_EQ(p.exitCode, 0) << p.err;
  EXPECT_NE(p.err.find("warning: " + (dir / "plain.vrt").string() + ": no georeferencing"), std::string::npos) << p.err;
  EXPECT_NE(p.out.find("(pixel units)"), std::string::npos) << p.out;
  writeText(dir / "p.csv", "x,y\n3.5,-5.5\n");
  const auto pq = runNestwalk("query ground " + quoted(dir / "p.tif") + " --points " + quoted(dir / "p.csv"));
  EXPECT_EQ(pq.out, "x,y,z\n3.5,-5.5,113\n");
}

TEST(ImportTerrain, ImageryIsImportedBesideTheTerrainAndKeptWithoutOverwrite) {
  const TempFolder folder;
  // The bundled dump and its orthophoto on the DEM's 1 m grid (make-terrain's default).
  const fs::path dem = folder / "made.tif", made = folder / "made_ortho.tif", ortho = folder / "striped.tif";
  const auto r0 = runNestwalk("make-terrain " + quoted(dem) + " --ortho " + quoted(made));
  ASSERT_EQ(r0.exitCode, 0) << r0.err;
  // ... as a plain GeoTIFF (striped, no overviews, uncompressed): one the import encodes.
  GDALAllRegister();
  GDALDatasetH src = GDALOpen(made.c_str(), GA_ReadOnly);
  ASSERT_NE(src, nullptr);
  GDALDatasetH plain = GDALCreateCopy(GDALGetDriverByName("GTiff"), ortho.c_str(), src, FALSE, nullptr, nullptr, nullptr);
  GDALClose(src);
  ASSERT_NE(plain, nullptr) << CPLGetLastErrorMsg();
  GDALClose(plain);
  const fs::path out = folder / "dump.tif", imagery = folder / "dump_imagery.tif";
  const auto r = runNestwalk("import-terrain " + quoted(dem) + " " + quoted(out) + " --imagery " + quoted(ortho));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("imagery:      " + imagery.string() + ": 1000 x 1000 pixels of 1, RGB, JPEG COG with 1 overviews"),
            std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(imagery));
  // Run again: the imagery (and the terrain) exist; refused before anything is written.
  const auto terrainBefore = snapshot(out), imageryBefore = snapshot(imagery);
  const auto again = runNestwalk("import-terrain " + quoted(dem) + " " + quoted(out) + " --imagery " + quoted(ortho));
  EXPECT_EQ(again.exitCode, 1);
  EXPECT_NE(again.err.find(imagery.string() + ": exists; pass --overwrite to replace it"), std::string::npos) << again.err;
  EXPECT_EQ(snapshot(out).mtime, terrainBefore.mtime);
  EXPECT_EQ(snapshot(imagery).mtime, imageryBefore.mtime);
  EXPECT_EQ(runNestwalk("import-terrain " + quoted(dem) + " " + quoted(out) + " --imagery " + quoted(ortho) +
                        " --overwrite").exitCode, 0);
}

TEST(ImportTerrain, ImageryThatIsAlreadyATiledGeoTiffReadyToDrapeIsCopiedAsItIs) {
  const TempFolder folder;
  // A drone's orthophoto at 0.5 m: make-terrain writes it as a JPEG COG with overviews in the DEM's CRS.
  const fs::path dem = folder / "made.tif", ortho = folder / "drone.tif";
  const auto made = runNestwalk("make-terrain " + quoted(dem) + " --ortho " + quoted(ortho) + " --ortho-pixel 0.5");
  ASSERT_EQ(made.exitCode, 0) << made.err;
  const fs::path out = folder / "dump.tif", imagery = folder / "dump_imagery.tif";
  const auto r = runNestwalk("import-terrain " + quoted(dem) + " " + quoted(out) + " --imagery " + quoted(ortho));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("imagery:      " + imagery.string() + ": 2000 x 2000 pixels of 0.5, RGB, copied as it is"),
            std::string::npos) << r.out;
  EXPECT_EQ(readText(imagery), readText(ortho)) << "not the orthophoto's own bytes";
  EXPECT_EQ(fs::file_size(imagery), fs::file_size(ortho));

  // Tiled, but its overviews in a .ovr beside it: a copy of the .tif alone would lose them, so it is
  // encoded.
  GDALAllRegister();
  const fs::path tiled = folder / "tiled.tif";
  GDALDatasetH src = GDALOpen(ortho.c_str(), GA_ReadOnly);
  ASSERT_NE(src, nullptr);
  const char* tiledOptions[] = {"TILED=YES", nullptr};
  GDALDatasetH copy = GDALCreateCopy(GDALGetDriverByName("GTiff"), tiled.c_str(), src, FALSE,
                                     const_cast<char**>(tiledOptions), nullptr, nullptr);
  GDALClose(src);
  ASSERT_NE(copy, nullptr) << CPLGetLastErrorMsg();
  GDALClose(copy);
  GDALDatasetH readOnly = GDALOpen(tiled.c_str(), GA_ReadOnly);  // read-only: the overviews go to tiled.tif.ovr
  ASSERT_NE(readOnly, nullptr);
  int levels[] = {2, 4};
  ASSERT_EQ(GDALBuildOverviews(readOnly, "AVERAGE", 2, levels, 0, nullptr, nullptr, nullptr), CE_None);
  GDALClose(readOnly);
  ASSERT_TRUE(fs::exists(folder / "tiled.tif.ovr"));
  const auto encoded = runNestwalk("import-terrain " + quoted(dem) + " " + quoted(folder / "second.tif") + " --imagery " +
                                   quoted(tiled));
  ASSERT_EQ(encoded.exitCode, 0) << encoded.err;
  EXPECT_NE(encoded.out.find("2000 x 2000 pixels of 0.5, RGB, JPEG COG with"), std::string::npos) << encoded.out;
}

}  // namespace
}  // namespace nestwalk::test
