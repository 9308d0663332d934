#include "nestwalk/scene/scene.h"

#include "nestwalk/core/angles.h"


namespace nestwalk {

Mat3<double> attitudeRotation(double headingDeg, double pitchDeg, double rollDeg) {
  const auto [sh, ch] = sinCosDegrees(-headingDeg);
  const auto [sp, cp] = sinCosDegrees(pitchDeg);
  const auto [sr, cr] = sinCosDegrees(rollDeg);
  Mat3<double> rz, rx, ry;
  rz << ch, -sh, 0, sh, ch, 0, 0, 0, 1;
  rx << 1, 0, 0, 0, cp, -sp, 0, sp, cp;
  ry << cr, 0, sr, 0, 1, 0, -sr, 0, cr;
  return rz * rx * ry;
}

std::vector<Aabb<double>> Scene::unitBoxes() const {
  std::vector<Aabb<double>> out;
  out.reserve(units.size());
  for (const auto& u : units) out.push_back(u.volume.outer);
  return out;
}

std::vector<std::string> Scene::unitGroups() const {
  std::vector<std::string> out;
  out.reserve(units.size());
  for (const auto& u : units) out.push_back(u.group);
  return out;
}

int Scene::findUnit(const std::string& name) const {
  for (std::size_t i = 0; i < units.size(); ++i)
    if (units[i].name == name) return int(i);
  return -1;
}

}  // namespace nestwalk
