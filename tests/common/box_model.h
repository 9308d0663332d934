// A box model file for tests: an axis-aligned box from `lo` to `hi` (file units), 12 triangles,
// written with osgDB in any format it writes (.osgt, .osgb).
#pragma once

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <osg/Geode>
#include <osg/Geometry>
#include <osgDB/WriteFile>

#include <filesystem>

namespace nestwalk::test {

inline void writeBoxModel(const std::filesystem::path& path, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  for (int k = 0; k < 8; ++k)
    v->push_back(osg::Vec3((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z()));
  osg::ref_ptr<osg::DrawElementsUShort> tris = new osg::DrawElementsUShort(GL_TRIANGLES);
  const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& q : quads)
    for (int k : {q[0], q[1], q[2], q[0], q[2], q[3]}) tris->push_back((unsigned short)k);
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setVertexArray(v);
  g->addPrimitiveSet(tris);
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(g);
  ASSERT_TRUE(osgDB::writeNodeFile(*geode, path.string()));
}

}  // namespace nestwalk::test
