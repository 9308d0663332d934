// Shared by the report tests: a run's worth of varied frame records (and the common temporary folder).
#pragma once

#include "nestwalk/report/render_record.h"
#include "nestwalk/walker/frame_record.h"
#include "tests/common/temp_folder.h"

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace nestwalk::testing {

/// The tests' one temporary folder (tests/common/temp_folder.h) and file reader.
using TempDir = test::TempFolder;
inline std::string readFile(const std::string& path) { return test::readText(path); }

/// `n` records at UTM magnitudes: a walk north-east with blocked stretches (by a unit, by a name
/// with a comma, by the terrain), every counter different, and step times of different orders
/// of magnitude per part (ground ~0.1 µs, broad ~1 µs, narrow ~5 µs, total ~10 µs), spiky.
inline std::vector<FrameRecord> sampleRecords(std::size_t n) {
  std::vector<FrameRecord> out;
  for (std::size_t i = 0; i < n; ++i) {
    FrameRecord r;
    r.frame = i + 1;
    r.time = double(i + 1) / 60.0;
    r.eye = Eigen::Vector3d(500123.45678 + 0.0251 * double(i), 4400987.65432 + 0.0173 * double(i), 312.5 - 0.001 * double(i));
    r.headingDeg = std::fmod(33.3333333 + 0.37 * double(i), 360.0);
    r.pitchDeg = -12.5 + 0.01 * double(i);
    r.flying = i % 50 >= 40;
    r.hasGround = i % 17 != 0;
    r.ground = r.hasGround ? r.eye.z() - 1.7 : 0.0;
    if (i % 10 == 3) {
      r.blocked = true;
      r.blockedBy = "bench2/station3/mast";
    } else if (i % 10 == 7) {
      r.blocked = true;
      r.blockedBy = "pole,north \"A\"";
    } else if (i % 25 == 9) {
      r.blocked = true;
      r.blockedBy = "terrain:step";
    }
    r.nodeTests = 10 + i % 7;
    r.stageTests = {{5 + i % 3, 2 + i % 2, i % 4 == 0 ? 1u : 0u}};
    r.primitiveTests = i % 5;
    r.volumesUpdated = 1;
    const double spike = i % 37 == 0 ? 8.0 : 1.0;
    r.micros[StepPart::Ground] = (0.1 + 0.001 * double(i % 13)) * spike;
    r.micros[StepPart::BroadPhase] = (1.0 + 0.01 * double(i % 11)) * spike;
    r.micros[StepPart::Narrow] = (5.0 + 0.05 * double(i % 7)) * spike;
    r.micros[StepPart::Total] = r.micros[StepPart::Ground] + r.micros[StepPart::BroadPhase] +
                                r.micros[StepPart::Narrow] + 3.0 + 0.1 * double(i % 5);
    out.push_back(r);
  }
  return out;
}

/// One render record per frame of sampleRecords(n): every third frame rendered, with its counts and
/// times (cull ~1.5 ms, draw ~30 ms, readback 2.5 ms, total ~34 ms).
inline std::vector<RenderRecord> sampleRenders(std::size_t n) {
  std::vector<RenderRecord> out(n);
  for (std::size_t i = 0; i < n; i += 3) {
    RenderRecord& r = out[i];
    r.rendered = true;
    r.triangles = 400000 + 37 * i;
    r.instancesDrawn = 100 + i % 9;
    r.culledByAabb = 700 - i % 9;
    r.culledByObb = i % 4;
    r.terrainErrorPx = 0.25 + 0.001 * double(i % 100);
    r.micros[RenderPart::Cull] = 1500.0 + double(i);
    r.micros[RenderPart::Draw] = 30000.0 + 10.0 * double(i);
    r.micros[RenderPart::Readback] = 2500.0;
    r.micros[RenderPart::Total] = 34000.0 + 11.0 * double(i);
  }
  return out;
}

}  // namespace nestwalk::testing
