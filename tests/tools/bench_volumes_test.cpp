// `nestwalk bench volumes --quick --json`: a smoke run of the benchmark a user runs. Times are
// not asserted (they belong to benchmarks); the verdict checks the benchmark makes against the
// double SAT are: every nestwalk form must agree with it on every pair.
#include "tests/common/run_command.h"

#include <nlohmann/json.hpp>

namespace nestwalk::test {
namespace {

TEST(BenchVolumes, QuickJsonRunHasEveryPeerAndNoDisagreement) {
  const CommandResult r = runNestwalk("bench volumes --quick --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.contains("benchmarks"));
  bool sawObbPeers = false;
  for (const auto& b : j["benchmarks"]) {
    SCOPED_TRACE(b["name"].get<std::string>());
    EXPECT_GT(b["ns_per_op"]["nestwalk"].get<double>(), 0.0);
    if (b.contains("disagreements") && b["disagreements"]["nestwalk"].is_number()) {
      const std::string test = b["test"].get<std::string>();
      // The float scalar test may differ inside its documented rounding band; the others may not.
      if (test.find("float scalar") == std::string::npos) {
        EXPECT_EQ(b["disagreements"]["nestwalk"].get<int>(), 0);
      }
    }
    const auto& ns = b["ns_per_op"];
    if (ns["fcl"].is_number() && ns["ccd_mpr"].is_number() && ns["bullet"].is_number())
      sawObbPeers = true;
  }
  EXPECT_TRUE(sawObbPeers) << "the OBB-OBB rows carry FCL, libccd and Bullet figures";
}

}  // namespace
}  // namespace nestwalk::test
