// A run's results as GIS layers (report/result_layers.h, written by the recorded run) on the
// bundled mining-dump scene's equipment walk, read back with OGR: the path holds every step
// (x, y, z and M = time exactly); the frames layer agrees with frames.csv to the CSV's precision;
// the contacts are the blocked transitions of frames.csv, each on the path, each stop gap the
// brute-force distance from the body box to the unit's triangles (no tree); the blocked stretches
// add up to the blocked frames; the expectations are the run's. The GeoJSON is RFC 7946 (no crs
// member, WGS 84 longitude and latitude: each contact where PROJ puts it, every step within 2 cm
// of the simplified path), and ogrinfo opens both files.
#include "nestwalk/session/recorded_run.h"

#include "nestwalk/geometry/triangle_box.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/walker/walker.h"
#include "tests/common/run_command.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <ogr_api.h>
#include <proj.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

constexpr double kDegreeRounding = 0.5e-7;  // degrees: the GeoJSON's 7 decimals
constexpr double kWebPathTol = 0.02;        // m: the path's 1 cm simplification plus that rounding

struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
};

CsvTable readCsv(const std::string& text) {  // frames.csv: only blocked_by could be quoted; it is not here
  CsvTable t;
  std::istringstream in(text);
  std::string line;
  auto split = [](const std::string& l) {
    std::vector<std::string> out;
    std::stringstream s(l);
    for (std::string cell; std::getline(s, cell, ',');) out.push_back(cell);
    if (!l.empty() && l.back() == ',') out.push_back("");
    return out;
  };
  std::getline(in, line);
  t.columns = split(line);
  while (std::getline(in, line)) t.rows.push_back(split(line));
  return t;
}

/// Half a unit of the last digit the CSV wrote ("57.0139" -> 5e-5).
double halfLastDigit(const std::string& cell) {
  const auto dot = cell.find('.');
  return dot == std::string::npos ? 0.5 : 0.5 * std::pow(10.0, -double(cell.size() - dot - 1));
}

double pointSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double u = d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (a + u * d)).norm();
}

TEST(ResultLayers, ReadBackWithOgrTheyAgreeWithTheRunTheCsvAndEachOther) {
  if (!fs::exists(test::bundledSceneFile())) GTEST_SKIP() << test::bundledSceneFile() << " is absent";
  const test::TempFolder folder;
  RecordedRunOptions o;
  o.scene = test::bundledSceneFile().string();
  o.script = test::bundledScript("equipment_walk.txt").string();
  o.out = folder.path().string();
  const RecordedRun run = recordRun(o);
  const auto& records = run.flythrough.records;
  const double dt = 1.0 / o.hz;
  const Scene scene = loadScene(o.scene);

  GDALAllRegister();
  GDALDatasetH ds = GDALOpenEx((folder / "results.gpkg").c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  ASSERT_NE(ds, nullptr);
  auto layer = [&](const char* name) {
    OGRLayerH l = GDALDatasetGetLayerByName(ds, name);
    EXPECT_NE(l, nullptr) << name;
    OGR_L_ResetReading(l);
    return l;
  };

  // The path: every step, exactly.
  {
    OGRLayerH l = layer("path");
    ASSERT_EQ(OGR_L_GetFeatureCount(l, TRUE), 1);
    OGRFeatureH f = OGR_L_GetNextFeature(l);
    OGRGeometryH g = OGR_F_GetGeometryRef(f);
    EXPECT_EQ(OGR_G_GetGeometryType(g), wkbLineStringZM);
    ASSERT_EQ(std::size_t(OGR_G_GetPointCount(g)), records.size());
    for (std::size_t i = 0; i < records.size(); ++i) {
      double x, y, z, m;
      OGR_G_GetPointZM(g, int(i), &x, &y, &z, &m);
      ASSERT_EQ(Eigen::Vector3d(x, y, z), records[i].eye) << "step " << i;
      ASSERT_EQ(m, records[i].time) << "step " << i;
    }
    EXPECT_EQ(OGR_F_GetFieldAsInteger64(f, OGR_F_GetFieldIndex(f, "frames")), GIntBig(records.size()));
    EXPECT_EQ(OGR_F_GetFieldAsInteger64(f, OGR_F_GetFieldIndex(f, "blocked_frames")), GIntBig(run.blockedSteps));
    EXPECT_EQ(OGR_F_GetFieldAsInteger64(f, OGR_F_GetFieldIndex(f, "contacts")), GIntBig(run.contacts.size()));
    EXPECT_EQ(OGR_F_GetFieldAsInteger64(f, OGR_F_GetFieldIndex(f, "expectations_met")), GIntBig(run.expectationsMet));
    OGR_F_Destroy(f);
  }

  // The frames layer against frames.csv, column by column, to the CSV's precision.
  const CsvTable csv = readCsv(test::readText(folder / "frames.csv"));
  ASSERT_EQ(csv.rows.size(), records.size());
  {
    OGRLayerH l = layer("frames");
    std::size_t features = 0;
    for (OGRFeatureH f = OGR_L_GetNextFeature(l); f; f = OGR_L_GetNextFeature(l), ++features) {
      const auto frame = std::size_t(OGR_F_GetFieldAsInteger64(f, OGR_F_GetFieldIndex(f, "frame")));
      ASSERT_TRUE(frame >= 1 && frame <= csv.rows.size());
      const auto& row = csv.rows[frame - 1];
      for (std::size_t c = 0; c < csv.columns.size(); ++c) {
        const int field = OGR_F_GetFieldIndex(f, csv.columns[c].c_str());
        ASSERT_GE(field, 0) << csv.columns[c];
        if (csv.columns[c] == "blocked_by") {
          EXPECT_EQ(std::string(OGR_F_GetFieldAsString(f, field)), row[c]);
        } else if (row[c].empty()) {
          EXPECT_FALSE(OGR_F_IsFieldSetAndNotNull(f, field)) << csv.columns[c];
        } else {
          EXPECT_NEAR(OGR_F_GetFieldAsDouble(f, field), std::stod(row[c]), halfLastDigit(row[c]) * (1 + 1e-9))
              << csv.columns[c] << " frame " << frame;
        }
      }
      OGR_F_Destroy(f);
    }
    EXPECT_EQ(features, (records.size() + 9) / 10 + ((records.size() - 1) % 10 != 0));  // every 10th and the last
  }

  // The contacts: frames.csv's blocked transitions, on the path, with brute-force stop gaps.
  {
    std::vector<std::size_t> events;  // record indices
    const std::size_t blocked = 10, blockedBy = 11;
    ASSERT_EQ(csv.columns[blocked], "blocked");
    ASSERT_EQ(csv.columns[blockedBy], "blocked_by");
    for (std::size_t i = 0; i < csv.rows.size(); ++i)
      if (csv.rows[i][blocked] == "1" &&
          (i == 0 || csv.rows[i - 1][blocked] == "0" || csv.rows[i - 1][blockedBy] != csv.rows[i][blockedBy]))
        events.push_back(i);
    ASSERT_GT(events.size(), 3u);
    OGRLayerH l = layer("contacts");
    ASSERT_EQ(std::size_t(OGR_L_GetFeatureCount(l, TRUE)), events.size());
    std::size_t k = 0, measured = 0;
    for (OGRFeatureH f = OGR_L_GetNextFeature(l); f; f = OGR_L_GetNextFeature(l), ++k) {
      const std::size_t i = events[k];
      EXPECT_EQ(OGR_F_GetFieldAsInteger64(f, OGR_F_GetFieldIndex(f, "frame")), GIntBig(records[i].frame));
      const std::string unit = OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "unit"));
      EXPECT_EQ(unit, csv.rows[i][blockedBy]);
      OGRGeometryH g = OGR_F_GetGeometryRef(f);
      EXPECT_EQ(Eigen::Vector3d(OGR_G_GetX(g, 0), OGR_G_GetY(g, 0), OGR_G_GetZ(g, 0)), records[i].eye);  // on the path
      const int u = scene.findUnit(unit);
      if (u >= 0) {
        EXPECT_EQ(std::string(OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "kind"))), scene.units[std::size_t(u)].kind);
        const Eigen::Vector3d feet = records[i].eye - Eigen::Vector3d(0, 0, scene.spec.viewer.eyeHeight);
        const Obb<double> body = bodyVolumeAt(scene.spec.viewer, scene.origin, feet, records[i].bodyYawDeg).inner;
        double brute = std::numeric_limits<double>::infinity();
        for (std::uint32_t inst : scene.units[std::size_t(u)].instances) {
          const SceneInstance& s = scene.instances[inst];
          const TriangleMesh& mesh = scene.models[s.model].mesh;
          for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            Triangle tri = mesh.triangle(t);
            for (auto& p : tri) p = s.toLocal.apply(p);
            brute = std::min(brute, triangleBoxDistance(tri, body));
          }
        }
        const double gap = OGR_F_GetFieldAsDouble(f, OGR_F_GetFieldIndex(f, "stop_gap_m"));
        EXPECT_NEAR(gap, brute, 1e-9 * (1 + brute)) << unit;
        const double approach = OGR_F_GetFieldAsDouble(f, OGR_F_GetFieldIndex(f, "approach_deg"));
        EXPECT_TRUE(approach >= 0 && approach <= 180) << approach;
        ++measured;
      }
      OGR_F_Destroy(f);
    }
    EXPECT_GT(measured, 3u);
  }

  // The blocked stretches add up to the blocked frames, each lasting its frames.
  {
    OGRLayerH l = layer("blocked");
    GIntBig frames = 0;
    for (OGRFeatureH f = OGR_L_GetNextFeature(l); f; f = OGR_L_GetNextFeature(l)) {
      const GIntBig n = OGR_F_GetFieldAsInteger64(f, OGR_F_GetFieldIndex(f, "frames"));
      EXPECT_NEAR(OGR_F_GetFieldAsDouble(f, OGR_F_GetFieldIndex(f, "duration_s")), double(n) * dt, 1e-9);
      EXPECT_GE(OGR_G_GetPointCount(OGR_F_GetGeometryRef(f)), 2);
      frames += n;
      OGR_F_Destroy(f);
    }
    EXPECT_EQ(frames, GIntBig(run.blockedSteps));
  }

  // The expectations, where and as they were checked.
  {
    OGRLayerH l = layer("expectations");
    const auto& want = run.flythrough.expectations;
    ASSERT_EQ(std::size_t(OGR_L_GetFeatureCount(l, TRUE)), want.size());
    std::size_t k = 0;
    for (OGRFeatureH f = OGR_L_GetNextFeature(l); f; f = OGR_L_GetNextFeature(l), ++k) {
      EXPECT_EQ(OGR_F_GetFieldAsInteger(f, OGR_F_GetFieldIndex(f, "line")), want[k].line);
      EXPECT_EQ(OGR_F_GetFieldAsInteger(f, OGR_F_GetFieldIndex(f, "met")) != 0, want[k].met);
      EXPECT_EQ(std::string(OGR_F_GetFieldAsString(f, OGR_F_GetFieldIndex(f, "text"))), want[k].text);
      OGR_F_Destroy(f);
    }
  }
  GDALClose(ds);

  // The GeoJSON: RFC 7946, against PROJ.
  const auto json = nlohmann::json::parse(test::readText(folder / "results.geojson"));
  EXPECT_FALSE(json.contains("crs"));
  PJ_CONTEXT* ctx = proj_context_create();
  PJ* raw = proj_create_crs_to_crs(ctx, scene.terrain->crsWkt().c_str(), "EPSG:4326", nullptr);
  ASSERT_NE(raw, nullptr);
  PJ* toLonLat = proj_normalize_for_visualization(ctx, raw);
  proj_destroy(raw);
  const auto& features = json["features"];
  ASSERT_EQ(features.size(), run.contacts.size() + 1);
  ASSERT_EQ(features[0]["properties"]["feature"], "path");
  std::vector<Eigen::Vector2d> path;  // back in the map frame
  for (const auto& c : features[0]["geometry"]["coordinates"]) {
    const PJ_COORD m = proj_trans(toLonLat, PJ_INV, proj_coord(c[0].get<double>(), c[1].get<double>(), 0, 0));
    path.push_back({m.xy.x, m.xy.y});
  }
  double worst = 0;
  for (const FrameRecord& r : records) {
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k + 1 < path.size(); ++k) d = std::min(d, pointSegment(r.eye.head<2>(), path[k], path[k + 1]));
    worst = std::max(worst, d);
  }
  EXPECT_LT(worst, kWebPathTol);
  for (std::size_t k = 0; k < run.contacts.size(); ++k) {
    const auto& f = features[k + 1];
    EXPECT_EQ(f["properties"]["feature"], "contact");
    const PJ_COORD ll = proj_trans(toLonLat, PJ_FWD, proj_coord(run.contacts[k].eye.x(), run.contacts[k].eye.y(), 0, 0));
    EXPECT_NEAR(f["geometry"]["coordinates"][0].get<double>(), ll.lp.lam, kDegreeRounding * 1.01);
    EXPECT_NEAR(f["geometry"]["coordinates"][1].get<double>(), ll.lp.phi, kDegreeRounding * 1.01);
  }
  proj_destroy(toLonLat);
  proj_context_destroy(ctx);
  std::printf("results layers: %zu steps, %zu contacts, %zu GeoJSON path points (worst step %.4f m from it)\n",
              records.size(), run.contacts.size(), path.size(), worst);

  // ogrinfo opens both.
  for (const char* file : {"results.gpkg", "results.geojson"}) {
    const auto r = test::runCommand("ogrinfo -al -so " + test::quoted(folder / file), folder / "ogrinfo");
    EXPECT_EQ(r.exitCode, 0) << file << ": " << r.err;
  }
}

}  // namespace
}  // namespace nestwalk
