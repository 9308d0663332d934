// A chunk's OSG nodes (engine/render/chunk_node.h): each draws exactly the index ranges it is given,
// in order, over the chunk's own positions and colours, which all the nodes of one maker share;
// every vertex finds its own colour in the chunk's texture; 16-bit indices while the chunk has at
// most 65535 vertices, 32-bit beyond.
#include "nestwalk/render/chunk_node.h"

#include "hills_terrain.h"

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/PrimitiveSet>
#include <osg/Texture2D>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace nestwalk {
namespace {

const osg::Geometry& geometryOf(const osg::MatrixTransform& node) {
  const osg::Geode* geode = node.getChild(0)->asGeode();
  return *geode->getDrawable(0)->asGeometry();
}

std::vector<std::uint32_t> indicesOf(const osg::Geometry& g) {
  const auto* e = dynamic_cast<const osg::DrawElements*>(g.getPrimitiveSet(0));
  std::vector<std::uint32_t> v;
  for (unsigned i = 0; i < e->getNumIndices(); ++i) v.push_back(e->index(i));
  return v;
}

TEST(ChunkNode, DrawsItsRangesInOrderOverSharedArrays) {
  const auto hf = test::hills();
  const terrain::ChunkLayout layout(hf->cols(), hf->rows(), 16);
  const terrain::ChunkMesh m = terrain::buildChunk(*hf, layout, {1, 2, 3});
  const terrain::ChunkQuadrant &a = m.quadrants[0], &b = m.quadrants[3];
  const ChunkNodeMaker maker(m);
  const osg::ref_ptr<osg::MatrixTransform> both = maker({{b.firstIndex, b.indexCount}, {a.firstIndex, a.indexCount}}, " both");
  const osg::ref_ptr<osg::MatrixTransform> one = maker({{a.firstIndex, a.indexCount}}, " one");
  std::vector<std::uint32_t> expected(m.indices.begin() + std::ptrdiff_t(b.firstIndex),
                                      m.indices.begin() + std::ptrdiff_t(b.firstIndex + b.indexCount));
  expected.insert(expected.end(), m.indices.begin() + std::ptrdiff_t(a.firstIndex),
                  m.indices.begin() + std::ptrdiff_t(a.firstIndex + a.indexCount));
  EXPECT_EQ(indicesOf(geometryOf(*both)), expected);
  EXPECT_EQ(geometryOf(*both).getPrimitiveSet(0)->getType(), osg::PrimitiveSet::DrawElementsUShortPrimitiveType);
  EXPECT_EQ(both->getName(), "chunk 1/2/3 both");
  // Shared arrays holding the mesh's values; the offset as the transform.
  EXPECT_EQ(geometryOf(*both).getVertexArray(), geometryOf(*one).getVertexArray());
  EXPECT_EQ(geometryOf(*both).getColorArray(), geometryOf(*one).getColorArray());
  EXPECT_EQ(geometryOf(*both).getTexCoordArray(0), geometryOf(*one).getTexCoordArray(0));
  EXPECT_EQ(both->getChild(0)->getStateSet(), one->getChild(0)->getStateSet());
  const auto* positions = dynamic_cast<const osg::Vec3Array*>(geometryOf(*one).getVertexArray());
  ASSERT_EQ(positions->size(), m.vertexCount());
  for (std::size_t v = 0; v < m.vertexCount(); v += 97)
    for (int k = 0; k < 3; ++k) EXPECT_EQ((*positions)[unsigned(v)][k], m.positions[3 * v + std::size_t(k)]);
  const osg::Vec3d t = both->getMatrix().getTrans();
  EXPECT_EQ(t, osg::Vec3d(m.offset.x(), m.offset.y(), m.offset.z()));
}

TEST(ChunkNode, EveryVertexLooksUpItsOwnColourInTheTexture) {
  // With holes, so that filled texels sit next to real ones.
  const auto hf = test::hills(0.05);
  const terrain::ChunkLayout layout(hf->cols(), hf->rows(), 16);
  for (const terrain::ChunkKey k : {terrain::ChunkKey{0, 5, 7}, terrain::ChunkKey{2, 1, 0}}) {
    const terrain::ChunkMesh m = terrain::buildChunk(*hf, layout, k);
    const terrain::ChunkQuadrant& q = m.quadrants[1];
    const osg::ref_ptr<osg::MatrixTransform> node = ChunkNodeMaker(m)({{q.firstIndex, q.indexCount}}, "");
    const osg::Geometry& g = geometryOf(*node);
    const auto* uv = dynamic_cast<const osg::Vec2Array*>(g.getTexCoordArray(0));
    ASSERT_NE(uv, nullptr);
    ASSERT_EQ(uv->size(), m.vertexCount());
    const osg::StateSet* state = node->getChild(0)->getStateSet();
    ASSERT_NE(state, nullptr);
    const auto* texture = dynamic_cast<const osg::Texture2D*>(state->getTextureAttribute(0, osg::StateAttribute::TEXTURE));
    ASSERT_NE(texture, nullptr);
    const osg::Image* image = texture->getImage();
    ASSERT_EQ(image->s(), m.textureWidth);
    ASSERT_EQ(image->t(), m.textureHeight);
    // The vertex colour (white over the texture) and the texel at the vertex's coordinates.
    const auto* colour = dynamic_cast<const osg::Vec4ubArray*>(g.getColorArray());
    ASSERT_EQ(colour->size(), 1u);
    EXPECT_EQ((*colour)[0], osg::Vec4ub(255, 255, 255, 255));
    std::size_t distinct = 0;
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
      const double s = (*uv)[unsigned(v)].x() * image->s(), t = (*uv)[unsigned(v)].y() * image->t();
      // At a texel centre: linear filtering returns that texel.
      EXPECT_NEAR(s - std::floor(s), 0.5, 1e-4);
      EXPECT_NEAR(t - std::floor(t), 0.5, 1e-4);
      const unsigned char* texel = image->data(unsigned(s), unsigned(t));
      for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(texel[c], m.colours[4 * v + c]) << "vertex " << v;
      distinct += v > 0 && m.colours[4 * v] != m.colours[0];
    }
    EXPECT_GT(distinct, m.vertexCount() / 4);  // shaded, not one colour
  }
}

TEST(ChunkNode, CountsTheBytesItsNodesHoldSharedArraysOnce) {
  // What the paged terrain's budget counts (paged_terrain.h, "Memory"): the arrays found in the
  // nodes, the shared ones once, against the maker's count as the nodes are made.
  const auto hf = test::hills();
  const terrain::ChunkLayout layout(hf->cols(), hf->rows(), 16);
  const terrain::ChunkMesh m = terrain::buildChunk(*hf, layout, {1, 2, 3});
  const ChunkNodeMaker maker(m);
  const osg::ref_ptr<osg::MatrixTransform> first = maker({{m.quadrants[0].firstIndex, m.quadrants[0].indexCount}}, "");
  const osg::Geometry& g = geometryOf(*first);
  const auto* texture = dynamic_cast<const osg::Texture2D*>(
      first->getChild(0)->getStateSet()->getTextureAttribute(0, osg::StateAttribute::TEXTURE));
  ASSERT_NE(texture, nullptr);
  const std::size_t shared = g.getVertexArray()->getNumElements() * sizeof(osg::Vec3f) +
                             g.getTexCoordArray(0)->getNumElements() * sizeof(osg::Vec2f) +
                             g.getColorArray()->getNumElements() * sizeof(osg::Vec4ub) +
                             std::size_t(texture->getImage()->s()) * std::size_t(texture->getImage()->t()) * 4;
  const std::size_t firstIndices = m.quadrants[0].indexCount * sizeof(std::uint16_t);
  EXPECT_EQ(maker.bytes(), shared + firstIndices);
  const osg::ref_ptr<osg::MatrixTransform> second =
      maker({{m.quadrants[1].firstIndex, m.quadrants[1].indexCount}, {m.quadrants[2].firstIndex, m.quadrants[2].indexCount}}, "");
  EXPECT_EQ(maker.bytes(), shared + firstIndices +
                               (m.quadrants[1].indexCount + m.quadrants[2].indexCount) * sizeof(std::uint16_t));
  EXPECT_EQ(geometryOf(*second).getVertexArray(), g.getVertexArray());  // counted once, as it is held once
}

TEST(ChunkNode, ChunksOfMoreThan65535VerticesGet32BitIndices) {
  const auto hf = test::hills();
  const terrain::ChunkLayout layout(hf->cols(), hf->rows(), 256);  // 257 x 257 samples and skirts
  const terrain::ChunkMesh m = terrain::buildChunk(*hf, layout, {0, 0, 0});
  ASSERT_GT(m.vertexCount(), 0xFFFFu);
  const terrain::ChunkQuadrant& q = m.quadrants[3];
  const osg::ref_ptr<osg::MatrixTransform> node = ChunkNodeMaker(m)({{q.firstIndex, q.indexCount}}, "");
  EXPECT_EQ(geometryOf(*node).getPrimitiveSet(0)->getType(), osg::PrimitiveSet::DrawElementsUIntPrimitiveType);
  EXPECT_EQ(indicesOf(geometryOf(*node)),
            std::vector<std::uint32_t>(m.indices.begin() + std::ptrdiff_t(q.firstIndex),
                                       m.indices.begin() + std::ptrdiff_t(q.firstIndex + q.indexCount)));
}

}  // namespace
}  // namespace nestwalk
