// `nestwalk bench walker --quick --json`: a smoke run of the walker benchmark a user runs. Times
// are not asserted. What the run checks is asserted from its JSON values: every broad phase, nestwalk's
// hierarchies, btDbvt and FCL, finds the same hits on every query (and nestwalk's default hierarchy
// those of brute force, FCL's boxes being exactly the benchmark's), and every hierarchy gives the same
// contacts on the bundled flythroughs (the fACT Table 2 part), with the template hierarchy as the
// 100 % row; every flythrough is recorded with its results layers and a 10,000-fix track planned.
#include "tests/common/run_command.h"
#include "tests/common/test_data.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>

namespace nestwalk::test {
namespace {

TEST(BenchWalker, QuickJsonRunHasStepsIdenticalBroadPhaseHitsAndTable2) {
  const CommandResult r = runNestwalk("bench walker --quick --json");
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["walker_steps"].size(), 2u);
  for (const auto& s : j["walker_steps"]) {
    EXPECT_GT(s["steps"].get<long>(), 1000);
    EXPECT_LE(s["p50_us"].get<double>(), s["p99_us"].get<double>());
    EXPECT_LE(s["p99_us"].get<double>(), s["max_us"].get<double>());
  }

  const nlohmann::json& bp = j["broad_phase"];
  std::map<long, long> hitsPerSize;  // boxes -> the hits every method must find
  for (const auto& b : bp["benchmarks"]) {
    SCOPED_TRACE(b["name"].get<std::string>());
    EXPECT_EQ(b["queries_differing_from_nestwalk"].get<long>(), 0);
    const auto [it, first] = hitsPerSize.emplace(b["boxes"].get<long>(), b["hits"].get<long>());
    EXPECT_EQ(b["hits"].get<long>(), it->second);
    EXPECT_GT(b["us_per_query"].get<double>(), 0.0);
  }
  EXPECT_EQ(hitsPerSize.size(), 2u);
  EXPECT_EQ(bp["benchmarks"].size(), 12u) << "4 hierarchies, btDbvt and FCL at 1k and 10k boxes";
  for (const auto& c : bp["brute_force_check"]) EXPECT_EQ(c["differing"].get<long>(), 0);
  for (const auto& [n, mismatches] : bp["fcl_aabb_mismatches"].items()) EXPECT_EQ(mismatches.get<long>(), 0) << n;

  if (std::filesystem::exists(test::bundledSceneFile())) {
    ASSERT_TRUE(j.contains("table2"));
    EXPECT_TRUE(j["table2_identical_contacts"].get<bool>());
    EXPECT_EQ(j["table2"][0]["hierarchy"], "template");
    EXPECT_DOUBLE_EQ(j["table2"][0]["percent_of_template"].get<double>(), 100.0);
    EXPECT_EQ(j["table2"].size(), 13u);
    // Routes and results: every bundled flythrough recorded, its layers a part of its run's time;
    // the GPS track of at least 10,000 fixes planned.
    ASSERT_EQ(j["results_layers"].size(), j["table2_scripts"].size());
    for (const auto& row : j["results_layers"]) {
      EXPECT_GT(row["layers_s"].get<double>(), 0.0) << row["script"];
      EXPECT_LT(row["layers_s"].get<double>(), row["run_s"].get<double>()) << row["script"];
    }
    EXPECT_GE(j["route_fixes"].get<std::size_t>(), 10000u);
    EXPECT_EQ(j["targets"].size(), 4u) << "btDbvt against nestwalk at 1k and 10k boxes, layers' share, route";
  } else {
    EXPECT_EQ(j["targets"].size(), 2u) << "btDbvt against nestwalk at 1k and 10k boxes";
  }
}

}  // namespace
}  // namespace nestwalk::test
