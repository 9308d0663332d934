// The model catalog: equipment types, each a model file and how to read it. A user's models come
// in any units, either up axis, with their origin anywhere (the shared dump truck is about 30
// units long with its origin mid-body; the excavator chassis' origin is its slewing joint); a
// type says how to bring its file into the engine's model frame: metres, z up, +y forward, origin
// at the base (the centre of the bottom of the model's bounding box).
//
// File format (JSON; the same object is a scene file's "types", scene_file.h):
//   {"types": {
//      "tank":    {"model": "models/tank.flt", "units": "m", "up": "z", "origin": "base", "kind": "vehicle"},
//      "gauge":   {"model": "gauge.stl", "units": "mm", "kind": "station", "scale": 1},
//      "barrier": {"model": "barrier.osgt", "kind": "barrier", "piece_length": 3.0, "max_gap": 0.3}}}
// Relative model paths are relative to the catalog's (or scene's) folder. Fields:
//   model        the model file, any format OpenSceneGraph reads, or glTF 2.0 (.gltf, .glb)
//                (required)
//   units        "mm", "cm", "m", "in", "ft", or a positive number of metres per file unit ("m")
//   up           the file's up axis: "z", "y", "-y" or "-z" ("z"; "y" for glTF); a y-up file is
//                turned +90 degrees about x (its -z becomes forward, +y), a -y-up file -90 degrees
//                (its +z becomes forward), a -z-up file 180 degrees (upside down: its -y becomes
//                forward)
//   forward      the model's forward axis once z is up: "+y", "-y", "+x" or "-x" ("+y"; "-y" for
//                glTF, whose specification puts an asset's front towards +z, which is -y once +y
//                is turned up); headings turn the forward axis (heading 0 points it north)
//   origin       where the model's reference point is: "base" (the bottom centre of its bounding
//                box: it stands on the ground), "centre" (the box's centre) or "file" (the file's
//                own origin) ("base")
//   kind         a free label (colours, reports)  ("")
//   use_only     part of its group's volume, never tested alone (false)
//   scale        the instances' default scale (uniform, after the units) (1)
//   piece_length for line features (fences, barrier rows): the length of one piece along the
//                line, metres (default: the model's extent along its forward axis, scaled)
//   max_gap      line features: the longest stretch of line a joint may leave uncovered, metres
//                (default: a tenth of the piece length; keep it below the walker's body width,
//                so that a fence stays closed)
//   max_overlap  line features: the longest stretch of line two pieces may both cover, metres
//                (default: half the piece length)
// Unknown keys are errors; every error names the file and the field ("catalog.json:
// types.gauge.units: expected mm, cm, m, in, ft or a number > 0, got 'furlong'").
// Thread safety: pure functions (readModelCatalog reads the file and checks that the models exist;
// nothing is kept).
#pragma once

#include "nestwalk/geometry/volumes.h"

#include <nlohmann/json.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace nestwalk {

enum class ModelUp : std::uint8_t { Z, Y, MinusY, MinusZ };
enum class ModelForward : std::uint8_t { PlusY, MinusY, PlusX, MinusX };
enum class ModelOrigin : std::uint8_t { Base, Centre, File };

struct ModelType {
  std::string name;
  std::string model;              // resolved path
  double metresPerUnit = 1.0;     // "units"
  std::string unitsText = "m";    // as written (for reports)
  ModelUp up = ModelUp::Z;
  ModelForward forward = ModelForward::PlusY;
  ModelOrigin origin = ModelOrigin::Base;
  std::string kind;
  bool useOnly = false;
  double scale = 1.0;
  std::optional<double> pieceLength;  // metres; nullopt: the model's forward extent
  std::optional<double> maxGap, maxOverlap;  // metres; nullopt: the defaults above
};

struct ModelCatalog {
  std::string path;                       // the file (or the scene file) it was read from
  std::map<std::string, ModelType> types;  // by name
};

/// Reads a catalog file; throws InputError naming the file and field. Model files must exist (all
/// missing ones are listed together).
ModelCatalog readModelCatalog(const std::string& path);
/// The same from the file's text (`path` names it in messages and anchors relative model paths).
ModelCatalog parseModelCatalog(const std::string& text, const std::string& path);

/// The types of an already parsed "types" object (`field` is its path for messages, e.g. "types");
/// relative model paths resolve against `folder`. Does not check that the files exist.
std::map<std::string, ModelType> parseModelTypes(const nlohmann::json& types, const std::string& file,
                                                 const std::string& folder, const std::string& field);

/// The JSON of one type as parseModelTypes reads it, with the model path written as `modelPath`
/// (build-scene writes the types it used into the scene file, paths relative to the scene).
nlohmann::json modelTypeJson(const ModelType& type, const std::string& modelPath);

/// The rotation part of a type: file axes to the engine's model frame (up, then forward), exact
/// (entries 0 and +-1).
Mat3<double> modelTypeRotation(const ModelType& type);

/// The similarity from the model file's frame to the engine's model frame (metres, z up, +y
/// forward, the origin as the type says): the units, the rotation above, then the
/// translation that puts the origin where asked, computed from `filePoints` (the model's points
/// in its file frame; its convex hull's vertices suffice).
Similarity<double> modelTypeTransform(const ModelType& type, const std::vector<Vec3<double>>& filePoints);

/// The length of one piece of a line of this type (metres): piece_length, or the extent of
/// `filePoints` along the forward axis after modelTypeTransform, times the type's scale.
double pieceLength(const ModelType& type, const std::vector<Vec3<double>>& filePoints);
/// max_gap and max_overlap with their defaults (a tenth and half of `piece`).
double maxGap(const ModelType& type, double piece);
double maxOverlap(const ModelType& type, double piece);

}  // namespace nestwalk
