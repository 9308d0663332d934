#include "assets/generators/equipment_models.h"

#include "assets/generators/mesh_builder.h"
#include "nestwalk/core/angles.h"
#include "nestwalk/core/input_error.h"

#include <osg/Geode>
#include <osg/Geometry>
#include <osgDB/WriteFile>

#include <algorithm>
#include <array>
#include <cmath>

namespace nestwalk::assets {
namespace {

using V3 = Eigen::Vector3d;

constexpr int kThinSides = 12;   // masts, spindles, wheels
constexpr int kRoundSides = 16;  // the pole, the piezometer casing

/// Rotation about the model's x axis by `deg` degrees (positive turns +y toward +z).
Eigen::Matrix3d rotX(double deg) {
  const double c = std::cos(radians(deg)), s = std::sin(radians(deg));
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, c, -s, 0, s, c;
  return r;
}

// --- sensor pole: 0.05 m diameter, 3 m, a sensor head (radar/camera box) under the top ---------
constexpr double kPoleDiameter = 0.05;
constexpr double kPoleHeight = 3.0;
void buildSensorPole(MeshBuilder& b) {
  b.addPrism(V3(0, 0, 0), V3::UnitZ(), 0.5 * kPoleDiameter, kPoleHeight, kRoundSides);
  b.addBoxMinMax(V3(-0.06, -0.06, 2.78), V3(0.06, 0.10, 2.90));  // sensor head, looking forward
  b.addBoxMinMax(V3(-0.07, -0.06, 2.90), V3(0.07, 0.12, 2.92));  // sun shield
}

// --- weather station mast ------------------------------------------------------------------------
constexpr double kMastDiameter = 0.06;
constexpr double kMastHeight = 3.0;
constexpr double kCrossArmZ = 2.80;        // centre height of the cross-arm
constexpr double kCrossArmHalfLength = 0.5;
constexpr double kStationPanelTiltDeg = 35.0;
void buildWeatherStation(MeshBuilder& b) {
  b.addPrism(V3(0, 0, 0), V3::UnitZ(), 0.5 * kMastDiameter, kMastHeight, kThinSides);
  b.addBox(V3(0, 0, kCrossArmZ), V3(kCrossArmHalfLength, 0.02, 0.02));
  // Anemometer on the +x end: spindle, three arms with cups.
  const V3 anemo(kCrossArmHalfLength - 0.02, 0, kCrossArmZ + 0.02);
  b.addPrism(anemo, V3::UnitZ(), 0.008, 0.16, kThinSides);
  for (int i = 0; i < 3; ++i) {
    const double a = radians(90.0 + 120.0 * i);
    const V3 dir(std::cos(a), std::sin(a), 0);
    const V3 cup = anemo + V3(0, 0, 0.14) + 0.09 * dir;
    Eigen::Matrix3d rz;
    rz << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
    b.addBox(anemo + V3(0, 0, 0.14) + 0.045 * dir, V3(0.045, 0.004, 0.004), rz);  // arm
    b.addBox(cup, V3(0.022, 0.022, 0.022), rz);                                    // cup
  }
  // Wind vane on the -x end: spindle and tail fin along y.
  const V3 vane(-kCrossArmHalfLength + 0.02, 0, kCrossArmZ + 0.02);
  b.addPrism(vane, V3::UnitZ(), 0.008, 0.12, kThinSides);
  b.addBoxMinMax(V3(-kCrossArmHalfLength + 0.015, -0.20, 2.88), V3(-kCrossArmHalfLength + 0.025, 0.06, 2.96));
  // Logger box on the front of the mast, and a small panel above it facing forward and up.
  b.addBoxMinMax(V3(-0.15, 0.03, 1.20), V3(0.15, 0.18, 1.60));
  b.addBox(V3(0, 0.17, 2.05), V3(0.20, 0.15, 0.012), rotX(-kStationPanelTiltDeg));
}

// --- solar panel on a frame ------------------------------------------------------------------------
constexpr double kPanelWidth = 1.6, kPanelLength = 1.0, kPanelThickness = 0.04;
constexpr double kPanelTiltDeg = 30.0;
constexpr double kPanelLowEdgeZ = 0.5;  // the panel's lowest point above the ground
void buildSolarPanel(MeshBuilder& b) {
  const Eigen::Matrix3d r = rotX(-kPanelTiltDeg);  // normal (0, sin, cos): forward and up
  const V3 half(0.5 * kPanelWidth, 0.5 * kPanelLength, 0.5 * kPanelThickness);
  // Lowest corner: local (., +len/2, -t/2) -> z = -sin(tilt) len/2 - cos(tilt) t/2 below the centre.
  const double drop = std::sin(radians(kPanelTiltDeg)) * half.y() + std::cos(radians(kPanelTiltDeg)) * half.z();
  const V3 centre(0, 0, kPanelLowEdgeZ + drop);
  b.addBox(centre, half, r);
  // Legs up to the panel's underside (local z = -t/2), front and back, near the sides.
  auto undersideZ = [&](double y) {
    // Points centre + r * (x, yl, -t/2): world y = c yl + s t/2, z = zc - s yl - c t/2 (c, s of tilt).
    const double c = std::cos(radians(kPanelTiltDeg)), s = std::sin(radians(kPanelTiltDeg));
    const double yl = (y - s * half.z()) / c;
    return centre.z() - s * yl - c * half.z();
  };
  constexpr double kLegX = 0.70, kLegY = 0.30, kLegHalf = 0.025;
  for (double y : {kLegY, -kLegY}) {
    const double top = undersideZ(y) - 0.01;
    for (double x : {kLegX, -kLegX}) b.addBoxMinMax(V3(x - kLegHalf, y - kLegHalf, 0), V3(x + kLegHalf, y + kLegHalf, top));
    b.addBoxMinMax(V3(-kLegX, y - 0.015, 0.28), V3(kLegX, y + 0.015, 0.32));  // rail
  }
}

// --- logger box: a cabinet on a post -----------------------------------------------------------------
void buildLoggerBox(MeshBuilder& b) {
  b.addBoxMinMax(V3(-0.20, -0.20, 0), V3(0.20, 0.20, 0.04));     // base plate
  b.addBoxMinMax(V3(-0.04, -0.04, 0.04), V3(0.04, 0.04, 0.90));  // post
  b.addBoxMinMax(V3(-0.25, -0.15, 0.90), V3(0.25, 0.15, 1.50));  // cabinet
  b.addBoxMinMax(V3(-0.28, -0.18, 1.50), V3(0.28, 0.18, 1.53));  // roof
}

// --- piezometer head ---------------------------------------------------------------------------------
constexpr double kPadSide = 0.6, kPadHeight = 0.1;
constexpr double kCasingDiameter = 0.15, kCasingHeight = 0.8;
constexpr double kCapDiameter = 0.18, kCapHeight = 0.08;
void buildPiezometer(MeshBuilder& b) {
  b.addBoxMinMax(V3(-0.5 * kPadSide, -0.5 * kPadSide, 0), V3(0.5 * kPadSide, 0.5 * kPadSide, kPadHeight));
  b.addPrism(V3(0, 0, kPadHeight), V3::UnitZ(), 0.5 * kCasingDiameter, kCasingHeight, kRoundSides);
  b.addPrism(V3(0, 0, kPadHeight + kCasingHeight), V3::UnitZ(), 0.5 * kCapDiameter, kCapHeight, kRoundSides);
}

// --- 20 ft ISO container (ISO 668 1CC: 6.058 x 2.438 x 2.591 m) -------------------------------------
constexpr double kContainerLength = 6.06, kContainerWidth = 2.44, kContainerHeight = 2.59;
constexpr double kRailHeight = 0.10, kRailWidth = 0.16;
void buildContainer(MeshBuilder& b) {
  const double hx = 0.5 * kContainerWidth, hy = 0.5 * kContainerLength;
  b.addBoxMinMax(V3(-hx, -hy, kRailHeight), V3(hx, hy, kContainerHeight));
  for (double s : {-1.0, 1.0}) {
    b.addBoxMinMax(V3(s > 0 ? hx - kRailWidth : -hx, -hy, 0), V3(s > 0 ? hx : -hx + kRailWidth, hy, kRailHeight));
    b.addBoxMinMax(V3(-hx + kRailWidth, s > 0 ? hy - kRailWidth : -hy, 0),
                   V3(hx - kRailWidth, s > 0 ? hy : -hy + kRailWidth, kRailHeight));
  }
}

// --- concrete jersey barrier (safety shape) ------------------------------------------------------------
constexpr double kBarrierLength = 3.0, kBarrierBase = 0.6, kBarrierHeight = 0.8;
void buildJerseyBarrier(MeshBuilder& b) {
  const double h = 0.5 * kBarrierBase;
  b.addExtrusionY({{-h, 0}, {h, 0}, {h, 0.075}, {0.20, 0.33}, {0.10, kBarrierHeight}, {-0.10, kBarrierHeight},
                   {-0.20, 0.33}, {-h, 0.075}},
                  -0.5 * kBarrierLength, 0.5 * kBarrierLength);
}

// --- pickup truck ----------------------------------------------------------------------------------------
constexpr double kPickupLength = 5.3, kPickupWidth = 1.9, kPickupHeight = 1.8;
constexpr double kWheelRadius = 0.38, kWheelWidth = 0.26;
void buildPickup(MeshBuilder& b) {
  const double hy = 0.5 * kPickupLength, hx = 0.5 * kPickupWidth;
  for (double y : {1.6, -1.6}) {  // axles, symmetric so the wheels' footprint is centred
    b.addPrism(V3(-hx, y, kWheelRadius), V3::UnitX(), kWheelRadius, kWheelWidth, kThinSides);
    b.addPrism(V3(hx - kWheelWidth, y, kWheelRadius), V3::UnitX(), kWheelRadius, kWheelWidth, kThinSides);
  }
  b.addBoxMinMax(V3(-0.93, -hy, 0.45), V3(0.93, hy, 0.95));               // body and chassis
  b.addBoxMinMax(V3(-0.90, 1.10, 0.95), V3(0.90, hy - 0.05, 1.15));        // hood
  b.addBoxMinMax(V3(-0.88, -0.60, 0.95), V3(0.88, 1.10, kPickupHeight));   // cab
  for (double s : {-1.0, 1.0})                                             // bed sides
    b.addBoxMinMax(V3(s > 0 ? 0.88 : -0.93, -hy, 0.95), V3(s > 0 ? 0.93 : -0.88, -0.60, 1.30));
  b.addBoxMinMax(V3(-0.88, -hy, 0.95), V3(0.88, -hy + 0.05, 1.30));        // tailgate
}

// --- drill rig: a crawler blast-hole rig with its lattice mast up, tessellated as CAD exports are --
// Tracks along y, a deck with the cab and the engine house, and at the front a 0.5 m square
// lattice mast 8.8 m tall (four chords, struts and zigzag braces on each face) holding the drill
// rod. Round parts are prisms of kRigSides sides cut into short segments along their length, as a
// tessellating exporter leaves them: 40,020 triangles, the heavy model of the bundled scene.
constexpr int kRigSides = 32;           // chords and rod
constexpr int kRigBraceSides = 16;      // struts and braces
constexpr double kRigSegment = 0.2;     // metres: the length of a round part's segments
constexpr double kMastY = 2.05;         // the mast's axis, metres ahead of the model's centre
constexpr double kMastHalf = 0.25;      // half the mast's side
constexpr double kMastFoot = 1.4, kMastTop = 10.2;
constexpr double kChordRadius = 0.04, kBraceRadius = 0.015, kRodRadius = 0.05;
constexpr double kBraceLevel = 0.4;     // metres between the mast's struts

/// A prism cut into segments of at most kRigSegment along its axis.
void addSegmentedPrism(MeshBuilder& b, const V3& base, const V3& axis, double radius, double length, int sides) {
  const int n = std::max(1, int(std::ceil(length / kRigSegment - 1e-9)));
  for (int i = 0; i < n; ++i) b.addPrism(base + (length * i / n) * axis, axis, radius, length / n, sides);
}

/// A strut or brace from p to q.
void addBar(MeshBuilder& b, const V3& p, const V3& q) {
  b.addPrism(p, (q - p).normalized(), kBraceRadius, (q - p).norm(), kRigBraceSides);
}

void buildDrillRig(MeshBuilder& b) {
  // Tracks: frame, pads, rollers.
  for (double s : {-1.0, 1.0}) {
    const double x0 = s * 0.675, x1 = s * 1.125, lo = std::min(x0, x1), hi = std::max(x0, x1);
    b.addBoxMinMax(V3(lo, -2.2, 0.08), V3(hi, 2.2, 0.7));
    for (int i = 0; i < 28; ++i) {
      const double y = -2.2 + (i + 0.5) * 4.4 / 28;
      b.addBoxMinMax(V3(lo - 0.02, y - 0.07, 0.0), V3(hi + 0.02, y + 0.07, 0.08));
    }
    for (int i = 0; i < 7; ++i)
      b.addPrism(V3(lo - 0.03, -1.8 + 0.6 * i, 0.3), V3::UnitX(), 0.12, hi - lo + 0.06, 24);
  }
  b.addBoxMinMax(V3(-1.15, -2.5, 0.75), V3(1.15, 1.5, 1.5));     // deck
  b.addBoxMinMax(V3(-1.15, 0.2, 1.5), V3(-0.1, 1.5, 3.0));        // cab
  b.addBoxMinMax(V3(-0.1, -2.5, 1.5), V3(1.15, -0.1, 2.6));       // engine house
  b.addBoxMinMax(V3(-1.0, -2.5, 1.5), V3(-0.2, -1.6, 2.2));       // counterweight
  b.addBoxMinMax(V3(-0.35, 1.5, 0.75), V3(0.35, 2.5, kMastFoot));  // mast foot
  // Mast: chords at its corners, struts at every level, a zigzag brace on each face.
  const double height = kMastTop - kMastFoot;
  std::array<V3, 4> corner;
  for (int c = 0; c < 4; ++c)
    corner[std::size_t(c)] = V3((c == 0 || c == 3 ? -1 : 1) * kMastHalf, kMastY + (c < 2 ? -1 : 1) * kMastHalf, kMastFoot);
  for (const V3& c : corner) addSegmentedPrism(b, c, V3::UnitZ(), kChordRadius, height, kRigSides);
  const int levels = int(std::lround(height / kBraceLevel));
  for (int l = 0; l < levels; ++l) {
    const V3 z0(0, 0, l * kBraceLevel), z1(0, 0, (l + 1) * kBraceLevel);
    for (int f = 0; f < 4; ++f) {
      const V3& a = corner[std::size_t(f)];
      const V3& c = corner[std::size_t((f + 1) % 4)];
      addBar(b, a + z1, c + z1);                              // strut
      addBar(b, (l % 2 ? a : c) + z0, (l % 2 ? c : a) + z1);  // brace
    }
  }
  // Drill rod down the mast's axis, and its rotary head near the top.
  addSegmentedPrism(b, V3(0, kMastY, 0.3), V3::UnitZ(), kRodRadius, 9.0, kRigSides);
  b.addBoxMinMax(V3(-0.2, kMastY - 0.2, 9.3), V3(0.2, kMastY + 0.2, 9.7));
}

struct Entry {
  ModelKind kind;
  const char* stem;
  const char* label;
  void (*build)(MeshBuilder&);
  osg::Vec4 colour;
};

const Entry& entry(ModelKind m) {
  static const Entry kEntries[] = {
      {ModelKind::SensorPole, "sensor_pole", "pole", buildSensorPole, {0.95f, 0.78f, 0.10f, 1}},
      {ModelKind::WeatherStation, "weather_station", "station", buildWeatherStation, {0.70f, 0.72f, 0.75f, 1}},
      {ModelKind::SolarPanel, "solar_panel", "solar", buildSolarPanel, {0.10f, 0.16f, 0.42f, 1}},
      {ModelKind::LoggerBox, "logger_box", "logger", buildLoggerBox, {0.86f, 0.86f, 0.80f, 1}},
      {ModelKind::Piezometer, "piezometer", "piezometer", buildPiezometer, {0.90f, 0.45f, 0.10f, 1}},
      {ModelKind::Container20ft, "container_20ft", "container", buildContainer, {0.62f, 0.20f, 0.10f, 1}},
      {ModelKind::JerseyBarrier, "jersey_barrier", "barrier", buildJerseyBarrier, {0.76f, 0.75f, 0.71f, 1}},
      {ModelKind::Pickup, "pickup", "vehicle", buildPickup, {0.95f, 0.95f, 0.95f, 1}},
      {ModelKind::DrillRig, "drill_rig", "drill rig", buildDrillRig, {0.93f, 0.60f, 0.12f, 1}},
  };
  return kEntries[static_cast<int>(m)];
}

}  // namespace

const char* modelStem(ModelKind m) { return entry(m).stem; }
const char* modelKindLabel(ModelKind m) { return entry(m).label; }
std::string modelFileName(ModelKind m) { return std::string(entry(m).stem) + ".osgt"; }

osg::ref_ptr<osg::Node> buildModel(ModelKind m) {
  MeshBuilder b;
  entry(m).build(b);
  return b.build(entry(m).stem, entry(m).colour);
}

Aabb<double> modelBounds(ModelKind m) {
  const osg::ref_ptr<osg::Node> node = buildModel(m);
  Aabb<double> box;
  const osg::Geode* geode = node->asGeode();
  for (unsigned i = 0; geode && i < geode->getNumDrawables(); ++i) {
    const osg::Geometry* g = geode->getDrawable(i)->asGeometry();
    const auto* v = g ? dynamic_cast<const osg::Vec3Array*>(g->getVertexArray()) : nullptr;
    if (!v) continue;
    for (const osg::Vec3& p : *v) box.extend(Vec3<double>(p.x(), p.y(), p.z()));
  }
  return box;
}

void writeModel(ModelKind m, const std::string& path) {
  const osg::ref_ptr<osg::Node> node = buildModel(m);
  if (!osgDB::writeNodeFile(*node, path)) throw InputError(path + ": OpenSceneGraph could not write the model");
}

}  // namespace nestwalk::assets
