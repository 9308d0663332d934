#include "nestwalk/scene/method_spec.h"

namespace nestwalk {

const char* volumeMethodName(VolumeMethod m) {
  switch (m) {
    case VolumeMethod::Nested: return "nested";
    case VolumeMethod::Aabb: return "aabb";
    case VolumeMethod::Obb: return "obb";
    case VolumeMethod::NestedMesh: return "nested+mesh";
    case VolumeMethod::Kdop18: return "kdop18";
    case VolumeMethod::Auto: return "auto";
  }
  return "?";
}

bool parseVolumeMethod(const std::string& name, VolumeMethod& out) {
  for (VolumeMethod m : {VolumeMethod::Nested, VolumeMethod::Aabb, VolumeMethod::Obb, VolumeMethod::NestedMesh,
                         VolumeMethod::Kdop18, VolumeMethod::Auto})
    if (name == volumeMethodName(m)) {
      out = m;
      return true;
    }
  return false;
}

std::string describe(const MethodSpec& m) {
  std::string s = std::string(volumeMethodName(m.volumes)) + ", ";
  if (m.templateHierarchy) {
    s += "template";
  } else {
    s += "auto delta=" + std::to_string(m.autoTree.degree) + " " + splitAxisName(m.autoTree.axis) + "/" +
         splitPointName(m.autoTree.point);
  }
  return s + ", " + fitterName(m.fitter);
}

}  // namespace nestwalk
