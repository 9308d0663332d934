// `nestwalk export`: the file it writes is read back with osgDB (instance transforms by name, the
// shared model node, the local-to-map translation, terrain and volume groups), in several formats;
// OUT is never replaced without --overwrite and no temporary file is left behind; bad input names
// the file and writes nothing.
#include "nestwalk/scene/model_geometry.h"
#include "tests/common/build_paths.h"
#include "tests/common/run_command.h"

#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osg/NodeVisitor>
#include <osgDB/ReadFile>

#include <algorithm>
#include <fstream>
#include <map>

namespace nestwalk::test {
namespace {

namespace fs = std::filesystem;

/// The terrain: an Arc/Info ASCII grid, 40 x 30 samples of 2 m, lower-left corner at UTM
/// (550000, 4650000), heights 100 + c + 0.5 r.
constexpr int kCols = 40, kRows = 30;
constexpr double kWest = 550000.0, kSouth = 4650000.0, kCell = 2.0;

std::string weatherStation() { return std::string(nestwalk::test::build::sourceDir()) + "/assets/models/weather_station.obj"; }

/// Writes terrain.asc and scene.json (three stations: two alone, a third use_only in a group) in `dir`.
fs::path writeScene(const fs::path& dir) {
  {
    std::ofstream o(dir / "terrain.asc");
    o << "ncols " << kCols << "\nnrows " << kRows << "\nxllcorner " << kWest << "\nyllcorner " << kSouth
      << "\ncellsize " << kCell << "\nNODATA_value -9999\n";
    for (int r = 0; r < kRows; ++r) {
      for (int c = 0; c < kCols; ++c) o << (c ? " " : "") << 100 + c + 0.5 * r;
      o << "\n";
    }
  }
  writeText(dir / "scene.json", R"({
  "terrain": "terrain.asc",
  "equipment": [
    {"name": "station-a", "model": ")" + weatherStation() + R"(", "position": [550020.5, 4650030.25], "heading": 30},
    {"name": "station-b", "model": ")" + weatherStation() + R"(", "position": [550040, 4650020], "scale": 1.5},
    {"name": "station-c", "model": ")" + weatherStation() + R"(", "position": [550060, 4650040, 120],
     "group": "bench1", "use_only": true}
  ]
})");
  return dir / "scene.json";
}


struct GraphSummary {
  std::map<std::string, osg::MatrixTransform*> transforms;  // by name, the terrain's chunks aside
  std::size_t chunks = 0, geometries = 0;
  bool volumes = false;
};

class Summarize : public osg::NodeVisitor {
 public:
  explicit Summarize(GraphSummary& s) : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN), s_(s) {}
  void apply(osg::MatrixTransform& t) override {
    if (t.getName().rfind("chunk ", 0) == 0)
      ++s_.chunks;
    else
      s_.transforms[t.getName()] = &t;
    traverse(t);
  }
  void apply(osg::Group& g) override {
    if (g.getName() == "volumes") s_.volumes = true;
    traverse(g);
  }
  void apply(osg::Geometry&) override { ++s_.geometries; }

 private:
  GraphSummary& s_;
};

GraphSummary readBack(const fs::path& file) {
  GraphSummary s;
  osg::ref_ptr<osg::Node> node = osgDB::readRefNodeFile(file.string());
  EXPECT_TRUE(node) << "osgDB cannot read " << file;
  if (!node) return s;
  Summarize v(s);
  node->accept(v);
  // Keep the graph alive for the caller's pointer checks.
  static std::vector<osg::ref_ptr<osg::Node>> keep;
  keep.push_back(node);
  return s;
}

/// Files in `dir` other than the scene's own (so leftovers such as temporary files show).
std::vector<std::string> otherFiles(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n != "scene.json" && n != "terrain.asc" && n != "capture") out.push_back(n);
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Export, WritesAGraphOsgReadsBackInEachFormat) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const fs::path scene = writeScene(dir);
  const TriangleMesh station = loadModelGeometry(weatherStation());
  const std::size_t triangles = station.triangles.size();
  const std::vector<Vec3<double>>& stationVertices = station.vertices;
  for (const char* name : {"scene.osgb", "scene.osgt", "scene.ive"}) {
    const fs::path out = dir / name;
    const auto r = runNestwalk("export " + quoted(scene) + " " + quoted(out));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    // The terrain is a plane: every level is exact, so the cut is the root chunk, within 0 m.
    const std::string line = "wrote " + out.string() + ": 3 instances, 1 models, " + std::to_string(3 * triangles) +
                             " equipment triangles, 3 units, terrain 40 x 30 samples: 1 chunk, ";
    EXPECT_EQ(r.out.substr(0, line.size()), line);
    EXPECT_EQ(r.out.substr(r.out.size() - std::min(r.out.size(), std::size_t(25))), " triangles, error <= 0 m\n");
    const GraphSummary g = readBack(out);
    for (const char* n : {"station-a", "station-b", "station-c"}) ASSERT_EQ(g.transforms.count(n), 1u) << n << " in " << name;
    // Instance transforms named after instances: three, plus local_to_map and terrain.
    EXPECT_EQ(g.transforms.size(), 5u) << name;
    EXPECT_EQ(g.transforms.at("station-a")->getChild(0), g.transforms.at("station-b")->getChild(0))
        << "the model node is stored once and shared (" << name << ")";
    // local -> map: the origin defaults to the terrain's centre (sample centres, z 0).
    const osg::Vec3d t = g.transforms.at("local_to_map")->getMatrix().getTrans();
    EXPECT_EQ(t, osg::Vec3d(kWest + 0.5 * kCols * kCell, kSouth + 0.5 * kRows * kCell, 0.0)) << name;
    // station-b: scale 1.5, heading 0, foot on the ground at its position.
    const osg::Matrixd b = g.transforms.at("station-b")->getMatrix() * g.transforms.at("local_to_map")->getMatrix();
    const osg::Vec3d foot = osg::Vec3d(0, 0, 0) * b, top = osg::Vec3d(0, 0, 1) * b;
    // The foot stands at the lowest ground under the footprint: the plane (100 + column + row / 2)
    // is lowest at one of the footprint's corners, i.e. at one of the scaled model's vertices.
    auto plane = [](double x, double y) {
      const double c = (x - kWest) / kCell - 0.5, row = (kSouth + kRows * kCell - y) / kCell - 0.5;
      return 100 + c + 0.5 * row;
    };
    double lowest = INFINITY;
    for (const auto& v : stationVertices) lowest = std::min(lowest, plane(550040.0 + 1.5 * v.x(), 4650020.0 + 1.5 * v.y()));
    EXPECT_NEAR(foot.x(), 550040.0, 1e-9);
    EXPECT_NEAR(foot.y(), 4650020.0, 1e-9);
    EXPECT_NEAR(foot.z(), lowest, 1e-9);
    EXPECT_NEAR(top.z() - foot.z(), 1.5, 1e-12);
    EXPECT_EQ(g.chunks, 1u);
    EXPECT_FALSE(g.volumes);
  }
  EXPECT_EQ(otherFiles(dir), (std::vector<std::string>{"scene.ive", "scene.osgb", "scene.osgt"})) << "no temporary files left";
}

TEST(Export, VolumesAndNoTerrain) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const fs::path scene = writeScene(dir);
  const fs::path out = dir / "v.osgt";
  const auto r = runNestwalk("export " + quoted(scene) + " " + quoted(out) + " --volumes --no-terrain");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("3 units, volume wireframes\n"), std::string::npos) << r.out;
  const GraphSummary g = readBack(out);
  EXPECT_TRUE(g.volumes);
  EXPECT_EQ(g.chunks, 0u);
  EXPECT_EQ(g.transforms.count("terrain"), 0u);
  EXPECT_EQ(g.transforms.size(), 4u);
}

TEST(Export, ExistingOutIsReplacedOnlyWithOverwrite) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const fs::path scene = writeScene(dir);
  const fs::path out = dir / "scene.osgb";
  writeText(out, "previous contents");
  auto r = runNestwalk("export " + quoted(scene) + " " + quoted(out));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_EQ(r.err, "nestwalk: error: " + out.string() + ": exists; pass --overwrite to replace it\n");
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(readText(out), "previous contents");
  r = runNestwalk("export " + quoted(scene) + " " + quoted(out) + " --overwrite");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(readBack(out).transforms.count("station-c"), 1u);
  EXPECT_EQ(otherFiles(dir), std::vector<std::string>{"scene.osgb"});
}

TEST(Export, BadInputNamesTheFileAndWritesNothing) {
  const TempFolder folder;
  const fs::path dir = folder.path();
  const fs::path scene = writeScene(dir);
  struct Case {
    std::string args, message;
  };
  writeText(dir / "bad.json", R"({"terrain": "terrain.asc", "equipment": [{"model": "gone.obj", "position": [1, 2]}]})");
  const std::vector<Case> cases = {
      {quoted(scene) + " " + quoted(dir / "out.xyzzy"),
       (dir / "out.xyzzy").string() + ": OpenSceneGraph has no plugin for '.xyzzy' files (try .glb, .gltf, .osgb, .osgt or .ive)"},
      {quoted(scene) + " " + quoted(dir / "out"), (dir / "out").string() + ": no file extension: name the format (.glb, .gltf, .osgb, .osgt, .ive, ...)"},
      {quoted(scene) + " " + quoted(dir / "none" / "out.osgb"),
       (dir / "none" / "out.osgb").string() + ": the folder " + (dir / "none").string() + " does not exist"},
      {quoted(dir / "bad.json") + " " + quoted(dir / "out.osgb"),
       (dir / "bad.json").string() + ": 1 model file not found: equipment[0].model: " + (dir / "gone.obj").string()},
      {quoted(dir / "none.json") + " " + quoted(dir / "out.osgb"), (dir / "none.json").string() + ": scene file not found"},
      {quoted(scene) + " " + quoted(dir / "out.osgb") + " --chunk-cells 3", "--chunk-cells: expected a power of two >= 2, got 3"},
  };
  for (const auto& c : cases) {
    const auto r = runNestwalk("export " + c.args);
    EXPECT_EQ(r.exitCode, 1) << c.args;
    EXPECT_EQ(r.err, "nestwalk: error: " + c.message + "\n") << c.args;
  }
  EXPECT_EQ(otherFiles(dir), std::vector<std::string>{"bad.json"}) << "nothing written";
}

}  // namespace
}  // namespace nestwalk::test
