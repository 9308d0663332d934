// The bundled equipment models, built procedurally (no model files are committed): triangles with
// flat normals and one colour per kind (osg::Material), written in OpenSceneGraph's native text
// format (.osgt) by `nestwalk make-scene`.
//
// Model frame: metres, z up, +y forward, +x right; the foot or base stands on z = 0, centred on
// x = y = 0 (the pole's, the mast's axis at the origin). A scene's heading turns +y to the heading.
// Cylinders are prisms with 12 or 16 sides whose vertices lie on the circle, with a vertex on the
// +x, +y, -x and -y axes, so a prism's x and y extents are exactly its diameter.
//
// Sizes (x width, y depth, z height of the whole model's box, metres):
//   sensor_pole     0.14 x 0.18 x 3.00   pole 0.05 diameter, 3 m, a sensor head under its top
//   weather_station 1.09 x 0.50 x 3.00   mast 0.06 diameter, cross-arm 1 m at 2.8 m, anemometer (+x
//                                        end), vane (-x end), logger box and a 35-degree panel on +y
//   solar_panel     1.60 x 0.89 x 1.03   panel 1.6 x 1.0 x 0.04 tilted 30 degrees facing +y (its low
//                                        edge 0.5 m up), four legs, two rails
//   logger_box      0.56 x 0.40 x 1.53   cabinet 0.5 x 0.3 x 0.6 on a post, base plate, roof
//   piezometer      0.60 x 0.60 x 0.98   concrete pad 0.6 x 0.6 x 0.1, steel casing 0.15 diameter x
//                                        0.8 m, cap 0.18 diameter
//   container_20ft  2.44 x 6.06 x 2.59   ISO 20 ft box (length along y), bottom rails
//   jersey_barrier  0.60 x 3.00 x 0.80   concrete safety-shape profile extruded 3 m along y
//   pickup          1.90 x 5.30 x 1.80   body, hood, cab, bed, four wheels (0.76 m) touching z = 0
//   drill_rig       2.31 x 5.00 x 10.22  crawler blast-hole rig, its lattice mast up at the front
//                                        (+y), round parts tessellated finely: 40,020 triangles
// Every model but the drill rig has a few hundred triangles at most; the rig is the heavy one, so
// that the report measures the exact stage where it costs (issue 27).
#pragma once

#include "nestwalk/geometry/volumes.h"

#include <osg/Node>
#include <osg/ref_ptr>

#include <array>
#include <cstdint>
#include <string>

namespace nestwalk::assets {

enum class ModelKind : std::uint8_t {
  SensorPole, WeatherStation, SolarPanel, LoggerBox, Piezometer, Container20ft, JerseyBarrier, Pickup, DrillRig,
};

inline constexpr std::array<ModelKind, 9> kAllModels = {
    ModelKind::SensorPole, ModelKind::WeatherStation, ModelKind::SolarPanel,    ModelKind::LoggerBox,
    ModelKind::Piezometer, ModelKind::Container20ft,  ModelKind::JerseyBarrier, ModelKind::Pickup,
    ModelKind::DrillRig,
};

/// The file stem ("sensor_pole"; the file is stem + ".osgt") and the scene's kind label ("pole").
const char* modelStem(ModelKind m);
const char* modelKindLabel(ModelKind m);
std::string modelFileName(ModelKind m);  // "sensor_pole.osgt"

/// The model as a scene graph: one Geode named after the stem, one Geometry, one Material.
osg::ref_ptr<osg::Node> buildModel(ModelKind m);

/// The model's axis-aligned box in its own frame, from its vertices (as stored: float).
Aabb<double> modelBounds(ModelKind m);

/// Writes the model to `path` (its extension picks the format; .osgt for the scene) with osgDB.
/// Throws InputError naming the path when no writer takes it or writing fails.
void writeModel(ModelKind m, const std::string& path);

}  // namespace nestwalk::assets
