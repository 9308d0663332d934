// The models' nodes rebuilt from the scene's .osgb bytes (model_nodes.h).
#include "nestwalk/render/model_nodes.h"

#include "nestwalk/scene/model_file.h"

#include <stdexcept>

namespace nestwalk {

std::vector<osg::ref_ptr<osg::Node>> buildModelNodes(const Scene& scene) {
  std::vector<osg::ref_ptr<osg::Node>> nodes;
  nodes.reserve(scene.models.size());
  for (const SceneModel& m : scene.models) {
    std::string problem = m.drawing.empty() ? "the scene holds no drawing of it" : "";
    osg::ref_ptr<osg::Node> node = problem.empty() ? nodeFromOsgb(m.drawing, problem) : nullptr;
    if (!node) throw std::runtime_error(m.path + ": the model's node cannot be rebuilt (" + problem + ")");
    nodes.push_back(std::move(node));
  }
  return nodes;
}

}  // namespace nestwalk
