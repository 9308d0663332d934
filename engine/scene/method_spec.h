// How a scene's walker tests contact: the contact method after the broad phase, the hierarchy and
// the OBB fitter ("method" in the scene file, scene_file.h; `run --method` and the report override
// it). Names as the scene file and the command line spell them.
// Thread safety: plain values and pure functions.
#pragma once

#include "nestwalk/geometry/obb_fitter.h"
#include "nestwalk/hierarchy/tree_options.h"

#include <cstdint>
#include <string>

namespace nestwalk {

// The walker's contact test against each unit (after the broad phase over the outer AABBs):
//   Nested     outer AABB, then AABB-OBB, then OBB-OBB (Ma et al.; the default)
//   Aabb       outer AABB only;  Obb  inner OBB only
//   NestedMesh the nested test, then the body box against the model's real triangles through a
//              k-DOP-18 tree (geometry/mesh_tree.h): blocks only on real contact (exact reference)
//   Kdop18     the body box against the real triangles through the same tree, right after the
//              broad phase (exact, no nested stage)
//   Auto       chosen per collision unit at load time from its own geometry (walker/contact_choice.h):
//              Nested where the inner OBB is tight around the unit's triangles, NestedMesh where it
//              is not (the mining-dump paper's future work: the test chosen by the kind of object),
//              unless the exact stage's sampled cost on the unit is too high
//              (walker/exact_stage_cost.h): then Nested
// The mesh methods test a unit without any triangle (points or lines only) by its nested volumes.
enum class VolumeMethod : std::uint8_t { Nested, Aabb, Obb, NestedMesh, Kdop18, Auto };
inline bool usesMeshes(VolumeMethod m) {
  return m == VolumeMethod::NestedMesh || m == VolumeMethod::Kdop18 || m == VolumeMethod::Auto;
}

struct MethodSpec {
  VolumeMethod volumes = VolumeMethod::Nested;
  bool templateHierarchy = false;  // "hierarchy": "template"
  AutoTreeOptions autoTree;        // used when !templateHierarchy
  ObbFitter fitter = ObbFitter::HullSearch;
};

const char* volumeMethodName(VolumeMethod m);  // "nested", "aabb", "obb", "nested+mesh", "kdop18", "auto"
// The method named so (the names above); false for an unknown name.
bool parseVolumeMethod(const std::string& name, VolumeMethod& out);
std::string describe(const MethodSpec& m);     // e.g. "nested, auto delta=4 longest/median, hull-search"

}  // namespace nestwalk
