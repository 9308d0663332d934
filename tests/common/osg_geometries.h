// Every osg::Geometry under a node, in traversal order (tests that look at what a reader or writer
// built: arrays, bindings, state sets).
#pragma once

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/NodeVisitor>

#include <vector>

namespace nestwalk::test {

inline std::vector<const osg::Geometry*> geometriesUnder(osg::Node& node) {
  struct Collect : osg::NodeVisitor {
    Collect() : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN) {}
    void apply(osg::Geode& g) override {
      for (unsigned i = 0; i < g.getNumDrawables(); ++i)
        if (const osg::Geometry* geo = g.getDrawable(i)->asGeometry()) found.push_back(geo);
    }
    std::vector<const osg::Geometry*> found;
  } c;
  node.accept(c);
  return c.found;
}

}  // namespace nestwalk::test
