// The per-frame CSV (engine/report/frame_csv.h): parsed back field by field with an RFC 4180
// reader written here, and byte-identical once the timing columns are cut when only timings differ.
#include "nestwalk/report/frame_csv.h"

#include "nestwalk/core/csv_reader.h"
#include "nestwalk/core/input_error.h"
#include "tests/report/report_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace nestwalk {
namespace {

using testing::readFile;
using testing::sampleRecords;
using testing::TempDir;

/// RFC 4180 records: fields split on commas, quoted fields may hold commas and doubled quotes.
std::vector<std::vector<std::string>> parseCsv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string field;
  bool quoted = false, any = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (quoted) {
      if (ch == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        field += ch;
      }
    } else if (ch == '"') {
      quoted = true;
      any = true;
    } else if (ch == ',') {
      row.push_back(field);
      field.clear();
      any = true;
    } else if (ch == '\n') {
      row.push_back(field);
      rows.push_back(row);
      row.clear();
      field.clear();
      any = false;
    } else {
      field += ch;
      any = true;
    }
  }
  if (any) ADD_FAILURE() << "the file does not end with a newline";
  return rows;
}

const std::vector<std::string> kHeader = {
    "frame",    "time",      "x",        "y",        "z",       "heading",  "pitch",    "flying",
    "has_ground", "ground",  "blocked",  "blocked_by", "node_tests", "aabb_aabb", "aabb_obb", "obb_obb",
    "np",       "nu",        "rendered", "triangles", "instances_drawn", "culled_aabb", "culled_obb",
    "terrain_error_px", "us_ground", "us_broad", "us_narrow", "us_total", "us_render_cull", "us_render_draw",
    "us_render_readback", "us_render_total"};

double num(const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  EXPECT_TRUE(!s.empty() && *end == '\0') << "'" << s << "' is not a number";
  return v;
}

TEST(FrameCsv, ParsesBackToTheRecords) {
  TempDir dir;
  const std::vector<FrameRecord> records = sampleRecords(200);
  const std::vector<RenderRecord> renders = testing::sampleRenders(200);
  const std::string path = dir / "frames.csv";
  writeFrameCsv(path, records, renders);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"frames.csv"});

  const auto rows = parseCsv(readFile(path));
  ASSERT_EQ(rows.size(), records.size() + 1);
  EXPECT_EQ(rows[0], kHeader);
  // Resolutions the header promises (half a unit in the last printed digit).
  constexpr double kPositionTol = 0.5e-4, kAngleTol = 0.5e-6, kTimeTol = 0.5e-6, kMicrosTol = 0.5e-3;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const FrameRecord& r = records[i];
    const RenderRecord& rr = renders[i];
    const std::vector<std::string>& f = rows[i + 1];
    ASSERT_EQ(f.size(), kHeader.size()) << "row " << i + 1;
    EXPECT_EQ(f[0], std::to_string(r.frame));
    EXPECT_NEAR(num(f[1]), r.time, kTimeTol);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(num(f[2 + std::size_t(k)]), r.eye[k], kPositionTol);
    EXPECT_NEAR(num(f[5]), r.headingDeg, kAngleTol);
    EXPECT_NEAR(num(f[6]), r.pitchDeg, kAngleTol);
    EXPECT_EQ(f[7], r.flying ? "1" : "0");
    EXPECT_EQ(f[8], r.hasGround ? "1" : "0");
    if (r.hasGround) {
      EXPECT_NEAR(num(f[9]), r.ground, kPositionTol);
    } else {
      EXPECT_EQ(f[9], "");
    }
    EXPECT_EQ(f[10], r.blocked ? "1" : "0");
    EXPECT_EQ(f[11], r.blockedBy);  // including the name with a comma and quotes
    EXPECT_EQ(f[12], std::to_string(r.nodeTests));
    EXPECT_EQ(f[13], std::to_string(r.stageTests[OverlapStage::AabbAabb]));
    EXPECT_EQ(f[14], std::to_string(r.stageTests[OverlapStage::AabbObb]));
    EXPECT_EQ(f[15], std::to_string(r.stageTests[OverlapStage::ObbObb]));
    EXPECT_EQ(f[16], std::to_string(r.primitiveTests));
    EXPECT_EQ(f[17], std::to_string(r.volumesUpdated));
    EXPECT_EQ(f[18], rr.rendered ? "1" : "0");
    EXPECT_EQ(f[19], std::to_string(rr.triangles));
    EXPECT_EQ(f[20], std::to_string(rr.instancesDrawn));
    EXPECT_EQ(f[21], std::to_string(rr.culledByAabb));
    EXPECT_EQ(f[22], std::to_string(rr.culledByObb));
    EXPECT_NEAR(num(f[23]), rr.terrainErrorPx, 0.5e-4);
    for (std::size_t k = 0; k < kStepParts; ++k) EXPECT_NEAR(num(f[24 + k]), r.micros.values[k], kMicrosTol);
    for (std::size_t k = 0; k < kRenderParts; ++k) EXPECT_NEAR(num(f[28 + k]), rr.micros.values[k], kMicrosTol);
  }
}

TEST(FrameCsv, FixedDecimalsAtUtmMagnitudes) {
  TempDir dir;
  FrameRecord r;
  r.frame = 7;
  r.time = 0.125;
  r.eye = Eigen::Vector3d(512345.67891, 4412345.12344, -3.5);
  r.headingDeg = 359.9999994;
  r.micros = {{0.0625, 1.5, 2.25, 10.0}};
  writeFrameCsv(dir / "f.csv", {r});
  const auto rows = parseCsv(readFile(dir / "f.csv"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1][1], "0.125000");
  EXPECT_EQ(rows[1][2], "512345.6789");
  EXPECT_EQ(rows[1][3], "4412345.1234");
  EXPECT_EQ(rows[1][4], "-3.5000");
  EXPECT_EQ(rows[1][5], "359.999999");
  EXPECT_EQ(rows[1][11], "");
  EXPECT_EQ(rows[1][24], "0.062");  // round half to even of 0.0625 (exact in binary)
  EXPECT_EQ(rows[1][27], "10.000");
}

/// The file with every column whose header starts with "us_" removed (what a user does with cut).
std::string withoutTimings(const std::string& text) {
  const auto rows = parseCsv(text);
  std::vector<bool> keep;
  for (const std::string& name : rows.at(0)) keep.push_back(name.rfind("us_", 0) != 0);
  // The timing columns are the last ones: a prefix of the line is kept, byte for byte.
  const std::size_t kept = std::size_t(std::count(keep.begin(), keep.end(), true));
  for (std::size_t i = 0; i < keep.size(); ++i) EXPECT_EQ(keep[i], i < kept) << "column " << rows[0][i];
  std::string out;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t eol = text.find('\n', pos);
    const std::string line = text.substr(pos, eol - pos);
    // Cut after the kept-th unquoted comma.
    std::size_t commas = 0, cut = line.size();
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      if (line[i] == '"') quoted = !quoted;
      if (line[i] == ',' && !quoted && ++commas == kept) {
        cut = i;
        break;
      }
    }
    out += line.substr(0, cut) + "\n";
    pos = eol + 1;
  }
  return out;
}

TEST(FrameCsv, ByteIdenticalWithoutTimingColumns) {
  TempDir dir;
  std::vector<FrameRecord> a = sampleRecords(300), b = a;
  for (std::size_t i = 0; i < b.size(); ++i)
    for (double& us : b[i].micros) us = us * 1.37 + double(i % 3);
  writeFrameCsv(dir / "a.csv", a);
  writeFrameCsv(dir / "b.csv", b);
  const std::string ta = readFile(dir / "a.csv"), tb = readFile(dir / "b.csv");
  EXPECT_NE(ta, tb);
  EXPECT_EQ(withoutTimings(ta), withoutTimings(tb));
  // Same inputs, same bytes, timing columns included.
  writeFrameCsv(dir / "a2.csv", a);
  EXPECT_EQ(readFile(dir / "a2.csv"), ta);
}

TEST(FrameCsv, EmptyRunHasTheHeaderOnly) {
  TempDir dir;
  writeFrameCsv(dir / "e.csv", {});
  const auto rows = parseCsv(readFile(dir / "e.csv"));
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0], kHeader);
}

TEST(FrameCsv, UnwritableFolderNamesTheFile) {
  TempDir dir;
  const std::string path = dir / "missing/frames.csv";
  try {
    writeFrameCsv(path, sampleRecords(3));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(FrameCsv, ReplacesAnExistingFile) {
  TempDir dir;
  writeFrameCsv(dir / "f.csv", sampleRecords(10));
  writeFrameCsv(dir / "f.csv", sampleRecords(2));
  EXPECT_EQ(parseCsv(readFile(dir / "f.csv")).size(), 3u);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"f.csv"});
}

TEST(FrameCsv, RoundTripsThroughTheCsvReader) {
  // What nestwalk writes, nestwalk reads: core/csv_reader.h gives the same rows as the independent
  // RFC 4180 parser above, including blocked_by names with commas and quotes.
  TempDir dir;
  const std::vector<FrameRecord> records = sampleRecords(300);
  const std::string path = dir / "frames.csv";
  writeFrameCsv(path, records, testing::sampleRenders(300));
  const auto expected = parseCsv(readFile(path));
  std::ifstream in(path, std::ios::binary);
  CsvReader csv(in, path);
  EXPECT_EQ(csv.header(), kHeader);
  std::vector<std::string> fields;
  std::size_t row = 1;
  const int blockedBy = csv.column("blocked_by"), x = csv.column("x");
  while (csv.next(fields)) {
    ASSERT_LT(row, expected.size());
    EXPECT_EQ(fields, expected[row]) << "row " << row;
    EXPECT_EQ(csv.line(), row + 1) << "one line per row: no name holds a line break";
    EXPECT_EQ(fields[std::size_t(blockedBy)], records[row - 1].blockedBy);
    EXPECT_NEAR(csv.number(fields, x), records[row - 1].eye.x(), 0.5e-4);
    ++row;
  }
  EXPECT_EQ(row, expected.size());
}

}  // namespace
}  // namespace nestwalk
