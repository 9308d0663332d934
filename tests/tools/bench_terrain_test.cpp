// `nestwalk bench terrain --quick --json`: a smoke run of the terrain benchmark a user runs. Times
// are not asserted. What the run says about agreement is asserted from its JSON values:
//  - vertical rays: Embree, Bullet and OSG (the same triangles, in float) hit exactly where
//    nestwalk's groundHeight hits (no hit/miss disagreement, the same hit fraction), at heights
//    within float rounding (kFloatHeightBound); intersectRay agrees with groundHeight within double
//    rounding (kDoubleHeightBound); the direct lookup (bilinear, not the triangles) hits everywhere
//    nestwalk does;
//  - oblique rays: the peers agree with intersectRay but for grazing rays, where float rounding
//    can move a hit past a ridge (kObliqueShare);
//  - the LOD table is monotone, and the targets are reported.
#include "tests/common/run_command.h"

#include <nlohmann/json.hpp>

#include <string>

namespace nestwalk::test {
namespace {

/// m: 32 float ulps at heights below 512 m (ulp 3.1e-5 m); a float peer computes a hit from a
/// float ray and float vertices in a few operations.
constexpr double kFloatHeightBound = 1e-3;
/// m: groundHeight and intersectRay are both double (ulp 5.7e-14 m at 400 m) but take different
/// arithmetic paths.
constexpr double kDoubleHeightBound = 1e-9;
/// Share of the oblique rays a float peer may answer otherwise (hit/miss, or a hit > 1 cm away):
/// grazing rays only, a few in 20k on the quick run's terrain.
constexpr double kObliqueShare = 1e-3;

const char* const kTrianglePeers[] = {"embree", "bullet", "osg_kdtree"};

/// The quick run's JSON, run once by the first test that asks (the run's capture folder is named
/// after that test).
const nlohmann::json& quickRun() {
  static const nlohmann::json run = [] {
    const CommandResult r = runNestwalk("bench terrain --quick --json");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return r.exitCode == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
  }();
  return run;
}

/// The quick run's row named "<query>/<set>".
const nlohmann::json& row(const std::string& name) {
  static const nlohmann::json none = nlohmann::json::object();
  for (const auto& b : quickRun()["benchmarks"])
    if (b["name"] == name) return b;
  ADD_FAILURE() << "no row " << name;
  return none;
}

TEST(BenchTerrain, TrianglePeersHitWhereGroundHeightHitsOnVerticalRays) {
  for (const char* set : {"vertical_random", "walking_path"}) {
    const nlohmann::json& b = row(std::string("ground_height/") + set);
    SCOPED_TRACE(set);
    const double hits = b["hit_fractions"]["nestwalk"].get<double>();
    EXPECT_GT(hits, 0.0);
    for (const char* peer : kTrianglePeers) {
      SCOPED_TRACE(peer);
      EXPECT_EQ(b["disagreements"][peer].get<long>(), 0);
      EXPECT_EQ(b["hit_fractions"][peer].get<double>(), hits);
      EXPECT_LT(b["max_height_diff"][peer].get<double>(), kFloatHeightBound);
      EXPECT_EQ(b["hits_over_1cm_apart"][peer].get<long>(), 0);
    }
    EXPECT_EQ(b["disagreements"]["direct_lookup"].get<long>(), 0);
    const nlohmann::json& ray = row(std::string("intersect_ray/") + set);
    EXPECT_EQ(ray["disagreements"]["nestwalk"].get<long>(), 0);
    EXPECT_LT(ray["max_height_diff"]["nestwalk"].get<double>(), kDoubleHeightBound);
  }
}

TEST(BenchTerrain, TrianglePeersAgreeWithIntersectRayOnObliqueRaysButGrazingOnes) {
  const nlohmann::json& b = row("intersect_ray/oblique");
  for (const char* peer : kTrianglePeers) {
    SCOPED_TRACE(peer);
    const double rays = b["rays"][peer].get<double>();
    EXPECT_GT(rays, 0.0);
    EXPECT_LE(b["disagreements"][peer].get<double>(), kObliqueShare * rays);
    EXPECT_LE(b["hits_over_1cm_apart"][peer].get<double>(), kObliqueShare * rays);
  }
}

TEST(BenchTerrain, RatiosAreThePeersTimeOverNestwalks) {
  for (const auto& b : quickRun()["benchmarks"])
    for (const auto& [peer, ratio] : b["ratio"].items()) {
      if (!ratio.is_number()) continue;
      EXPECT_NEAR(ratio.get<double>(), b["ns_per_ray"][peer].get<double>() / b["ns_per_ray"]["nestwalk"].get<double>(),
                  1e-9 * ratio.get<double>())
          << b["name"] << " " << peer;
    }
}

TEST(BenchTerrain, LodLevelsAreMonotoneAndTargetsReported) {
  double previousError = -1.0;
  for (const auto& level : quickRun()["lod_levels"]) {
    const double e = level["max_error_m"].get<double>();
    EXPECT_GE(e, previousError) << "coarser levels never have a smaller recorded error";
    previousError = e;
  }
  EXPECT_EQ(quickRun()["targets"].size(), 5u);
}

}  // namespace
}  // namespace nestwalk::test
