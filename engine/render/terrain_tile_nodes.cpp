// The static terrain tiles as OpenSceneGraph nodes (terrain_tile_nodes.h).
#include "nestwalk/render/terrain_tile_nodes.h"

#include <osg/Array>
#include <osg/Geode>
#include <osg/PrimitiveSet>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace nestwalk {

osg::ref_ptr<osg::Geometry> terrainTileGeometry(const terrain::TerrainMesh& mesh, const terrain::TerrainTile& t, int level,
                                                bool colours) {
  const terrain::TerrainGrid& grid = mesh.grid();
  const std::vector<terrain::GridTriangle> tris = mesh.triangles(t, level);
  if (tris.empty()) return nullptr;
  const int s = 1 << level;
  const int nx = t.cellsX / s + 1, ny = t.cellsY / s + 1;
  std::vector<std::int32_t> index(std::size_t(nx) * std::size_t(ny), -1);
  osg::ref_ptr<osg::Vec3Array> vertices = new osg::Vec3Array;
  std::vector<osg::Vec3d> normalSum;
  auto vertexOf = [&](int c, int r) -> unsigned {
    const std::size_t k = std::size_t((r - t.row0) / s) * std::size_t(nx) + std::size_t((c - t.col0) / s);
    if (index[k] < 0) {
      index[k] = std::int32_t(vertices->size());
      vertices->push_back(osg::Vec3(float(c * grid.dx), float(-r * grid.dy), grid.height(c, r)));
      normalSum.emplace_back(0, 0, 0);
    }
    return unsigned(index[k]);
  };
  osg::ref_ptr<osg::DrawElementsUInt> elements = new osg::DrawElementsUInt(GL_TRIANGLES);
  elements->reserve(tris.size() * 3);
  for (const terrain::GridTriangle& g : tris) {
    // The heightfield's vertex order is clockwise seen from above; OpenGL's front faces are
    // counter-clockwise, so the second and third vertices swap.
    const unsigned a = vertexOf(g.col[0], g.row[0]), b = vertexOf(g.col[2], g.row[2]), c = vertexOf(g.col[1], g.row[1]);
    elements->push_back(a);
    elements->push_back(b);
    elements->push_back(c);
    const osg::Vec3d pa((*vertices)[a]), pb((*vertices)[b]), pc((*vertices)[c]);
    const osg::Vec3d n = (pb - pa) ^ (pc - pa);  // area-weighted, pointing up
    normalSum[a] += n;
    normalSum[b] += n;
    normalSum[c] += n;
  }
  osg::ref_ptr<osg::Vec3Array> normals = new osg::Vec3Array;
  normals->reserve(normalSum.size());
  for (osg::Vec3d n : normalSum) {
    if (n.normalize() <= 0) n.set(0, 0, 1);
    normals->push_back(osg::Vec3(n));
  }
  osg::ref_ptr<osg::Geometry> geom = new osg::Geometry;
  geom->setVertexArray(vertices.get());
  geom->setNormalArray(normals.get(), osg::Array::BIND_PER_VERTEX);
  if (colours) {
    const float lo = mesh.heightLow(), hi = mesh.heightHigh();
    const float range = hi > lo ? hi - lo : 1.0f;
    osg::ref_ptr<osg::Vec4Array> colourArray = new osg::Vec4Array;
    colourArray->reserve(vertices->size());
    for (const osg::Vec3& p : *vertices) {
      // Green valleys, brown slopes, white tops.
      const float f = std::clamp((p.z() - lo) / range, 0.0f, 1.0f);
      const osg::Vec4 green(0.25f, 0.45f, 0.2f, 1), brown(0.5f, 0.4f, 0.3f, 1), white(0.95f, 0.95f, 0.95f, 1);
      colourArray->push_back(f < 0.6f ? green * (1 - f / 0.6f) + brown * (f / 0.6f)
                                      : brown * (1 - (f - 0.6f) / 0.4f) + white * ((f - 0.6f) / 0.4f));
    }
    geom->setColorArray(colourArray.get(), osg::Array::BIND_PER_VERTEX);
  }
  geom->addPrimitiveSet(elements.get());
  geom->setUseDisplayList(false);
  geom->setUseVertexBufferObjects(true);
  return geom;
}

osg::ref_ptr<osg::LOD> terrainTileLod(const terrain::TerrainMesh& mesh, const terrain::TerrainTile& t,
                                      const terrain::LodRule& rule, bool colours) {
  osg::ref_ptr<osg::LOD> lod = new osg::LOD;
  lod->setRangeMode(osg::LOD::DISTANCE_FROM_EYE_POINT);
  const Eigen::AlignedBox3f box = mesh.tileBox(t);
  if (!box.isEmpty()) {
    const Eigen::Vector3f centre = box.center();
    lod->setCenterMode(osg::LOD::USER_DEFINED_CENTER);
    lod->setCenter(osg::Vec3(centre.x(), centre.y(), centre.z()));
    lod->setRadius(0.5f * box.diagonal().norm());
  }
  const std::vector<double> d = mesh.switchDistances(t, rule);
  for (int k = 0; k < t.levels; ++k) {
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    if (osg::ref_ptr<osg::Geometry> g = terrainTileGeometry(mesh, t, k, colours)) geode->addDrawable(g.get());
    const float lo = float(d[std::size_t(k)]);
    const float hi = k + 1 < t.levels ? float(d[std::size_t(k) + 1]) : std::numeric_limits<float>::max();
    lod->addChild(geode.get(), lo, hi);
  }
  return lod;
}

}  // namespace nestwalk
