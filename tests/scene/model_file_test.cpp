// readModelFile (scene/model_file.h): model files are untrusted input. For one file per format
// OpenSceneGraph reads here (osgb, osgt, ive, obj, 3ds, stl, ply, flt, dae), made from the shared
// real models where present and from the bundled pickup otherwise (written by OSG's own writers;
// the PLY and the COLLADA by hand: OSG has no PLY writer, its dae writer fails here), the test writes corrupted copies: cut at 20, 40, 60 and
// 80 % of their bytes, and with 1, 4, 16 and 64 bytes flipped at random places. Every copy must
// come back within the time limit, either as a node whose geometry can be collected or with a
// reason; a reader that loops or allocates without end is stopped (a truncated .osgb does both
// when read directly). Good files read through the guard give exactly the geometry of a direct
// read. Per format the test prints how the copies ended, the longest time and the largest memory
// a reading child reached.
#include "nestwalk/scene/model_file.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/scene/node_geometry.h"
#include "tests/common/temp_folder.h"
#include "tests/common/test_data.h"

#include <gtest/gtest.h>
#include <osgDB/ReadFile>
#include <osgDB/Registry>
#include <osgDB/WriteFile>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;

/// The limits the corrupted copies are read under (the defaults: the 10 s and 2 GiB).
const ProcessLimits kLimits{};
/// Seconds a read may take beyond the time limit: the kill, the wait, the poll interval.
constexpr double kKillSlack = 1.5;

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void writeBytes(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out << bytes;
}

/// The pickup's triangles as a COLLADA 1.4.1 document (OSG's dae writer fails here).
void writeCollada(const TriangleMesh& mesh, const fs::path& p) {
  std::ofstream out(p);
  out << "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
         "<COLLADA xmlns=\"http://www.collada.org/2005/11/COLLADASchema\" version=\"1.4.1\">\n"
         " <asset><unit name=\"meter\" meter=\"1\"/><up_axis>Z_UP</up_axis></asset>\n"
         " <library_geometries><geometry id=\"m\"><mesh>\n"
         "  <source id=\"m-p\"><float_array id=\"m-p-a\" count=\"" << 3 * mesh.vertices.size() << "\">";
  for (const auto& v : mesh.vertices) out << v.x() << " " << v.y() << " " << v.z() << " ";
  out << "</float_array>\n   <technique_common><accessor source=\"#m-p-a\" count=\"" << mesh.vertices.size()
      << "\" stride=\"3\"><param name=\"X\" type=\"float\"/><param name=\"Y\" type=\"float\"/>"
         "<param name=\"Z\" type=\"float\"/></accessor></technique_common></source>\n"
         "  <vertices id=\"m-v\"><input semantic=\"POSITION\" source=\"#m-p\"/></vertices>\n"
         "  <triangles count=\"" << mesh.triangles.size() << "\"><input semantic=\"VERTEX\" source=\"#m-v\" offset=\"0\"/><p>";
  for (const auto& t : mesh.triangles) out << t[0] << " " << t[1] << " " << t[2] << " ";
  out << "</p></triangles>\n </mesh></geometry></library_geometries>\n"
         " <library_visual_scenes><visual_scene id=\"s\"><node id=\"n\"><instance_geometry url=\"#m\"/></node>"
         "</visual_scene></library_visual_scenes>\n"
         " <scene><instance_visual_scene url=\"#s\"/></scene>\n</COLLADA>\n";
}

/// The pickup's triangles as an ASCII PLY (OSG reads PLY but does not write it).
void writePly(const TriangleMesh& mesh, const fs::path& p) {
  std::ofstream out(p);
  out << "ply\nformat ascii 1.0\nelement vertex " << mesh.vertices.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << mesh.triangles.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& v : mesh.vertices) out << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& t : mesh.triangles) out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
}

struct Sample {
  std::string format;
  fs::path file;
};

/// One file per format: shared real models where present, the bundled pickup written otherwise.
std::vector<Sample> samples(const fs::path& dir) {
  std::vector<Sample> out;
  const fs::path shared = test::sharedData() / "models";
  std::map<std::string, fs::path> real;
  if (!test::sharedData().empty()) {
    real["osgb"] = shared / "street_lamp.osgb";
    real["osgt"] = shared / "dumptruck.osgt";
    real["obj"] = shared / "excavator_chassis.obj";
    real["3ds"] = shared / "jeep1" / "jeep1.3ds";
  }
  const fs::path pickupFile = test::bundledSceneFolder() / "models" / "pickup.osgt";
  const osg::ref_ptr<osg::Node> pickup = osgDB::readNodeFile(pickupFile.string());
  for (const std::string format : {"osgb", "osgt", "ive", "obj", "3ds", "stl", "ply", "flt", "dae"}) {
    if (real.count(format) && fs::exists(real[format])) {
      fs::copy_file(real[format], dir / ("real." + format));
      out.push_back({format, dir / ("real." + format)});
      continue;
    }
    if (!pickup) continue;
    const fs::path p = dir / ("pickup." + format);
    if (format == "ply") {
      writePly(collectModelGeometry(*pickup, pickupFile.string()), p);
    } else if (format == "dae") {
      if (!osgDB::Registry::instance()->getReaderWriterForExtension(format)) continue;
      writeCollada(collectModelGeometry(*pickup, pickupFile.string()), p);
    } else if (!osgDB::Registry::instance()->getReaderWriterForExtension(format) ||
               !osgDB::writeNodeFile(*pickup, p.string())) {
      std::printf("[%s] no OpenSceneGraph writer here: format left out\n", format.c_str());
      continue;
    }
    if (!fs::exists(p) || fs::file_size(p) == 0) {
      std::printf("[%s] OpenSceneGraph's writer left %s empty: format left out\n", format.c_str(), p.c_str());
      continue;
    }
    out.push_back({format, p});
  }
  return out;
}

/// The corrupted copies of `bytes`: 4 cuts, 4 flips.
std::vector<std::pair<std::string, std::string>> corruptions(const std::string& bytes, unsigned seed) {
  std::vector<std::pair<std::string, std::string>> out;
  for (int percent : {20, 40, 60, 80}) out.emplace_back("cut at " + std::to_string(percent) + " %",
                                                        bytes.substr(0, bytes.size() * percent / 100));
  std::mt19937 rng(seed);
  for (int flips : {1, 4, 16, 64}) {
    std::string b = bytes;
    for (int i = 0; i < flips; ++i) b[rng() % b.size()] ^= char(1 + rng() % 255);
    out.emplace_back(std::to_string(flips) + " bytes flipped", b);
  }
  return out;
}

TEST(ModelFile, GoodFilesReadThroughTheGuardAsDirectly) {
  const test::TempFolder folder;
  const std::vector<Sample> files = samples(folder.path());
  if (files.empty()) GTEST_SKIP() << "neither the shared models nor the bundled scene are present";
  for (const Sample& s : files) {
    SCOPED_TRACE(s.file.string());
    const ModelFile guarded = readModelFile(s.file.string());
    const ModelFile direct = readModelFileUnguarded(s.file.string());
    ASSERT_TRUE(direct.node) << direct.problem;
    ASSERT_TRUE(guarded.node) << guarded.problem;
    const TriangleMesh a = collectModelGeometry(*guarded.node, s.file.string());
    const TriangleMesh b = collectModelGeometry(*direct.node, s.file.string());
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    for (std::size_t i = 0; i < a.vertices.size(); ++i) ASSERT_EQ(a.vertices[i], b.vertices[i]) << "vertex " << i;
    EXPECT_EQ(a.triangles, b.triangles);
    std::printf("[%s] %s: %zu triangles, the same through the guard\n", s.format.c_str(),
                s.file.filename().c_str(), a.triangles.size());
  }
}

TEST(ModelFile, CorruptedCopiesNeverHangOrCrash) {
  const test::TempFolder folder;
  const std::vector<Sample> files = samples(folder.path());
  if (files.empty()) GTEST_SKIP() << "neither the shared models nor the bundled scene are present";
  unsigned seed = 1;
  for (const Sample& s : files) {
    const std::string bytes = readBytes(s.file);
    int read = 0, refused = 0;
    double longest = 0;
    std::uint64_t largest = 0;
    std::map<std::string, int> reasons;
    for (const auto& [what, corrupted] : corruptions(bytes, ++seed)) {
      const fs::path copy = folder.path() / ("bad_" + std::to_string(seed) + "_" + std::to_string(read + refused) + "." +
                                             s.format);
      writeBytes(copy, corrupted);
      const auto t0 = std::chrono::steady_clock::now();
      const ModelFile m = readModelFile(copy.string(), kLimits);
      const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      EXPECT_LT(took, kLimits.seconds + kKillSlack) << s.format << ", " << what;
      longest = std::max(longest, took);
      if (m.node) {
        ++read;  // a corruption the reader can live with (a cut OBJ is a smaller OBJ)
        try {
          collectModelGeometry(*m.node, copy.string());
        } catch (const InputError&) {
          // no vertices left: an error the caller reports, not a crash
        }
      } else {
        ++refused;
        EXPECT_FALSE(m.problem.empty()) << s.format << ", " << what;
        const std::string message = modelFileError(copy.string(), m.problem);
        EXPECT_EQ(message.rfind(copy.string() + ": ", 0), 0u) << message;
        ++reasons[m.problem.substr(0, m.problem.find_first_of("(;"))];
      }
    }
    // The children's peak memory: measured by a read of the worst copy kind again, as the
    // guard's own figure for the last child is what ModelFile does not keep.
    for (const auto& [what, corrupted] : corruptions(bytes, seed)) {
      writeBytes(folder.path() / ("peak." + s.format), corrupted);
      const GuardedResult g = runGuarded(
          [&] {
            const ModelFile m = readModelFileUnguarded((folder.path() / ("peak." + s.format)).string());
            return std::string(m.node ? "node" : "none");
          },
          kLimits);
      largest = std::max(largest, g.peakResidentBytes);
    }
    std::string why;
    for (const auto& [reason, n] : reasons) why += " | " + std::to_string(n) + "x " + reason;
    std::printf("[%s] %s (%zu bytes): 8 copies, %d read, %d refused%s; longest %.2f s, largest child %.0f MiB\n",
                s.format.c_str(), s.file.filename().c_str(), bytes.size(), read, refused, why.c_str(), longest,
                double(largest) / (1 << 20));
  }
}

TEST(ModelFile, MessagesNameTheFileAndTheReason) {
  EXPECT_EQ(modelFileError("a.osgb", "no such file"), "a.osgb: no such file");
  EXPECT_EQ(modelFileError("a.osgb", "took longer than 10 s"), "a.osgb: could not be read as a model (took longer than 10 s)");
  const test::TempFolder folder;
  EXPECT_EQ(readModelFile((folder.path() / "missing.osgt").string()).problem, "no such file");
  EXPECT_EQ(readModelFile(folder.path().string()).problem, "is a folder, not a model file");
  test::writeText(folder.path() / "m.xyzzy", "no plugin");
  EXPECT_EQ(readModelFile((folder.path() / "m.xyzzy").string()).problem, "no OpenSceneGraph plugin reads it");
}

}  // namespace
}  // namespace nestwalk
