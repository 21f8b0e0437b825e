// Test-only: builds small glTF files by hand (JSON + one binary buffer), so
// the reader can be checked on exactly the structures the spec lists.
#pragma once

#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace restitch::test {

inline std::string base64(const std::vector<std::uint8_t>& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const std::uint32_t v = (in[i] << 16) | (in[i + 1] << 8) | in[i + 2];
    out += t[v >> 18], out += t[(v >> 12) & 63], out += t[(v >> 6) & 63], out += t[v & 63];
  }
  if (i + 1 == in.size()) {
    const std::uint32_t v = in[i] << 16;
    out += t[v >> 18], out += t[(v >> 12) & 63], out += "==";
  } else if (i + 2 == in.size()) {
    const std::uint32_t v = (in[i] << 16) | (in[i + 1] << 8);
    out += t[v >> 18], out += t[(v >> 12) & 63], out += t[(v >> 6) & 63], out += '=';
  }
  return out;
}

/// Accumulates buffer views and accessors into one buffer.
struct GltfBuilder {
  nlohmann::json j = {{"asset", {{"version", "2.0"}}},          {"buffers", nlohmann::json::array()},
                      {"bufferViews", nlohmann::json::array()}, {"accessors", nlohmann::json::array()},
                      {"meshes", nlohmann::json::array()},      {"nodes", nlohmann::json::array()},
                      {"scenes", nlohmann::json::array()}};
  std::vector<std::uint8_t> bin;

  int view(const void* data, std::size_t bytes) {
    while (bin.size() % 4) bin.push_back(0);
    const std::size_t off = bin.size();
    bin.insert(bin.end(), static_cast<const std::uint8_t*>(data), static_cast<const std::uint8_t*>(data) + bytes);
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", bytes}});
    return int(j["bufferViews"].size()) - 1;
  }
  int floats(const std::vector<float>& v, const char* type, int comps, bool minmax = false) {
    const int bv = view(v.data(), v.size() * 4);
    nlohmann::json a = {{"bufferView", bv}, {"componentType", 5126}, {"count", v.size() / comps}, {"type", type}};
    if (minmax) {
      std::vector<float> lo(comps, 1e30f), hi(comps, -1e30f);
      for (std::size_t i = 0; i < v.size(); ++i)
        lo[i % comps] = std::min(lo[i % comps], v[i]), hi[i % comps] = std::max(hi[i % comps], v[i]);
      a["min"] = lo, a["max"] = hi;
    }
    j["accessors"].push_back(a);
    return int(j["accessors"].size()) - 1;
  }
  int indices(const std::vector<std::uint16_t>& v) {
    const int bv = view(v.data(), v.size() * 2);
    j["accessors"].push_back({{"bufferView", bv}, {"componentType", 5123}, {"count", v.size()}, {"type", "SCALAR"}});
    return int(j["accessors"].size()) - 1;
  }
  /// Finishes with the buffer embedded as a data URI; returns the JSON text.
  std::string gltf_text() {
    nlohmann::json k = j;
    k["buffers"] = {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
    return k.dump();
  }
  /// Finishes as a .glb (JSON chunk + BIN chunk).
  std::vector<std::uint8_t> glb() {
    nlohmann::json k = j;
    std::vector<std::uint8_t> b = bin;
    while (b.size() % 4) b.push_back(0);
    k["buffers"] = {{{"byteLength", b.size()}}};
    std::string js = k.dump();
    while (js.size() % 4) js += ' ';
    std::vector<std::uint8_t> out;
    auto u32 = [&](std::uint32_t v) {
      for (int i = 0; i < 4; ++i) out.push_back(std::uint8_t(v >> (8 * i)));
    };
    out.insert(out.end(), {'g', 'l', 'T', 'F'});
    u32(2);
    u32(std::uint32_t(12 + 8 + js.size() + 8 + b.size()));
    u32(std::uint32_t(js.size()));
    out.insert(out.end(), {'J', 'S', 'O', 'N'});
    out.insert(out.end(), js.begin(), js.end());
    u32(std::uint32_t(b.size()));
    out.insert(out.end(), {'B', 'I', 'N', 0});
    out.insert(out.end(), b.begin(), b.end());
    return out;
  }
};

/// A unit quad (two triangles) in the z = 0 plane with normals and UVs.
inline int add_quad_mesh(GltfBuilder& b, int mode = 4, bool indexed = true, int material = -1) {
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::vector<float> nrm = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const std::vector<float> uv = {0, 1, 1, 1, 1, 0, 0, 0};
  nlohmann::json prim = {{"attributes",
                          {{"POSITION", b.floats(pos, "VEC3", 3, true)},
                           {"NORMAL", b.floats(nrm, "VEC3", 3)},
                           {"TEXCOORD_0", b.floats(uv, "VEC2", 2)}}},
                         {"mode", mode}};
  if (indexed) {
    std::vector<std::uint16_t> idx = mode == 4   ? std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3}
                                     : mode == 5 ? std::vector<std::uint16_t>{0, 1, 3, 2}
                                                 : std::vector<std::uint16_t>{0, 1, 2, 3};
    prim["indices"] = b.indices(idx);
  }
  if (material >= 0) prim["material"] = material;
  b.j["meshes"].push_back({{"primitives", {prim}}});
  return int(b.j["meshes"].size()) - 1;
}

}  // namespace restitch::test
