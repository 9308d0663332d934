// The OSG nodes of a terrain chunk (chunk_node.h).
#include "nestwalk/render/chunk_node.h"

#include <osg/Geode>
#include <osg/Geometry>

#include <algorithm>

namespace nestwalk {

ChunkNodeMaker::ChunkNodeMaker(const terrain::ChunkMesh& mesh)
    : mesh_(mesh),
      positions_(new osg::Vec3Array(unsigned(mesh.vertexCount()))),
      colours_(new osg::Vec4ubArray(unsigned(mesh.vertexCount()))) {
  if (mesh.vertexCount() == 0) return;
  std::copy(mesh.positions.begin(), mesh.positions.end(), &(*positions_)[0][0]);
  std::copy(mesh.colours.begin(), mesh.colours.end(), &(*colours_)[0][0]);
  colours_->setNormalize(true);
}

osg::ref_ptr<osg::MatrixTransform> ChunkNodeMaker::operator()(const std::vector<IndexRange>& ranges,
                                                              const std::string& suffix) const {
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setUseDisplayList(false);
  g->setUseVertexBufferObjects(true);
  g->setVertexArray(positions_.get());
  g->setColorArray(colours_.get(), osg::Array::BIND_PER_VERTEX);
  std::size_t count = 0;
  for (const IndexRange& r : ranges) count += r.count;
  auto fill = [&](auto* elements) {
    auto out = elements->begin();
    for (const IndexRange& r : ranges) {
      const auto first = mesh_.indices.begin() + std::ptrdiff_t(r.first);
      out = std::copy(first, first + std::ptrdiff_t(r.count), out);
    }
    g->addPrimitiveSet(elements);
  };
  if (mesh_.vertexCount() <= 0xFFFF)
    fill(new osg::DrawElementsUShort(GL_TRIANGLES, unsigned(count)));
  else
    fill(new osg::DrawElementsUInt(GL_TRIANGLES, unsigned(count)));
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(g.get());
  osg::ref_ptr<osg::MatrixTransform> t =
      new osg::MatrixTransform(osg::Matrixd::translate(mesh_.offset.x(), mesh_.offset.y(), mesh_.offset.z()));
  t->setName("chunk " + std::to_string(mesh_.key.level) + "/" + std::to_string(mesh_.key.x) + "/" +
             std::to_string(mesh_.key.y) + suffix);
  t->addChild(geode.get());
  return t;
}

}  // namespace nestwalk
