// The walk session (walk_session.h): loading and the start search, the recording lifecycle, each
// frame's HUD data and events, the closing lines.
#include "nestwalk/session/walk_session.h"

#include "nestwalk/core/angles.h"
#include "nestwalk/core/input_error.h"
#include "nestwalk/core/output_file.h"
#include "nestwalk/core/statistics.h"
#include "nestwalk/report/result_layers.h"
#include "nestwalk/scene/scene_loader.h"
#include "nestwalk/viewer/walk_recording.h"
#include "nestwalk/terrain/dem_reader.h"
#include "nestwalk/walker/animation_path.h"
#include "nestwalk/walker/script_file.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace nestwalk {

namespace fs = std::filesystem;

std::string poseText(const ViewPose& p) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "eye %.17g %.17g %.17g heading %.17g pitch %.17g", p.eye.x(), p.eye.y(), p.eye.z(),
                p.headingDeg, p.pitchDeg);
  return buf;
}

namespace {

/// The options, once the recording folder is known to be usable (before the scene loads). The
/// default folder may exist from an earlier session: the first recording then asks for
/// `overwrite` (toggleRecording); a folder named by hand must not exist without it.
WalkSessionOptions checked(WalkSessionOptions o) {
  if (!o.recordFolder.empty() && fs::exists(o.recordFolder) && !o.overwrite && o.recordFolder != "recordings")
    throw InputError(o.recordFolder + ": the recording folder exists; pass --overwrite to write into it");
  return o;
}

}  // namespace

WalkSession::WalkSession(WalkSessionOptions options)
    : options_(checked(std::move(options))), scene_(loadScene(options_.scene)) {
  const WalkSessionOptions& o = options_;
  method_ = o.method ? o.method(scene_.spec.method) : scene_.spec.method;
  world_ = std::make_unique<CollisionWorld>(CollisionWorld::fromScene(scene_, method_));
  walkerOptions_.viewer = scene_.spec.viewer;
  walkerOptions_.dt = 1.0 / o.hz;
  if (playsScript()) played_ = runFlythrough(scene_, *world_, readScript(o.script), walkerOptions_);
  walker_ = std::make_unique<Walker>(*scene_.terrain, *world_, scene_.origin, walkerOptions_);
  if (!playsScript()) placeAtStart();
  crs_ = terrain::crsName(scene_.terrain->crsWkt());
}

WalkSession::~WalkSession() = default;

void WalkSession::say(const std::string& line) const {
  if (options_.say) options_.say(line);
}

void WalkSession::placeAtStart() {
  const terrain::Heightfield& hf = *scene_.terrain;
  const std::vector<double>& start = options_.start;
  // Sample (0, 0) is the north-west corner; rows run south.
  const Eigen::Vector3d centre(hf.origin().x() + 0.5 * (hf.cols() - 1) * hf.dx(),
                               hf.origin().y() - 0.5 * (hf.rows() - 1) * hf.dy(), 0);
  const Eigen::Vector3d at = start.size() >= 2 ? Eigen::Vector3d(start[0], start[1], 0) : centre;
  const double heading = start.size() >= 3 ? start[2] : 0.0;
  const double clearance = walkerOptions_.viewer.flyClearance;
  std::string why = walker_->place(at, false, heading, options_.fly, clearance);
  if (!why.empty() && start.size() >= 2)
    throw InputError("--start " + std::to_string(at.x()) + " " + std::to_string(at.y()) + ": " + why);
  const double reach = 0.5 * std::max(hf.cols() * hf.dx(), hf.rows() * hf.dy());
  for (double r = kStartRingStep; !why.empty() && r <= reach; r += kStartRingStep)
    for (int k = 0; k < kStartRingDirections && !why.empty(); ++k) {
      const auto [sn, cs] = sinCosDegrees(360.0 / kStartRingDirections * k);
      why = walker_->place(at + r * Eigen::Vector3d(sn, cs, 0), false, heading, options_.fly, clearance);
    }
  if (!why.empty())
    throw InputError(options_.scene + ": no free ground to start on near the terrain's centre; give --start X Y");
}

void WalkSession::toggleRecording() {
  if (playsScript()) return;
  if (recording_) {
    stopRecording();
    return;
  }
  const std::string& folder = options_.recordFolder;
  if (!recordFolderMade_) {
    if (fs::exists(folder) && !options_.overwrite) {
      status_ = folder + " exists: restart with --overwrite or --record NEW_FOLDER";
      say("recording not started: " + status_);
      return;
    }
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec) {
      status_ = folder + ": cannot create the folder: " + ec.message();
      say("recording not started: " + status_);
      return;
    }
    recordFolderMade_ = true;
  }
  recording_ = std::make_unique<WalkRecording>(*walker_, options_.scene, volumeMethodName(method_.volumes));
  recorded_.clear();
  status_ = "RECORDING";
  say("recording started");
}

void WalkSession::recordStep(const StepInput& input, const StepReport& report) {
  if (!recording_) return;
  recording_->add(input, *walker_);
  // Counted from the recording's start (its layers' times and frames), not the window's.
  FrameRecord r = makeFrameRecord(*walker_, report);
  if (recorded_.empty()) recordStart_ = {r.frame - 1, r.time - walkerOptions_.dt};
  r.frame -= recordStart_.first;
  r.time -= recordStart_.second;
  recorded_.push_back(std::move(r));
}

void WalkSession::stopRecording() {
  char name[32];
  std::snprintf(name, sizeof name, "walk_%03d", ++recordings_);
  const fs::path script = fs::path(options_.recordFolder) / (std::string(name) + ".txt");
  const fs::path path = fs::path(options_.recordFolder) / (std::string(name) + ".path");
  writeFileAtomically(script.string(), recording_->scriptText());
  writeAnimationPath(path.string(), recording_->camera());
  RunSummaryInfo info;
  info.scene = options_.scene;
  info.script = script.string();
  info.method = volumeMethodName(method_.volumes);
  info.dt = walkerOptions_.dt;
  const fs::path layers = fs::path(options_.recordFolder) / name;
  writeResultLayers(layers.string(), scene_.terrain->crsWkt(), info, recorded_, {},
                    runContacts(scene_, recorded_, world_->meshes().get()));
  status_ = "recorded " + script.string();
  say("recording written " + script.string() + ", " + path.string() + " and " + layers.string() + ".gpkg (" +
      std::to_string(recording_->steps()) + " steps, " + std::to_string(recording_->contacts().size()) + " contacts)");
  recording_.reset();
}

HudState WalkSession::frame(const WalkFrame& f) {
  HudState h;
  const ViewPose& pose = f.pose;
  h.frameMs = frameMs_.empty() ? 0 : frameMs_.back();
  h.fps = h.frameMs > 0 ? 1000.0 / h.frameMs : 0;
  if (f.lastStep) {
    h.stepMicros = f.lastStep->micros[StepPart::Total];
    h.stageTests = f.lastStep->counters.stageTests;
    h.primitiveTests = f.lastStep->counters.primitiveTests;
  }
  h.stepsThisFrame = f.stepsThisFrame;
  h.eye = pose.eye;
  h.crs = crs_;
  h.headingDeg = pose.headingDeg;
  h.pitchDeg = pose.pitchDeg;
  const std::optional<double> ground = scene_.terrain->groundHeight(pose.eye.x(), pose.eye.y());
  h.hasGround = ground.has_value();
  h.ground = ground.value_or(0);
  h.flying = walker_->state().flying;
  h.sliding = walker_->options().slide;
  h.method = volumeMethodName(method_.volumes);
  h.terrainChunks = f.terrain.chunksDrawn;
  h.terrainLoading = f.terrain.chunksWanted;
  h.terrainErrorPx = f.terrain.maxErrorPx;
  h.terrainMiB = double(f.terrain.residentBytes) / (1 << 20);
  h.terrainBudgetMiB = double(f.terrainBudgetBytes) / (1 << 20);
  h.status = f.paused ? "PAUSED (K resumes, L steps)" : status_;
  if (!f.walkerMessage.empty() && status_.empty()) h.status = f.walkerMessage;
  if (f.shown) {
    for (const ExpectationResult& e : played_.expectations)
      if (e.frame <= f.shown->frame)
        h.expectations.push_back("line " + std::to_string(e.line) + ": " + e.text +
                                 (e.met ? ": met" : ": FAILED (" + e.detail + ")"));
    for (; expectationsSaid_ < h.expectations.size(); ++expectationsSaid_) say(h.expectations[expectationsSaid_]);
  }
  if (pose.blocked && !wasBlocked_) {
    char at[128];
    std::snprintf(at, sizeof at, " at %.3f %.3f %.3f", pose.eye.x(), pose.eye.y(), pose.eye.z());
    say("blocked by " + pose.blockedBy + at);
  }
  wasBlocked_ = pose.blocked;
  return h;
}

void WalkSession::finish(const ViewPose& end, const FrameRecord* shown, double seconds) {
  if (recording_) stopRecording();
  // The first frame compiles the scene's GL objects: left out of the rate.
  const std::vector<double> steady(frameMs_.size() > 1 ? frameMs_.begin() + 1 : frameMs_.begin(), frameMs_.end());
  double steadyMs = 0;
  for (double m : steady) steadyMs += m;
  char line[256];
  std::snprintf(line, sizeof line, "frames %zu in %.2f s: %.1f fps, frame ms p50 %.1f p95 %.1f (first frame %.0f ms)",
                frameMs_.size(), seconds, steady.empty() ? 0.0 : 1000.0 * double(steady.size()) / steadyMs,
                percentile(steady, 50), percentile(steady, 95), frameMs_.empty() ? 0.0 : frameMs_.front());
  say("stopped " + poseText(end) +
      (shown ? " at frame " + std::to_string(shown->frame) + " of " + std::to_string(played_.records.size())
             : " after " + std::to_string(walker_->state().frame) + " steps") +
      (end.blocked ? ", blocked by " + end.blockedBy : ""));
  say(line);
}

}  // namespace nestwalk
