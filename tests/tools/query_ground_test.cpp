// `nestwalk query ground`: on every shared DEM, original and imported, the answers agree with GDAL's
// own sample values at samples and at midpoints between horizontally / vertically adjacent samples;
// nodata gives an empty z. GDAL's values are read independently of nestwalk with GDAL's own
// utilities (gdalinfo -json for the frame, gdal_translate to raw Float64 for RasterIO's samples).
#include "tests/common/run_command.h"
#include "tests/common/test_data.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;

bool haveGdalTools() { return std::system("gdal_translate --version >/dev/null 2>&1 && gdalinfo --version >/dev/null 2>&1") == 0; }

struct Reference {
  int cols = 0, rows = 0;
  double gt[6] = {};
  bool hasNoData = false;
  double noData = 0;
  std::vector<double> v;
  double at(int c, int r) const { return v[std::size_t(r) * std::size_t(cols) + std::size_t(c)]; }
  bool valid(int c, int r) const { return !(hasNoData && at(c, r) == noData) && std::isfinite(at(c, r)); }
};

/// GDAL's own view of band 1, through its command-line tools.
Reference gdalReference(const fs::path& raster, const fs::path& dir) {
  Reference ref;
  const fs::path json = dir / "info.json", bin = dir / "ref.bin";
  const std::string info = "gdalinfo -json '" + raster.string() + "' >'" + json.string() + "'";
  EXPECT_EQ(std::system(info.c_str()), 0);
  const auto j = nlohmann::json::parse(readText(json));
  ref.cols = j["size"][0];
  ref.rows = j["size"][1];
  // gdalinfo prints the geotransform with 16 decimals, which rounds a degree pixel size; a VRT
  // written by gdal_translate keeps every digit (17 significant).
  const fs::path vrt = dir / "ref.vrt";
  const std::string toVrt = "gdal_translate -q -of VRT '" + raster.string() + "' '" + vrt.string() + "'";
  EXPECT_EQ(std::system(toVrt.c_str()), 0);
  const std::string xml = readText(vrt);
  const auto at = xml.find("<GeoTransform>");
  EXPECT_NE(at, std::string::npos) << xml;
  const char* s = xml.c_str() + at + std::strlen("<GeoTransform>");
  for (int k = 0; k < 6; ++k) {
    char* end = nullptr;
    ref.gt[k] = std::strtod(s, &end);
    s = end + (*end == ',' ? 1 : 0);
  }
  const auto& band = j["bands"][0];
  if (band.contains("noDataValue") && band["noDataValue"].is_number()) {
    ref.hasNoData = true;
    ref.noData = band["noDataValue"];
  }
  const std::string tr = "gdal_translate -q -b 1 -of ENVI -ot Float64 '" + raster.string() + "' '" + bin.string() + "'";
  EXPECT_EQ(std::system(tr.c_str()), 0);
  ref.v.resize(std::size_t(ref.cols) * std::size_t(ref.rows));
  std::ifstream in(bin, std::ios::binary);
  in.read(reinterpret_cast<char*>(ref.v.data()), std::streamsize(ref.v.size() * sizeof(double)));
  EXPECT_TRUE(in.good());
  return ref;
}

struct Point {
  double x, y;
  std::optional<double> z;  // expected
};

/// Samples and midpoints (stride over large rasters) with their expected answers.
std::vector<Point> probePoints(const Reference& ref) {
  const int stride = ref.cols * ref.rows > 200000 ? 7 : 1;
  // Sample (c, r) centre as the heightfield computes it: origin (half a pixel in) + index * step.
  const double ox = ref.gt[0] + 0.5 * ref.gt[1], oy = ref.gt[3] + 0.5 * ref.gt[5];
  auto pos = [&](int c, int r) { return std::pair<double, double>{ox + c * ref.gt[1], oy + r * ref.gt[5]}; };
  std::vector<Point> pts;
  for (int r = 0; r < ref.rows; r += stride) {
    for (int c = 0; c < ref.cols; c += stride) {
      const auto [x, y] = pos(c, r);
      pts.push_back({x, y, ref.valid(c, r) ? std::optional<double>(ref.at(c, r)) : std::nullopt});
      if (c + 1 < ref.cols) {
        const double xm = 0.5 * (x + pos(c + 1, r).first);
        const bool ok = ref.valid(c, r) && ref.valid(c + 1, r);
        pts.push_back({xm, y, ok ? std::optional<double>(0.5 * (ref.at(c, r) + ref.at(c + 1, r))) : std::nullopt});
      }
      if (r + 1 < ref.rows) {
        const double ym = 0.5 * (y + pos(c, r + 1).second);
        const bool ok = ref.valid(c, r) && ref.valid(c, r + 1);
        pts.push_back({x, ym, ok ? std::optional<double>(0.5 * (ref.at(c, r) + ref.at(c, r + 1))) : std::nullopt});
      }
    }
  }
  return pts;
}

std::string pointsCsv(const std::vector<Point>& pts) {
  std::string s = "x,y\n";
  char buf[96];
  for (const auto& p : pts) std::snprintf(buf, sizeof buf, "%.17g,%.17g\n", p.x, p.y), s += buf;
  return s;
}

struct Agreement {
  std::size_t samples = 0, empty = 0;
  double maxDiff = 0;
};

Agreement checkAnswers(const std::string& out, const std::vector<Point>& pts, const std::string& name) {
  Agreement a;
  std::stringstream ss(out);
  std::string line;
  std::getline(ss, line);
  EXPECT_EQ(line, "x,y,z");
  for (const auto& p : pts) {
    if (!std::getline(ss, line)) {
      ADD_FAILURE() << name << ": fewer output rows than points";
      break;
    }
    const auto comma = line.rfind(',');
    const std::string z = line.substr(comma + 1);
    if (!p.z) {
      EXPECT_TRUE(z.empty()) << name << ": expected no ground at " << line;
      ++a.empty;
      continue;
    }
    if (z.empty()) {
      ADD_FAILURE() << name << ": no ground at " << line << ", GDAL says " << *p.z;
      continue;
    }
    a.maxDiff = std::max(a.maxDiff, std::abs(std::stod(z) - *p.z));
    ++a.samples;
  }
  EXPECT_LE(a.maxDiff, 1e-4) << name;
  return a;
}

TEST(QueryGround, AgreesWithGdalOnEverySharedDemOriginalAndImported) {
  const fs::path data = sharedData();
  if (data.empty()) GTEST_SKIP() << "shared data folder absent (NESTWALK_SHARED_DATA): no DEM to query";
  if (!haveGdalTools()) GTEST_SKIP() << "gdalinfo / gdal_translate not on PATH: no independent GDAL reference";
  const TempFolder folder;
  const fs::path dir = folder.path();
  int dems = 0;
  for (const auto& e : fs::directory_iterator(data / "terrain")) {
    const auto ext = e.path().extension().string();
    if (ext != ".tif" && ext != ".asc") continue;
    ++dems;
    const std::string name = e.path().filename().string();
    const fs::path imported = dir / (name + ".cog.tif");
    const auto imp = runNestwalk("import-terrain '" + e.path().string() + "' '" + imported.string() + "'");
    ASSERT_EQ(imp.exitCode, 0) << imp.err;
    const Reference ref = gdalReference(e.path(), dir);
    const auto pts = probePoints(ref);
    writeText(dir / "points.csv", pointsCsv(pts));
    for (const fs::path& terrain : {e.path(), imported}) {
      const auto r = runNestwalk("query ground '" + terrain.string() + "' --points '" + (dir / "points.csv").string() + "'");
      ASSERT_EQ(r.exitCode, 0) << r.err;
      const Agreement a = checkAnswers(r.out, pts, terrain.filename().string());
      std::printf("[ ground   ] %-32s %7zu points: %7zu with ground, %6zu empty, max |z - GDAL| %.3g m\n",
                  terrain.filename().string().c_str(), pts.size(), a.samples, a.empty, a.maxDiff);
    }
  }
  EXPECT_GT(dems, 0);
}

TEST(QueryGround, OutsideAndBadPointsFile) {
  const fs::path data = sharedData();
  if (data.empty()) GTEST_SKIP() << "shared data folder absent (NESTWALK_SHARED_DATA)";
  const TempFolder folder;
  const fs::path dir = folder.path();
  const std::string dem = (data / "terrain/storml_elev_orig.tif").string();
  writeText(dir / "p.csv", "x,y\n0,0\n325621.072,5103476.983\n");
  const auto r = runNestwalk("query ground '" + dem + "' --points '" + (dir / "p.csv").string() + "'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, 14), "x,y,z\n0,0,\n325");
  writeText(dir / "bad.csv", "x,z\n1,2\n");
  const auto b = runNestwalk("query ground '" + dem + "' --points '" + (dir / "bad.csv").string() + "'");
  EXPECT_EQ(b.exitCode, 1);
  EXPECT_NE(b.err.find("bad.csv"), std::string::npos) << b.err;
  EXPECT_TRUE(b.out.empty());
  writeText(dir / "text.tif", "hello\n");
  const auto t = runNestwalk("query ground '" + (dir / "text.tif").string() + "' --points '" + (dir / "p.csv").string() + "'");
  EXPECT_EQ(t.exitCode, 1);
  EXPECT_NE(t.err.find("text.tif: not a raster"), std::string::npos) << t.err;
}

}  // namespace
}  // namespace nestwalk::test
