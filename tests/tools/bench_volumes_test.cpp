// `nestwalk bench volumes --quick --json`: a smoke run of the benchmark a user runs. Times are not
// asserted (they belong to benchmarks). What the run counts, asserted from its JSON values:
//  - every nestwalk form agrees with the double SAT (testNested<double> for the queries) on every
//    pair, the float scalar test inside its documented rounding band (kFloatShare);
//  - every peer answers the same question on the same boxes: it disagrees with the double SAT on
//    a few near-touching pairs at most (kPeerShare), where a wrong conversion (transposed axes,
//    half against full extents) would disagree on a large share;
//  - the pair sets are what their names say (kOverlapTolerance), and a query's final hits are
//    among its stage-1 survivors;
//  - a ratio is the peer's ns over nestwalk's, and the targets are reported.
#include "tests/common/run_command.h"

#include <nlohmann/json.hpp>

#include <map>
#include <string>

namespace nestwalk::test {
namespace {

/// Share of the pairs the float scalar SAT may decide otherwise: pairs within float rounding of
/// touching (a few in 20k).
constexpr double kFloatShare = 1e-3;
/// Share of the pairs a peer may decide otherwise: its own tolerances near touching (libccd's MPR
/// tolerance, Bullet's float boxes); 1 pair in 20k on the quick run.
constexpr double kPeerShare = 1e-3;
/// The overlap fraction of a pair set against its target: the scale is bisected to within one
/// pair of the quick run's 20k.
constexpr double kOverlapTolerance = 1e-3;

TEST(BenchVolumes, QuickRunAgreesWithTheDoubleSatAndPeersAnswerTheSameQuestion) {
  const CommandResult result = runNestwalk("bench volumes --quick --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json run = nlohmann::json::parse(result.out);
  const std::map<std::string, double> setTargets = {{"50%", 0.5}, {"5%", 0.05}};
  std::size_t rowsWithPeers = 0;
  for (const auto& b : run["benchmarks"]) {
    SCOPED_TRACE(b["name"].get<std::string>());
    const std::string test = b["test"].get<std::string>(), set = b["set"].get<std::string>();
    const double pairs = 20000;  // --quick: pairs per set
    if (setTargets.count(set)) {
      EXPECT_NEAR(b["overlap_fraction"].get<double>(), setTargets.at(set), kOverlapTolerance);
    }
    const auto& disagreements = b["disagreements"];
    if (disagreements["nestwalk"].is_number()) {
      const bool floatScalar = test.find("float scalar") != std::string::npos;
      EXPECT_LE(disagreements["nestwalk"].get<double>(), floatScalar ? kFloatShare * pairs : 0.0);
    }
    bool peers = false;
    for (const char* peer : {"fcl", "ccd_mpr", "bullet"}) {
      if (!disagreements[peer].is_number()) continue;
      peers = true;
      EXPECT_LE(disagreements[peer].get<double>(), kPeerShare * pairs) << peer;
      EXPECT_NEAR(b["ratio"][peer].get<double>(),
                  b["ns_per_op"][peer].get<double>() / b["ns_per_op"]["nestwalk"].get<double>(),
                  1e-9 * b["ratio"][peer].get<double>())
          << peer;
    }
    rowsWithPeers += peers ? 1 : 0;
  }
  EXPECT_EQ(rowsWithPeers, 12u)
      << "6 OBB-OBB forms (query overlap's batch, portable and scalar first) x 2 pair sets with FCL, libccd and"
         " Bullet";
  EXPECT_EQ(run["targets"].size(), 2u);
}

}  // namespace
}  // namespace nestwalk::test
