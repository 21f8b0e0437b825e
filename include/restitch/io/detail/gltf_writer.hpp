// restitch/io/detail/gltf_writer.hpp - a Mesh as a glTF model, then as .glb or .gltf bytes.
//
// Part of restitch/io/gltf.hpp, which includes it after configuring and
// including tinygltf and after declaring GltfAssets; do not include it on its
// own.
//
// `build_model` writes one mesh, one node, one scene into a fresh model with
// a single buffer: the pass-through assets first (image bytes in their own
// bufferViews; an image whose format cannot be named is an unsupported
// error), or plain materials when the mesh has no assets; then one TRIANGLES
// primitive per non-empty group, in group order, whose vertices are the
// group's compacted in first-use order, with exactly the attributes the
// group carries (float POSITION with min/max, NORMAL, TANGENT, TEXCOORD_n,
// COLOR_0) and uint16 indices (uint32 past 65535 vertices). Every bufferView
// starts 4-byte aligned. `serialize` turns the model into bytes. The output
// depends only on the mesh: deterministic. Never throws.
//
// Cost: linear in the mesh size plus the image bytes.
#pragma once

#ifndef RESTITCH_GLTF_PARTS
#error "include restitch/io/gltf.hpp, not its detail parts"
#endif

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "restitch/io/detail/gltf_accessor.hpp"
#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch::detail {

inline void align4(std::vector<unsigned char>& buf) {
  while (buf.size() % 4) buf.push_back(0);
}

// Appends a bufferView + accessor holding `values` (count x comps floats).
template <class = void>
int add_float_accessor(tinygltf::Model& m, const std::vector<float>& values, int comps, int type, bool minmax) {
  std::vector<unsigned char>& buf = m.buffers[0].data;
  align4(buf);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buf.size();
  view.byteLength = values.size() * sizeof(float);
  view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
  const auto* p = reinterpret_cast<const unsigned char*>(values.data());
  buf.insert(buf.end(), p, p + view.byteLength);
  m.bufferViews.push_back(view);
  tinygltf::Accessor acc;
  acc.bufferView = int(m.bufferViews.size()) - 1;
  acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  acc.count = values.size() / comps;
  acc.type = type;
  if (minmax) {
    acc.minValues.assign(comps, INFINITY);
    acc.maxValues.assign(comps, -INFINITY);
    for (std::size_t i = 0; i < acc.count; ++i)
      for (int c = 0; c < comps; ++c) {
        acc.minValues[c] = std::min(acc.minValues[c], double(values[i * comps + c]));
        acc.maxValues[c] = std::max(acc.maxValues[c], double(values[i * comps + c]));
      }
  }
  m.accessors.push_back(acc);
  return int(m.accessors.size()) - 1;
}

// Appends a bufferView + accessor holding `idx`: uint16 when the primitive
// has at most 65535 vertices, else uint32.
template <class = void>
int add_index_accessor(tinygltf::Model& m, const std::vector<std::uint32_t>& idx, std::size_t vertex_count) {
  std::vector<unsigned char>& buf = m.buffers[0].data;
  align4(buf);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buf.size();
  view.target = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
  tinygltf::Accessor acc;
  if (vertex_count <= 65535) {
    std::vector<std::uint16_t> s(idx.begin(), idx.end());
    const auto* p = reinterpret_cast<const unsigned char*>(s.data());
    buf.insert(buf.end(), p, p + s.size() * 2);
    view.byteLength = s.size() * 2;
    acc.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  } else {
    const auto* p = reinterpret_cast<const unsigned char*>(idx.data());
    buf.insert(buf.end(), p, p + idx.size() * 4);
    view.byteLength = idx.size() * 4;
    acc.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  }
  m.bufferViews.push_back(view);
  acc.bufferView = int(m.bufferViews.size()) - 1;
  acc.count = idx.size();
  acc.type = TINYGLTF_TYPE_SCALAR;
  m.accessors.push_back(acc);
  return int(m.accessors.size()) - 1;
}

// Copies the pass-through assets into `m`, each image's bytes into its own bufferView.
template <class = void>
Status add_assets(const GltfAssets& assets, tinygltf::Model& m) {
  const tinygltf::Model& a = assets.model;
  m.asset.copyright = a.asset.copyright;
  m.materials = a.materials;
  m.textures = a.textures;
  m.samplers = a.samplers;
  m.extensionsUsed = a.extensionsUsed;
  m.extensionsRequired = a.extensionsRequired;
  for (const tinygltf::Image& im : a.images) {
    tinygltf::Image out = im;
    out.image.clear();
    if (!im.image.empty()) {
      std::vector<unsigned char>& buf = m.buffers[0].data;
      align4(buf);
      tinygltf::BufferView view;
      view.buffer = 0;
      view.byteOffset = buf.size();
      view.byteLength = im.image.size();
      buf.insert(buf.end(), im.image.begin(), im.image.end());
      m.bufferViews.push_back(view);
      out.bufferView = int(m.bufferViews.size()) - 1;
      out.uri.clear();
      if (out.mimeType.empty()) out.mimeType = sniff_mime(im.image);
      if (out.mimeType.empty())
        return error(StatusCode::unsupported, "image " + std::to_string(&im - a.images.data()) +
                                                  " is in a format restitch cannot name (not PNG, JPEG, WebP or KTX2)");
    }
    m.images.push_back(out);
  }
  return {};
}

// Writes the mesh's plain materials (when there are no assets).
template <class = void>
void add_plain_materials(const Mesh& mesh, tinygltf::Model& m) {
  for (const Material& mat : mesh.materials) {
    tinygltf::Material gm;
    gm.name = mat.name;
    gm.pbrMetallicRoughness.baseColorFactor = {mat.base_color[0], mat.base_color[1], mat.base_color[2],
                                               mat.base_color[3]};
    gm.pbrMetallicRoughness.metallicFactor = mat.metallic;
    gm.pbrMetallicRoughness.roughnessFactor = mat.roughness;
    gm.doubleSided = mat.double_sided;
    m.materials.push_back(gm);
  }
}

// The primitive of group `g` (faces `faces`, in face order): its vertices
// compacted in first-use order, with the group's attributes. `remap` is
// all -1 on entry and on return.
template <class = void>
tinygltf::Primitive group_primitive(const Mesh& mesh, std::size_t g, const std::vector<std::uint32_t>& faces,
                                           std::vector<std::int64_t>& remap, tinygltf::Model& m) {
  const AttributeSet& a = mesh.groups[g].attributes;
  std::vector<std::uint32_t> used, idx;
  for (std::uint32_t f : faces)
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t v = mesh.F(f, c);
      if (remap[v] < 0) remap[v] = std::int64_t(used.size()), used.push_back(v);
      idx.push_back(std::uint32_t(remap[v]));
    }
  for (std::uint32_t v : used) remap[v] = -1;
  auto gather = [&](auto&& row, int comps) {
    std::vector<float> out;
    out.reserve(used.size() * comps);
    for (std::uint32_t v : used)
      for (int c = 0; c < comps; ++c) out.push_back(row(v, c));
    return out;
  };
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.material = mesh.groups[g].material;
  prim.attributes["POSITION"] = add_float_accessor(m, gather([&](std::uint32_t v, int c) { return mesh.V(v, c); }, 3),
                                                   3, TINYGLTF_TYPE_VEC3, true);
  if (a.normals)
    prim.attributes["NORMAL"] = add_float_accessor(m, gather([&](std::uint32_t v, int c) { return mesh.N(v, c); }, 3),
                                                   3, TINYGLTF_TYPE_VEC3, false);
  if (a.tangents)
    prim.attributes["TANGENT"] = add_float_accessor(m, gather([&](std::uint32_t v, int c) { return mesh.T(v, c); }, 4),
                                                    4, TINYGLTF_TYPE_VEC4, false);
  for (int s = 0; s < a.uv_sets; ++s)
    prim.attributes["TEXCOORD_" + std::to_string(s)] = add_float_accessor(
        m, gather([&](std::uint32_t v, int c) { return mesh.UV[s](v, c); }, 2), 2, TINYGLTF_TYPE_VEC2, false);
  if (a.color_components)
    prim.attributes["COLOR_0"] = add_float_accessor(
        m, gather([&](std::uint32_t v, int c) { return mesh.C(v, c); }, a.color_components), a.color_components,
        a.color_components == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4, false);
  prim.indices = add_index_accessor(m, idx, used.size());
  return prim;
}

// The mesh as a fresh model (see the header comment).
template <class = void>
Status build_model(const Mesh& mesh, tinygltf::Model& m) {
  RESTITCH_TRY(validate(mesh));
  m = tinygltf::Model();
  m.asset.version = "2.0";
  m.asset.generator = "restitch";
  m.buffers.emplace_back();
  if (mesh.assets)
    RESTITCH_TRY(add_assets(*mesh.assets, m));
  else
    add_plain_materials(mesh, m);

  tinygltf::Mesh gm;
  gm.name = "restitch";
  // Faces of each group, in face order.
  std::vector<std::vector<std::uint32_t>> faces_of(mesh.groups.size());
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) faces_of[mesh.FG(f)].push_back(std::uint32_t(f));
  std::vector<std::int64_t> remap(mesh.V.rows(), -1);
  for (std::size_t g = 0; g < mesh.groups.size(); ++g)
    if (!faces_of[g].empty()) gm.primitives.push_back(group_primitive(mesh, g, faces_of[g], remap, m));
  align4(m.buffers[0].data);
  m.meshes.push_back(gm);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = "restitch";
  m.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  m.scenes.push_back(scene);
  m.defaultScene = 0;
  return {};
}

// The model as bytes: binary .glb, or pretty-printed JSON with the buffer as a data URI.
template <class = void>
Status serialize(const tinygltf::Model& m, bool binary, std::vector<std::uint8_t>& out) {
  std::ostringstream os;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&m, os, /*prettyPrint=*/!binary, binary))
    return error(StatusCode::internal, "the glTF writer failed");
  const std::string s = os.str();
  out.assign(s.begin(), s.end());
  return {};
}

}  // namespace restitch::detail
