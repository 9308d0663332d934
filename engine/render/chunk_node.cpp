// The OSG nodes of a terrain chunk (chunk_node.h).
#include "nestwalk/render/chunk_node.h"

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Image>
#include <osg/Texture2D>

#include <algorithm>

namespace nestwalk {

ChunkNodeMaker::ChunkNodeMaker(const terrain::ChunkMesh& mesh)
    : mesh_(mesh), positions_(new osg::Vec3Array(unsigned(mesh.vertexCount()))) {
  if (mesh.vertexCount() == 0) return;
  std::copy(mesh.positions.begin(), mesh.positions.end(), &(*positions_)[0][0]);
  sharedBytes_ = positions_->getTotalDataSize();
  const bool textured = !mesh.texture.empty() && mesh.texCoords.size() == 2 * mesh.vertexCount();
  if (!textured) {
    colours_ = new osg::Vec4ubArray(unsigned(mesh.vertexCount()));
    std::copy(mesh.colours.begin(), mesh.colours.end(), &(*colours_)[0][0]);
    colours_->setNormalize(true);
    sharedBytes_ += colours_->getTotalDataSize();
    return;
  }
  perVertexColours_ = false;
  colours_ = new osg::Vec4ubArray(1);
  (*colours_)[0] = osg::Vec4ub(255, 255, 255, 255);
  colours_->setNormalize(true);
  texCoords_ = new osg::Vec2Array(unsigned(mesh.vertexCount()));
  std::copy(mesh.texCoords.begin(), mesh.texCoords.end(), &(*texCoords_)[0][0]);
  osg::ref_ptr<osg::Image> image = new osg::Image;
  image->allocateImage(mesh.textureWidth, mesh.textureHeight, 1, GL_RGBA, GL_UNSIGNED_BYTE);
  std::copy(mesh.texture.begin(), mesh.texture.end(), image->data());
  osg::ref_ptr<osg::Texture2D> texture = new osg::Texture2D(image.get());
  texture->setResizeNonPowerOfTwoHint(false);  // one texel per sample, whatever the chunk's size
  texture->setWrap(osg::Texture::WRAP_S, osg::Texture::CLAMP_TO_EDGE);
  texture->setWrap(osg::Texture::WRAP_T, osg::Texture::CLAMP_TO_EDGE);
  texture->setFilter(osg::Texture::MAG_FILTER, osg::Texture::LINEAR);
  // No mipmaps: on llvmpipe they cost 14 ms a frame (bench_patrol, 1280 x 720: 45-49 ms p50
  // against 31-33 with vertex colours and 33-35 with linear filtering alone). A chunk's level keeps
  // its cells near a pixel or more wherever the terrain is rough, so its texels seldom shrink below
  // one.
  texture->setFilter(osg::Texture::MIN_FILTER, osg::Texture::LINEAR);
  sharedBytes_ += colours_->getTotalDataSize() + texCoords_->getTotalDataSize() + image->getTotalSizeInBytes();
  textureState_ = new osg::StateSet;
  textureState_->setTextureAttributeAndModes(0, texture.get(), osg::StateAttribute::ON);
}

ChunkNodeMaker::ChunkNodeMaker(const terrain::ChunkMesh& mesh, double spanX, double spanY) : ChunkNodeMaker(mesh) {
  if (mesh.vertexCount() == 0 || !perVertexColours_) return;  // a mesh with its own texture keeps it
  texCoords_ = new osg::Vec2Array(unsigned(mesh.vertexCount()));
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
    (*texCoords_)[unsigned(v)].set(float(double(mesh.positions[3 * v]) / spanX), float(-double(mesh.positions[3 * v + 1]) / spanY));
  sharedBytes_ += texCoords_->getTotalDataSize();
}

osg::ref_ptr<osg::MatrixTransform> ChunkNodeMaker::operator()(const std::vector<IndexRange>& ranges,
                                                              const std::string& suffix) const {
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setUseDisplayList(false);
  g->setUseVertexBufferObjects(true);
  g->setVertexArray(positions_.get());
  g->setColorArray(colours_.get(), perVertexColours_ ? osg::Array::BIND_PER_VERTEX : osg::Array::BIND_OVERALL);
  if (texCoords_) g->setTexCoordArray(0, texCoords_.get());
  std::size_t count = 0;
  for (const IndexRange& r : ranges) count += r.count;
  auto fill = [&](auto* elements) {
    auto out = elements->begin();
    for (const IndexRange& r : ranges) {
      const auto first = mesh_.indices.begin() + std::ptrdiff_t(r.first);
      out = std::copy(first, first + std::ptrdiff_t(r.count), out);
    }
    g->addPrimitiveSet(elements);
    indexBytes_ += elements->getTotalDataSize();
  };
  if (mesh_.vertexCount() <= 0xFFFF)
    fill(new osg::DrawElementsUShort(GL_TRIANGLES, unsigned(count)));
  else
    fill(new osg::DrawElementsUInt(GL_TRIANGLES, unsigned(count)));
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(g.get());
  if (textureState_) geode->setStateSet(textureState_.get());
  osg::ref_ptr<osg::MatrixTransform> t =
      new osg::MatrixTransform(osg::Matrixd::translate(mesh_.offset.x(), mesh_.offset.y(), mesh_.offset.z()));
  t->setName("chunk " + std::to_string(mesh_.key.level) + "/" + std::to_string(mesh_.key.x) + "/" +
             std::to_string(mesh_.key.y) + suffix);
  t->addChild(geode.get());
  return t;
}

}  // namespace nestwalk
