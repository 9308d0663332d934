// A drawn scene as glTF 2.0 (gltf_scene_writer.h).
#include "nestwalk/render/gltf_scene_writer.h"

#include <osg/BlendFunc>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Material>
#include <osg/Texture2D>
#include <osg/Transform>
#include <osg/TriangleIndexFunctor>
#include <osgDB/Registry>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace nestwalk {
namespace {

namespace gl = tinygltf;

constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;  // bufferView targets
constexpr const char* kUnlit = "KHR_materials_unlit";
constexpr const char* kInstancing = "EXT_mesh_gpu_instancing";
/// An instance transform written as translation, rotation and scale must give back its matrix to
/// this fraction of its largest entry (a shear or a non-uniform scale after a rotation does not).
constexpr double kTrsTolerance = 1e-9;

/// The drawing state that decides a glTF material, inherited down the graph (a child's attribute
/// replaces its parent's).
struct DrawState {
  const osg::Material* material = nullptr;
  const osg::Texture2D* texture = nullptr;
  bool blend = false, unlit = false, cullBack = false;

  DrawState under(const osg::StateSet* s) const {
    DrawState out = *this;
    if (!s) return out;
    if (auto* m = dynamic_cast<const osg::Material*>(s->getAttribute(osg::StateAttribute::MATERIAL))) out.material = m;
    if (auto* t = dynamic_cast<const osg::Texture2D*>(s->getTextureAttribute(0, osg::StateAttribute::TEXTURE)))
      out.texture = t;
    if (s->getAttribute(osg::StateAttribute::BLENDFUNC) || s->getRenderingHint() == osg::StateSet::TRANSPARENT_BIN)
      out.blend = true;
    const osg::StateAttribute::GLModeValue lighting = s->getMode(GL_LIGHTING);
    if (lighting != osg::StateAttribute::INHERIT) out.unlit = !(lighting & osg::StateAttribute::ON);
    const osg::StateAttribute::GLModeValue cull = s->getMode(GL_CULL_FACE);
    if (cull != osg::StateAttribute::INHERIT) out.cullBack = (cull & osg::StateAttribute::ON) != 0;
    return out;
  }
};

/// A geometry's primitives, as glTF wants them: triangle, line-pair and point index lists.
struct TriangleList {
  std::vector<std::uint32_t>* out = nullptr;
  void operator()(unsigned i, unsigned j, unsigned k) {
    if (i == j || j == k || i == k) return;  // degenerate: drawn as nothing
    out->insert(out->end(), {i, j, k});
  }
};
struct Primitives {
  std::vector<std::uint32_t> triangles, lines, points;
};
Primitives primitivesOf(const osg::Geometry& g) {
  Primitives p;
  osg::TriangleIndexFunctor<TriangleList> tri;
  tri.out = &p.triangles;
  for (unsigned s = 0; s < g.getNumPrimitiveSets(); ++s) {
    const osg::PrimitiveSet& set = *g.getPrimitiveSet(s);
    const unsigned n = set.getNumIndices();
    switch (set.getMode()) {
      case GL_POINTS:
        for (unsigned k = 0; k < n; ++k) p.points.push_back(set.index(k));
        break;
      case GL_LINES:
        for (unsigned k = 0; k + 1 < n; k += 2) p.lines.insert(p.lines.end(), {set.index(k), set.index(k + 1)});
        break;
      case GL_LINE_STRIP:
      case GL_LINE_LOOP:
        for (unsigned k = 0; k + 1 < n; ++k) p.lines.insert(p.lines.end(), {set.index(k), set.index(k + 1)});
        if (set.getMode() == GL_LINE_LOOP && n > 2) p.lines.insert(p.lines.end(), {set.index(n - 1), set.index(0)});
        break;
      case GL_TRIANGLES:
        if (set.getDrawElements()) {  // whole triangles only (OSG's functor reads past a partial one)
          for (unsigned k = 0; k + 2 < n; k += 3) tri(set.index(k), set.index(k + 1), set.index(k + 2));
          break;
        }
        set.accept(tri);
        break;
      default:
        set.accept(tri);  // strips, fans, quads, polygons
    }
  }
  return p;
}

class Writer {
 public:
  Writer(const GltfSceneInfo& info, GltfWriteStats& stats) : stats_(stats), instancing_(info.instancing) {
    doc_.asset.version = "2.0";
    doc_.asset.generator = info.generator;
    gl::Value::Object extras;
    extras["map_origin"] = gl::Value(
        gl::Value::Array{gl::Value(info.mapOrigin.x()), gl::Value(info.mapOrigin.y()), gl::Value(info.mapOrigin.z())});
    extras["crs"] = gl::Value(info.crsWkt);
    extras["crs_name"] = gl::Value(info.crsName);
    extras["frame"] = gl::Value(
        std::string("glTF metres, +y up; a glTF point (x, y, z) is the map point (x, -z, y) + map_origin in the CRS "
                    "(x east, y north, z up)"));
    gl::Value::Object root;
    root["nestwalk"] = gl::Value(extras);
    doc_.asset.extras = gl::Value(root);
    doc_.buffers.emplace_back();
  }

  void write(const osg::Node& root, const std::string& path, bool binary) {
    gl::Node frame;
    frame.name = "nestwalk_local_frame";
    frame.matrix = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1};  // column-major: local z up -> glTF y up
    const int frameIndex = addNode(frame);
    const int child = node(root, DrawState{}.under(root.getStateSet()));
    if (child >= 0) doc_.nodes[static_cast<std::size_t>(frameIndex)].children.push_back(child);
    gl::Scene scene;
    scene.name = "nestwalk";
    scene.nodes.push_back(frameIndex);
    doc_.scenes.push_back(scene);
    doc_.defaultScene = 0;
    doc_.buffers[0].data = std::move(bin_);
    if (usesUnlit_) doc_.extensionsUsed.push_back(kUnlit);
    if (usesInstancing_) {  // no fallback is written: a reader without it would draw each mesh once
      doc_.extensionsUsed.push_back(kInstancing);
      doc_.extensionsRequired.push_back(kInstancing);
    }
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error(path + ": could not be opened for writing");
    gl::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&doc_, out, false, binary) || !out.flush())
      throw std::runtime_error(path + ": could not be written");
    out.close();
    stats_.nodes = doc_.nodes.size();
    stats_.meshes = doc_.meshes.size();
    stats_.materials = doc_.materials.size();
    stats_.images = doc_.images.size();
    stats_.bytes = static_cast<std::size_t>(std::filesystem::file_size(path));
  }

 private:
  int addNode(gl::Node n) {
    doc_.nodes.push_back(std::move(n));
    return static_cast<int>(doc_.nodes.size()) - 1;
  }

  /// The glTF node of `n` and its subtree (-1 when it draws nothing).
  int node(const osg::Node& n, const DrawState& state) {
    gl::Node out;
    out.name = n.getName();
    if (const osg::Transform* t = n.asTransform()) {
      osg::Matrixd m;
      t->computeLocalToWorldMatrix(m, nullptr);
      if (!m.isIdentity()) out.matrix.assign(m.ptr(), m.ptr() + 16);  // OSG's storage is glTF's column-major order
    }
    std::vector<int> children;
    if (const osg::Geode* geode = n.asGeode()) {
      out.mesh = mesh(*geode, state);
    } else if (const osg::Geometry* g = n.asGeometry()) {
      out.mesh = mesh(*g, state);
    } else if (const osg::Group* group = n.asGroup()) {
      std::vector<bool> instanced(group->getNumChildren(), false);
      if (instancing_) children = instancedChildren(*group, state, instanced);
      for (unsigned i = 0; i < group->getNumChildren(); ++i) {
        if (instanced[i]) continue;
        const osg::Node& c = *group->getChild(i);
        const int k = node(c, state.under(c.getStateSet()));
        if (k >= 0) children.push_back(k);
      }
    }
    if (out.mesh < 0 && children.empty()) return -1;
    const int index = addNode(std::move(out));
    doc_.nodes[static_cast<std::size_t>(index)].children = std::move(children);
    countDrawn(doc_.nodes[static_cast<std::size_t>(index)].mesh);
    return index;
  }

  /// EXT_mesh_gpu_instancing: the children of `group` that are transforms over one shared node
  /// (a model's instances), at least kMinGltfInstances of them, become one node per mesh of the
  /// shared node, drawn at every instance's transform. Marks the children it wrote; falls back to
  /// plain nodes for a shared node whose transforms are not translation, rotation and scale.
  std::vector<int> instancedChildren(const osg::Group& group, const DrawState& state, std::vector<bool>& written) {
    std::map<const osg::Node*, std::vector<unsigned>> byShared;
    for (unsigned i = 0; i < group.getNumChildren(); ++i) {
      const osg::Transform* t = group.getChild(i)->asTransform();
      if (t && t->getNumChildren() == 1 && sameDrawing(state, state.under(t->getStateSet())))
        byShared[t->getChild(0)].push_back(i);
    }
    std::vector<int> out;
    for (const auto& [shared, members] : byShared) {
      if (members.size() < kMinGltfInstances) continue;
      std::vector<osg::Matrixd> instances;
      for (unsigned i : members) {
        osg::Matrixd m;
        group.getChild(i)->asTransform()->computeLocalToWorldMatrix(m, nullptr);
        instances.push_back(m);
      }
      std::vector<Leaf> leaves;
      collectLeaves(*shared, osg::Matrixd::identity(), state.under(shared->getStateSet()), leaves);
      std::vector<InstanceTrs> trs;
      for (const Leaf& leaf : leaves) {
        std::optional<InstanceTrs> t = instanceTrs(leaf, instances);
        if (!t) break;
        trs.push_back(std::move(*t));
      }
      if (trs.size() != leaves.size()) continue;  // the plain nodes below draw them
      for (std::size_t k = 0; k < leaves.size(); ++k) out.push_back(instancedNode(leaves[k].mesh, trs[k]));
      for (unsigned i : members) written[i] = true;
    }
    return out;
  }

  static bool sameDrawing(const DrawState& a, const DrawState& b) {
    return a.material == b.material && a.texture == b.texture && a.blend == b.blend && a.unlit == b.unlit &&
           a.cullBack == b.cullBack;
  }

  struct Leaf {
    int mesh = -1;
    osg::Matrixd toShared;  // the leaf's frame in the shared node's (row-vector order, as OSG's)
  };

  void collectLeaves(const osg::Node& n, const osg::Matrixd& above, const DrawState& state, std::vector<Leaf>& out) {
    osg::Matrixd here = above;
    if (const osg::Transform* t = n.asTransform()) {
      osg::Matrixd m;
      t->computeLocalToWorldMatrix(m, nullptr);
      here = m * above;
    }
    int m = -1;
    if (const osg::Geode* geode = n.asGeode())
      m = mesh(*geode, state);
    else if (const osg::Geometry* g = n.asGeometry())
      m = mesh(*g, state);
    else if (const osg::Group* group = n.asGroup())
      for (unsigned i = 0; i < group->getNumChildren(); ++i)
        collectLeaves(*group->getChild(i), here, state.under(group->getChild(i)->getStateSet()), out);
    if (m >= 0) out.push_back({m, here});
  }

  struct InstanceTrs {
    std::vector<float> translation, rotation, scale;  // per instance: 3, 4 (x, y, z, w), 3
    std::size_t count = 0;
  };

  /// Every instance's transform after the leaf's own as translation, rotation and scale, or nothing
  /// when one of them is not exactly that (within kTrsTolerance).
  static std::optional<InstanceTrs> instanceTrs(const Leaf& leaf, const std::vector<osg::Matrixd>& instances) {
    InstanceTrs out;
    for (const osg::Matrixd& instance : instances) {
      const osg::Matrixd m = leaf.toShared * instance;
      osg::Vec3d t, s;
      osg::Quat r, so;
      m.decompose(t, r, s, so);
      r /= r.length();
      const osg::Matrixd back = osg::Matrixd::scale(s) * osg::Matrixd::rotate(r) * osg::Matrixd::translate(t);
      double error = 0, size = 1;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          error = std::max(error, std::abs(back(i, j) - m(i, j)));
          size = std::max(size, std::abs(m(i, j)));
        }
      if (error > kTrsTolerance * size) return std::nullopt;
      out.translation.insert(out.translation.end(), {float(t.x()), float(t.y()), float(t.z())});
      out.rotation.insert(out.rotation.end(), {float(r.x()), float(r.y()), float(r.z()), float(r.w())});
      out.scale.insert(out.scale.end(), {float(s.x()), float(s.y()), float(s.z())});
      ++out.count;
    }
    return out;
  }

  /// A node drawing `mesh` at every instance of `trs`.
  int instancedNode(int mesh, const InstanceTrs& trs) {
    gl::Value::Object attributes;
    const std::size_t n = trs.count;
    attributes["TRANSLATION"] =
        gl::Value(addAccessor(trs.translation.data(), n, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 12, 0));
    attributes["ROTATION"] =
        gl::Value(addAccessor(trs.rotation.data(), n, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, 16, 0));
    attributes["SCALE"] =
        gl::Value(addAccessor(trs.scale.data(), n, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 12, 0));
    gl::Value::Object extension;
    extension["attributes"] = gl::Value(attributes);
    gl::Node node;
    node.mesh = mesh;
    node.extensions[kInstancing] = gl::Value(extension);
    usesInstancing_ = true;
    const int index = addNode(std::move(node));
    for (std::size_t i = 0; i < n; ++i) countDrawn(mesh);
    return index;
  }

  void countDrawn(int mesh) {
    if (mesh < 0) return;
    const Counts& c = meshCounts_[mesh];
    stats_.triangles += c.triangles;
    stats_.lineSegments += c.lines;
    stats_.points += c.points;
  }

  int mesh(const osg::Geode& geode, const DrawState& state) {
    return meshOf(&geode, geode.getName(), state, [&](gl::Mesh& m, Counts& counts) {
      for (unsigned i = 0; i < geode.getNumDrawables(); ++i) {
        const osg::Drawable& d = *geode.getDrawable(i);
        if (const osg::Geometry* g = d.asGeometry()) addPrimitives(m, *g, state.under(d.getStateSet()), counts);
      }
    });
  }

  int mesh(const osg::Geometry& g, const DrawState& state) {
    return meshOf(&g, g.getName(), state, [&](gl::Mesh& m, Counts& counts) { addPrimitives(m, g, state, counts); });
  }

  /// The glTF mesh of a geode or geometry drawn in `state`: made once by `fill`, then reused.
  template <class Fill>
  int meshOf(const void* source, const std::string& name, const DrawState& state, const Fill& fill) {
    const MeshKey key{source, state.material, state.texture, state.blend, state.unlit, state.cullBack};
    if (auto found = meshes_.find(key); found != meshes_.end()) return found->second;
    gl::Mesh m;
    m.name = name;
    Counts counts;
    fill(m, counts);
    return finishMesh(key, std::move(m), counts);
  }

  struct Counts {
    std::size_t triangles = 0, lines = 0, points = 0;
  };
  using MeshKey = std::tuple<const void*, const osg::Material*, const osg::Texture2D*, bool, bool, bool>;

  int finishMesh(const MeshKey& key, gl::Mesh m, const Counts& counts) {
    int index = -1;
    if (!m.primitives.empty()) {
      doc_.meshes.push_back(std::move(m));
      index = static_cast<int>(doc_.meshes.size()) - 1;
      meshCounts_[index] = counts;
      stats_.primitives += doc_.meshes.back().primitives.size();
    }
    meshes_[key] = index;
    return index;
  }

  /// Appends bytes to the buffer as a new view (4-byte aligned, as every component needs).
  int addView(const void* data, std::size_t bytes, int target) {
    while (bin_.size() % 4) bin_.push_back(0);
    gl::BufferView v;
    v.buffer = 0;
    v.byteOffset = bin_.size();
    v.byteLength = bytes;
    v.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    bin_.insert(bin_.end(), p, p + bytes);
    doc_.bufferViews.push_back(v);
    return static_cast<int>(doc_.bufferViews.size()) - 1;
  }

  int addAccessor(const void* data, std::size_t count, int componentType, int type, std::size_t elementBytes,
                  int target, bool normalized = false) {
    gl::Accessor a;
    a.bufferView = addView(data, count * elementBytes, target);
    a.componentType = componentType;
    a.type = type;
    a.count = count;
    a.normalized = normalized;
    doc_.accessors.push_back(a);
    return static_cast<int>(doc_.accessors.size()) - 1;
  }

  /// The vertex attributes of a geometry, written once however many meshes use it.
  struct Attributes {
    std::map<std::string, int> accessors;
    std::size_t vertices = 0;
    std::optional<osg::Vec4> overallColour;
  };

  const Attributes& attributes(const osg::Geometry& g, bool textured) {
    const auto key = std::make_pair(&g, textured);
    if (auto found = attributes_.find(key); found != attributes_.end()) return found->second;
    Attributes& a = attributes_[key];
    const osg::Array* vertexArray = g.getVertexArray();
    std::vector<float> xyz;
    if (auto* v = dynamic_cast<const osg::Vec3Array*>(vertexArray)) {
      const auto* f = static_cast<const float*>(v->getDataPointer());
      xyz.assign(f, f + 3 * v->size());
    } else if (auto* vd = dynamic_cast<const osg::Vec3dArray*>(vertexArray)) {
      for (const osg::Vec3d& p : *vd) xyz.insert(xyz.end(), {float(p.x()), float(p.y()), float(p.z())});
    } else {
      if (vertexArray) stats_.notes.push_back("geometry '" + g.getName() + "': vertices not 3-D, left out");
      return a;
    }
    a.vertices = xyz.size() / 3;
    if (a.vertices == 0) return a;
    const int pos =
        addAccessor(xyz.data(), a.vertices, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 12, kArrayBuffer);
    gl::Accessor& acc = doc_.accessors[static_cast<std::size_t>(pos)];
    acc.minValues = {xyz[0], xyz[1], xyz[2]};
    acc.maxValues = acc.minValues;
    for (std::size_t i = 0; i < a.vertices; ++i)
      for (int k = 0; k < 3; ++k) {
        acc.minValues[k] = std::min<double>(acc.minValues[k], xyz[3 * i + k]);
        acc.maxValues[k] = std::max<double>(acc.maxValues[k], xyz[3 * i + k]);
      }
    a.accessors["POSITION"] = pos;

    auto perVertex = [&](const osg::Array* array) {
      return array && array->getBinding() == osg::Array::BIND_PER_VERTEX && array->getNumElements() == a.vertices;
    };
    if (auto* n = dynamic_cast<const osg::Vec3Array*>(g.getNormalArray()); n && perVertex(n)) {
      std::vector<float> unit;
      unit.reserve(3 * a.vertices);
      for (osg::Vec3 v : *n) {
        const float length = v.length();
        if (!(length > 0) || !std::isfinite(length))
          v.set(0, 0, 1);  // glTF normals are unit vectors
        else
          v /= length;
        unit.insert(unit.end(), {v.x(), v.y(), v.z()});
      }
      a.accessors["NORMAL"] =
          addAccessor(unit.data(), a.vertices, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 12, kArrayBuffer);
    }
    const osg::Array* colours = g.getColorArray();
    if (colours && colours->getBinding() == osg::Array::BIND_OVERALL && colours->getNumElements() >= 1) {
      if (auto* c = dynamic_cast<const osg::Vec4Array*>(colours)) a.overallColour = (*c)[0];
      if (auto* c = dynamic_cast<const osg::Vec4ubArray*>(colours))
        a.overallColour =
            osg::Vec4((*c)[0].r() / 255.0f, (*c)[0].g() / 255.0f, (*c)[0].b() / 255.0f, (*c)[0].a() / 255.0f);
    } else if (perVertex(colours)) {
      if (auto* c = dynamic_cast<const osg::Vec4Array*>(colours))
        a.accessors["COLOR_0"] = addAccessor(c->getDataPointer(), a.vertices, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                             TINYGLTF_TYPE_VEC4, 16, kArrayBuffer);
      if (auto* c = dynamic_cast<const osg::Vec4ubArray*>(colours))
        a.accessors["COLOR_0"] = addAccessor(c->getDataPointer(), a.vertices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                             TINYGLTF_TYPE_VEC4, 4, kArrayBuffer, true);
    }
    if (auto* t = dynamic_cast<const osg::Vec2Array*>(g.getTexCoordArray(0));
        textured && t && t->size() == a.vertices) {
      std::vector<float> uv;
      uv.reserve(2 * a.vertices);
      for (const osg::Vec2& p : *t) uv.insert(uv.end(), {p.x(), 1.0f - p.y()});  // glTF's v runs from the top
      a.accessors["TEXCOORD_0"] =
          addAccessor(uv.data(), a.vertices, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, 8, kArrayBuffer);
    }
    return a;
  }

  void addPrimitives(gl::Mesh& m, const osg::Geometry& g, const DrawState& state, Counts& counts) {
    const bool textured = state.texture && state.texture->getImage() && state.texture->getImage()->data();
    const Attributes& a = attributes(g, textured);
    if (a.vertices == 0) return;
    Primitives p = primitivesOf(g);
    const int material = this->material(state, a.overallColour, textured && a.accessors.count("TEXCOORD_0"));
    auto add = [&](std::vector<std::uint32_t>& indices, std::size_t perElement, int mode) {
      std::vector<std::uint32_t> kept;
      kept.reserve(indices.size());
      for (std::size_t i = 0; i + perElement <= indices.size(); i += perElement) {
        bool inside = true;
        for (std::size_t k = 0; k < perElement; ++k) inside = inside && indices[i + k] < a.vertices;
        if (inside)
          kept.insert(kept.end(), indices.begin() + std::ptrdiff_t(i),
                      indices.begin() + std::ptrdiff_t(i + perElement));
      }
      if (kept.empty()) return std::size_t(0);
      gl::Primitive prim;
      prim.attributes = a.accessors;
      prim.mode = mode;
      prim.material = material;
      if (a.vertices <= 0xFFFF) {
        const std::vector<std::uint16_t> shorts(kept.begin(), kept.end());
        prim.indices = addAccessor(shorts.data(), shorts.size(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                   TINYGLTF_TYPE_SCALAR, 2, kElementArrayBuffer);
      } else {
        prim.indices = addAccessor(kept.data(), kept.size(), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                   4, kElementArrayBuffer);
      }
      m.primitives.push_back(std::move(prim));
      return kept.size() / perElement;
    };
    counts.triangles += add(p.triangles, 3, TINYGLTF_MODE_TRIANGLES);
    counts.lines += add(p.lines, 2, TINYGLTF_MODE_LINE);
    counts.points += add(p.points, 1, TINYGLTF_MODE_POINTS);
  }

  int material(const DrawState& state, const std::optional<osg::Vec4>& overall, bool textured) {
    osg::Vec4 colour(1, 1, 1, 1);
    if (overall)
      colour = *overall;
    else if (state.material)
      colour = state.material->getDiffuse(osg::Material::FRONT);
    const osg::Texture2D* texture = textured ? state.texture : nullptr;
    const auto key = std::make_tuple(colour.r(), colour.g(), colour.b(), colour.a(), texture, state.blend, state.unlit,
                                     state.cullBack);
    if (auto found = materials_.find(key); found != materials_.end()) return found->second;
    gl::Material m;
    m.pbrMetallicRoughness.baseColorFactor = {colour.r(), colour.g(), colour.b(), colour.a()};
    m.pbrMetallicRoughness.metallicFactor = 0.0;
    m.pbrMetallicRoughness.roughnessFactor = 1.0;
    m.doubleSided = !state.cullBack;  // OSG culls no face unless told (the terrain's back faces are)
    if (state.blend || colour.a() < 1.0f) m.alphaMode = "BLEND";
    if (texture) m.pbrMetallicRoughness.baseColorTexture.index = this->texture(*texture);
    if (state.unlit) {
      m.extensions[kUnlit] = gl::Value(gl::Value::Object());
      usesUnlit_ = true;
    }
    doc_.materials.push_back(m);
    const int index = static_cast<int>(doc_.materials.size()) - 1;
    materials_[key] = index;
    return index;
  }

  static int wrap(osg::Texture::WrapMode w) {
    switch (w) {
      case osg::Texture::CLAMP:
      case osg::Texture::CLAMP_TO_EDGE:
      case osg::Texture::CLAMP_TO_BORDER:
        return TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
      case osg::Texture::MIRROR:
        return TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT;
      default:
        return TINYGLTF_TEXTURE_WRAP_REPEAT;
    }
  }

  /// OSG's minification filter as glTF's (a filter without mipmaps keeps a viewer from making them:
  /// the renderer draws the terrain's textures so, since mipmapping costs software GL dearly).
  static int minFilter(osg::Texture::FilterMode f) {
    switch (f) {
      case osg::Texture::NEAREST:
        return TINYGLTF_TEXTURE_FILTER_NEAREST;
      case osg::Texture::LINEAR:
        return TINYGLTF_TEXTURE_FILTER_LINEAR;
      case osg::Texture::NEAREST_MIPMAP_NEAREST:
        return TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST;
      case osg::Texture::LINEAR_MIPMAP_NEAREST:
        return TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST;
      case osg::Texture::NEAREST_MIPMAP_LINEAR:
        return TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR;
      default:
        return TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    }
  }

  int texture(const osg::Texture2D& t) {
    if (auto found = textures_.find(&t); found != textures_.end()) return found->second;
    gl::Sampler s;
    s.wrapS = wrap(t.getWrap(osg::Texture::WRAP_S));
    s.wrapT = wrap(t.getWrap(osg::Texture::WRAP_T));
    s.magFilter = t.getFilter(osg::Texture::MAG_FILTER) == osg::Texture::NEAREST ? TINYGLTF_TEXTURE_FILTER_NEAREST
                                                                                 : TINYGLTF_TEXTURE_FILTER_LINEAR;
    s.minFilter = minFilter(t.getFilter(osg::Texture::MIN_FILTER));
    doc_.samplers.push_back(s);
    gl::Texture tex;
    tex.sampler = static_cast<int>(doc_.samplers.size()) - 1;
    tex.source = image(*t.getImage());
    doc_.textures.push_back(tex);
    const int index = static_cast<int>(doc_.textures.size()) - 1;
    textures_[&t] = index;
    return index;
  }

  /// The image encoded by OSG's plugin: JPEG when every pixel is opaque, PNG otherwise.
  int image(const osg::Image& source) {
    if (auto found = images_.find(&source); found != images_.end()) return found->second;
    osg::ref_ptr<osg::Image> image = new osg::Image(source, osg::CopyOp::DEEP_COPY_ALL);
    bool opaque = true;
    for (int y = 0; y < image->t() && opaque; ++y)
      for (int x = 0; x < image->s() && opaque; ++x) opaque = image->getColor(x, y).a() >= 1.0f;
    if (opaque && (image->getPixelFormat() != GL_RGB || image->getDataType() != GL_UNSIGNED_BYTE)) {
      osg::ref_ptr<osg::Image> rgb = new osg::Image;  // JPEG holds three 8-bit channels
      rgb->allocateImage(image->s(), image->t(), 1, GL_RGB, GL_UNSIGNED_BYTE);
      for (int y = 0; y < image->t(); ++y)
        for (int x = 0; x < image->s(); ++x) {
          const osg::Vec4 c = image->getColor(x, y);
          unsigned char* p = rgb->data(x, y);
          for (int k = 0; k < 3; ++k)
            p[k] = static_cast<unsigned char>(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
        }
      image = rgb;
    }
    const char* ext = opaque ? "jpeg" : "png";
    osgDB::ReaderWriter* rw = osgDB::Registry::instance()->getReaderWriterForExtension(ext);
    if (!rw) throw std::runtime_error(std::string("OpenSceneGraph's ") + ext + " plugin is missing");
    std::ostringstream bytes(std::ios::binary);
    osg::ref_ptr<osgDB::Options> options = new osgDB::Options("JPEG_QUALITY " + std::to_string(kGltfJpegQuality));
    const osgDB::ReaderWriter::WriteResult w = rw->writeImage(*image, bytes, options.get());
    if (!w.success())
      throw std::runtime_error("an image could not be encoded as " + std::string(ext) + ": " + w.message());
    const std::string data = bytes.str();
    gl::Image out;
    out.name = source.getFileName();
    out.mimeType = opaque ? "image/jpeg" : "image/png";
    out.bufferView = addView(data.data(), data.size(), 0);
    doc_.bufferViews.back().target = 0;  // image views have no target
    doc_.images.push_back(out);
    const int index = static_cast<int>(doc_.images.size()) - 1;
    images_[&source] = index;
    return index;
  }

  gl::Model doc_;
  std::vector<unsigned char> bin_;
  GltfWriteStats& stats_;
  bool usesUnlit_ = false, usesInstancing_ = false;
  bool instancing_ = false;
  std::map<MeshKey, int> meshes_;
  std::map<int, Counts> meshCounts_;
  std::map<std::pair<const osg::Geometry*, bool>, Attributes> attributes_;
  std::map<std::tuple<float, float, float, float, const osg::Texture2D*, bool, bool, bool>, int> materials_;
  std::map<const osg::Texture2D*, int> textures_;
  std::map<const osg::Image*, int> images_;
};

}  // namespace

GltfWriteStats writeGltfScene(const osg::Node& root, const GltfSceneInfo& info, const std::string& path, bool binary) {
  GltfWriteStats stats;
  Writer(info, stats).write(root, path, binary);
  return stats;
}

}  // namespace nestwalk
