// `nestwalk query overlap`: verdicts on pairs whose answer is known by construction, at the
// origin and at UTM magnitudes, thousands of hard pairs against testBoxPair called here, and the
// errors for malformed input.
#include "tests/common/run_command.h"
#include "tests/geometry/box_pair_generators.h"

#include "nestwalk/geometry/nested.h"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <vector>

namespace nestwalk::test {
namespace {

struct Box {
  Eigen::Vector3d c;
  Eigen::Matrix3d axes;
  Eigen::Vector3d e;
};

Box aabb(const Eigen::Vector3d& c, const Eigen::Vector3d& e) { return {c, Eigen::Matrix3d::Identity(), e}; }

std::string header() {
  std::string h = "id";
  for (char p : {'a', 'b'}) {
    for (const char* f : {"cx", "cy", "cz", "ux", "uy", "uz", "vx", "vy", "vz", "wx", "wy", "wz", "ex", "ey", "ez"})
      h += std::string(",") + p + f;
  }
  return h + "\n";
}

std::string row(const std::string& id, const Box& a, const Box& b) {
  std::string r = id;
  char buf[64];
  for (const Box* box : {&a, &b}) {
    for (int k = 0; k < 3; ++k) std::snprintf(buf, sizeof buf, ",%.17g", box->c[k]), r += buf;
    for (int col = 0; col < 3; ++col)
      for (int k = 0; k < 3; ++k) std::snprintf(buf, sizeof buf, ",%.17g", box->axes(k, col)), r += buf;
    for (int k = 0; k < 3; ++k) std::snprintf(buf, sizeof buf, ",%.17g", box->e[k]), r += buf;
  }
  return r + "\n";
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string l; std::getline(ss, l);) out.push_back(l);
  return out;
}

// Pairs whose verdict follows from their construction: the gap along a known direction.
std::string knownPairs(const Eigen::Vector3d& origin) {
  const Eigen::Matrix3d rot45 = Eigen::AngleAxisd(std::numbers::pi / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::string csv = header();
  // 1 m cubes side by side along x: gaps of 1 mm, 0 (touching) and -1 mm.
  csv += row("aabb_gap_1mm", aabb(origin, {0.5, 0.5, 0.5}), aabb(origin + Eigen::Vector3d(1.001, 0, 0), {0.5, 0.5, 0.5}));
  csv += row("aabb_touch", aabb(origin, {0.5, 0.5, 0.5}), aabb(origin + Eigen::Vector3d(1.0, 0.2, 0), {0.5, 0.5, 0.5}));
  csv += row("aabb_gap_y", aabb(origin, {0.5, 0.5, 0.5}), aabb(origin + Eigen::Vector3d(0, 1.26, 0), {0.5, 0.75, 0.5}));
  // A cube turned 45 degrees about z, whose vertical edge points at an AABB's face: its edge is at
  // distance sqrt(1/2) from its centre, so its exact AABB already separates a 1 mm gap.
  const double reach = std::sqrt(0.5);
  csv += row("obb_vertex_gap_1mm", aabb(origin, {0.5, 0.5, 0.5}),
             {origin + Eigen::Vector3d(0.5 + reach + 0.001, 0, 0), rot45, {0.5, 0.5, 0.5}});
  csv += row("obb_vertex_pen_1mm", aabb(origin, {0.5, 0.5, 0.5}),
             {origin + Eigen::Vector3d(0.5 + reach - 0.001, 0, 0), rot45, {0.5, 0.5, 0.5}});
  // Two turned cubes face to face along their common face normal n = (1, 1, 0)/sqrt(2): their
  // AABBs and A's AABB against B overlap, only the OBB-OBB stage separates them (on A's u axis).
  const Eigen::Vector3d n = Eigen::Vector3d(1, 1, 0).normalized();
  csv += row("obb_obb_gap_1mm", {origin, rot45, {0.5, 0.5, 0.5}}, {origin + (1.0 + 0.001) * n, rot45, {0.5, 0.5, 0.5}});
  // A 2 cm pole 30 m tall (an AABB) before the turned cube's face: the pole's nearest edge is
  // 1 mm from the face plane (its corner reaches 0.01 * sqrt(2) towards the face).
  csv += row("pole_gap_1mm", {origin, rot45, {0.5, 0.5, 0.5}},
             aabb(origin + (0.5 + 0.01 * std::sqrt(2.0) + 0.001) * n, {0.01, 0.01, 15}));
  return csv;
}

const std::vector<std::string> kExpected = {
    "id,overlap,stage,axis",           "aabb_gap_1mm,0,aabb-aabb,x",      "aabb_touch,1,aabb-aabb,",
    "aabb_gap_y,0,aabb-aabb,y",        "obb_vertex_gap_1mm,0,aabb-aabb,x", "obb_vertex_pen_1mm,1,aabb-obb,",
    "obb_obb_gap_1mm,0,obb-obb,A0",    "pole_gap_1mm,0,aabb-obb,A0",
};

TEST(QueryOverlap, KnownPairsAtOrigin) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  writeText(dir / "pairs.csv", knownPairs(Eigen::Vector3d::Zero()));
  const CommandResult r = runNestwalk("query overlap '" + (dir / "pairs.csv").string() + "'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(lines(r.out), kExpected);
}

TEST(QueryOverlap, KnownPairsAtUtmMagnitudes) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  writeText(dir / "pairs.csv", knownPairs({550123.456, 4650789.123, 1234.5}));
  const CommandResult r = runNestwalk("query overlap '" + (dir / "pairs.csv").string() + "'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(lines(r.out), kExpected);
}

Box boxOf(const Obb<double>& b) { return {b.center, b.axes, b.halfExtents}; }

/// 3,000 pairs near touching, turned about the vertical, with an axis-aligned box, flat or
/// random, at UTM magnitudes (the command reads and tests them in several chunks), and the
/// command's expected output from testBoxPair called here one pair at a time.
std::pair<std::string, std::vector<std::string>> hardPairs() {
  const Vec3<double> origin(612345.678, 7012345.678, 321.0);
  boxgen::Gen g(2211);
  std::string csv = header();
  std::vector<std::string> expected = {"id,overlap,stage,axis"};
  for (int k = 0; k < 3000; ++k) {
    boxgen::Pair p;
    switch (k % 5) {
      case 0: p = boxgen::nearTouchingPair(g, origin); break;
      case 1: p = boxgen::verticalPair(g, origin, true); break;
      case 2: p = boxgen::oneAlignedPair(g, origin, true); break;
      case 3: p = boxgen::degeneratePair(g, origin); break;
      default: p = boxgen::randomPair(g, origin); break;
    }
    const std::string id = "p" + std::to_string(k);
    const std::string line = row(id, boxOf(p.first), boxOf(p.second));
    csv += line;
    // The pair as the command reads it back (printed with 17 digits: the same doubles).
    const NestedResult r = testBoxPair(p.first, p.second);
    const char* axis = r.stage == OverlapStage::AabbAabb ? aabbAxisName(r.axis) : satAxisName(r.axis);
    expected.push_back(id + (r.overlap ? ",1," : ",0,") + stageName(r.stage) + "," + axis);
  }
  return {csv, expected};
}

// The batch answers as testBoxPair; so does --scalar, the timing reference (testBoxPair one pair at
// a time), and the timing line names the path that ran.
TEST(QueryOverlap, ThousandsOfHardPairsAnswerAsTestBoxPair) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const auto [csv, expected] = hardPairs();
  writeText(dir / "pairs.csv", csv);
  for (const std::string path : {"", "--scalar "}) {
    const CommandResult r = runNestwalk("query overlap --timing " + path + "'" + (dir / "pairs.csv").string() + "'");
    ASSERT_EQ(r.exitCode, 0) << path << r.err;
    EXPECT_EQ(lines(r.out), expected) << path;
    EXPECT_NE(r.err.find("query overlap: 3000 pairs;"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("testBoxPair one at a time") != std::string::npos, !path.empty()) << r.err;
  }
}

TEST(QueryOverlap, BadRowAfterSeveralChunksPrintsNothing) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  std::string csv = hardPairs().first;
  csv += "late,1,2\n";
  writeText(dir / "pairs.csv", csv);
  const CommandResult r = runNestwalk("query overlap '" + (dir / "pairs.csv").string() + "'");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("pairs.csv:3002: 3 fields, but the header has 31"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "") << "the chunks answered before the bad row are not printed";
}

TEST(QueryOverlap, MalformedRowNamesTheLine) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  std::string csv = knownPairs(Eigen::Vector3d::Zero());
  csv += "broken,1,2,three\n";
  writeText(dir / "pairs.csv", csv);
  const CommandResult r = runNestwalk("query overlap '" + (dir / "pairs.csv").string() + "'");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("pairs.csv:9:"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "") << "no partial output on bad input";
}

TEST(QueryOverlap, NotANumberNamesLineAndColumn) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  std::string csv = header() + row("p", aabb({0, 0, 0}, {1, 1, 1}), aabb({3, 0, 0}, {1, 1, 1}));
  csv.replace(csv.find(",3,"), 3, ",x3,");
  writeText(dir / "pairs.csv", csv);
  const CommandResult r = runNestwalk("query overlap '" + (dir / "pairs.csv").string() + "'");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("pairs.csv:2: column 'bcx': 'x3' is not a number"), std::string::npos) << r.err;
}

TEST(QueryOverlap, NonOrthonormalAxesAndNegativeExtentsAreRefused) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  Box skew = aabb({0, 0, 0}, {1, 1, 1});
  skew.axes(0, 1) = 0.5;
  writeText(dir / "skew.csv", header() + row("p", skew, aabb({3, 0, 0}, {1, 1, 1})));
  CommandResult r = runNestwalk("query overlap '" + (dir / "skew.csv").string() + "'");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("skew.csv:2: the axes of box A are not orthonormal"), std::string::npos) << r.err;

  writeText(dir / "neg.csv", header() + row("p", aabb({0, 0, 0}, {1, 1, 1}), aabb({3, 0, 0}, {1, -1, 1})));
  r = runNestwalk("query overlap '" + (dir / "neg.csv").string() + "'");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("neg.csv:2: box B has a negative half extent"), std::string::npos) << r.err;
}

TEST(QueryOverlap, MissingColumnAndMissingFile) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  writeText(dir / "cols.csv", "id,acx\n1,2\n");
  CommandResult r = runNestwalk("query overlap '" + (dir / "cols.csv").string() + "'");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("cols.csv: the header has no column 'acy'"), std::string::npos) << r.err;

  r = runNestwalk("query overlap '" + (dir / "absent.csv").string() + "'");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("absent.csv: cannot open the file"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace nestwalk::test
