#include "nestwalk/walker/flythrough.h"

#include "nestwalk/scene/scene.h"
#include "nestwalk/walker/script_player.h"

namespace nestwalk {

bool FlythroughResult::expectationsMet() const {
  for (const auto& e : expectations)
    if (!e.met) return false;
  return true;
}

FrameRecord makeFrameRecord(const Walker& walker, const StepReport& report) {
  const WalkerState& s = walker.state();
  FrameRecord r;
  r.frame = s.frame;
  r.time = s.time;
  r.eye = walker.eye();
  r.headingDeg = s.headingDeg;
  r.bodyYawDeg = s.bodyYawDeg;
  r.pitchDeg = s.pitchDeg;
  r.flying = s.flying;
  r.hasGround = s.hasGround;
  r.ground = s.ground;
  r.blocked = s.blocked;
  if (s.blocked)
    r.blockedBy = s.reason == BlockReason::Equipment && s.blockedUnit >= 0
                      ? walker.world().name(std::size_t(s.blockedUnit))
                      : std::string(blockReasonName(s.reason));
  r.nodeTests = report.counters.nodeTests;
  r.stageTests = report.counters.stageTests;
  r.primitiveTests = report.counters.primitiveTests;
  r.volumesUpdated = report.volumesUpdated;
  r.groundWaits = report.groundWaits;
  r.micros = report.micros;
  return r;
}

FlythroughResult runFlythrough(const Scene& scene, const CollisionWorld& world, const Script& script,
                               const WalkerOptions& options, const std::function<void(const FrameRecord&)>& onRecord) {
  FlythroughResult out;
  Walker walker(*scene.terrain, world, scene.origin, options);
  ScriptPlayer player(script, walker);
  player.run([&](const Walker& w, const StepReport& report) {
    out.records.push_back(makeFrameRecord(w, report));
    out.camera.push_back({w.state().time, w.eye(), w.state().headingDeg, w.state().pitchDeg});
    if (onRecord) onRecord(out.records.back());
  });
  out.expectations = player.expectations();
  return out;
}

}  // namespace nestwalk
