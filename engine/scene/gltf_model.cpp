// glTF 2.0 models as OpenSceneGraph graphs (gltf_model.h).
#include "nestwalk/scene/gltf_model.h"

#include <osg/BlendFunc>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Image>
#include <osg/Material>
#include <osg/MatrixTransform>
#include <osg/Texture2D>
#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

namespace nestwalk {
namespace {

namespace fs = std::filesystem;
using Document = tinygltf::Model;

/// The binary container's first four bytes (glTF 2.0, section 4.4.3).
constexpr char kGlbMagic[4] = {'g', 'l', 'T', 'F'};
/// Extensions a file may require that this reader honours: quantized attributes are read as the
/// normalized or plain integers they are; unlit materials draw as lit ones with their base colour.
const std::set<std::string> kReadableRequiredExtensions = {"KHR_mesh_quantization", "KHR_materials_unlit",
                                                           "EXT_mesh_gpu_instancing"};
constexpr const char* kInstancing = "EXT_mesh_gpu_instancing";

/// A bad file: the message names the glTF object and the problem.
struct GltfProblem : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string item(const char* array, std::size_t index) {
  return std::string(array) + "[" + std::to_string(index) + "]";
}

// tinygltf's file access, without its path expansion (wordexp on POSIX: a path from the file is
// never given to a shell's expansion) and without writing.
bool fileExists(const std::string& path, void*) {
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}
std::string expandNothing(const std::string& path, void*) { return path; }
bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (err) *err += "'" + path + "' could not be opened\n";
    return false;
  }
  out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return true;
}
bool refuseWriting(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "the model reader writes no files\n";
  return false;
}

/// tinygltf's message, one line, without its trailing newline.
std::string oneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  std::replace(text.begin(), text.end(), '\n', ';');
  return text;
}

/// A checked view of one accessor's elements: element i starts at data + i * stride and holds
/// `components` values of `componentType`.
struct AccessorView {
  const unsigned char* data = nullptr;
  std::size_t stride = 0, count = 0;
  int components = 0, componentType = 0;
  bool normalized = false;

  /// Component c of element i as a float (normalized integers mapped to [0, 1] or [-1, 1]).
  float value(std::size_t i, int c) const {
    const unsigned char* p = data + i * stride;
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return load<float>(p, c);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return scaled(load<std::uint8_t>(p, c), 255.0f);
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        return signedScaled(load<std::int8_t>(p, c), 127.0f);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return scaled(load<std::uint16_t>(p, c), 65535.0f);
      case TINYGLTF_COMPONENT_TYPE_SHORT:
        return signedScaled(load<std::int16_t>(p, c), 32767.0f);
      default:
        return static_cast<float>(load<std::uint32_t>(p, c));
    }
  }
  /// Element i as an index (unsigned integer component types only).
  std::uint32_t index(std::size_t i) const {
    const unsigned char* p = data + i * stride;
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return load<std::uint8_t>(p, 0);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return load<std::uint16_t>(p, 0);
      default:
        return load<std::uint32_t>(p, 0);
    }
  }

 private:
  template <class T>
  static T load(const unsigned char* p, int c) {
    T v;
    std::memcpy(&v, p + static_cast<std::size_t>(c) * sizeof(T), sizeof(T));  // glTF data need not be aligned here
    return v;
  }
  template <class T>
  float scaled(T v, float max) const {
    return normalized ? static_cast<float>(v) / max : static_cast<float>(v);
  }
  template <class T>
  float signedScaled(T v, float max) const {
    return normalized ? std::max(static_cast<float>(v) / max, -1.0f) : static_cast<float>(v);
  }
};

/// Builds the graph of one parsed document; every reference is checked before it is followed.
class GraphBuilder {
 public:
  GraphBuilder(const Document& doc, std::vector<std::string>& notes) : doc_(doc), notes_(notes) {}

  osg::ref_ptr<osg::Node> build() {
    for (const std::string& ext : doc_.extensionsRequired)
      if (!kReadableRequiredExtensions.count(ext))
        throw GltfProblem("extensionsRequired: " + ext + " is not read by nestwalk (write the model without it)");
    const std::vector<int> roots = sceneRoots();
    checkTrees(roots);
    osg::ref_ptr<osg::Group> root = new osg::Group;
    for (int n : roots) root->addChild(nodeGraph(n).get());
    if (!doc_.animations.empty()) notes_.push_back("animations skipped (the model is read at rest)");
    if (!doc_.skins.empty()) notes_.push_back("skins skipped (the model is read at rest)");
    return root;
  }

 private:
  /// The nodes of the scene that is drawn (see the header).
  std::vector<int> sceneRoots() const {
    if (!doc_.scenes.empty()) {
      const int s = doc_.defaultScene >= 0 ? doc_.defaultScene : 0;
      if (static_cast<std::size_t>(s) >= doc_.scenes.size())
        throw GltfProblem("scene " + std::to_string(s) + " does not exist (the file has " +
                          std::to_string(doc_.scenes.size()) + " scenes)");
      const std::vector<int>& nodes = doc_.scenes[static_cast<std::size_t>(s)].nodes;
      for (int n : nodes) checkIndex(n, doc_.nodes.size(), item("scenes", static_cast<std::size_t>(s)), "node");
      return nodes;
    }
    std::vector<bool> isChild(doc_.nodes.size(), false);
    for (std::size_t n = 0; n < doc_.nodes.size(); ++n)
      for (int c : doc_.nodes[n].children)
        if (c >= 0 && static_cast<std::size_t>(c) < isChild.size()) isChild[static_cast<std::size_t>(c)] = true;
    std::vector<int> roots;
    for (std::size_t n = 0; n < doc_.nodes.size(); ++n)
      if (!isChild[n]) roots.push_back(static_cast<int>(n));
    return roots;
  }

  static void checkIndex(int index, std::size_t size, const std::string& where, const char* what) {
    if (index < 0 || static_cast<std::size_t>(index) >= size)
      throw GltfProblem(where + ": " + what + " " + std::to_string(index) + " does not exist (the file has " +
                        std::to_string(size) + ")");
  }

  /// The node graphs are trees (each node has one parent, no cycle) and instance at most
  /// kMaxInstancedGltfVertices vertices: checked before anything is built.
  void checkTrees(const std::vector<int>& roots) {
    std::vector<int> parent(doc_.nodes.size(), -2);  // -2: not reached; -1: a scene root
    std::vector<int> stack;
    for (int r : roots) {
      if (parent[static_cast<std::size_t>(r)] != -2)
        throw GltfProblem(item("nodes", static_cast<std::size_t>(r)) + ": listed twice in the scene");
      parent[static_cast<std::size_t>(r)] = -1;
      stack.push_back(r);
    }
    std::uint64_t vertices = 0;
    while (!stack.empty()) {
      const std::size_t n = static_cast<std::size_t>(stack.back());
      stack.pop_back();
      const tinygltf::Node& node = doc_.nodes[n];
      if (node.mesh >= 0) {
        checkIndex(node.mesh, doc_.meshes.size(), item("nodes", n), "mesh");
        vertices += meshVertexClaim(static_cast<std::size_t>(node.mesh)) * instanceClaim(node);
        if (vertices > kMaxInstancedGltfVertices)
          throw GltfProblem("the nodes instance more than " + std::to_string(kMaxInstancedGltfVertices) +
                            " vertices, more than one model may draw");
      }
      for (int c : node.children) {
        checkIndex(c, doc_.nodes.size(), item("nodes", n), "child node");
        int& p = parent[static_cast<std::size_t>(c)];
        if (p != -2)
          throw GltfProblem(item("nodes", static_cast<std::size_t>(c)) + ": has two parents, or is its own ancestor " +
                            "(glTF nodes form trees)");
        p = static_cast<int>(n);
        stack.push_back(c);
      }
    }
  }

  /// The instances a node's EXT_mesh_gpu_instancing claims (its TRANSLATION, ROTATION or SCALE
  /// count, unchecked), 1 without it.
  std::uint64_t instanceClaim(const tinygltf::Node& node) const {
    const auto ext = node.extensions.find(kInstancing);
    if (ext == node.extensions.end() || !ext->second.Get("attributes").IsObject()) return 1;
    const tinygltf::Value& attributes = ext->second.Get("attributes");
    std::uint64_t count = 1;
    for (const char* name : {"TRANSLATION", "ROTATION", "SCALE"}) {
      const tinygltf::Value& a = attributes.Get(name);
      if (!a.IsInt()) continue;
      const int k = a.GetNumberAsInt();
      if (k >= 0 && static_cast<std::size_t>(k) < doc_.accessors.size())
        count = std::max<std::uint64_t>(count, doc_.accessors[static_cast<std::size_t>(k)].count);
    }
    return count;
  }

  /// The vertices a mesh's triangle primitives claim (their POSITION counts), unchecked.
  std::uint64_t meshVertexClaim(std::size_t m) const {
    std::uint64_t sum = 0;
    for (const tinygltf::Primitive& p : doc_.meshes[m].primitives) {
      const auto pos = p.attributes.find("POSITION");
      if (pos != p.attributes.end() && pos->second >= 0 &&
          static_cast<std::size_t>(pos->second) < doc_.accessors.size())
        sum += doc_.accessors[static_cast<std::size_t>(pos->second)].count;
    }
    return sum;
  }

  osg::ref_ptr<osg::Node> nodeGraph(int index) {
    const std::size_t n = static_cast<std::size_t>(index);
    const tinygltf::Node& node = doc_.nodes[n];
    const std::string where = item("nodes", n);
    osg::ref_ptr<osg::Group> group;
    if (const std::optional<osg::Matrixd> m = nodeMatrix(node, where)) {
      group = new osg::MatrixTransform(*m);
    } else {
      group = new osg::Group;
    }
    group->setName(node.name);
    if (node.mesh >= 0) {
      osg::ref_ptr<osg::Geode> mesh = meshGeode(static_cast<std::size_t>(node.mesh));
      if (node.extensions.count(kInstancing)) {
        for (const osg::Matrixd& m : instances(node, where)) {
          osg::ref_ptr<osg::MatrixTransform> instance = new osg::MatrixTransform(m);
          instance->addChild(mesh.get());
          group->addChild(instance.get());
        }
      } else {
        group->addChild(mesh.get());
      }
    }
    for (int c : node.children) group->addChild(nodeGraph(c).get());
    if (node.camera >= 0) notes_.push_back(where + ": camera skipped");
    return group;
  }

  /// EXT_mesh_gpu_instancing's transforms of a node's mesh (in the node's frame): translation,
  /// rotation and scale accessors of one count, each optional, as floats (rotations also as
  /// normalized integers).
  std::vector<osg::Matrixd> instances(const tinygltf::Node& node, const std::string& where) const {
    const std::string at = where + ": " + kInstancing;
    const tinygltf::Value& attributes = node.extensions.at(kInstancing).Get("attributes");
    if (!attributes.IsObject()) throw GltfProblem(at + ": no attributes");
    std::optional<AccessorView> views[3];
    const char* names[3] = {"TRANSLATION", "ROTATION", "SCALE"};
    std::optional<std::size_t> count;
    for (int k = 0; k < 3; ++k) {
      const tinygltf::Value& a = attributes.Get(names[k]);
      if (!a.IsInt()) continue;
      views[k] = accessorView(a.GetNumberAsInt(), at, names[k]);
      if (views[k]->components != (k == 1 ? 4 : 3) ||
          (k != 1 && views[k]->componentType != TINYGLTF_COMPONENT_TYPE_FLOAT))
        throw GltfProblem(at + ": " + names[k] + " is not of " + (k == 1 ? "4" : "3") + "-component floats");
      if (count && *count != views[k]->count) throw GltfProblem(at + ": its attributes differ in count");
      count = views[k]->count;
    }
    std::vector<osg::Matrixd> out(count.value_or(0));
    for (std::size_t i = 0; i < out.size(); ++i) {
      osg::Matrixd m;
      if (views[2]) m.postMultScale(osg::Vec3d(views[2]->value(i, 0), views[2]->value(i, 1), views[2]->value(i, 2)));
      if (views[1])
        m.postMultRotate(
            osg::Quat(views[1]->value(i, 0), views[1]->value(i, 1), views[1]->value(i, 2), views[1]->value(i, 3)));
      if (views[0])
        m.postMultTranslate(osg::Vec3d(views[0]->value(i, 0), views[0]->value(i, 1), views[0]->value(i, 2)));
      out[i] = m;
    }
    return out;
  }

  /// The node's local transform, or nothing when it is the identity by omission.
  static std::optional<osg::Matrixd> nodeMatrix(const tinygltf::Node& node, const std::string& where) {
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16)
        throw GltfProblem(where + ": matrix has " + std::to_string(node.matrix.size()) + " numbers, not 16");
      // glTF's column-major array is OSG's row-vector matrix as stored (OSG multiplies v * M).
      return osg::Matrixd(node.matrix.data());
    }
    if (node.translation.empty() && node.rotation.empty() && node.scale.empty()) return std::nullopt;
    auto need = [&](const std::vector<double>& v, std::size_t size, const char* name) {
      if (!v.empty() && v.size() != size)
        throw GltfProblem(where + ": " + name + " has " + std::to_string(v.size()) + " numbers, not " +
                          std::to_string(size));
    };
    need(node.translation, 3, "translation");
    need(node.rotation, 4, "rotation");
    need(node.scale, 3, "scale");
    osg::Matrixd m;  // T * R * S applied to column vectors: in OSG's row-vector order S, then R, then T
    if (!node.scale.empty()) m.postMultScale(osg::Vec3d(node.scale[0], node.scale[1], node.scale[2]));
    if (!node.rotation.empty())
      m.postMultRotate(osg::Quat(node.rotation[0], node.rotation[1], node.rotation[2], node.rotation[3]));
    if (!node.translation.empty())
      m.postMultTranslate(osg::Vec3d(node.translation[0], node.translation[1], node.translation[2]));
    return m;
  }

  osg::ref_ptr<osg::Geode> meshGeode(std::size_t m) {
    auto found = meshes_.find(m);
    if (found != meshes_.end()) return found->second;
    const tinygltf::Mesh& mesh = doc_.meshes[m];
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->setName(mesh.name);
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const std::string where = item("meshes", m) + "." + item("primitives", p);
      if (osg::ref_ptr<osg::Geometry> g = primitiveGeometry(mesh.primitives[p], where)) geode->addDrawable(g.get());
    }
    meshes_[m] = geode;
    return geode;
  }

  osg::ref_ptr<osg::Geometry> primitiveGeometry(const tinygltf::Primitive& prim, const std::string& where) {
    GLenum mode = 0;
    switch (prim.mode) {
      case TINYGLTF_MODE_TRIANGLES:
        mode = GL_TRIANGLES;
        break;
      case TINYGLTF_MODE_TRIANGLE_STRIP:
        mode = GL_TRIANGLE_STRIP;
        break;
      case TINYGLTF_MODE_TRIANGLE_FAN:
        mode = GL_TRIANGLE_FAN;
        break;
      default: {
        const char* names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
        const std::string name =
            prim.mode >= 0 && prim.mode < 4 ? names[prim.mode] : "mode " + std::to_string(prim.mode);
        notes_.push_back(where + ": " + name + " skipped (nestwalk reads triangles)");
        return nullptr;
      }
    }
    const auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) throw GltfProblem(where + ": has no POSITION attribute");
    const AccessorView positions = attribute(pos->second, where, "POSITION", {3});
    osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
    osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array(static_cast<unsigned>(positions.count));
    for (std::size_t i = 0; i < positions.count; ++i)
      (*v)[i].set(positions.value(i, 0), positions.value(i, 1), positions.value(i, 2));
    g->setVertexArray(v.get());
    if (!prim.targets.empty()) notes_.push_back(where + ": morph targets skipped");

    for (const auto& [name, accessor] : prim.attributes) {
      if (name == "NORMAL") {
        const AccessorView a = attribute(accessor, where, name, {3}, positions.count);
        osg::ref_ptr<osg::Vec3Array> nrm = new osg::Vec3Array(static_cast<unsigned>(a.count));
        for (std::size_t i = 0; i < a.count; ++i) (*nrm)[i].set(a.value(i, 0), a.value(i, 1), a.value(i, 2));
        g->setNormalArray(nrm.get(), osg::Array::BIND_PER_VERTEX);
      } else if (name.rfind("TEXCOORD_", 0) == 0) {
        const unsigned unit = texcoordSet(name);
        if (unit > kMaxTexcoordSets) continue;
        const AccessorView a = attribute(accessor, where, name, {2}, positions.count);
        osg::ref_ptr<osg::Vec2Array> t = new osg::Vec2Array(static_cast<unsigned>(a.count));
        // glTF's v runs down the image from its first row, as OpenGL's t runs from the first row
        // of the uploaded pixels (tinygltf decodes top row first): the coordinate is kept as is.
        for (std::size_t i = 0; i < a.count; ++i) (*t)[i].set(a.value(i, 0), a.value(i, 1));
        g->setTexCoordArray(unit, t.get(), osg::Array::BIND_PER_VERTEX);
      } else if (name == "COLOR_0") {
        const AccessorView a = attribute(accessor, where, name, {3, 4}, positions.count);
        osg::ref_ptr<osg::Vec4Array> c = new osg::Vec4Array(static_cast<unsigned>(a.count));
        for (std::size_t i = 0; i < a.count; ++i)
          (*c)[i].set(a.value(i, 0), a.value(i, 1), a.value(i, 2), a.components == 4 ? a.value(i, 3) : 1.0f);
        g->setColorArray(c.get(), osg::Array::BIND_PER_VERTEX);
      }
    }

    if (prim.indices >= 0) {
      const AccessorView idx = accessorView(prim.indices, where, "indices");
      if (idx.components != 1 || (idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                  idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                  idx.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        throw GltfProblem(where + ": indices: accessor " + std::to_string(prim.indices) +
                          " is not one unsigned byte, short or int per element");
      std::size_t count = idx.count;
      if (mode == GL_TRIANGLES && count % 3 != 0) {  // whole triangles only (OSG's functors read past a partial one)
        notes_.push_back(where + ": " + std::to_string(count) + " indices, not whole triangles; the last " +
                         std::to_string(count % 3) + " ignored");
        count -= count % 3;
      }
      osg::ref_ptr<osg::DrawElementsUInt> e = new osg::DrawElementsUInt(mode, static_cast<unsigned>(count));
      for (std::size_t i = 0; i < count; ++i) {
        const std::uint32_t k = idx.index(i);
        if (k >= positions.count)
          throw GltfProblem(where + ": index " + std::to_string(k) + " (element " + std::to_string(i) +
                            " of accessor " + std::to_string(prim.indices) + ") is past the " +
                            std::to_string(positions.count) + " vertices");
        (*e)[i] = k;
      }
      g->addPrimitiveSet(e.get());
    } else {
      g->addPrimitiveSet(new osg::DrawArrays(mode, 0, static_cast<GLsizei>(positions.count)));
    }
    applyMaterial(*g, prim.material, where);
    return g;
  }

  static constexpr unsigned kMaxTexcoordSets = 7;  // TEXCOORD_0 .. TEXCOORD_7: OSG's fixed-function units

  static unsigned texcoordSet(const std::string& name) {
    const std::string digits = name.substr(std::strlen("TEXCOORD_"));
    if (digits.empty() || digits.size() > 2 ||
        !std::all_of(digits.begin(), digits.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
      return kMaxTexcoordSets + 1;
    return static_cast<unsigned>(std::stoi(digits));
  }

  /// A vertex attribute: its accessor checked, with `allowed` component counts, and (when
  /// `vertices` is given) one element per vertex.
  AccessorView attribute(int accessor, const std::string& where, const std::string& name,
                         std::initializer_list<int> allowed,
                         std::optional<std::size_t> vertices = std::nullopt) const {
    const AccessorView a = accessorView(accessor, where, name.c_str());
    if (std::find(allowed.begin(), allowed.end(), a.components) == allowed.end())
      throw GltfProblem(where + ": " + name + ": accessor " + std::to_string(accessor) + " has " +
                        std::to_string(a.components) + " components per element");
    if (vertices && a.count != *vertices)
      throw GltfProblem(where + ": " + name + ": accessor " + std::to_string(accessor) + " has " +
                        std::to_string(a.count) + " elements for " + std::to_string(*vertices) + " vertices");
    return a;
  }

  /// Accessor `index`, with every byte it reads checked to lie in its buffer view and buffer.
  AccessorView accessorView(int index, const std::string& where, const char* role) const {
    const std::string at = where + ": " + role;
    checkIndex(index, doc_.accessors.size(), at, "accessor");
    const tinygltf::Accessor& a = doc_.accessors[static_cast<std::size_t>(index)];
    const std::string self = "accessor " + std::to_string(index);
    if (a.sparse.isSparse) throw GltfProblem(at + ": " + self + " is sparse, which nestwalk does not read");
    if (a.bufferView < 0) throw GltfProblem(at + ": " + self + " has no buffer view");
    checkIndex(a.bufferView, doc_.bufferViews.size(), at + ": " + self, "buffer view");
    const tinygltf::BufferView& view = doc_.bufferViews[static_cast<std::size_t>(a.bufferView)];
    const std::string viewName = "buffer view " + std::to_string(a.bufferView);
    checkIndex(view.buffer, doc_.buffers.size(), at + ": " + viewName, "buffer");
    const std::vector<unsigned char>& buffer = doc_.buffers[static_cast<std::size_t>(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
      throw GltfProblem(at + ": " + viewName + " reads past the end of buffer " + std::to_string(view.buffer) + " (" +
                        std::to_string(buffer.size()) + " bytes)");
    const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    const int componentBytes = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
    if (components <= 0 || componentBytes <= 0 || a.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE)
      throw GltfProblem(at + ": " + self + " has an unknown type or component type");
    const std::size_t element = static_cast<std::size_t>(components) * static_cast<std::size_t>(componentBytes);
    const std::size_t stride = view.byteStride > 0 ? view.byteStride : element;
    if (stride < element)
      throw GltfProblem(at + ": " + viewName + "'s stride " + std::to_string(stride) +
                        " is shorter than an element of " + self);
    // The last byte read: byteOffset + stride * (count - 1) + element, computed without overflow.
    if (a.count > 0) {
      const std::size_t room = view.byteLength;
      if (a.byteOffset > room || element > room - a.byteOffset ||
          (a.count - 1) > (room - a.byteOffset - element) / stride)
        throw GltfProblem(at + ": " + self + " reads past the end of " + viewName + " (" + std::to_string(a.count) +
                          " elements of " + std::to_string(element) + " bytes from byte " +
                          std::to_string(a.byteOffset) + ", the view has " + std::to_string(view.byteLength) + ")");
    }
    AccessorView out;
    out.data = buffer.data() + view.byteOffset + a.byteOffset;
    out.stride = stride;
    out.count = a.count;
    out.components = components;
    out.componentType = a.componentType;
    out.normalized = a.normalized;
    return out;
  }

  void applyMaterial(osg::Geometry& g, int index, const std::string& where) {
    if (index < 0) return;  // glTF's default material: white, which OSG draws without one
    checkIndex(index, doc_.materials.size(), where, "material");
    auto found = states_.find(index);
    if (found == states_.end()) found = states_.emplace(index, materialState(static_cast<std::size_t>(index))).first;
    g.setStateSet(found->second.state.get());
    // The base colour factor multiplies the vertex colours; without them it is the colour.
    const osg::Vec4 factor = found->second.baseColour;
    if (auto* colours = dynamic_cast<osg::Vec4Array*>(g.getColorArray())) {
      for (osg::Vec4& c : *colours) c = osg::componentMultiply(c, factor);
    } else {
      osg::ref_ptr<osg::Vec4Array> overall = new osg::Vec4Array(1);
      (*overall)[0] = factor;
      g.setColorArray(overall.get(), osg::Array::BIND_OVERALL);
    }
  }

  struct MaterialState {
    osg::ref_ptr<osg::StateSet> state;
    osg::Vec4 baseColour;
  };

  MaterialState materialState(std::size_t index) {
    const tinygltf::Material& mat = doc_.materials[index];
    const std::string where = item("materials", index);
    MaterialState out;
    out.state = new osg::StateSet;
    const std::vector<double>& f = mat.pbrMetallicRoughness.baseColorFactor;
    if (f.size() != 4)
      throw GltfProblem(where + ": baseColorFactor has " + std::to_string(f.size()) + " numbers, not 4");
    out.baseColour.set(static_cast<float>(f[0]), static_cast<float>(f[1]), static_cast<float>(f[2]),
                       static_cast<float>(f[3]));
    // The colour array carries the base colour (applyMaterial): the material follows it.
    osg::ref_ptr<osg::Material> material = new osg::Material;
    material->setColorMode(osg::Material::AMBIENT_AND_DIFFUSE);
    out.state->setAttributeAndModes(material.get());
    if (mat.alphaMode == "BLEND") {
      out.state->setAttributeAndModes(new osg::BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA));
      out.state->setRenderingHint(osg::StateSet::TRANSPARENT_BIN);
    }
    const tinygltf::TextureInfo& tex = mat.pbrMetallicRoughness.baseColorTexture;
    if (tex.index >= 0) {
      checkIndex(tex.index, doc_.textures.size(), where + ": baseColorTexture", "texture");
      const unsigned unit = tex.texCoord >= 0 && tex.texCoord <= static_cast<int>(kMaxTexcoordSets)
                                ? static_cast<unsigned>(tex.texCoord)
                                : 0;
      if (osg::ref_ptr<osg::Texture2D> t = texture(static_cast<std::size_t>(tex.index)))
        out.state->setTextureAttributeAndModes(unit, t.get());
    }
    return out;
  }

  osg::ref_ptr<osg::Texture2D> texture(std::size_t index) {
    const tinygltf::Texture& tex = doc_.textures[index];
    const std::string where = item("textures", index);
    if (tex.source < 0) {
      notes_.push_back(where + ": no image in a format nestwalk reads (PNG or JPEG); drawn untextured");
      return nullptr;
    }
    checkIndex(tex.source, doc_.images.size(), where, "image");
    const tinygltf::Image& img = doc_.images[static_cast<std::size_t>(tex.source)];
    const std::string imageName = item("images", static_cast<std::size_t>(tex.source));
    if (img.image.empty() || img.width <= 0 || img.height <= 0) {
      if (!img.uri.empty() && img.uri.rfind("data:", 0) != 0)
        throw GltfProblem(imageName + ": '" + img.uri +
                          "' could not be read (missing beside the model, or not a PNG or JPEG)");
      throw GltfProblem(imageName + ": holds no picture");
    }
    const GLenum type = img.bits == 16 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_BYTE;
    const GLenum formats[] = {GL_LUMINANCE, GL_LUMINANCE_ALPHA, GL_RGB, GL_RGBA};
    if (img.component < 1 || img.component > 4 || (img.bits != 8 && img.bits != 16))
      throw GltfProblem(imageName + ": " + std::to_string(img.component) + " channels of " + std::to_string(img.bits) +
                        " bits");
    const std::size_t bytes = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height) *
                              static_cast<std::size_t>(img.component) * static_cast<std::size_t>(img.bits / 8);
    if (img.image.size() < bytes) throw GltfProblem(imageName + ": holds fewer pixels than its size");
    osg::ref_ptr<osg::Image> image = new osg::Image;
    image->allocateImage(img.width, img.height, 1, formats[img.component - 1], type);
    std::memcpy(image->data(), img.image.data(), bytes);
    image->setInternalTextureFormat(formats[img.component - 1]);
    image->setFileName(img.uri.rfind("data:", 0) == 0 ? img.name : img.uri);
    osg::ref_ptr<osg::Texture2D> t = new osg::Texture2D(image.get());
    if (tex.sampler >= 0) {
      checkIndex(tex.sampler, doc_.samplers.size(), where, "sampler");
      const tinygltf::Sampler& s = doc_.samplers[static_cast<std::size_t>(tex.sampler)];
      t->setWrap(osg::Texture::WRAP_S, wrap(s.wrapS));
      t->setWrap(osg::Texture::WRAP_T, wrap(s.wrapT));
    } else {
      t->setWrap(osg::Texture::WRAP_S, osg::Texture::REPEAT);  // glTF's default sampler
      t->setWrap(osg::Texture::WRAP_T, osg::Texture::REPEAT);
    }
    t->setFilter(osg::Texture::MIN_FILTER, osg::Texture::LINEAR_MIPMAP_LINEAR);
    t->setFilter(osg::Texture::MAG_FILTER, osg::Texture::LINEAR);
    return t;
  }

  static osg::Texture::WrapMode wrap(int mode) {
    switch (mode) {
      case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
        return osg::Texture::CLAMP_TO_EDGE;
      case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
        return osg::Texture::MIRROR;
      default:
        return osg::Texture::REPEAT;
    }
  }

  const Document& doc_;
  std::vector<std::string>& notes_;
  std::map<std::size_t, osg::ref_ptr<osg::Geode>> meshes_;
  std::map<int, MaterialState> states_;
};

std::uint32_t littleEndian32(std::string_view bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(i)]);
  return v;
}

/// The binary container's header and chunk lengths (glTF 2.0, section 4.4), checked before the
/// parser sees them so that the message says which length is wrong; "" when they hold together.
std::string glbContainerProblem(std::string_view bytes) {
  constexpr std::size_t kHeader = 12, kChunkHeader = 8;
  constexpr std::uint32_t kJson = 0x4E4F534A, kBin = 0x004E4942;
  if (bytes.size() < kHeader + kChunkHeader) return "shorter than a .glb header and its JSON chunk's header (20 bytes)";
  const std::string size = std::to_string(bytes.size());
  if (littleEndian32(bytes, 4) != 2) return "a .glb of version " + std::to_string(littleEndian32(bytes, 4)) + ", not 2";
  if (littleEndian32(bytes, 8) != bytes.size())
    return "the .glb header's length " + std::to_string(littleEndian32(bytes, 8)) + " is not the file's " + size +
           " bytes";
  const std::uint64_t jsonLength = littleEndian32(bytes, 12);
  if (littleEndian32(bytes, 16) != kJson) return "the .glb's first chunk is not its JSON chunk";
  if (kHeader + kChunkHeader + jsonLength > bytes.size())
    return "the JSON chunk's length " + std::to_string(jsonLength) + " runs past the end of the file (" + size +
           " bytes)";
  const std::uint64_t bin = kHeader + kChunkHeader + jsonLength;
  if (bin + kChunkHeader <= bytes.size()) {
    const std::uint64_t binLength = littleEndian32(bytes, bin);
    if (littleEndian32(bytes, bin + 4) == kBin && bin + kChunkHeader + binLength > bytes.size())
      return "the BIN chunk's length " + std::to_string(binLength) + " runs past the end of the file (" + size +
             " bytes)";
  }
  return "";
}

/// Parses and builds; the problem names the glTF object or the parser's complaint.
GltfModel build(std::string_view bytes, const std::string& folder) {
  GltfModel out;
  try {
    if (bytes.size() > std::numeric_limits<unsigned>::max()) {
      out.problem = "larger than the 4 GiB a glTF file may hold";
      return out;
    }
    tinygltf::TinyGLTF parser;
    parser.SetFsCallbacks({&fileExists, &expandNothing, &readWholeFile, &refuseWriting, nullptr});
    Document doc;
    std::string err, warn;
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), kGlbMagic, 4) == 0;
    if (binary) {
      out.problem = glbContainerProblem(bytes);
      if (!out.problem.empty()) return out;
    }
    const unsigned length = static_cast<unsigned>(bytes.size());
    const bool parsed =
        binary ? parser.LoadBinaryFromMemory(&doc, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                             length, folder)
               : parser.LoadASCIIFromString(&doc, &err, &warn, bytes.data(), length, folder);
    if (!parsed) {
      out.problem = std::string(binary ? "not a valid .glb file" : "not a valid glTF file") + " (" +
                    oneLine(err.empty() ? warn : err) + ")";
      return out;
    }
    out.node = GraphBuilder(doc, out.notes).build();
  } catch (const GltfProblem& e) {
    out.node = nullptr;
    out.problem = e.what();
  } catch (const std::bad_alloc&) {
    out.node = nullptr;
    out.problem = "ran out of memory";
  }
  return out;
}

}  // namespace

bool isGltfPath(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".gltf" || ext == ".glb";
}

GltfModel readGltfModel(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    GltfModel out;
    out.problem = "could not be opened";
    return out;
  }
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const fs::path folder = fs::path(path).parent_path();
  return gltfModelFromBytes(bytes, folder.empty() ? std::string(".") : folder.string());
}

GltfModel gltfModelFromBytes(std::string_view bytes, const std::string& folder) { return build(bytes, folder); }

}  // namespace nestwalk
