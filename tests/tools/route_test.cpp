// `nestwalk route` on the bundled mining-dump scene: a UTM line becomes a script that `nestwalk run`
// plays to its last point, and `run --route` walks the same frames in one step; an existing script
// is kept unless --overwrite; a route of points only is refused with exit 1, the file and layer
// named, and nothing written.
#include "tests/common/build_paths.h"
#include "tests/common/run_command.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <sstream>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;

const fs::path kScene = fs::path(nestwalk::test::build::bundledSceneDir()) / "scene.json";

/// A GeoJSON layer in the bundled scene's CRS (UTM 51N, named by the legacy crs member OGR reads).
std::string geojson(const std::string& geometry) {
  return R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32651"}},
"features": [{"type": "Feature", "properties": {"name": "r"}, "geometry": )" + geometry + "}]}";
}

TEST(RouteCommand, WritesAScriptThatRunPlaysToTheEnd) {
  if (!fs::exists(kScene)) GTEST_SKIP() << kScene << " is absent: build the bundled_scene target";
  const TempFolder dir;
  writeText(dir / "line.geojson",
            geojson(R"({"type": "LineString", "coordinates": [[549600, 4650100], [549650, 4650120], [549700, 4650100]]})"));
  const std::string route = "route " + quoted(kScene) + " " + quoted(dir / "line.geojson") + " --speed 3 --out ";
  const auto made = runNestwalk(route + quoted(dir / "walk.txt"));
  ASSERT_EQ(made.exitCode, 0) << made.out << made.err;
  EXPECT_NE(made.out.find("walk.txt: 2 gotos, 107.7 m"), std::string::npos) << made.out;
  const std::string script = readText(dir / "walk.txt");
  EXPECT_NE(script.find("speed 3\nstart 549600 4650100 heading"), std::string::npos) << script;
  EXPECT_NE(script.find("goto 549700 4650100\n"), std::string::npos) << script;

  const auto run = runNestwalk("run " + quoted(kScene) + " --script " + quoted(dir / "walk.txt") + " --headless --quiet --out " +
                               quoted(dir / "run"));
  ASSERT_EQ(run.exitCode, 0) << run.out << run.err;
  const std::string frames = readText(dir / "run" / "frames.csv");
  const std::size_t last = frames.rfind('\n', frames.size() - 2);
  EXPECT_NE(frames.find(",549700.0000,4650100.0000,", last), std::string::npos) << frames.substr(last);
  // `run --route` in one step walks the same path, frame for frame (positions and headings).
  const auto direct = runNestwalk("run " + quoted(kScene) + " --route " + quoted(dir / "line.geojson") +
                                  " --speed 3 --headless --quiet --out " + quoted(dir / "direct"));
  ASSERT_EQ(direct.exitCode, 0) << direct.out << direct.err;
  const std::string directFrames = readText(dir / "direct" / "frames.csv");
  EXPECT_EQ(readText(dir / "direct" / "route_script.txt"), readText(dir / "walk.txt"));  // the played script, kept
  auto positions = [](const std::string& csv) {  // frame, time, x, y, z, heading of every row
    std::string out;
    std::stringstream in(csv);
    for (std::string line; std::getline(in, line);) {
      std::size_t pos = 0;
      for (int i = 0; i < 6 && pos != std::string::npos; ++i) pos = line.find(',', pos + 1);
      out += line.substr(0, pos) + "\n";
    }
    return out;
  };
  EXPECT_EQ(positions(directFrames), positions(frames));

  // Kept unless asked; replaced with --overwrite.
  writeText(dir / "walk.txt", "# mine\n");
  const auto kept = runNestwalk(route + quoted(dir / "walk.txt"));
  EXPECT_EQ(kept.exitCode, 1);
  EXPECT_NE(kept.err.find("walk.txt: exists; pass --overwrite"), std::string::npos) << kept.err;
  EXPECT_EQ(readText(dir / "walk.txt"), "# mine\n");
  EXPECT_EQ(runNestwalk(route + quoted(dir / "walk.txt") + " --overwrite").exitCode, 0);
  EXPECT_NE(readText(dir / "walk.txt").find("goto 549700 4650100"), std::string::npos);
}

TEST(RouteCommand, PointsOnlyAreRefusedAndNothingIsWritten) {
  if (!fs::exists(kScene)) GTEST_SKIP() << kScene << " is absent: build the bundled_scene target";
  const TempFolder dir;
  writeText(dir / "wells.geojson", geojson(R"({"type": "Point", "coordinates": [549600, 4650100]})"));
  const auto r = runNestwalk("route " + quoted(kScene) + " " + quoted(dir / "wells.geojson") + " --out " +
                             quoted(dir / "walk.txt"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("wells.geojson: layer 'wells' feature 0: is a Point, not a line"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "walk.txt"));
  for (const auto& e : fs::directory_iterator(dir.path())) EXPECT_EQ(e.path().filename(), "wells.geojson");
}

// The bundled GPS track replayed at its pace (the main job's run): the walk ends at the last fix's
// time plus the stop's wait, within a step, and the run writes its layers. The GIS sample's copy of
// the track plays on the scene built from the GIS inputs (the same site, its own scene file).
TEST(RouteCommand, BundledTrackReplaysAtItsRecordedPace) {
  if (!fs::exists(kScene)) GTEST_SKIP() << kScene << " is absent: build the bundled_scene target";
  const TempFolder dir;
  const fs::path gpx = kScene.parent_path() / "routes" / "patrol_track.gpx";
  const std::string text = readText(gpx);
  std::size_t fixes = 0;
  for (std::size_t at = text.find("<trkpt"); at != std::string::npos; at = text.find("<trkpt", at + 1)) ++fixes;
  ASSERT_GT(fixes, 40u);
  const auto r = runNestwalk("run " + quoted(kScene) + " --route " + quoted(gpx) +
                             " --use-times --stops waypoints --stop-wait 3 --headless --quiet --out " + quoted(dir / "run"));
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const auto summary = nlohmann::json::parse(readText(dir / "run" / "summary.json"));
  const double want = double(fixes - 1) + 3.0;  // one fix a second, and the wait at the station
  EXPECT_NEAR(summary["simulated_seconds"].get<double>(), want, 1.0 / 60 + 1e-9);
  EXPECT_TRUE(fs::exists(dir / "run" / "results.gpkg"));
  EXPECT_TRUE(fs::exists(dir / "run" / "results.geojson"));

  const fs::path gisScene = kScene.parent_path().parent_path() / "gis_dump" / "scene.json";
  const fs::path gisTrack = kScene.parent_path().parent_path() / "gis_dump_inputs" / "routes" / "patrol_track.gpx";
  ASSERT_TRUE(fs::exists(gisScene)) << "the gis_sample_scene target builds it";
  ASSERT_TRUE(fs::exists(gisTrack));
  const auto g = runNestwalk("run " + quoted(gisScene) + " --route " + quoted(gisTrack) +
                             " --use-times --headless --quiet --out " + quoted(dir / "gis"));
  ASSERT_EQ(g.exitCode, 0) << g.out << g.err;
  const auto gisSummary = nlohmann::json::parse(readText(dir / "gis" / "summary.json"));
  EXPECT_NEAR(gisSummary["simulated_seconds"].get<double>(), double(fixes - 1), 1.0 / 60 + 1e-9);
}

}  // namespace
}  // namespace nestwalk::test
