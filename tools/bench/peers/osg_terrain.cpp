// OpenSceneGraph as a peer of the terrain benchmark (terrain_peers.h): the grid's triangles as one
// osg::Geometry (float vertices, GL_TRIANGLES) in a Geode, with the KdTree osg::KdTreeBuilder
// attaches; each ray becomes an osgUtil::LineSegmentIntersector (double end points, nearest hit
// only) run by an IntersectionVisitor, as an OSG application picks.
#include "tools/bench/peers/terrain_peers.h"

#include "tools/bench/bench_runner.h"

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/KdTree>
#include <osgUtil/IntersectionVisitor>
#include <osgUtil/LineSegmentIntersector>

#include <limits>

namespace nestwalk::bench {

RayPeer osgTerrain(const HeightGrid& grid) {
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  for (std::size_t i = 0; i < grid.heights.size(); ++i) {
    const Eigen::Vector3f p = grid.vertex(i);
    v->push_back(osg::Vec3(p.x(), p.y(), p.z()));
  }
  const std::vector<unsigned> t = grid.triangles();
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setVertexArray(v.get());
  g->addPrimitiveSet(new osg::DrawElementsUInt(GL_TRIANGLES, unsigned(t.size()), t.data()));
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(g.get());
  osg::ref_ptr<osg::KdTreeBuilder> builder = new osg::KdTreeBuilder;
  geode->accept(*builder);
  return [geode](const Rays& rays, std::size_t n, double* z) {
    osg::Geode& node = *geode;
    return answerAll(n, z, [&](std::size_t k) {
      const Eigen::Vector3d& o = rays.origin[k];
      const Eigen::Vector3d e = rays.end(k);
      osg::ref_ptr<osgUtil::LineSegmentIntersector> lsi =
          new osgUtil::LineSegmentIntersector(osg::Vec3d(o.x(), o.y(), o.z()), osg::Vec3d(e.x(), e.y(), e.z()));
      lsi->setIntersectionLimit(osgUtil::Intersector::LIMIT_NEAREST);
      osgUtil::IntersectionVisitor iv(lsi.get());
      node.accept(iv);
      if (!lsi->containsIntersections()) return std::numeric_limits<double>::quiet_NaN();
      return lsi->getFirstIntersection().getWorldIntersectPoint().z();
    });
  };
}

}  // namespace nestwalk::bench
