// The equipment models as OpenSceneGraph nodes, the drawing side's table keyed by the scene's model
// index: node k is rebuilt from Scene::models[k].drawing (the .osgb bytes the guarded read handed
// back at load), so a model file is read once per load and drawn as it was measured, even if the
// file has changed on disk since.
//
// Cost: one parse of OSG's native binary form per model and table (milliseconds for the bundled
// models; ~3 ms for a 23k-triangle truck, model_file.h).
// Ownership: the nodes are new graphs owned by the table's holder (ref_ptr), shared with no other
// table: two tables built from one Scene may be drawn from different threads.
// Thread safety: building reads only the Scene; the nodes then belong to one drawing thread.
#pragma once

#include "nestwalk/scene/scene.h"

#include <osg/Node>
#include <osg/ref_ptr>

#include <vector>

namespace nestwalk {

/// Node k: model k's scene graph. Throws std::runtime_error naming the model when its bytes do not
/// parse (they parsed at load: only memory corruption gets here) or it has none (a Scene assembled
/// by hand rather than loaded).
std::vector<osg::ref_ptr<osg::Node>> buildModelNodes(const Scene& scene);

}  // namespace nestwalk
