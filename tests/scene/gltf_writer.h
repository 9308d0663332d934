// A small glTF 2.0 document builder for the tests: accessors over one binary buffer, written as
// a .glb (JSON and BIN chunks), as a .gltf with the buffer beside it, or as a .gltf with the buffer
// in a base64 data URI. It writes exactly what the test asks for (including broken references), so
// the reader's checks can be driven one by one; it validates nothing.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace nestwalk::test {

/// RFC 4648 base64 (for data URIs).
inline std::string base64(const std::string& bytes) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = (std::uint32_t(std::uint8_t(bytes[i])) << 16) |
                            (std::uint32_t(std::uint8_t(bytes[i + 1])) << 8) | std::uint8_t(bytes[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += alphabet[(v >> s) & 63];
  }
  if (i < bytes.size()) {
    std::uint32_t v = std::uint32_t(std::uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? alphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

struct GltfWriter {
  nlohmann::json doc = {{"asset", {{"version", "2.0"}, {"generator", "nestwalk tests"}}}};
  std::string bin;  // buffer 0's bytes

  /// Appends `bytes` to buffer 0 (4-byte aligned) as a new buffer view; returns its index.
  int addView(const void* data, std::size_t bytes, std::size_t stride = 0) {
    while (bin.size() % 4) bin.push_back('\0');
    nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
    if (stride) view["byteStride"] = stride;
    bin.append(static_cast<const char*>(data), bytes);
    doc["bufferViews"].push_back(view);
    return static_cast<int>(doc["bufferViews"].size()) - 1;
  }
  /// A new accessor over a new view holding `values`; returns its index.
  template <class T>
  int addAccessor(const std::vector<T>& values, int componentType, const char* type, std::size_t count,
                  bool normalized = false) {
    const int view = addView(values.data(), values.size() * sizeof(T));
    nlohmann::json a = {{"bufferView", view}, {"componentType", componentType}, {"type", type}, {"count", count}};
    if (normalized) a["normalized"] = true;
    doc["accessors"].push_back(a);
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
  int addPositions(const std::vector<float>& xyz) { return addAccessor(xyz, 5126, "VEC3", xyz.size() / 3); }

  /// A mesh of the given primitives; returns its index.
  int addMesh(const nlohmann::json& primitives) {
    doc["meshes"].push_back({{"primitives", primitives}});
    return static_cast<int>(doc["meshes"].size()) - 1;
  }
  int addNode(const nlohmann::json& node) {
    doc["nodes"].push_back(node);
    return static_cast<int>(doc["nodes"].size()) - 1;
  }
  void setScene(const std::vector<int>& roots) {
    doc["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }

  /// The .glb container: header, JSON chunk (space-padded), BIN chunk (zero-padded).
  /// `claimedBufferBytes` replaces buffer 0's true byteLength (a buffer that claims more than the
  /// BIN chunk holds).
  std::string glb(std::size_t claimedBufferBytes = 0) const {
    nlohmann::json d = doc;
    d["buffers"] = nlohmann::json::array({{{"byteLength", claimedBufferBytes ? claimedBufferBytes : bin.size()}}});
    std::string json = d.dump();
    while (json.size() % 4) json.push_back(' ');
    std::string body = bin;
    while (body.size() % 4) body.push_back('\0');
    std::string out = "glTF";
    auto u32 = [&out](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + body.size()));
    u32(static_cast<std::uint32_t>(json.size()));
    u32(0x4E4F534A);  // "JSON"
    out += json;
    u32(static_cast<std::uint32_t>(body.size()));
    u32(0x004E4942);  // "BIN\0"
    out += body;
    return out;
  }
  /// The .gltf JSON with buffer 0 as `uri` (a file written beside it by writeGltf, or a data URI).
  std::string gltf(const std::string& uri) const {
    nlohmann::json d = doc;
    d["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}, {"uri", uri}}});
    return d.dump(1);
  }
  std::string gltfWithDataUri() const { return gltf("data:application/octet-stream;base64," + base64(bin)); }
};

inline void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

}  // namespace nestwalk::test
