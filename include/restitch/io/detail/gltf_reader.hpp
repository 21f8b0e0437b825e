// restitch/io/detail/gltf_reader.hpp - glTF bytes parsed, then flattened into one world-space Mesh.
//
// Part of restitch/io/gltf.hpp, which includes it after configuring and
// including tinygltf and after declaring the public types; do not include it
// on its own.
//
// `parse_model` runs tinygltf on .glb or .gltf bytes (image bytes kept as
// they are, never decoded; truncated or foreign bytes refused with a message
// saying which). `build_mesh` turns the parsed model into a Mesh: file-level
// checks, the scene walk (gltf_scene.hpp), each instanced mesh decoded once
// at its first instance with a usable transform (gltf_primitives.hpp), then
// every instance placed in world space, primitives grouped by (material,
// attribute set) in first-seen order, the groups flattened into the mesh,
// and materials and assets attached. Warnings and errors come in the order
// of a single depth-first pass. Never throws.
//
// Cost: linear in the file size plus the instanced vertex count.
#pragma once

#ifndef RESTITCH_GLTF_PARTS
#error "include restitch/io/gltf.hpp, not its detail parts"
#endif

#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "restitch/io/detail/gltf_primitives.hpp"
#include "restitch/io/detail/gltf_scene.hpp"
#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch::detail {

// Image bytes are kept as they are: resizing never touches textures.
template <class = void>
bool keep_image_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                             const unsigned char* bytes, int size, void*) {
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  image->width = image->height = -1;
  image->component = -1;
  return true;
}

inline bool has_glb_magic(const std::uint8_t* data, std::size_t size) {
  return size >= 4 && std::memcmp(data, "glTF", 4) == 0;
}

template <class = void>
Status parse_model(const std::uint8_t* data, std::size_t size, const std::string& base_dir, bool binary,
                          tinygltf::Model& model, GltfLoadReport& report) {
  if (size == 0) return error(StatusCode::parse_error, "the file is empty");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&keep_image_bytes, nullptr);
  loader.SetPreserveImageChannels(true);
  std::string err, warn;
  bool ok;
  if (binary) {
    if (size < 20)
      return error(StatusCode::parse_error, "the binary glTF is truncated (shorter than its 20-byte header)");
    std::uint32_t declared = 0;
    std::memcpy(&declared, data + 8, 4);
    if (declared > size)
      return error(StatusCode::parse_error, "the binary glTF is truncated: its header declares " +
                                                std::to_string(declared) + " bytes but the file has " +
                                                std::to_string(size));
    ok = loader.LoadBinaryFromMemory(&model, &err, &warn, data, unsigned(size), base_dir);
  } else {
    if (data[0] != '{' && !std::isspace(data[0]))
      return error(StatusCode::parse_error,
                   "not a glTF file: it neither starts with the binary magic 'glTF' nor is JSON");
    ok = loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(data), unsigned(size), base_dir);
  }
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    for (auto& ch : err)
      if (ch == '\n') ch = ';';
    return error(StatusCode::parse_error,
                 "not a valid glTF file: " + (err.empty() ? std::string("unknown reason") : err));
  }
  if (!warn.empty()) {
    std::istringstream ws(warn);
    for (std::string line; std::getline(ws, line);)
      if (!line.empty()) report.warnings.push_back("glTF reader: " + line);
  }
  return {};
}

// Placed primitives grouped by (material, attribute set), in first-seen order.
struct PrimitiveGroups {
  std::vector<PrimitiveData> data;
  std::vector<std::pair<int, AttributeSet>> keys;
  std::vector<std::string> names;  // the `where` of every primitive instance, comma-separated

  // The data of the group for `p`'s key (a new group if none has it yet).
  template <class = void>
  PrimitiveData& group_for(const DecodedPrimitive& p) {
    std::size_t g = 0;
    while (g < keys.size() && !(keys[g].first == p.material && keys[g].second == p.attributes)) ++g;
    if (g == keys.size()) {
      keys.emplace_back(p.material, p.attributes);
      data.emplace_back();
      names.push_back(p.where);
    } else {
      names[g] += ", " + p.where;
    }
    return data[g];
  }
};

// Meshes decoded so far, each at its first usable instance.
struct DecodedMeshes {
  std::vector<DecodedMesh> meshes;
  std::vector<bool> done;
};

// Places every primitive of `inst`'s mesh in world space into `groups`,
// decoding the mesh first if no earlier instance did. A singular transform
// drops the instance with a warning (and decodes nothing).
template <class = void>
Status place_instance(const tinygltf::Model& model, const MeshInstance& inst, DecodedMeshes& decoded,
                             PrimitiveGroups& groups, GltfLoadReport& report, const GltfLimits& limits) {
  InstanceTransform xf;
  xf.world = inst.world;
  xf.L = xf.world.block<3, 3>(0, 0);
  const double det = xf.L.determinant();
  if (!(std::abs(det) > 0)) {
    add_warning(report.warnings, "node " + std::to_string(inst.node) +
                                     " has a singular transform (zero scale): its geometry is dropped");
    return {};
  }
  xf.Ln = xf.L.inverse().transpose();
  xf.mirrored = det < 0;
  if (!decoded.done[inst.mesh]) {
    RESTITCH_TRY(decode_mesh(model, inst.mesh, decoded.meshes[inst.mesh], report.warnings, limits));
    decoded.done[inst.mesh] = true;
  }
  // The scene's totals with this instance, before it is placed: instancing a mesh many times (a node
  // tree) must not build more than the limits allow either.
  std::uint64_t nv = 0, nf = 0;
  for (const PrimitiveData& g : groups.data) nv += g.pos.size() / 3, nf += g.tris.size() / 3;
  for (const DecodedPrimitive& p : decoded.meshes[inst.mesh]) nv += p.data.pos.size() / 3, nf += p.data.tris.size() / 3;
  const std::string where = "the default scene (up to node " + std::to_string(inst.node) + ")";
  if (nv > limits.max_vertices) return over_limit(where, nv, "vertices", limits.max_vertices);
  if (nf > limits.max_triangles) return over_limit(where, nf, "triangles", limits.max_triangles);
  for (const DecodedPrimitive& p : decoded.meshes[inst.mesh]) {
    ++report.primitives;
    place_primitive(p.data, xf, groups.group_for(p));
  }
  return {};
}

// Flattens the groups into `mesh` (replacing it): vertices and faces group
// after group, channels sized for all vertices when any group has them.
template <class = void>
Status flatten_groups(const PrimitiveGroups& groups, Mesh& mesh) {
  std::size_t nv = 0, nf = 0;
  bool any_n = false, any_t = false, any_c = false;
  int max_uv = 0;
  for (std::size_t g = 0; g < groups.data.size(); ++g) {
    nv += groups.data[g].pos.size() / 3;
    nf += groups.data[g].tris.size() / 3;
    any_n |= groups.keys[g].second.normals;
    any_t |= groups.keys[g].second.tangents;
    any_c |= groups.keys[g].second.color_components > 0;
    max_uv = std::max(max_uv, groups.keys[g].second.uv_sets);
  }
  if (nf == 0) return error(StatusCode::invalid_mesh, "the default scene has no triangles (nothing to resize)");
  mesh = Mesh();
  mesh.V.resize(nv, 3);
  mesh.F.resize(nf, 3);
  mesh.FG.resize(nf);
  if (any_n) mesh.N.setZero(nv, 3);
  if (any_t) mesh.T.setZero(nv, 4);
  if (any_c) mesh.C.setOnes(nv, 4);
  mesh.UV.assign(max_uv, MatrixX2f::Zero(nv, 2));
  std::size_t v0 = 0, f0 = 0;
  for (std::size_t g = 0; g < groups.data.size(); ++g) {
    const PrimitiveData& d = groups.data[g];
    const AttributeSet& a = groups.keys[g].second;
    const std::size_t n = d.pos.size() / 3;
    for (std::size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) mesh.V(v0 + i, c) = float(d.pos[3 * i + c]);
      if (a.normals)
        for (int c = 0; c < 3; ++c) mesh.N(v0 + i, c) = float(d.nrm[3 * i + c]);
      if (a.tangents)
        for (int c = 0; c < 4; ++c) mesh.T(v0 + i, c) = float(d.tan[4 * i + c]);
      for (int s = 0; s < a.uv_sets; ++s)
        for (int c = 0; c < 2; ++c) mesh.UV[s](v0 + i, c) = float(d.uv[s][2 * i + c]);
      for (int c = 0; c < a.color_components; ++c) mesh.C(v0 + i, c) = float(d.col[a.color_components * i + c]);
    }
    for (std::size_t t = 0; t < d.tris.size() / 3; ++t) {
      for (int c = 0; c < 3; ++c) mesh.F(f0 + t, c) = std::uint32_t(v0 + d.tris[3 * t + c]);
      mesh.FG(f0 + t) = std::uint32_t(g);
    }
    v0 += n;
    f0 += d.tris.size() / 3;
    Group group;
    group.material = groups.keys[g].first;
    group.attributes = a;
    group.name = groups.names[g];
    mesh.groups.push_back(group);
  }
  return {};
}

// The parsed model as one world-space Mesh (see the header comment).
template <class = void>
Status build_mesh(const tinygltf::Model& model, Mesh& mesh, GltfLoadReport& report, const GltfLimits& limits) {
  RESTITCH_TRY(check_model(model, report.warnings));
  report.meshes = model.meshes.size();
  report.nodes = model.nodes.size();
  report.materials = model.materials.size();
  report.textures = model.textures.size();
  report.images = model.images.size();

  std::vector<MeshInstance> instances;
  const Status walked = walk_scene(model, instances);  // on error, the instances before it are still placed first
  DecodedMeshes decoded;
  decoded.meshes.resize(model.meshes.size());
  decoded.done.assign(model.meshes.size(), false);
  PrimitiveGroups groups;
  for (const MeshInstance& inst : instances) RESTITCH_TRY(place_instance(model, inst, decoded, groups, report, limits));
  RESTITCH_TRY(walked);

  RESTITCH_TRY(flatten_groups(groups, mesh));
  mesh.materials = plain_materials(model);
  mesh.assets = pass_through_assets(model);
  return validate(mesh);
}

}  // namespace restitch::detail
