// assets/generators/scene_generator.h: the bundled mining-dump scene, generated once and measured
// from what was written (scene.json parsed as JSON, the terrain read back from terrain.tif, the
// models loaded through osgDB and fitted with the engine's OBB fitter): enough pieces, every one
// standing on flat berm at its bench's level, distinct groups apart, the scripts' lanes as they
// claim (blocked where the patrol expects, free on the ramp), and the same bytes from the same seed.
#include "assets/generators/scene_generator.h"
#include "nestwalk/core/input_error.h"
#include "nestwalk/geometry/nested.h"
#include "nestwalk/geometry/obb_fit.h"
#include "nestwalk/scene/model_geometry.h"
#include "nestwalk/terrain/dem_reader.h"
#include "tests/common/temp_folder.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <ogr_api.h>
#include <proj.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <unistd.h>

namespace nestwalk::assets {
namespace {

namespace fs = std::filesystem;

constexpr double kBermTolerance = 0.3;   // metres: ground under a piece vs its berm's level
constexpr double kBenchHeight = 10.0;    // metres between berms (terrain/mining_dump.h default)
constexpr double kGroupClearance = 0.5;  // metres at least between the fitted boxes of different groups
const Eigen::Vector3d kBodyHalf(0.25, 0.25, 0.9);  // the scene's walker body (scene_file.h default)

using test::readText;

/// The scene of seed 1, generated and written once for the whole program.
struct Written {
  GeneratedScene scene;
  fs::path dir;
  nlohmann::json json;
};

const Written& written() {
  static const Written w = [] {
    Written r;
    r.scene = generateScene(1);
    static const test::TempFolder folder("scene");  // the whole program's, removed at its end
    r.dir = folder / "mining_dump";
    writeScene(r.scene, r.dir.string(), false);
    r.json = nlohmann::json::parse(readText(r.dir / "scene.json"));
    return r;
  }();
  return w;
}

/// A piece as the scene file says, with its model's geometry placed on the terrain.
struct Piece {
  std::string name, group, kind;
  int bench = 0;
  Eigen::Vector2d position;
  double heading = 0;
  Obb<double> box;              // the fitted OBB, placed (map frame, base on the ground)
  std::vector<Eigen::Vector2d> footprint;  // the model AABB's four ground corners, map frame
};

/// Model frame -> map axes for a heading clockwise from north (+y forward, +x right).
Mat3<double> headingRotation(double deg) {
  const double h = deg * std::numbers::pi / 180;
  Mat3<double> r;
  r << std::cos(h), std::sin(h), 0, -std::sin(h), std::cos(h), 0, 0, 0, 1;
  return r;
}

const std::vector<Piece>& pieces() {
  static const std::vector<Piece> all = [] {
    const Written& w = written();
    const terrain::Heightfield hf = terrain::readDem((w.dir / "terrain.tif").string());
    std::map<std::string, std::pair<Obb<double>, Aabb<double>>> models;
    std::vector<Piece> out;
    const std::regex benchRe("^bench([0-9]+)/[a-z]+[0-9]+$");
    for (const auto& e : w.json["equipment"]) {
      Piece p;
      p.name = e["name"];
      p.group = e["group"];
      p.kind = e["kind"];
      std::smatch m;
      EXPECT_TRUE(std::regex_match(p.group, m, benchRe)) << p.group;
      p.bench = m.empty() ? 0 : std::stoi(m[1]);
      EXPECT_EQ(e["position"].size(), 2u);  // no z: stands on the ground
      p.position = {e["position"][0].get<double>(), e["position"][1].get<double>()};
      p.heading = e.value("heading", 0.0);
      const std::string model = (w.dir / e["model"].get<std::string>()).string();
      if (!models.count(model)) {
        const TriangleMesh g = loadModelGeometry(model);
        Aabb<double> b;
        for (const auto& v : g.vertices) b.extend(v);
        models[model] = {fitObb(g.vertices, ObbFitter::HullSearch), b};
      }
      const auto& [obb, aabb] = models[model];
      const Mat3<double> r = headingRotation(p.heading);
      const double ground = hf.groundHeight(p.position.x(), p.position.y()).value_or(NAN);
      const Vec3<double> at(p.position.x(), p.position.y(), ground);
      p.box = {r * obb.center + at, r * obb.axes, obb.halfExtents};
      for (int i = 0; i < 4; ++i) {
        const Vec3<double> c((i & 1) ? aabb.max.x() : aabb.min.x(), (i & 2) ? aabb.max.y() : aabb.min.y(), 0);
        p.footprint.push_back((r * c + at).head<2>());
      }
      out.push_back(p);
    }
    return out;
  }();
  return all;
}

TEST(SceneGenerator, EnoughPiecesOfEveryKindWithUniqueNames) {
  const auto& ps = pieces();
  EXPECT_GE(ps.size(), 200u);
  std::set<std::string> names;
  std::map<std::string, int> kinds;
  for (const Piece& p : ps) {
    EXPECT_TRUE(names.insert(p.name).second) << p.name;
    EXPECT_EQ(p.name.rfind(p.group + "/", 0), 0u) << p.name;
    ++kinds[p.kind];
  }
  for (const char* k : {"pole", "station", "solar", "logger", "piezometer", "container", "barrier", "vehicle"})
    EXPECT_GT(kinds[k], 0) << k;
  EXPECT_GE(kinds["vehicle"], 1);
  EXPECT_LE(kinds["vehicle"], 2);
  // Stations are a mast, a logger box and a panel; fence segments are use_only, nothing else is.
  std::map<std::string, std::multiset<std::string>> stationParts;
  for (const auto& e : written().json["equipment"]) {
    const std::string g = e["group"], kind = e["kind"];
    EXPECT_EQ(e.value("use_only", false), kind == "barrier") << e["name"];
    if (g.find("/station") != std::string::npos) stationParts[g].insert(kind);
  }
  for (const auto& [g, parts] : stationParts) EXPECT_EQ(parts, (std::multiset<std::string>{"logger", "solar", "station"})) << g;
}

TEST(SceneGenerator, EveryPieceStandsOnFlatBermAtItsBenchLevel) {
  const Written& w = written();
  const terrain::Heightfield hf = terrain::readDem((w.dir / "terrain.tif").string());
  const double base = w.scene.dump.layout.baseHeight;
  for (const Piece& p : pieces()) {
    SCOPED_TRACE(p.name);
    const double level = base + p.bench * kBenchHeight;
    ASSERT_GE(p.bench, 1);
    const auto z = hf.groundHeight(p.position.x(), p.position.y());
    ASSERT_TRUE(z);
    EXPECT_NEAR(*z, level, kBermTolerance);
    for (const auto& c : p.footprint) {
      const auto zc = hf.groundHeight(c.x(), c.y());
      ASSERT_TRUE(zc);
      EXPECT_NEAR(*zc, *z, kBermTolerance);
    }
  }
}

TEST(SceneGenerator, DistinctGroupsKeepApart) {
  const auto& ps = pieces();
  int pairs = 0;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    Obb<double> a = ps[i].box;
    a.halfExtents.array() += 0.5 * kGroupClearance;
    for (std::size_t j = i + 1; j < ps.size(); ++j) {
      if (ps[i].group == ps[j].group) continue;
      if ((ps[i].position - ps[j].position).norm() > 20.0) continue;  // far apart: the biggest piece is 6.1 m
      Obb<double> b = ps[j].box;
      b.halfExtents.array() += 0.5 * kGroupClearance;
      EXPECT_FALSE(testBoxPair(a, b).overlap) << ps[i].name << " and " << ps[j].name;
      ++pairs;
    }
  }
  EXPECT_GT(pairs, 100);  // the check saw neighbours
}

/// The walker's body box with its feet at a map point, facing a heading.
Obb<double> bodyAt(const terrain::Heightfield& hf, const Eigen::Vector2d& p, double heading) {
  Obb<double> b;
  b.axes = headingRotation(heading);
  b.center = Vec3<double>(p.x(), p.y(), *hf.groundHeight(p.x(), p.y()) + kBodyHalf.z());
  b.halfExtents = kBodyHalf;
  return b;
}

TEST(SceneGenerator, PatrolLaneIsFreeUpToTheStationThatStandsOnIt) {
  const Written& w = written();
  const ScriptPoints& P = w.scene.points;
  const terrain::Heightfield hf = terrain::readDem((w.dir / "terrain.tif").string());
  const Eigen::Vector2d dir = (P.patrolTarget - P.patrolStart).normalized();
  const double toMast = (P.patrolMast - P.patrolStart).dot(dir);
  EXPECT_LT(((P.patrolMast - P.patrolStart) - toMast * dir).norm(), 1e-2);  // the mast stands on the lane's line
  const Piece* mast = nullptr;
  for (const Piece& p : pieces())
    if (p.group == P.patrolStation && p.kind == "station") mast = &p;
  ASSERT_NE(mast, nullptr);
  // Walking the lane: free until within the body's half length plus the mast box's reach.
  const double stopAt = (P.patrolBlockedAt - P.patrolStart).dot(dir);
  EXPECT_NEAR(toMast - stopAt, 0.75, 0.3);
  int blockedAt = -1;
  for (int k = 0; k * 0.05 < toMast; ++k) {
    const Obb<double> body = bodyAt(hf, P.patrolStart + k * 0.05 * dir, P.patrolHeading);
    for (const Piece& p : pieces())
      if ((p.position - P.patrolStart - k * 0.05 * dir).norm() < 10 && testBoxPair(body, p.box).overlap) {
        EXPECT_EQ(p.group, P.patrolStation) << "the lane is blocked by " << p.name;
        if (blockedAt < 0) blockedAt = k;
      }
  }
  ASSERT_GE(blockedAt, 0);
  EXPECT_NEAR(blockedAt * 0.05, stopAt, 0.1);
  // The script says so.
  const std::string patrol = readText(w.dir / "scripts" / "bench_patrol.txt");
  EXPECT_NE(patrol.find("expect blocked by " + P.patrolStation + "\n"), std::string::npos) << patrol;
  EXPECT_NE(patrol.find("expect free\n"), std::string::npos);
  EXPECT_NE(patrol.find("expect ground within 0.01\n"), std::string::npos);
}

TEST(SceneGenerator, RampIsWhereTheGeometrySaysAndItsPathIsFreeAndWalkable) {
  const Written& w = written();
  const DumpGeometry& g = w.scene.geometry;
  const ScriptPoints& P = w.scene.points;
  const terrain::Heightfield hf = terrain::readDem((w.dir / "terrain.tif").string());
  // The recomputed ramp matches the generated heights on its centre line (5 cm roughness).
  for (double u = g.rampStart + 1; u < g.rampEnd; u += 5) {
    const Eigen::Vector2d p = g.toMap(u, g.rampV);
    EXPECT_NEAR(*hf.groundHeight(p.x(), p.y()), g.rampHeight(u), 0.06) << "u " << u;
  }
  const Eigen::Vector2d top = g.toMap(g.rampEnd + 12, g.rampV);
  EXPECT_NEAR(*hf.groundHeight(top.x(), top.y()), g.layout.topHeight, 0.06);
  // The descent: no piece on the way, slopes under 30 degrees along it.
  const Eigen::Vector2d d = P.rampToe - P.rampTop;
  const double len = d.norm();
  double prev = *hf.groundHeight(P.rampTop.x(), P.rampTop.y());
  for (double s = 0.5; s <= len; s += 0.5) {
    const Eigen::Vector2d p = P.rampTop + d * (s / len);
    const Obb<double> body = bodyAt(hf, p, P.rampHeading);
    for (const Piece& q : pieces()) {
      if ((q.position - p).norm() < 10) {
        EXPECT_FALSE(testBoxPair(body, q.box).overlap) << q.name;
      }
    }
    const double z = *hf.groundHeight(p.x(), p.y());
    EXPECT_LT(std::abs(z - prev) / 0.5, std::tan(30 * std::numbers::pi / 180));
    prev = z;
  }
  EXPECT_NEAR(prev, w.scene.dump.layout.baseHeight, 1.0);  // down at the toe
}

TEST(SceneGenerator, ScriptsUseTheirCommands) {
  const Written& w = written();
  const std::string ramp = readText(w.dir / "scripts" / "ramp_descent.txt");
  EXPECT_NE(ramp.find("mode walk\n"), std::string::npos);
  EXPECT_NE(ramp.find(" within 1\n"), std::string::npos);
  const std::string flight = readText(w.dir / "scripts" / "low_flight.txt");
  EXPECT_NE(flight.find("mode fly\n"), std::string::npos);
  EXPECT_NE(flight.find("clearance 5.000\n"), std::string::npos);
  EXPECT_NE(flight.find("expect clearance at least 5.000\n"), std::string::npos);
  EXPECT_NE(flight.find("expect free\n"), std::string::npos);
}

TEST(SceneGenerator, SameSeedSameBytesOtherSeedOtherScene) {
  const Written& w = written();
  const GeneratedScene again = generateScene(1);
  EXPECT_EQ(again.sceneJson, w.scene.sceneJson);
  EXPECT_EQ(again.scripts, w.scene.scripts);
  const fs::path dir2 = w.dir.parent_path() / "again";
  writeScene(again, dir2.string(), false);
  EXPECT_EQ(readText(dir2 / "scene.json"), readText(w.dir / "scene.json"));
  EXPECT_EQ(readText(dir2 / "ortho.tif"), readText(w.dir / "ortho.tif")) << "the orthophoto's noise is seeded";
  for (const auto& f : fs::directory_iterator(w.dir / "models"))
    EXPECT_EQ(readText(dir2 / "models" / f.path().filename()), readText(f.path())) << f.path();
  for (const auto& f : fs::directory_iterator(w.dir / "scripts"))
    EXPECT_EQ(readText(dir2 / "scripts" / f.path().filename()), readText(f.path())) << f.path();
  EXPECT_NE(generateScene(2).sceneJson, w.scene.sceneJson);
}

TEST(SceneGenerator, ExistingFolderIsKeptWithoutOverwrite) {
  const Written& w = written();
  const fs::path dir = w.dir.parent_path() / "kept";
  fs::create_directories(dir);
  std::ofstream(dir / "mine.txt") << "keep me";
  EXPECT_THROW(writeScene(w.scene, dir.string(), false), InputError);
  EXPECT_EQ(readText(dir / "mine.txt"), "keep me");
  EXPECT_FALSE(fs::exists(dir / "scene.json"));
  writeScene(w.scene, dir.string(), true);
  EXPECT_FALSE(fs::exists(dir / "mine.txt"));
  EXPECT_TRUE(fs::exists(dir / "scene.json"));
  // No temporary folder is left beside it.
  for (const auto& f : fs::directory_iterator(dir.parent_path()))
    EXPECT_EQ(f.path().filename().string().find(".kept"), std::string::npos) << f.path();
}

}  // namespace
}  // namespace nestwalk::assets

namespace nestwalk::assets {
namespace {

// The bundled GPS track (routes/patrol_track.gpx), read back with OGR's GPX driver as a user's
// track is: one track of fixes one second apart, each within 25 cm (5 sigma) of the patrol's lane
// (the line through the patrol's start and mast, the scene's own points, carried to WGS 84 by PROJ
// here), its ele the ground's height rounded to 0.1 m, a pause of 12 fixes in a row within 25 cm
// of each other, and the station as its waypoint.
TEST(PhoneTrack, BundledTrackIsAPhonesRecordOfThePatrolLane) {
  const Written& w = written();
  const fs::path gpx = w.dir / "routes" / "patrol_track.gpx";
  ASSERT_TRUE(fs::exists(gpx));
  GDALAllRegister();
  GDALDatasetH ds = GDALOpenEx(gpx.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  ASSERT_NE(ds, nullptr);
  PJ_CONTEXT* ctx = proj_context_create();
  PJ* raw = proj_create_crs_to_crs(ctx, "EPSG:4326", w.scene.site.crs, nullptr);
  PJ* toMap = proj_normalize_for_visualization(ctx, raw);
  proj_destroy(raw);
  auto mapOf = [&](double lon, double lat) {
    const PJ_COORD c = proj_trans(toMap, PJ_FWD, proj_coord(lon, lat, 0, 0));
    return Eigen::Vector2d(c.xy.x, c.xy.y);
  };
  const terrain::Heightfield hf = terrain::readDem((w.dir / "terrain.tif").string());
  const ScriptPoints& P = w.scene.points;
  const Eigen::Vector2d along = (P.patrolMast - P.patrolStart).normalized();

  OGRLayerH points = GDALDatasetGetLayerByName(ds, "track_points");
  ASSERT_NE(points, nullptr);
  std::vector<Eigen::Vector2d> fixes;
  std::vector<double> seconds;
  const int timeField = OGR_FD_GetFieldIndex(OGR_L_GetLayerDefn(points), "time");
  const int eleField = OGR_FD_GetFieldIndex(OGR_L_GetLayerDefn(points), "ele");
  for (OGRFeatureH f = OGR_L_GetNextFeature(points); f; f = OGR_L_GetNextFeature(points)) {
    OGRGeometryH g = OGR_F_GetGeometryRef(f);
    const Eigen::Vector2d p = mapOf(OGR_G_GetX(g, 0), OGR_G_GetY(g, 0));
    const Eigen::Vector2d off = p - P.patrolStart;
    EXPECT_LT(std::abs(off.x() * along.y() - off.y() * along.x()), 0.25) << "fix " << fixes.size() << " off the lane";
    const std::optional<double> ground = hf.groundHeight(p.x(), p.y());
    ASSERT_TRUE(ground.has_value());
    EXPECT_NEAR(OGR_F_GetFieldAsDouble(f, eleField), *ground, 0.05 + 1e-9);
    int y, mo, d, h, mi, tz;
    float s;
    ASSERT_TRUE(OGR_F_GetFieldAsDateTimeEx(f, timeField, &y, &mo, &d, &h, &mi, &s, &tz));
    seconds.push_back(h * 3600.0 + mi * 60.0 + s);
    fixes.push_back(p);
    OGR_F_Destroy(f);
  }
  ASSERT_GT(fixes.size(), 40u);
  int still = 1, longestStill = 1;  // fixes in a row standing still
  for (std::size_t k = 1; k < fixes.size(); ++k) {
    EXPECT_EQ(seconds[k] - seconds[k - 1], 1.0) << "fix " << k;
    still = (fixes[k] - fixes[k - 1]).norm() < 0.25 ? still + 1 : 1;
    longestStill = std::max(longestStill, still);
  }
  EXPECT_GE(longestStill, 12);
  OGRLayerH waypoints = GDALDatasetGetLayerByName(ds, "waypoints");
  ASSERT_EQ(OGR_L_GetFeatureCount(waypoints, TRUE), 1);
  OGRFeatureH wpt = OGR_L_GetNextFeature(waypoints);
  EXPECT_EQ(std::string(OGR_F_GetFieldAsString(wpt, OGR_F_GetFieldIndex(wpt, "name"))), P.patrolStation);
  const Eigen::Vector2d station = mapOf(OGR_G_GetX(OGR_F_GetGeometryRef(wpt), 0), OGR_G_GetY(OGR_F_GetGeometryRef(wpt), 0));
  EXPECT_LT((station - P.patrolMast).norm(), 0.002);  // 8 decimals of a degree: about a millimetre
  OGR_F_Destroy(wpt);
  proj_destroy(toMap);
  proj_context_destroy(ctx);
  GDALClose(ds);
}

}  // namespace
}  // namespace nestwalk::assets
