// Routes as scripts (gis/route_plan.h): a line in every vector format OGR reads, in a geographic
// and a projected CRS, gives the same script, its points where PROJ puts them (proj_trans, called
// here) within 1 mm. Played on a scene: the walk passes each point within 1 cm, sets off along each
// segment at its grid azimuth (from PROJ's points) within 1e-6 degrees and stays on its line
// within 1 um; a GPX track with times replayed with --use-times is at each fix within one step of
// its recorded time, pauses included; flying keeps the eye at the asked height over each point; a
// stop turns the view to its instrument. Bad routes are refused naming the file, layer and feature.
#include "nestwalk/gis/route_plan.h"
#include "nestwalk/scene/scene.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/collision_world.h"
#include "nestwalk/walker/flythrough.h"
#include "nestwalk/walker/script.h"
#include "tests/common/input_error_of.h"
#include "tests/gis/gis_test_util.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

constexpr double kScriptTol = 1e-3;      // m: the issue's "the same script within 1 mm"
constexpr double kVertexTol = 0.01;      // m: the played path passes each point within 1 cm
constexpr double kAzimuthTol = 1e-6;     // degrees
constexpr double kOnLineTol = 1e-6;      // m: every step on its segment's line
constexpr double kDt = 1.0 / 60.0;       // s: the walker's default step

/// Degrees clockwise from grid north of a map direction (the test's own, not core's headingOf).
double azimuth(const Eigen::Vector2d& d) { return std::atan2(d.x(), d.y()) * 180.0 / std::numbers::pi; }

struct Latitude {
  const char* name;
  test::UtmTerrain terrain;
};
const Latitude kLatitudes[] = {
    {"utm12n_46deg", {32612, 400000.0, 5100400.0, 400}},
    {"utm33n_70deg", {32633, 620000.0, 7770400.0, 400}},
};

/// The route's points in UTM: a zigzag with a sharp turn, inside the 400 m terrain.
std::vector<Eigen::Vector2d> routeUtm(const test::UtmTerrain& t) {
  const double x = t.west, y = t.north;
  return {{x + 50.3, y - 60.1}, {x + 120.7, y - 75.2}, {x + 131.0, y - 140.9}, {x + 70.2, y - 150.4}, {x + 200.5, y - 320.8}};
}

/// A scene over `dem.tif` in `dir` with one box far from every route (scene.json).
fs::path writeScene(const fs::path& dir, const test::UtmTerrain& t,
                    std::optional<std::pair<int, int>> holeAt = std::nullopt) {
  test::writeUtmTerrain(dir / "dem.tif", t, holeAt);
  test::writeBoxModel(dir / "box.osgt", {-0.5, -0.5, 0.0}, {0.5, 0.5, 1.0});
  char buf[512];
  std::snprintf(buf, sizeof buf,
                R"({"terrain": "dem.tif", "equipment": [{"name": "far", "model": "box.osgt", "position": [%.3f, %.3f]}]})",
                t.west + 380.0, t.north - 20.0);
  test::writeText(dir / "scene.json", buf);
  return dir / "scene.json";
}

/// A test's site: a scene over the terrain at `lat` in the test's folder, the route's UTM points and
/// PROJ's longitudes and latitudes of them.
struct Site {
  explicit Site(const Latitude& l)
      : lat(l), proj(l.terrain.epsg), scene(writeScene(dir.path(), l.terrain)), utm(routeUtm(l.terrain)) {
    for (const auto& p : utm) lonLat.push_back(proj.toLonLat(p));
  }
  const Latitude& lat;
  const test::TempFolder dir;
  const test::ProjOracle proj;
  const fs::path scene;
  const std::vector<Eigen::Vector2d> utm;
  std::vector<Eigen::Vector2d> lonLat;
};

/// A GPX track of `lonLat` points (with times when given: seconds after 2026-05-04T06:00:00Z; ele
/// 1000 m unless given).
std::string gpxTrack(const std::vector<Eigen::Vector2d>& lonLat, const std::vector<double>& times = {},
                     const std::vector<double>& eles = {}) {
  std::string s = R"(<?xml version="1.0" encoding="UTF-8"?>
<gpx version="1.1" creator="nestwalk test" xmlns="http://www.topografix.com/GPX/1/1">
<wpt lat="0" lon="0"><name>unused</name></wpt>
<trk><name>walk</name><trkseg>
)";
  char buf[256];
  for (std::size_t k = 0; k < lonLat.size(); ++k) {
    std::snprintf(buf, sizeof buf, R"(<trkpt lat="%.15f" lon="%.15f"><ele>%.6f</ele>)", lonLat[k].y(), lonLat[k].x(),
                  eles.empty() ? 1000.0 : eles[k]);
    s += buf;
    if (!times.empty()) {
      const double t = times[k];
      const int whole = int(std::floor(t));
      std::snprintf(buf, sizeof buf, "<time>2026-05-04T%02d:%02d:%06.3fZ</time>", 6 + whole / 3600, (whole / 60) % 60,
                    std::fmod(t, 60.0));
      s += buf;
    }
    s += "</trkpt>\n";
  }
  return s + "</trkseg></trk>\n</gpx>\n";
}

/// The numbers after `op` on each line of the script that starts with it.
std::vector<std::vector<double>> linesOf(const std::string& text, const std::string& op) {
  std::vector<std::vector<double>> out;
  const Script s = parseScript(text, "route");
  for (const ScriptCommand& c : s.commands) {
    if (std::string(scriptOpName(c.op)) != op) continue;
    out.push_back({c.v.x(), c.v.y(), c.v.z(), c.hasTime ? c.time : -1.0, c.hasHeading ? c.heading : -1.0});
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Formats and CRSs: the same script, at PROJ's positions.

struct Format {
  const char* name;
  const char* driver;  // OGR driver; "GPX" and "CSV" are written by hand
  const char* extension;
  bool projected;      // the layer in the terrain's UTM CRS instead of EPSG:4326
};
const Format kFormats[] = {{"gpx", "GPX", ".gpx", false},           {"gpkg", "GPKG", ".gpkg", false},
                           {"gpkg_utm", "GPKG", ".gpkg", true},    {"shapefile", "ESRI Shapefile", ".shp", false},
                           {"geojson", "GeoJSON", ".geojson", false}, {"kml", "LIBKML", ".kml", false},
                           {"csv", "CSV", ".csv", false}};

/// A one-feature line layer in EPSG:`epsg` (map coordinates), written with OGR's `driver`.
void writeProjectedLine(const fs::path& path, const char* driver, const char* layer, int epsg,
                        const std::vector<Eigen::Vector2d>& points) {
  GDALAllRegister();
  GDALDatasetH ds = GDALCreate(GDALGetDriverByName(driver), path.c_str(), 0, 0, 0, GDT_Unknown, nullptr);
  ASSERT_NE(ds, nullptr);
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  OSRImportFromEPSG(srs, epsg);
  OGRLayerH l = GDALDatasetCreateLayer(ds, layer, srs, wkbLineString, nullptr);
  OGRFeatureH feature = OGR_F_Create(OGR_L_GetLayerDefn(l));
  OGRGeometryH g = OGR_G_CreateGeometry(wkbLineString);
  for (const auto& p : points) OGR_G_AddPoint_2D(g, p.x(), p.y());
  OGR_F_SetGeometryDirectly(feature, g);
  ASSERT_EQ(OGR_L_CreateFeature(l, feature), OGRERR_NONE);
  OGR_F_Destroy(feature);
  OSRDestroySpatialReference(srs);
  GDALClose(ds);
}

void writeRoute(const fs::path& path, const Format& f, const std::vector<Eigen::Vector2d>& lonLat,
                const std::vector<Eigen::Vector2d>& utm, int epsg) {
  const std::string driver = f.driver;
  if (driver == "GPX") return test::writeText(path, gpxTrack(lonLat));
  if (driver == "CSV") {
    std::string wkt = "wkt,name\n\"LINESTRING (";
    char buf[96];
    for (std::size_t k = 0; k < lonLat.size(); ++k) {
      std::snprintf(buf, sizeof buf, "%s%.15g %.15g", k ? ", " : "", lonLat[k].x(), lonLat[k].y());
      wkt += buf;
    }
    return test::writeText(path, wkt + ")\",walk\n");
  }
  if (!f.projected) return test::writeGeoLayer(path, f.driver, "route", {{"route", "walk", std::nullopt, lonLat}});
  writeProjectedLine(path, f.driver, "route", epsg, utm);
}

class RouteFormats : public ::testing::TestWithParam<std::tuple<Latitude, Format>> {};

TEST_P(RouteFormats, ScriptPointsAreProjsWithinAMillimetre) {
  const auto& [lat, format] = GetParam();
  const test::TempFolder dir;
  const test::ProjOracle proj(lat.terrain.epsg);
  const fs::path scene = writeScene(dir.path(), lat.terrain);
  std::vector<Eigen::Vector2d> lonLat;
  for (const auto& p : routeUtm(lat.terrain)) lonLat.push_back(proj.toLonLat(p));
  std::vector<Eigen::Vector2d> want;  // PROJ's UTM points of the geographic route
  for (const auto& p : lonLat) want.push_back(format.projected ? Eigen::Vector2d(0, 0) : proj.toUtm(p));
  if (format.projected) want = routeUtm(lat.terrain);
  const fs::path file = dir / (std::string("route") + format.extension);
  writeRoute(file, format, lonLat, routeUtm(lat.terrain), lat.terrain.epsg);

  gis::RouteRequest request;
  request.route.source = file.string();
  if (std::string(format.driver) == "CSV") request.route.assumedCrs = "EPSG:4326";
  const gis::RouteScript script = gis::planRoute(scene.string(), request);
  const auto starts = linesOf(script.text, "start"), gotos = linesOf(script.text, "goto");
  ASSERT_EQ(starts.size(), 1u);
  ASSERT_EQ(gotos.size(), want.size() - 1);
  double worst = std::hypot(starts[0][0] - want[0].x(), starts[0][1] - want[0].y());
  for (std::size_t k = 0; k < gotos.size(); ++k)
    worst = std::max(worst, std::hypot(gotos[k][0] - want[k + 1].x(), gotos[k][1] - want[k + 1].y()));
  EXPECT_LT(worst, kScriptTol) << script.text;
  // The start faces the first segment: its grid azimuth from PROJ's points.
  const Eigen::Vector2d d = want[1] - want[0];
  EXPECT_NEAR(std::remainder(starts[0][4] - azimuth(d), 360.0), 0.0, kAzimuthTol);
  EXPECT_NE(script.text.find("mode walk"), std::string::npos);
  std::printf("[%s %s] worst point %.3g m from PROJ's\n", lat.name, format.name, worst);
}

INSTANTIATE_TEST_SUITE_P(
    All, RouteFormats, ::testing::Combine(::testing::ValuesIn(kLatitudes), ::testing::ValuesIn(kFormats)),
    [](const auto& info) { return std::string(std::get<0>(info.param).name) + "_" + std::get<1>(info.param).name; });

// ---------------------------------------------------------------------------------------------
// Played: the walk, a timed replay, a flight, a stop.

struct Played {
  std::unique_ptr<Scene> scene;
  FlythroughResult result;
};

Played play(const fs::path& sceneFile, const std::string& text) {
  Played p;
  p.scene = std::make_unique<Scene>(loadScene(sceneFile.string()));
  const CollisionWorld world = CollisionWorld::fromScene(*p.scene, p.scene->spec.method);
  WalkerOptions options;
  options.viewer = p.scene->spec.viewer;
  options.dt = kDt;
  p.result = runFlythrough(*p.scene, world, parseScript(text, "route"), options);
  return p;
}

double horizontal(const FrameRecord& r, const Eigen::Vector2d& p) { return std::hypot(r.eye.x() - p.x(), r.eye.y() - p.y()); }

/// The record (from `from` on) of the closest approach to `p` horizontally, the first time the
/// eye comes within `tol` of it; npos when it never does.
std::size_t reach(const std::vector<FrameRecord>& records, std::size_t from, const Eigen::Vector2d& p, double tol) {
  for (std::size_t i = from; i < records.size(); ++i)
    if (horizontal(records[i], p) <= tol) {
      while (i + 1 < records.size() && horizontal(records[i + 1], p) < horizontal(records[i], p)) ++i;
      return i;
    }
  return std::string::npos;
}

TEST(RoutePlayed, WalkPassesEveryPointAndWalksEachSegmentAtItsAzimuth) {
  const Latitude& lat = kLatitudes[1];  // 70 N: convergence near 3 degrees
  const test::TempFolder dir;
  const test::ProjOracle proj(lat.terrain.epsg);
  const fs::path scene = writeScene(dir.path(), lat.terrain);
  std::vector<Eigen::Vector2d> lonLat, want;
  for (const auto& p : routeUtm(lat.terrain)) lonLat.push_back(proj.toLonLat(p));
  for (const auto& p : lonLat) want.push_back(proj.toUtm(p));
  test::writeText(dir / "walk.gpx", gpxTrack(lonLat));
  gis::RouteRequest request;
  request.route.source = (dir / "walk.gpx").string();
  request.script.speed = 2.0;
  const Played p = play(scene, gis::planRoute(scene.string(), request).text);
  const auto& records = p.result.records;
  std::size_t at = 0;
  double worstPoint = 0, worstAzimuth = 0, worstLine = 0;
  for (std::size_t k = 1; k < want.size(); ++k) {
    const std::size_t i = reach(records, at, want[k], kVertexTol);
    ASSERT_NE(i, std::string::npos) << "point " << k << " never reached within 1 cm";
    worstPoint = std::max(worstPoint, std::hypot(records[i].eye.x() - want[k].x(), records[i].eye.y() - want[k].y()));
    // The first step along the segment faces its azimuth; every step stays on its line (the
    // player re-aims at the point every step, so near the end the heading answers the map
    // coordinates' rounding, 1e-9 m at 7.8e6 m, and is not compared there).
    const Eigen::Vector2d d = want[k] - want[k - 1];
    const double segAzimuth = azimuth(d);
    bool first = true;
    for (std::size_t j = at + 1; j <= i; ++j) {
      const Eigen::Vector2d step = (records[j].eye - records[j - 1].eye).head<2>();
      if (step.norm() < 1e-9) continue;  // turning in place
      if (first) worstAzimuth = std::max(worstAzimuth, std::abs(std::remainder(records[j].headingDeg - segAzimuth, 360.0)));
      first = false;
      const Eigen::Vector2d rel = records[j].eye.head<2>() - want[k - 1];
      worstLine = std::max(worstLine, std::abs(rel.x() * d.y() - rel.y() * d.x()) / d.norm());
    }
    at = i;
  }
  EXPECT_LT(worstPoint, kVertexTol);
  EXPECT_LT(worstAzimuth, kAzimuthTol);
  EXPECT_LT(worstLine, kOnLineTol);
  std::printf("walked: worst point %.3g m, worst heading off its segment's azimuth %.3g degrees, worst step %.3g m "
              "off its segment\n", worstPoint, worstAzimuth, worstLine);
}

TEST(RoutePlayed, TimedGpxReachesEachFixWithinOneStepOfItsTime) {
  const Latitude& lat = kLatitudes[0];
  const test::TempFolder dir;
  const test::ProjOracle proj(lat.terrain.epsg);
  const fs::path scene = writeScene(dir.path(), lat.terrain);
  // A phone's track: 1 s fixes at about 1.3 m/s with a few centimetres of noise, a 12 s pause
  // (fixes jittering 4 cm about one place), then on; times in whole seconds plus a fraction.
  std::vector<Eigen::Vector2d> utm;
  std::vector<double> times;
  double t = 3.25, pauseFrom = 0, pauseTo = 0;
  Eigen::Vector2d p(lat.terrain.west + 80.0, lat.terrain.north - 90.0);
  for (int k = 0; k < 60; ++k) {
    utm.push_back(p + Eigen::Vector2d(0.03 * std::sin(k * 1.7), 0.03 * std::cos(k * 2.3)));
    times.push_back(t);
    if (k == 25) {  // standing still: the fixes jitter by a few centimetres about one place
      pauseFrom = times.back();
      for (int w = 0; w < 12; ++w) {
        t += 1.0;
        utm.push_back(p + Eigen::Vector2d(0.04 * std::sin(w * 2.9), 0.04 * std::cos(w * 1.3)));
        times.push_back(t);
      }
      pauseTo = times.back();
    }
    p += Eigen::Vector2d(1.3 * std::cos(k * 0.05), -1.3 * std::sin(k * 0.05));
    t += 1.0;
  }
  std::vector<Eigen::Vector2d> lonLat, want;
  for (const auto& q : utm) lonLat.push_back(proj.toLonLat(q));
  for (const auto& q : lonLat) want.push_back(proj.toUtm(q));
  test::writeText(dir / "walk.gpx", gpxTrack(lonLat, times));
  gis::RouteRequest request;
  request.route.source = (dir / "walk.gpx").string();
  request.script.useTimes = true;
  const gis::RouteScript script = gis::planRoute(scene.string(), request);
  EXPECT_NEAR(script.duration, times.back() - times.front(), 1e-3);
  const Played played = play(scene, script.text);
  // At each fix's recorded time (within one step either way) the eye is at the fix: arrivals, and
  // the 12 s pause, kept to the step.
  const auto& records = played.result.records;
  double worstLate = 0;
  for (std::size_t k = 1; k < want.size(); ++k) {
    const double when = times[k] - times[0];
    double best = std::numeric_limits<double>::infinity(), bestOff = 0;
    for (const FrameRecord& r : records)
      if (std::abs(r.time - when) <= kDt + 1e-9 && horizontal(r, want[k]) < best) {
        best = horizontal(r, want[k]);
        bestOff = std::abs(r.time - when);
      }
    EXPECT_LT(best, kVertexTol) << "fix " << k << " at " << when << " s: the eye is " << best << " m from it";
    if (best < kVertexTol) worstLate = std::max(worstLate, bestOff);
  }
  // Standing still, the view does not swing after the jitter (each fix closer than the timed
  // view distance keeps the heading).
  double swing = 0;
  const double pauseHeading = [&] {
    for (const FrameRecord& r : records)
      if (r.time >= pauseFrom - times[0]) return r.headingDeg;
    return 0.0;
  }();
  for (const FrameRecord& r : records)
    if (r.time >= pauseFrom - times[0] && r.time <= pauseTo - times[0])
      swing = std::max(swing, std::abs(std::remainder(r.headingDeg - pauseHeading, 360.0)));
  EXPECT_EQ(swing, 0.0);
  std::printf("timed: worst arrival %.4f s off the fix's time (one step %.4f s)\n", worstLate, kDt);
}

TEST(RoutePlayed, FlightKeepsTheEyeAtTheHeightOverEachPoint) {
  const Latitude& lat = kLatitudes[0];
  const test::TempFolder dir;
  const fs::path scene = writeScene(dir.path(), lat.terrain);
  const auto utm = routeUtm(lat.terrain);
  gis::RouteRequest request;
  request.script.fly = true;
  request.script.height = 20.0;
  writeProjectedLine(dir / "line.gpkg", "GPKG", "flight", lat.terrain.epsg, utm);  // the terrain's own CRS
  request.route.source = (dir / "line.gpkg").string();
  const Played p = play(scene, gis::planRoute(scene.string(), request).text);
  std::size_t at = 0;
  for (std::size_t k = 1; k < utm.size(); ++k) {
    const std::size_t i = reach(p.result.records, at, utm[k], kVertexTol);
    ASSERT_NE(i, std::string::npos) << "point " << k;
    const double ground = lat.terrain.height(utm[k].x(), utm[k].y());
    // The DEM's surface is the samples' triangulation: within a few mm of the formula here.
    EXPECT_NEAR(p.result.records[i].eye.z(), ground + 20.0, 0.01) << "point " << k;
    at = i;
  }
}

TEST(RoutePlayed, FlightWithoutAHeightFliesAtTheRoutesOwnHeights) {
  const Site site(kLatitudes[1]);
  const auto& [lat, dir, proj, scene, utm, lonLat] = site;
  std::vector<double> eles;  // 25 m over the ground at each point, and 40 m over the third
  for (std::size_t k = 0; k < utm.size(); ++k)
    eles.push_back(lat.terrain.height(utm[k].x(), utm[k].y()) + (k == 2 ? 40.0 : 25.0));
  test::writeText(dir / "flight.gpx", gpxTrack(lonLat, {}, eles));
  gis::RouteRequest request;
  request.route.source = (dir / "flight.gpx").string();
  request.script.fly = true;
  const Played p = play(scene, gis::planRoute(scene.string(), request).text);
  std::size_t at = 0;
  for (std::size_t k = 1; k < utm.size(); ++k) {
    const std::size_t i = reach(p.result.records, at, utm[k], kVertexTol);
    ASSERT_NE(i, std::string::npos) << "point " << k;
    EXPECT_NEAR(p.result.records[i].eye.z(), eles[k], 1e-6) << "point " << k;
    at = i;
  }
  // Walking, the same track's heights are left out of the script.
  request.script.fly = false;
  const Script walked = parseScript(gis::planRoute(scene.string(), request).text, "walked");
  for (const ScriptCommand& c : walked.commands) EXPECT_FALSE(c.hasZ) << "line " << c.line;
}

TEST(RoutePlayed, StopTurnsTheViewToTheInstrument) {
  const Site site(kLatitudes[0]);
  const auto& [lat, dir, proj, scene, utm, lonLat] = site;
  // An instrument 6 m to the side of the first segment's middle, one 40 m away (not visited).
  const Eigen::Vector2d mid = 0.5 * (utm[0] + utm[1]), along = (utm[1] - utm[0]).normalized();
  const Eigen::Vector2d side(along.y(), -along.x());
  const Eigen::Vector2d near = mid + 6.0 * side, far = mid - 40.0 * side;
  test::writeGeoLayer(dir / "instruments.gpkg", "GPKG", "piezometers",
                      {{"stop", "pz1", std::nullopt, {proj.toLonLat(near)}}, {"stop", "pz2", std::nullopt, {proj.toLonLat(far)}}});
  test::writeText(dir / "walk.gpx", gpxTrack(lonLat));
  gis::RouteRequest request;
  request.route.source = (dir / "walk.gpx").string();
  request.stops = (dir / "instruments.gpkg").string();
  request.script.stopWait = 2.0;
  const gis::RouteScript script = gis::planRoute(scene.string(), request);
  EXPECT_EQ(script.stops, 1u);
  EXPECT_NE(script.text.find("# stop: pz1"), std::string::npos) << script.text;
  EXPECT_EQ(script.text.find("pz2"), std::string::npos);
  const Played p = play(scene, script.text);
  // Standing at the route's nearest point to the stop for the wait, facing it, looking down at it.
  const Eigen::Vector2d stand = proj.toUtm(lonLat[0]) + (near - proj.toUtm(lonLat[0])).dot(along) * along;
  std::size_t still = 0, facing = 0;
  for (const FrameRecord& r : p.result.records)
    if (std::hypot(r.eye.x() - stand.x(), r.eye.y() - stand.y()) < kVertexTol) {
      ++still;
      const Eigen::Vector2d d = near - r.eye.head<2>();
      if (std::abs(std::remainder(r.headingDeg - azimuth(d), 360.0)) < 1e-3 && r.pitchDeg < 0) ++facing;
    }
  EXPECT_GE(facing, std::size_t(2.0 / kDt)) << "steps at the stop: " << still;
}

// ---------------------------------------------------------------------------------------------
// Bad routes: refused, naming the file, the layer and the feature.

TEST(RouteBadInput, RefusedWithFileLayerAndFeature) {
  const Site site(kLatitudes[0]);
  const auto& [lat, dir, proj, scene, utm, lonLat] = site;
  auto plan = [&](const fs::path& file, bool useTimes = false, const std::string& assumedCrs = "") {
    gis::RouteRequest r;
    r.route.source = file.string();
    r.route.assumedCrs = assumedCrs;
    r.script.useTimes = useTimes;
    return test::inputError([&] { gis::planRoute(site.scene.string(), r); });
  };

  test::writeGeoLayer(dir / "points.gpkg", "GPKG", "wells", {{"x", "a", std::nullopt, {lonLat[0]}}});
  EXPECT_NE(plan(dir / "points.gpkg").find("points.gpkg: layer 'wells' feature 1: is a Point, not a line"),
            std::string::npos);

  test::writeText(dir / "untimed.gpx", gpxTrack(lonLat));
  EXPECT_NE(plan(dir / "untimed.gpx", true).find("untimed.gpx: layer 'track_points' feature 0: has no time"),
            std::string::npos);

  std::vector<Eigen::Vector2d> leaving = lonLat;
  leaving[3] = proj.toLonLat({lat.terrain.west + 500.0, lat.terrain.north - 100.0});  // 100 m east of the terrain
  leaving[4] = proj.toLonLat({lat.terrain.west + 600.0, lat.terrain.north - 100.0});
  test::writeText(dir / "leaving.gpx", gpxTrack(leaving));
  EXPECT_NE(plan(dir / "leaving.gpx").find("leaving.gpx: layer 'track_points' feature 3 at ("), std::string::npos);
  EXPECT_NE(plan(dir / "leaving.gpx").find("outside the terrain"), std::string::npos);

  // Over a hole in the DEM (nodata), well inside it: the point is named.
  {
    const fs::path holed = dir / "holed";
    fs::create_directories(holed);
    const fs::path holedScene = writeScene(holed, lat.terrain, std::pair<int, int>{200, 200});
    std::vector<Eigen::Vector2d> overHole = lonLat;
    overHole[2] = proj.toLonLat({lat.terrain.west + 200.5, lat.terrain.north - 200.5});
    test::writeText(holed / "hole.gpx", gpxTrack(overHole));
    gis::RouteRequest r;
    r.route.source = (holed / "hole.gpx").string();
    const std::string message = test::inputError([&] { gis::planRoute(holedScene.string(), r); });
    EXPECT_NE(message.find("hole.gpx: layer 'track_points' feature 2 at ("), std::string::npos) << message;
    EXPECT_NE(message.find("over a hole"), std::string::npos) << message;
  }

  test::writeText(dir / "nocrs.csv", "wkt,name\n\"LINESTRING (1 2, 3 4)\",a\n");
  EXPECT_NE(plan(dir / "nocrs.csv").find("nocrs.csv: layer 'nocrs': has no CRS"), std::string::npos);
  EXPECT_NE(plan(dir / "nocrs.csv", false, "EPSG:99999").find("cannot read the CRS 'EPSG:99999'"), std::string::npos);

  test::writeGeoLayer(dir / "empty.gpkg", "GPKG", "lines", {});
  EXPECT_NE(plan(dir / "empty.gpkg").find("empty.gpkg: has no layer with features"), std::string::npos);

  std::string wpts = R"(<?xml version="1.0"?><gpx version="1.1" creator="t" xmlns="http://www.topografix.com/GPX/1/1">
<wpt lat="46.0" lon="-111.0"><name>a</name></wpt></gpx>)";
  test::writeText(dir / "waypoints.gpx", wpts);
  EXPECT_NE(plan(dir / "waypoints.gpx").find("waypoints.gpx: has no track and no route"), std::string::npos);
}

}  // namespace
}  // namespace nestwalk
