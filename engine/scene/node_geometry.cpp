// The geometry under an OpenSceneGraph node (node_geometry.h).
#include "nestwalk/scene/node_geometry.h"

#include "nestwalk/core/input_error.h"

#include <osg/Geometry>
#include <osg/NodeVisitor>
#include <osg/TriangleIndexFunctor>

#include <unordered_map>

namespace nestwalk {
namespace {

// Collects the triangles of one primitive set stream, in the geometry's own vertex indices.
struct TriangleCollector {
  std::vector<std::array<std::uint32_t, 3>>* out = nullptr;
  void operator()(unsigned i, unsigned j, unsigned k) {
    if (i != j && j != k && i != k) out->push_back({i, j, k});
  }
};

class GeometryCollector : public osg::NodeVisitor {
 public:
  explicit GeometryCollector(TriangleMesh& out)
      : osg::NodeVisitor(osg::NodeVisitor::TRAVERSE_ALL_CHILDREN), out_(out) {}

  void apply(osg::Drawable& drawable) override {
    const osg::Geometry* geometry = drawable.asGeometry();
    if (!geometry || !geometry->getVertexArray()) return;
    const osg::Matrixd toModel = osg::computeLocalToWorld(getNodePath());
    collect(*geometry, toModel);
  }

 private:
  static bool readVertex(const osg::Array& array, unsigned i, osg::Vec3d& v) {
    if (i >= array.getNumElements()) return false;
    switch (array.getType()) {
      case osg::Array::Vec3ArrayType: v = static_cast<const osg::Vec3Array&>(array)[i]; return true;
      case osg::Array::Vec3dArrayType: v = static_cast<const osg::Vec3dArray&>(array)[i]; return true;
      case osg::Array::Vec2ArrayType: {
        const osg::Vec2 p = static_cast<const osg::Vec2Array&>(array)[i];
        v.set(p.x(), p.y(), 0.0);
        return true;
      }
      case osg::Array::Vec4ArrayType: {
        const osg::Vec4 p = static_cast<const osg::Vec4Array&>(array)[i];
        if (p.w() == 0.0f) return false;
        v.set(p.x() / p.w(), p.y() / p.w(), p.z() / p.w());
        return true;
      }
      default: return false;
    }
  }

  void collect(const osg::Geometry& geometry, const osg::Matrixd& toModel) {
    const osg::Array& array = *geometry.getVertexArray();
    // Only vertices some primitive refers to belong to the model; they are added once each.
    std::unordered_map<unsigned, std::uint32_t> remap;
    auto modelIndex = [&](unsigned i, std::uint32_t& out) {
      auto it = remap.find(i);
      if (it != remap.end()) {
        out = it->second;
        return true;
      }
      osg::Vec3d v;
      if (!readVertex(array, i, v)) return false;
      const osg::Vec3d p = v * toModel;
      out = std::uint32_t(out_.vertices.size());
      out_.vertices.emplace_back(p.x(), p.y(), p.z());
      remap.emplace(i, out);
      return true;
    };

    osg::TriangleIndexFunctor<TriangleCollector> triangles;
    std::vector<std::array<std::uint32_t, 3>> local;
    triangles.out = &local;
    for (unsigned p = 0; p < geometry.getNumPrimitiveSets(); ++p) {
      const osg::PrimitiveSet& set = *geometry.getPrimitiveSet(p);
      if (set.getMode() == GL_TRIANGLES && set.getDrawElements()) {
        // OSG's functor reads past the end of an index list whose length is not a multiple of
        // three (osg/TriangleIndexFunctor, 3.6.5; a fuzzed glTF found it): whole triangles only.
        const unsigned whole = set.getNumIndices() / 3 * 3;
        for (unsigned k = 0; k < whole; k += 3) triangles(set.index(k), set.index(k + 1), set.index(k + 2));
      } else {
        set.accept(triangles);
      }
    }
    for (const auto& t : local) {
      std::array<std::uint32_t, 3> m;
      if (modelIndex(t[0], m[0]) && modelIndex(t[1], m[1]) && modelIndex(t[2], m[2])) out_.triangles.push_back(m);
    }
    // Points and lines contribute vertices (a point cloud still has volumes).
    for (unsigned p = 0; p < geometry.getNumPrimitiveSets(); ++p) {
      const osg::PrimitiveSet& set = *geometry.getPrimitiveSet(p);
      const GLenum mode = set.getMode();
      if (mode != GL_POINTS && mode != GL_LINES && mode != GL_LINE_STRIP && mode != GL_LINE_LOOP) continue;
      std::uint32_t ignored;
      for (unsigned k = 0; k < set.getNumIndices(); ++k) modelIndex(set.index(k), ignored);
    }
  }

  TriangleMesh& out_;
};

}  // namespace

TriangleMesh collectModelGeometry(const osg::Node& node, const std::string& name) {
  TriangleMesh geometry;
  GeometryCollector collector(geometry);
  const_cast<osg::Node&>(node).accept(collector);
  if (geometry.vertices.empty())
    throw InputError(name + ": the model holds no vertices (no geometry that a primitive refers to)");
  for (const Vec3<double>& v : geometry.vertices)
    if (!v.allFinite())  // a corrupt file, or a transform that overflows
      throw InputError(name + ": the model has a vertex with a coordinate that is not a finite number");
  return geometry;
}

}  // namespace nestwalk
