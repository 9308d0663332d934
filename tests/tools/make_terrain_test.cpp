// `nestwalk make-terrain`: deterministic from the seed, written in EPSG:32651 as the terrain COG,
// and the benches measured from the generated grid (through `query ground` along a profile across
// the dump's long side): berms about 10 m apart, faces about 35 degrees. With --ortho, the synthetic
// orthophoto lies on the DEM's grid and shows, where the profile found them, the top, the berms,
// the faces, the ditch and the ground in their materials' colours.
#include "tests/common/run_command.h"
#include "tests/tools/ortho_material.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <filesystem>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;

std::vector<std::optional<double>> zColumn(const std::string& csv) {
  std::vector<std::optional<double>> z;
  std::stringstream ss(csv);
  std::string line;
  std::getline(ss, line);
  while (std::getline(ss, line)) {
    const std::string f = line.substr(line.rfind(',') + 1);
    z.push_back(f.empty() ? std::nullopt : std::optional<double>(std::stod(f)));
  }
  return z;
}

std::string gridPoints(double e0, double n0, double step, int n) {
  std::string s = "x,y\n";
  char buf[96];
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) std::snprintf(buf, sizeof buf, "%.6f,%.6f\n", e0 + i * step, n0 + j * step), s += buf;
  return s;
}

TEST(MakeTerrain, DeterministicFromTheSeedInUtm51N) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  for (const char* name : {"a.tif", "b.tif"}) {
    const auto r = runNestwalk("make-terrain " + quoted(dir / name) + " --seed 7 --size 400");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("EPSG:32651"), std::string::npos) << r.out;
  }
  ASSERT_EQ(runNestwalk("make-terrain " + quoted(dir / "c.tif") + " --seed 8 --size 400").exitCode, 0);
  writeText(dir / "p.csv", gridPoints(549801.3, 4649801.7, 9.7, 41));
  auto query = [&](const char* name) {
    const auto r = runNestwalk("query ground " + quoted(dir / name) + " --points " + quoted(dir / "p.csv"));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return r.out;
  };
  const std::string a = query("a.tif"), b = query("b.tif"), c = query("c.tif");
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  for (const auto& z : zColumn(a)) EXPECT_TRUE(z.has_value());  // ground everywhere inside the area
  // An existing OUT is kept without --overwrite.
  const auto again = runNestwalk("make-terrain " + quoted(dir / "a.tif") + " --seed 9 --size 400");
  EXPECT_EQ(again.exitCode, 1);
  EXPECT_NE(again.err.find("already exists"), std::string::npos);
  EXPECT_EQ(query("a.tif"), a);
  // GDAL's own view of the file, where its tools are installed.
  if (std::system("gdalinfo --version >/dev/null 2>&1") == 0) {
    ASSERT_EQ(std::system(("gdalinfo -json " + quoted(dir / "a.tif") + " >" + quoted(dir / "info.json")).c_str()), 0);
    const auto j = nlohmann::json::parse(readText(dir / "info.json"));
    EXPECT_NE(j["coordinateSystem"]["wkt"].get<std::string>().find("ID[\"EPSG\",32651]"), std::string::npos);
    EXPECT_EQ(j["metadata"]["IMAGE_STRUCTURE"]["LAYOUT"], "COG");
    EXPECT_EQ(j["bands"][0]["type"], "Float32");
    EXPECT_EQ(j["size"][0], 400);
    EXPECT_NEAR(j["geoTransform"][0].get<double>(), 549800.0, 1e-6);
    EXPECT_NEAR(j["geoTransform"][3].get<double>(), 4650200.0, 1e-6);
  }
}

TEST(MakeTerrain, BenchesAreTenMetresAndFacesThirtyFiveDegrees) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const fs::path out = dir / "dump.tif", ortho = dir / "ortho.tif";
  const auto r = runNestwalk("make-terrain " + quoted(out) + " --seed 3 --ortho " + quoted(ortho));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("ortho:"), std::string::npos) << r.out;
  double ce = 0, cn = 0, az = 0;
  const auto at = r.out.find("centre ");
  ASSERT_NE(at, std::string::npos) << r.out;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at, "centre %lf %lf, long axis azimuth %lf", &ce, &cn, &az), 3) << r.out;
  // A profile from the centre across the long side away from the ramp (azimuth az + 90).
  const double a = (az + 90.0) * std::numbers::pi / 180.0, step = 0.25;
  const int n = 1000;  // 250 m
  std::string csv = "x,y\n";
  char buf[96];
  for (int i = 0; i < n; ++i)
    std::snprintf(buf, sizeof buf, "%.6f,%.6f\n", ce + i * step * std::sin(a), cn + i * step * std::cos(a)), csv += buf;
  writeText(dir / "profile.csv", csv);
  const auto q = runNestwalk("query ground " + quoted(out) + " --points " + quoted(dir / "profile.csv"));
  ASSERT_EQ(q.exitCode, 0) << q.err;
  const auto zs = zColumn(q.out);
  ASSERT_EQ(zs.size(), std::size_t(n));
  std::vector<double> z;
  for (const auto& v : zs) z.push_back(*v);
  // Slope over a 2 m baseline (the grid has 1 m cells and centimetre roughness).
  const int w = 8;
  auto slopeDeg = [&](int i) { return std::atan(std::abs(z[i + w] - z[i]) / (w * step)) * 180.0 / std::numbers::pi; };
  std::vector<double> flats, faces;  // flat levels (median z), face slopes (fitted)
  std::vector<int> flatMiddles, faceMiddles;  // profile indices of their middles
  int toe = 0;                                // profile index where the last face ends
  int i = 0;
  while (i + w < n) {
    const bool steep = slopeDeg(i) > 20.0, flat = slopeDeg(i) < 4.0;
    int j = i;
    while (j + w < n && (steep ? slopeDeg(j) > 20.0 : flat ? slopeDeg(j) < 4.0 : false)) ++j;
    if (steep && (j - i) * step > 6.0) {
      // The face between its toe and crest, trimmed by 1.5 m at each end: rise over run.
      const int t = int(1.5 / step), s0 = i + t, s1 = j + w - t;
      faces.push_back(std::atan(std::abs(z[s1] - z[s0]) / ((s1 - s0) * step)) * 180.0 / std::numbers::pi);
      faceMiddles.push_back((s0 + s1) / 2);
      toe = j + w;
    }
    if (flat && (j - i) * step > 3.0) {
      std::vector<double> seg(z.begin() + i, z.begin() + j + w);
      std::nth_element(seg.begin(), seg.begin() + seg.size() / 2, seg.end());
      flats.push_back(seg[seg.size() / 2]);
      flatMiddles.push_back((i + j + w) / 2);
    }
    i = std::max(j, i + 1);
  }
  std::printf("[ dump     ] flats:");
  for (double f : flats) std::printf(" %.2f", f);
  std::printf("\n[ dump     ] faces (deg):");
  for (double f : faces) std::printf(" %.2f", f);
  std::printf("\n");
  // From the top: the top and three berms (flats 10 m apart), four faces, then the natural ground.
  ASSERT_GE(flats.size(), 4u);
  ASSERT_GE(faces.size(), 4u);
  for (std::size_t k = 0; k + 1 < 4; ++k) EXPECT_NEAR(flats[k] - flats[k + 1], 10.0, 0.3) << k;
  for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(faces[k], 35.0, 1.5) << k;

  // The orthophoto: on the DEM's grid, and the materials where the profile measured them. The
  // profile starts on the top; the ditch's bottom is the lowest point within 12 m beyond the toe of
  // the lowest face; 20 m beyond that toe lies natural ground (pits keep 25 m from the toe).
  const OrthoProbe probe(ortho);
  probe.expectOnTheGridOf(out);
  auto materialAt = [&](int k) { return probe.materialAt(ce + k * step * std::sin(a), cn + k * step * std::cos(a)); };
  EXPECT_EQ(materialAt(flatMiddles[0]), "top");
  for (std::size_t k = 1; k < 4; ++k) EXPECT_EQ(materialAt(flatMiddles[k]), "berm") << "flat " << k;
  for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(materialAt(faceMiddles[k]), "face") << "face " << k;
  const int ditchEnd = std::min(n - 1, toe + int(12.0 / step));
  const int ditch = int(std::min_element(z.begin() + toe, z.begin() + ditchEnd) - z.begin());
  EXPECT_GT(z[std::size_t(toe)] - z[std::size_t(ditch)], 1.0) << "the ditch is a trough";
  EXPECT_EQ(materialAt(ditch), "ditch");
  ASSERT_LT(toe + int(20.0 / step), n);
  EXPECT_EQ(materialAt(toe + int(20.0 / step)), "ground");
}

TEST(MakeTerrain, OrthoIsKeptWithoutOverwriteAndIsNotTheTerrain) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  writeText(dir / "ortho.tif", "mine");
  const auto kept = runNestwalk("make-terrain " + quoted(dir / "a.tif") + " --size 200 --ortho " + quoted(dir / "ortho.tif"));
  EXPECT_EQ(kept.exitCode, 1);
  EXPECT_NE(kept.err.find((dir / "ortho.tif").string() + ": already exists"), std::string::npos) << kept.err;
  EXPECT_EQ(readText(dir / "ortho.tif"), "mine");
  EXPECT_FALSE(fs::exists(dir / "a.tif")) << "nothing written when the ortho is refused";
  const auto same = runNestwalk("make-terrain " + quoted(dir / "a.tif") + " --size 200 --ortho " + quoted(dir / "a.tif"));
  EXPECT_EQ(same.exitCode, 1);
  EXPECT_NE(same.err.find("--ortho names the terrain file"), std::string::npos) << same.err;
  const auto over = runNestwalk("make-terrain " + quoted(dir / "a.tif") + " --size 200 --overwrite --ortho " +
                                quoted(dir / "ortho.tif"));
  ASSERT_EQ(over.exitCode, 0) << over.err;
  const OrthoProbe probe(dir / "ortho.tif");
  probe.expectOnTheGridOf(dir / "a.tif");
}

TEST(MakeTerrain, FinerOrthoPixelWritesADronesOrthophotoAndACoarserOneIsRefused) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto coarse = runNestwalk("make-terrain " + quoted(dir / "a.tif") + " --size 200 --ortho " +
                                  quoted(dir / "ortho.tif") + " --ortho-pixel 2");
  EXPECT_EQ(coarse.exitCode, 1);
  EXPECT_NE(coarse.err.find("--ortho-pixel must not be coarser than --cell"), std::string::npos) << coarse.err;
  EXPECT_FALSE(fs::exists(dir / "a.tif"));
  const auto fine = runNestwalk("make-terrain " + quoted(dir / "a.tif") + " --size 200 --ortho " +
                                quoted(dir / "ortho.tif") + " --ortho-pixel 0.25");
  ASSERT_EQ(fine.exitCode, 0) << fine.err;
  EXPECT_NE(fine.out.find("RGB JPEG at 0.25 m a pixel (materials, gravel, stones and vegetation patches)"),
            std::string::npos) << fine.out;
  // The same area as the DEM, four pixels a cell (the materials at the pixels are checked in
  // tests/terrain/mining_dump_ortho_test.cpp).
  const auto info = runCommand("gdalinfo " + quoted(dir / "ortho.tif"));
  EXPECT_NE(info.out.find("Size is 800, 800"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("Pixel Size = (0.250000000000000,-0.250000000000000)"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("JPEG"), std::string::npos) << info.out;
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename().string().find(".ortho.tif."), std::string::npos) << "a scratch file is left: " << entry.path();
}

}  // namespace
}  // namespace nestwalk::test
