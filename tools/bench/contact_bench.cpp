// The contact benchmark (see contact_bench.h).
#include "tools/bench/contact_bench.h"

#include "tools/bench/bench_document.h"
#include "tools/bench/bench_process.h"
#include "tools/bench/peers/contact_peers.h"

#include "assets/generators/bundled_scene.h"
#include "assets/generators/equipment_models.h"

#include "nestwalk/core/input_error.h"
#include "nestwalk/core/statistics.h"
#include "nestwalk/core/stopwatch.h"
#include "nestwalk/geometry/coherent_sweep.h"
#include "nestwalk/geometry/mesh_tree.h"
#include "nestwalk/geometry/sat.h"
#include "nestwalk/scene/model_geometry.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <ostream>

namespace nestwalk::bench {
namespace {

namespace fs = std::filesystem;
using V3 = Vec3<double>;
constexpr double kNone = std::numeric_limits<double>::infinity();

constexpr double kPeerRatio = 5.0;          // target: a peer's time / ours, at p50 and at p99
constexpr double kAgreementMm = 0.1;        // target: time of contact within this of ours (mm)
constexpr double kStepMetres = 1.4 / 60.0;  // a walking step at 60 Hz
constexpr double kPressBackMetres = 5e-4;   // the walker stops this short of a contact
// Conservative advancement (the referee where a peer disagrees): touching at this distance (m);
// it never passes a contact, and stops at most this early.
constexpr double kAdvanceTouch = 1e-7;
constexpr int kMaxAdvanceSteps = 100000;
constexpr double kClockResolutionMicros = 1e-3;  // the steady clock's tick here (1 ns)

struct Model {
  std::string name;
  TriangleMesh mesh;  // metres, z up
};

/// FILE[:UNITS[:UP]] read, scaled to metres and turned z up.
Model readModel(const std::string& spec) {
  std::string file = spec, units = "1", up = "z";
  if (const auto colon = spec.find(':'); colon != std::string::npos) {
    file = spec.substr(0, colon);
    units = spec.substr(colon + 1);
    if (const auto second = units.find(':'); second != std::string::npos) {
      up = units.substr(second + 1);
      units = units.substr(0, second);
    }
  }
  char* end = nullptr;
  const double scale = std::strtod(units.c_str(), &end);
  if (end == units.c_str() || *end || !(scale > 0))
    throw InputError(spec + ": the units '" + units + "' are not a positive number of metres");
  const std::string axes[] = {"x", "y", "z", "-x", "-y", "-z"};
  const auto found = std::find(std::begin(axes), std::end(axes), up);
  if (found == std::end(axes)) throw InputError(spec + ": the up axis '" + up + "' is not x, y, z, -x, -y or -z");
  const int index = int(found - std::begin(axes));
  const V3 upAxis = (index < 3 ? 1.0 : -1.0) * V3::Unit(index % 3);
  const Mat3<double> turn = Eigen::Quaterniond::FromTwoVectors(upAxis, V3::UnitZ()).toRotationMatrix();
  Model m{fs::path(file).filename().string(), loadModelGeometry(file)};
  for (V3& v : m.mesh.vertices) v = scale * (turn * v);
  return m;
}

std::vector<std::string> defaultModels() {
  const fs::path models = fs::path(sharedDataFolder()) / "models";
  std::vector<std::string> out;
  const fs::path rig = fs::path(assets::bundledSceneFile()).parent_path() / "models" /
                       assets::modelFileName(assets::ModelKind::DrillRig);
  if (fs::is_regular_file(rig)) out.push_back(rig.string() + ":1:z");
  if (fs::is_regular_file(models / "dumptruck.osgt")) out.push_back((models / "dumptruck.osgt").string() + ":0.3:z");
  if (fs::is_regular_file(models / "excavator_chassis.obj"))
    out.push_back((models / "excavator_chassis.obj").string() + ":1:-y");
  return out;
}

struct Sweep {
  Obb<double> box;
  V3 d;
};

/// The approaches of contact_bench.h, found with our tree (it decides where each approach ends).
std::vector<Sweep> approaches(const TriangleMesh& mesh, const KdopTree& tree, int sides) {
  Aabb<double> bounds{V3::Constant(kNone), V3::Constant(-kNone)};
  for (const V3& v : mesh.vertices) bounds.extend(Aabb<double>{v, v});
  const V3 half(0.25, 0.25, 0.9), centre = bounds.center();
  const double reach = 0.5 * bounds.size().head<2>().norm() + half.head<2>().norm() + 1.0;
  std::vector<Sweep> out;
  for (const double bottom : {bounds.min.z() + 0.05, bounds.min.z() + 0.5 * bounds.size().z()})
    for (int side = 0; side < sides; ++side) {
      const double angle = 2 * std::numbers::pi * side / sides + 0.1;  // off the models' own axes
      const V3 toward(-std::sin(angle), -std::cos(angle), 0);
      Obb<double> box{V3(centre.x(), centre.y(), bottom + half.z()) - reach * toward,
                      Eigen::AngleAxisd(std::atan2(toward.y(), toward.x()), V3::UnitZ()).toRotationMatrix(), half};
      const V3 d = kStepMetres * toward;
      for (int step = 0; step < 100000; ++step, box.center += d) {
        Aabb<double> swept = aabbOf(box);
        swept.extend(Aabb<double>{swept.min + d, swept.max + d});
        if (!satAabbAabb(swept, bounds).overlap) continue;
        out.push_back({box, d});
        const MeshSweepHit hit = tree.sweep(box, d);
        if (!hit.contact) continue;
        // Held at the face: pressing on, turning.
        Obb<double> held = box;
        held.center += std::max(0.0, hit.t * kStepMetres - kPressBackMetres) / kStepMetres * d;
        for (const double turn : {-20.0, -10.0, 10.0, 20.0})
          out.push_back({held, Eigen::AngleAxisd(turn * std::numbers::pi / 180, V3::UnitZ()) * d});
        break;
      }
    }
  return out;
}

/// The first time the box moved by t d comes within kAdvanceTouch of the triangles, by
/// conservative advancement on the tree's exact distances; kNone when not within the step.
double advancementTime(const KdopTree& tree, const Sweep& s) {
  const double length = s.d.norm();
  Obb<double> moved = s.box;
  double t = 0;
  for (int k = 0; k < kMaxAdvanceSteps; ++k) {
    moved.center = s.box.center + t * s.d;
    const double distance = tree.distance(moved);
    if (distance <= kAdvanceTouch) return t;
    t += (distance - 0.5 * kAdvanceTouch) / length;
    if (t > 1.0) return kNone;
  }
  return t;
}

/// The clock's own cost in microseconds: the least time of an empty timed call (taken off every
/// sweep's time, so that the ratios compare the sweeps' work, not two clock reads).
double clockFloorMicros() {
  double least = kNone;
  for (int i = 0; i < 10000; ++i) least = std::min(least, 1e6 * leastSeconds(1, [] {}));
  return least;
}

/// Distance along the step between two times of contact, mm (infinite when only one touches).
double apartMm(double a, double b, const Sweep& s) {
  if (a == kNone && b == kNone) return 0;
  if (a == kNone || b == kNone) return kNone;
  return 1e3 * std::abs(a - b) * s.d.norm();
}

}  // namespace

int runBenchmark(const ContactBenchOptions& opts, std::ostream& out) {
  const int repetitions = opts.quick ? 2 : opts.repetitions;
  const int sides = opts.quick ? 4 : opts.sides;
  const std::vector<std::string> specs = opts.models.empty() ? defaultModels() : opts.models;
  Document doc("nestwalk bench contact: us per sweep of the body box against a heavy model's triangles: "
               "nestwalk's k-DOP tree against FCL's continuous collision and Bullet's convex sweep");
  if (specs.empty()) doc.text << "no models: the shared data folder (" << sharedDataFolder() << ") has none; give --models\n";
  Table table;
  table.column(Column("model", "/model", 24, 0, true)).column(Column("method", "/method", 9, 0, true));
  struct NumberColumn {
    const char *title, *path;
    int width, decimals;
  };
  for (const NumberColumn& c : {NumberColumn{"triangles", "/triangles", 10, 0}, {"sweeps", "/sweeps", 7, 0},
                                {"contacts", "/contacts", 9, 0}, {"us p50", "/us/p50", 10, 2}, {"us p99", "/us/p99", 10, 2},
                                {"us mean", "/us/mean", 10, 2}, {"x ours p50", "/ratio/p50", 11, 1},
                                {"x ours p99", "/ratio/p99", 11, 1}, {"remembered %", "/remembered", 13, 1},
                                {"BV tests", "/bv_tests", 9, 1},
                                {"tri tests", "/triangle_tests", 10, 1}, {"toc apart max mm", "/apart_mm/max", 17, 4},
                                {"apart > 0.1 mm", "/apart_mm/over", 15, 0},
                                {"of which ours right", "/apart_mm/ours_right", 20, 0}})
    table.column(Column(c.title, c.path, c.width, c.decimals));
  double worstRatio = kNone, worstUnresolvedMm = 0;
  std::size_t differing = 0;  // sweeps (all repetitions) where ours as the walker sweeps and alone differ
  const double clockFloor = clockFloorMicros();
  for (const std::string& spec : specs) {
    Model model;
    try {
      model = readModel(spec);
    } catch (const std::exception& e) {
      doc.errors["--models"] = e.what();
      continue;
    }
    const KdopTree tree(model.mesh);
    const std::vector<Sweep> sweeps = approaches(model.mesh, tree, sides);
    const std::unique_ptr<ContactPeer> fcl = fclContactPeer(model.mesh), bullet = bulletContactPeer(model.mesh);
    // Ours as the walker sweeps (one mover's CoherentSweep), ours each step alone (MeshTree::sweep,
    // the same answers: counted where they differ), then the peers.
    const char* names[] = {"nestwalk", "alone", "FCL", "Bullet"};
    constexpr int kMethods = 4;
    std::vector<std::vector<double>> micros(kMethods, std::vector<double>(sweeps.size(), kNone));
    std::vector<std::vector<double>> toc(kMethods, std::vector<double>(sweeps.size(), kNone));
    MeshQueryCounters work[2];  // ours, one call per sweep
    CoherentSweep walker;
    for (int r = 0; r < repetitions; ++r)
      for (int m = 0; m < kMethods; ++m)
        for (std::size_t i = 0; i < sweeps.size(); ++i) {
          const Sweep& s = sweeps[i];
          MeshQueryCounters* counters = r == 0 && m < 2 ? &work[m] : nullptr;
          double t = kNone;
          const double us = 1e6 * leastSeconds(1, [&] {
            if (m < 2) {
              const MeshSweepHit hit = m == 0 ? walker.sweep(tree, s.box, s.d, 0.0, counters)
                                              : tree.sweep(s.box, s.d, 0.0, counters);
              t = hit.contact ? hit.t : kNone;
            } else {
              t = (m == 2 ? *fcl : *bullet).timeOfContact(s.box, s.d);
            }
          });
          // Less the clock's cost, and no less than its resolution (1 ns), so every ratio is finite.
          micros[std::size_t(m)][i] = std::min(micros[std::size_t(m)][i], std::max(kClockResolutionMicros, us - clockFloor));
          toc[std::size_t(m)][i] = t;
          // The walker's answer of this repetition (m 0 plays before m 1) against the step alone.
          if (m == 1) differing += t != toc[0][i];
        }
    const double oursP50 = percentile(micros[0], 50), oursP99 = percentile(micros[0], 99);
    for (int m = 0; m < kMethods; ++m) {
      const auto& us = micros[std::size_t(m)];
      double apartMax = 0;
      int over = 0, oursRight = 0;
      std::size_t contacts = 0;
      for (std::size_t i = 0; i < sweeps.size(); ++i) {
        contacts += toc[std::size_t(m)][i] != kNone;
        if (m < 2) continue;
        const double apart = apartMm(toc[std::size_t(m)][i], toc[0][i], sweeps[i]);
        apartMax = std::max(apartMax, apart);
        if (apart <= kAgreementMm) continue;
        ++over;
        const double referee = advancementTime(tree, sweeps[i]);
        if (apartMm(referee, toc[0][i], sweeps[i]) <= kAgreementMm) ++oursRight;
        else worstUnresolvedMm = std::max(worstUnresolvedMm, apartMm(referee, toc[0][i], sweeps[i]));
      }
      Json row{{"model", model.name},
               {"triangles", model.mesh.triangles.size()},
               {"method", names[m]},
               {"sweeps", sweeps.size()},
               {"contacts", contacts},
               {"us", {{"p50", percentile(us, 50)}, {"p99", percentile(us, 99)}, {"mean", mean(us)}}}};
      if (m == 0) row["remembered"] = 100.0 * double(walker.counters().remembered) / double(repetitions * sweeps.size());
      if (m < 2) {
        row["bv_tests"] = double(work[m].nodeTests) / double(sweeps.size());
        row["triangle_tests"] = double(work[m].triangleTests) / double(sweeps.size());
      }
      if (m > 0) {
        const double r50 = percentile(us, 50) / oursP50, r99 = percentile(us, 99) / oursP99;
        row["ratio"] = {{"p50", r50}, {"p99", r99}};
        if (m > 1) {
          row["apart_mm"] = {{"max", apartMax}, {"over", over}, {"ours_right", oursRight}};
          worstRatio = std::min({worstRatio, r50, r99});
        }
      }
      table.add(row);
    }
  }
  doc.text << "sweeps: the body box (0.5 x 0.5 x 1.8 m) walking at 1.4 m/s (60 Hz steps) into each model from " << sides
           << " sides, on the ground and at half its height, then pressing on turned +-10 and +-20 degrees; each method plays the "
           << "sweeps in order, as a walker steps, " << repetitions << " times, and keeps each sweep's least time, less the clock's own cost ("
           << clockFloor * 1e3 << " ns, the least of an empty timed call); ours as the walker sweeps, with its memory of free paths "
           << "(coherent_sweep.h; remembered: steps answered from it), and alone: each step's own tree sweep, the same answers; BV and triangle tests: ours, per sweep; toc apart: the peer's time "
           << "of contact against ours, as distance along the step (inf: one touches, the other not); where over "
           << "0.1 mm, conservative advancement on exact distances referees\n";
  doc.table("models", table, "  ");
  doc.target("peers' time / ours as the walker sweeps (with its memory), worst of p50 and p99", "", worstRatio == kNone ? Json() : Json(worstRatio), ">=", kPeerRatio);
  doc.target("sweeps answered differently from memory and each step alone", "", double(differing), "<=", 0.0);
  doc.target("our time of contact off the advancement reference where a peer disagrees, mm", "", worstUnresolvedMm,
             "<=", kAgreementMm);
  return doc.write(out, opts.json);
}

}  // namespace nestwalk::bench
