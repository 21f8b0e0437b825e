// restitch/io/gltf.hpp - glTF 2.0 in and out, losing nothing a resize can carry.
//
// Reading (`load_gltf`, `load_gltf_from_memory`): .glb or .gltf (embedded,
// data-URI or external buffers and images). Every triangle primitive of the
// default scene is flattened into one restitch::Mesh in world space (node
// transforms applied: positions by the matrix, normals by its inverse
// transpose, tangents by its linear part; a mirroring transform flips the
// winding back). Indexed or not; modes TRIANGLES, TRIANGLE_STRIP and
// TRIANGLE_FAN; any accessor component type (normalized integers too, as in
// KHR_mesh_quantization) and sparse accessors. Primitives with the same
// material and the same attribute set become one group.
// Materials, textures, images, samplers and their extensions pass through
// unchanged (`Mesh::assets`): image bytes are kept as they are, never decoded.
//
// What restitch cannot carry is reported, never dropped silently: skins,
// morph targets, animations, cameras, POINTS and LINES primitives, vertex
// colour sets past COLOR_0 and custom attributes produce a warning that
// names what was dropped; a required extension restitch cannot decode
// (Draco, meshopt...) is an error.
//
// Bad input (missing file, a directory, wrong magic, truncated binary,
// broken JSON, an accessor or index out of range, NaN positions, no
// triangles in the default scene) gives a non-ok Status whose message names
// the problem.
//
// Writing (`save_gltf`, `save_glb_to_memory`): one mesh, one node, one scene;
// one primitive per group with exactly the attributes the group carries
// (float POSITION with min/max, NORMAL, TANGENT, TEXCOORD_n, COLOR_0; uint16
// or uint32 indices), and the pass-through assets (images stored in the
// binary buffer). `.glb` writes binary, `.gltf` writes JSON with the buffer as
// a data URI. The file is written to a temporary name in the same folder and
// renamed, so a failed save leaves no partial file. Output is deterministic.
//
// tinygltf is compiled in ONE translation unit of the program: there,
// `#define RESTITCH_GLTF_IMPLEMENTATION` before including this header (as
// with stb). Everywhere else include it plainly.
//
// Cost: linear in the file size.
#pragma once

#ifndef TINYGLTF_NOEXCEPTION
#define TINYGLTF_NOEXCEPTION
#endif
#ifndef TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE
#endif
#ifndef TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#endif
#ifndef TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#endif
#ifndef TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#endif
#ifdef RESTITCH_GLTF_IMPLEMENTATION
#define TINYGLTF_IMPLEMENTATION
#endif
#include <tiny_gltf.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "restitch/detail/file.hpp"
#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// The pass-through part of a glTF file (see mesh.hpp): its materials,
/// textures, images (raw encoded bytes in `Image::image`, `mimeType` set),
/// samplers, the asset's copyright, and the extensions they use.
struct GltfAssets {
  tinygltf::Model model;  // only materials, textures, images, samplers, extensionsUsed, asset are meaningful
};

/// What a load found besides the mesh.
struct GltfLoadReport {
  std::size_t meshes = 0;      ///< glTF meshes in the file
  std::size_t primitives = 0;  ///< triangle primitives instanced by the default scene
  std::size_t nodes = 0;       ///< nodes in the file
  std::size_t materials = 0;
  std::size_t textures = 0;
  std::size_t images = 0;
  std::vector<std::string> warnings;  ///< each names what was dropped and why
};

namespace detail {

inline Status gltf_error(StatusCode code, const std::string& where, const std::string& what) {
  return error(code, where.empty() ? what : where + ": " + what);
}

// Image bytes are kept as they are: resizing never touches textures.
inline bool keep_image_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                             const unsigned char* bytes, int size, void*) {
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  image->width = image->height = -1;
  image->component = -1;
  return true;
}

inline std::string sniff_mime(const std::vector<unsigned char>& b) {
  auto starts = [&](const char* magic, std::size_t n, std::size_t at = 0) {
    return b.size() >= at + n && std::memcmp(b.data() + at, magic, n) == 0;
  };
  if (starts("\x89PNG", 4)) return "image/png";
  if (starts("\xFF\xD8\xFF", 3)) return "image/jpeg";
  if (starts("RIFF", 4) && starts("WEBP", 4, 8)) return "image/webp";
  if (starts("\xABKTX 20", 7)) return "image/ktx2";
  return "";
}

// Reads accessor `index` as doubles (count by components), normalized
// integers mapped to [0,1] / [-1,1] per the glTF spec, sparse values applied.
inline Status read_accessor(const tinygltf::Model& m, int index, std::vector<double>& out, int& components,
                            const std::string& where) {
  if (index < 0 || index >= int(m.accessors.size()))
    return gltf_error(
        StatusCode::parse_error, where,
        "refers to accessor " + std::to_string(index) + ", but the file has " + std::to_string(m.accessors.size()));
  const tinygltf::Accessor& a = m.accessors[index];
  const std::string here = where + " (accessor " + std::to_string(index) + ")";
  components = tinygltf::GetNumComponentsInType(a.type);
  const int csize = tinygltf::GetComponentSizeInBytes(a.componentType);
  if (components <= 0 || csize <= 0) return gltf_error(StatusCode::parse_error, here, "has an unknown type");
  if (a.type == TINYGLTF_TYPE_MAT2 || a.type == TINYGLTF_TYPE_MAT3 || a.type == TINYGLTF_TYPE_MAT4)
    return gltf_error(StatusCode::unsupported, here, "is a matrix accessor, not a vertex attribute");
  const std::size_t count = a.count;
  if (count > (std::size_t(1) << 31)) return gltf_error(StatusCode::parse_error, here, "has an absurd count");
  out.assign(count * components, 0.0);

  auto decode = [&](const unsigned char* p, int comp_type, bool normalized) -> double {
    switch (comp_type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, p, 4);
        return f;
      }
      case TINYGLTF_COMPONENT_TYPE_DOUBLE: {
        double d;
        std::memcpy(&d, p, 8);
        return d;
      }
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        std::int8_t v;
        std::memcpy(&v, p, 1);
        return normalized ? std::max(v / 127.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
        std::uint8_t v;
        std::memcpy(&v, p, 1);
        return normalized ? v / 255.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? std::max(v / 32767.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? v / 65535.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_INT: {
        std::int32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
    }
    return 0.0;
  };
  // Locates `n` elements of `elem_size` bytes in bufferView `bv` at `offset` with `stride`.
  auto locate = [&](int bv, std::size_t offset, std::size_t stride, std::size_t elem, std::size_t n,
                    const unsigned char*& base) -> Status {
    if (bv < 0 || bv >= int(m.bufferViews.size()))
      return gltf_error(StatusCode::parse_error, here,
                        "refers to bufferView " + std::to_string(bv) + ", which does not exist");
    const tinygltf::BufferView& view = m.bufferViews[bv];
    if (view.buffer < 0 || view.buffer >= int(m.buffers.size()))
      return gltf_error(StatusCode::parse_error, here, "its bufferView refers to a buffer that does not exist");
    const tinygltf::Buffer& buf = m.buffers[view.buffer];
    if (n == 0) {
      base = nullptr;
      return {};
    }
    const std::size_t need = offset + stride * (n - 1) + elem;
    if (view.byteOffset + view.byteLength > buf.data.size() || need > view.byteLength)
      return gltf_error(StatusCode::parse_error, here,
                        "reads past the end of its data (needs " + std::to_string(need) + " bytes of bufferView " +
                            std::to_string(bv) + ", which has " + std::to_string(view.byteLength) + "; buffer " +
                            std::to_string(view.buffer) + " holds " + std::to_string(buf.data.size()) + ")");
    base = buf.data.data() + view.byteOffset + offset;
    return {};
  };

  const std::size_t elem = std::size_t(components) * csize;
  if (a.bufferView >= 0) {
    const tinygltf::BufferView& view =
        m.bufferViews.size() > std::size_t(a.bufferView) ? m.bufferViews[a.bufferView] : tinygltf::BufferView();
    const std::size_t stride = view.byteStride ? view.byteStride : elem;
    const unsigned char* base = nullptr;
    RESTITCH_TRY(locate(a.bufferView, a.byteOffset, stride, elem, count, base));
    for (std::size_t i = 0; i < count; ++i)
      for (int c = 0; c < components; ++c)
        out[i * components + c] = decode(base + i * stride + std::size_t(c) * csize, a.componentType, a.normalized);
  }
  if (a.sparse.isSparse) {
    const std::size_t n = a.sparse.count;
    const int isize = tinygltf::GetComponentSizeInBytes(a.sparse.indices.componentType);
    if (isize <= 0 || n > count) return gltf_error(StatusCode::parse_error, here, "has a malformed sparse block");
    const unsigned char* ib = nullptr;
    const unsigned char* vb = nullptr;
    RESTITCH_TRY(locate(a.sparse.indices.bufferView, a.sparse.indices.byteOffset, isize, isize, n, ib));
    RESTITCH_TRY(locate(a.sparse.values.bufferView, a.sparse.values.byteOffset, elem, elem, n, vb));
    for (std::size_t s = 0; s < n; ++s) {
      const double idx = decode(ib + s * isize, a.sparse.indices.componentType, false);
      if (!(idx >= 0 && idx < double(count)))
        return gltf_error(StatusCode::parse_error, here, "has a sparse index out of range");
      for (int c = 0; c < components; ++c)
        out[std::size_t(idx) * components + c] =
            decode(vb + s * elem + std::size_t(c) * csize, a.componentType, a.normalized);
    }
  }
  return {};
}

inline Eigen::Matrix4d node_local_matrix(const tinygltf::Node& n) {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  if (n.matrix.size() == 16) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) M(r, c) = n.matrix[c * 4 + r];  // column-major
    return M;
  }
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity(), R = Eigen::Matrix4d::Identity(), S = Eigen::Matrix4d::Identity();
  if (n.translation.size() == 3)
    T.block<3, 1>(0, 3) = Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]);
  if (n.rotation.size() == 4) {
    Eigen::Quaterniond q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
    if (q.norm() > 0) q.normalize();
    R.block<3, 3>(0, 0) = q.toRotationMatrix();
  }
  if (n.scale.size() == 3) S.diagonal().head<3>() = Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]);
  return T * R * S;
}

// Vertex data of one primitive instance, before merging into the mesh.
struct PrimitiveData {
  std::vector<double> pos, nrm, tan, col;
  std::vector<std::vector<double>> uv;
  int col_components = 0;
  std::vector<std::uint32_t> tris;  // corner indices into this primitive's vertices
};

// Turns a primitive's index list (or implicit 0..n-1) into triangles per its mode.
inline void triangulate(int mode, const std::vector<std::uint32_t>& idx, std::vector<std::uint32_t>& tris) {
  const std::size_t n = idx.size();
  // Triangles are kept as the file has them, degenerate ones included (they
  // carry no surface, and dropping them would change the file's counts);
  // only the zero-area joints a strip uses to restart are skipped.
  auto push = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    tris.push_back(a), tris.push_back(b), tris.push_back(c);
  };
  auto push_strip = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (a != b && b != c && a != c) push(a, b, c);
  };
  if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (std::size_t i = 2; i < n; ++i)
      (i % 2 == 0) ? push_strip(idx[i - 2], idx[i - 1], idx[i]) : push_strip(idx[i - 1], idx[i - 2], idx[i]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (std::size_t i = 2; i < n; ++i) push(idx[0], idx[i - 1], idx[i]);
  } else {
    for (std::size_t i = 0; i + 2 < n; i += 3) push(idx[i], idx[i + 1], idx[i + 2]);
  }
}

inline const char* mode_name(int mode) {
  switch (mode) {
    case TINYGLTF_MODE_POINTS:
      return "POINTS";
    case TINYGLTF_MODE_LINE:
      return "LINES";
    case TINYGLTF_MODE_LINE_LOOP:
      return "LINE_LOOP";
    case TINYGLTF_MODE_LINE_STRIP:
      return "LINE_STRIP";
  }
  return "an unknown mode";
}

// Extensions restitch decodes or passes through untouched with the materials.
inline bool extension_is_carried(const std::string& e) {
  static const char* known[] = {"KHR_materials_",
                                "KHR_texture_transform",
                                "KHR_texture_basisu",
                                "EXT_texture_webp",
                                "EXT_texture_avif",
                                "KHR_mesh_quantization",
                                "KHR_materials_emissive_strength"};
  for (const char* k : known)
    if (e.rfind(k, 0) == 0) return true;
  return false;
}

inline Status build_mesh(const tinygltf::Model& model, Mesh& mesh, GltfLoadReport& report) {
  auto warn = [&](std::string w) {
    if (std::find(report.warnings.begin(), report.warnings.end(), w) == report.warnings.end())
      report.warnings.push_back(std::move(w));
  };
  for (const std::string& e : model.extensionsRequired)
    if (!extension_is_carried(e))
      return error(StatusCode::unsupported, "the file requires the extension " + e +
                                                ", which restitch cannot decode (re-export the model without it)");
  for (const std::string& e : model.extensionsUsed)
    if (!extension_is_carried(e)) warn("extension " + e + " is not carried: what it adds is dropped");
  if (!model.animations.empty())
    warn(std::to_string(model.animations.size()) + " animation(s) dropped: the output is static");
  if (!model.skins.empty()) warn(std::to_string(model.skins.size()) + " skin(s) dropped: the output is not skinned");
  if (!model.cameras.empty()) warn(std::to_string(model.cameras.size()) + " camera(s) dropped");

  report.meshes = model.meshes.size();
  report.nodes = model.nodes.size();
  report.materials = model.materials.size();
  report.textures = model.textures.size();
  report.images = model.images.size();

  // Roots: the default scene; a file without scenes has nothing to show.
  std::vector<int> roots;
  if (model.scenes.empty()) {
    return error(StatusCode::invalid_mesh, "the file has no scene, so nothing to resize");
  }
  int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (scene >= int(model.scenes.size()))
    return error(StatusCode::parse_error, "the default scene index is out of range");
  roots = model.scenes[scene].nodes;

  // Depth-first traversal with world matrices; a cycle or a bad index is an error.
  struct Item {
    int node;
    Eigen::Matrix4d world;
    int depth;
  };
  std::vector<Item> stack;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, Eigen::Matrix4d::Identity(), 0});
  std::vector<int> visits(model.nodes.size(), 0);

  // Groups by (material, attribute set), in first-seen order.
  std::vector<PrimitiveData> group_data;
  std::vector<std::pair<int, AttributeSet>> group_keys;
  std::vector<std::string> group_names;

  while (!stack.empty()) {
    Item item = stack.back();
    stack.pop_back();
    if (item.node < 0 || item.node >= int(model.nodes.size()))
      return error(StatusCode::parse_error,
                   "the scene refers to node " + std::to_string(item.node) + ", which does not exist");
    if (++visits[item.node] > 1 || item.depth > 1024)
      return error(StatusCode::parse_error,
                   "node " + std::to_string(item.node) + " is reached twice: the node hierarchy is not a tree");
    const tinygltf::Node& node = model.nodes[item.node];
    const Eigen::Matrix4d world = item.world * node_local_matrix(node);
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back({*c, world, item.depth + 1});
    if (node.mesh < 0) continue;
    if (node.mesh >= int(model.meshes.size()))
      return error(StatusCode::parse_error, "node " + std::to_string(item.node) + " refers to mesh " +
                                                std::to_string(node.mesh) + ", which does not exist");
    if (!world.allFinite())
      return error(StatusCode::invalid_mesh, "node " + std::to_string(item.node) + " has a non-finite transform");
    const tinygltf::Mesh& gm = model.meshes[node.mesh];
    const Eigen::Matrix3d L = world.block<3, 3>(0, 0);
    const double det = L.determinant();
    if (!(std::abs(det) > 0)) {
      warn("node " + std::to_string(item.node) + " has a singular transform (zero scale): its geometry is dropped");
      continue;
    }
    const Eigen::Matrix3d Ln = L.inverse().transpose();
    const bool mirrored = det < 0;

    for (std::size_t pi = 0; pi < gm.primitives.size(); ++pi) {
      const tinygltf::Primitive& prim = gm.primitives[pi];
      const std::string where = "mesh " + std::to_string(node.mesh) + (gm.name.empty() ? "" : " '" + gm.name + "'") +
                                " primitive " + std::to_string(pi);
      const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
      if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
          mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        warn(where + " is " + mode_name(mode) + ", not triangles: dropped");
        continue;
      }
      if (!prim.targets.empty()) warn(where + ": " + std::to_string(prim.targets.size()) + " morph target(s) dropped");
      for (const auto& ext : prim.extensions)
        if (!extension_is_carried(ext.first)) warn(where + ": primitive extension " + ext.first + " dropped");
      auto pos_it = prim.attributes.find("POSITION");
      if (pos_it == prim.attributes.end()) {
        warn(where + " has no POSITION attribute: dropped");
        continue;
      }
      PrimitiveData d;
      int comps = 0;
      RESTITCH_TRY(read_accessor(model, pos_it->second, d.pos, comps, where + " POSITION"));
      if (comps != 3) return gltf_error(StatusCode::parse_error, where, "POSITION is not VEC3");
      const std::size_t nv = d.pos.size() / 3;
      for (std::size_t i = 0; i < d.pos.size(); ++i)
        if (!std::isfinite(d.pos[i]))
          return gltf_error(StatusCode::invalid_mesh, where,
                            "POSITION has a NaN or infinite coordinate at vertex " + std::to_string(i / 3));
      AttributeSet attrs;
      for (const auto& kv : prim.attributes) {
        const std::string& name = kv.first;
        std::vector<double> values;
        if (name == "POSITION") continue;
        if (name == "NORMAL" || name == "TANGENT" || name.rfind("TEXCOORD_", 0) == 0 || name.rfind("COLOR_", 0) == 0) {
          if (name.rfind("COLOR_", 0) == 0 && name != "COLOR_0") {
            warn(where + ": vertex colour set " + name + " dropped (only COLOR_0 is carried)");
            continue;
          }
          RESTITCH_TRY(read_accessor(model, kv.second, values, comps, where + " " + name));
          if (values.size() / std::max(comps, 1) != nv)
            return gltf_error(StatusCode::parse_error, where, name + " has a different count from POSITION");
          for (double v : values)
            if (!std::isfinite(v))
              return gltf_error(StatusCode::invalid_mesh, where, name + " has a NaN or infinite value");
        }
        if (name == "NORMAL") {
          if (comps != 3) return gltf_error(StatusCode::parse_error, where, "NORMAL is not VEC3");
          d.nrm = std::move(values), attrs.normals = true;
        } else if (name == "TANGENT") {
          if (comps != 4) return gltf_error(StatusCode::parse_error, where, "TANGENT is not VEC4");
          d.tan = std::move(values), attrs.tangents = true;
        } else if (name.rfind("TEXCOORD_", 0) == 0) {
          if (comps != 2) return gltf_error(StatusCode::parse_error, where, name + " is not VEC2");
          const int set = std::atoi(name.c_str() + 9);
          if (set < 0 || set > 7)
            return gltf_error(StatusCode::unsupported, where, name + " is past the 8 UV sets restitch carries");
          if (int(d.uv.size()) <= set) d.uv.resize(set + 1);
          d.uv[set] = std::move(values);
        } else if (name == "COLOR_0") {
          if (comps != 3 && comps != 4)
            return gltf_error(StatusCode::parse_error, where, "COLOR_0 is neither VEC3 nor VEC4");
          d.col = std::move(values), d.col_components = comps, attrs.color_components = comps;
        } else if (name.rfind("JOINTS_", 0) == 0 || name.rfind("WEIGHTS_", 0) == 0) {
          warn(where + ": skinning attribute " + name + " dropped");
        } else {
          warn(where + ": attribute " + name + " dropped (restitch carries normals, tangents, UVs and COLOR_0)");
        }
      }
      // UV sets must be contiguous from 0 to be written back as TEXCOORD_0..k.
      int uv_sets = 0;
      while (uv_sets < int(d.uv.size()) && !d.uv[uv_sets].empty()) ++uv_sets;
      if (uv_sets < int(d.uv.size())) {
        warn(where + ": UV sets after a missing TEXCOORD_" + std::to_string(uv_sets) + " dropped");
        d.uv.resize(uv_sets);
      }
      attrs.uv_sets = uv_sets;

      std::vector<std::uint32_t> idx;
      if (prim.indices >= 0) {
        std::vector<double> iv;
        RESTITCH_TRY(read_accessor(model, prim.indices, iv, comps, where + " indices"));
        if (comps != 1) return gltf_error(StatusCode::parse_error, where, "indices are not SCALAR");
        const tinygltf::Accessor& ia = model.accessors[prim.indices];
        if (ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
          return gltf_error(StatusCode::parse_error, where, "indices are not unsigned integers");
        idx.reserve(iv.size());
        for (std::size_t i = 0; i < iv.size(); ++i) {
          if (iv[i] >= double(nv))
            return gltf_error(StatusCode::parse_error, where,
                              "index " + std::to_string(std::uint64_t(iv[i])) + " at position " + std::to_string(i) +
                                  " is out of range (" + std::to_string(nv) + " vertices)");
          idx.push_back(std::uint32_t(iv[i]));
        }
      } else {
        idx.resize(nv);
        for (std::size_t i = 0; i < nv; ++i) idx[i] = std::uint32_t(i);
      }
      triangulate(mode, idx, d.tris);
      if (mirrored)
        for (std::size_t t = 0; t < d.tris.size(); t += 3) std::swap(d.tris[t + 1], d.tris[t + 2]);

      // World space.
      for (std::size_t i = 0; i < nv; ++i) {
        Eigen::Vector4d p(d.pos[3 * i], d.pos[3 * i + 1], d.pos[3 * i + 2], 1.0);
        const Eigen::Vector4d w = world * p;
        for (int c = 0; c < 3; ++c) d.pos[3 * i + c] = w[c];
        if (!d.nrm.empty()) {
          Eigen::Vector3d n = Ln * Eigen::Vector3d(d.nrm[3 * i], d.nrm[3 * i + 1], d.nrm[3 * i + 2]);
          if (n.norm() > 0) n.normalize();
          for (int c = 0; c < 3; ++c) d.nrm[3 * i + c] = n[c];
        }
        if (!d.tan.empty()) {
          Eigen::Vector3d t = L * Eigen::Vector3d(d.tan[4 * i], d.tan[4 * i + 1], d.tan[4 * i + 2]);
          if (t.norm() > 0) t.normalize();
          for (int c = 0; c < 3; ++c) d.tan[4 * i + c] = t[c];
          if (mirrored) d.tan[4 * i + 3] = -d.tan[4 * i + 3];
        }
      }
      if (prim.material >= int(model.materials.size()))
        return gltf_error(StatusCode::parse_error, where,
                          "refers to material " + std::to_string(prim.material) + ", which does not exist");

      ++report.primitives;
      const std::pair<int, AttributeSet> key{prim.material, attrs};
      std::size_t g = 0;
      while (g < group_keys.size() && !(group_keys[g].first == key.first && group_keys[g].second == key.second)) ++g;
      if (g == group_keys.size()) {
        group_keys.push_back(key);
        group_data.emplace_back();
        group_names.push_back(where);
      } else {
        group_names[g] += ", " + where;
      }
      // Append d to the group's data with offset indices.
      PrimitiveData& gd = group_data[g];
      const std::uint32_t base = std::uint32_t(gd.pos.size() / 3);
      gd.pos.insert(gd.pos.end(), d.pos.begin(), d.pos.end());
      gd.nrm.insert(gd.nrm.end(), d.nrm.begin(), d.nrm.end());
      gd.tan.insert(gd.tan.end(), d.tan.begin(), d.tan.end());
      gd.col.insert(gd.col.end(), d.col.begin(), d.col.end());
      gd.col_components = d.col_components;
      gd.uv.resize(d.uv.size());
      for (std::size_t s = 0; s < d.uv.size(); ++s) gd.uv[s].insert(gd.uv[s].end(), d.uv[s].begin(), d.uv[s].end());
      for (std::uint32_t t : d.tris) gd.tris.push_back(base + t);
    }
  }

  // Flatten the groups into the mesh.
  std::size_t nv = 0, nf = 0;
  bool any_n = false, any_t = false, any_c = false;
  int max_uv = 0;
  for (std::size_t g = 0; g < group_data.size(); ++g) {
    nv += group_data[g].pos.size() / 3;
    nf += group_data[g].tris.size() / 3;
    any_n |= group_keys[g].second.normals;
    any_t |= group_keys[g].second.tangents;
    any_c |= group_keys[g].second.color_components > 0;
    max_uv = std::max(max_uv, group_keys[g].second.uv_sets);
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
  for (std::size_t g = 0; g < group_data.size(); ++g) {
    const PrimitiveData& d = group_data[g];
    const AttributeSet& a = group_keys[g].second;
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
    group.material = group_keys[g].first;
    group.attributes = a;
    group.name = group_names[g];
    mesh.groups.push_back(group);
  }
  // Plain material descriptions (for reports and for writers without the assets).
  for (const tinygltf::Material& gm : model.materials) {
    Material mat;
    mat.name = gm.name;
    const auto& bc = gm.pbrMetallicRoughness.baseColorFactor;
    if (bc.size() == 4) mat.base_color = Eigen::Vector4f(float(bc[0]), float(bc[1]), float(bc[2]), float(bc[3]));
    mat.metallic = float(gm.pbrMetallicRoughness.metallicFactor);
    mat.roughness = float(gm.pbrMetallicRoughness.roughnessFactor);
    mat.double_sided = gm.doubleSided;
    mesh.materials.push_back(mat);
  }
  auto assets = std::make_shared<GltfAssets>();
  assets->model.materials = model.materials;
  assets->model.textures = model.textures;
  assets->model.images = model.images;
  assets->model.samplers = model.samplers;
  assets->model.asset = model.asset;
  for (const std::string& e : model.extensionsUsed)
    if (extension_is_carried(e) && e != "KHR_mesh_quantization") assets->model.extensionsUsed.push_back(e);
  for (const std::string& e : model.extensionsRequired)
    if (extension_is_carried(e) && e != "KHR_mesh_quantization") assets->model.extensionsRequired.push_back(e);
  // Images read from a bufferView: tinygltf keeps the index, but the bytes
  // now live in `image`; they are written back into the new buffer.
  for (tinygltf::Image& im : assets->model.images) {
    if (im.mimeType.empty()) im.mimeType = sniff_mime(im.image);
    im.bufferView = -1;
    if (!im.image.empty()) im.uri.clear();
  }
  mesh.assets = std::move(assets);
  return validate(mesh);
}

inline bool has_glb_magic(const std::uint8_t* data, std::size_t size) {
  return size >= 4 && std::memcmp(data, "glTF", 4) == 0;
}

inline Status parse_model(const std::uint8_t* data, std::size_t size, const std::string& base_dir, bool binary,
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

}  // namespace detail

/// Loads a glTF model from bytes. `base_dir` is where external buffers and
/// images are looked up ("" = none may be external). Warnings go to `report`.
inline Result<Mesh> load_gltf_from_memory(const std::uint8_t* data, std::size_t size, const std::string& base_dir = "",
                                          GltfLoadReport* report = nullptr) {
  GltfLoadReport local;
  GltfLoadReport& r = report ? *report : local;
  r = GltfLoadReport();
  tinygltf::Model model;
  RESTITCH_TRY(detail::parse_model(data, size, base_dir, detail::has_glb_magic(data, size), model, r));
  Mesh mesh;
  RESTITCH_TRY(detail::build_mesh(model, mesh, r));
  return mesh;
}

/// Loads a .glb or .gltf file (see the header comment for what is carried).
inline Result<Mesh> load_gltf(const std::string& path, GltfLoadReport* report = nullptr) {
  std::vector<std::uint8_t> bytes;
  RESTITCH_TRY(detail::read_file(path, bytes));
  Result<Mesh> mesh = load_gltf_from_memory(bytes.data(), bytes.size(), detail::parent_dir(path), report);
  if (!mesh) return Status(mesh.status().code(), path + ": " + mesh.status().message());
  return mesh;
}

namespace detail {

inline void align4(std::vector<unsigned char>& buf) {
  while (buf.size() % 4) buf.push_back(0);
}

// Appends a bufferView + accessor holding `values` (count x comps floats).
inline int add_float_accessor(tinygltf::Model& m, const std::vector<float>& values, int comps, int type, bool minmax) {
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

inline int add_index_accessor(tinygltf::Model& m, const std::vector<std::uint32_t>& idx, std::size_t vertex_count) {
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

inline Status build_model(const Mesh& mesh, tinygltf::Model& m) {
  RESTITCH_TRY(validate(mesh));
  m = tinygltf::Model();
  m.asset.version = "2.0";
  m.asset.generator = "restitch";
  m.buffers.emplace_back();
  if (mesh.assets) {
    const tinygltf::Model& a = mesh.assets->model;
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
          return error(StatusCode::unsupported,
                       "image " + std::to_string(&im - a.images.data()) +
                           " is in a format restitch cannot name (not PNG, JPEG, WebP or KTX2)");
      }
      m.images.push_back(out);
    }
  } else {
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

  tinygltf::Mesh gm;
  gm.name = "restitch";
  // Faces of each group, in face order; vertices compacted per group in first-use order.
  std::vector<std::vector<std::uint32_t>> faces_of(mesh.groups.size());
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) faces_of[mesh.FG(f)].push_back(std::uint32_t(f));
  std::vector<std::int64_t> remap(mesh.V.rows(), -1);
  for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
    if (faces_of[g].empty()) continue;
    const AttributeSet& a = mesh.groups[g].attributes;
    std::vector<std::uint32_t> used, idx;
    for (std::uint32_t f : faces_of[g])
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
      prim.attributes["TANGENT"] = add_float_accessor(
          m, gather([&](std::uint32_t v, int c) { return mesh.T(v, c); }, 4), 4, TINYGLTF_TYPE_VEC4, false);
    for (int s = 0; s < a.uv_sets; ++s)
      prim.attributes["TEXCOORD_" + std::to_string(s)] = add_float_accessor(
          m, gather([&](std::uint32_t v, int c) { return mesh.UV[s](v, c); }, 2), 2, TINYGLTF_TYPE_VEC2, false);
    if (a.color_components)
      prim.attributes["COLOR_0"] = add_float_accessor(
          m, gather([&](std::uint32_t v, int c) { return mesh.C(v, c); }, a.color_components), a.color_components,
          a.color_components == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4, false);
    prim.indices = add_index_accessor(m, idx, used.size());
    gm.primitives.push_back(prim);
  }
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

inline Status serialize(const tinygltf::Model& m, bool binary, std::vector<std::uint8_t>& out) {
  std::ostringstream os;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&m, os, /*prettyPrint=*/!binary, binary))
    return error(StatusCode::internal, "the glTF writer failed");
  const std::string s = os.str();
  out.assign(s.begin(), s.end());
  return {};
}

}  // namespace detail

/// Encodes a mesh as .glb bytes (deterministic).
inline Result<std::vector<std::uint8_t>> save_glb_to_memory(const Mesh& mesh) {
  tinygltf::Model m;
  RESTITCH_TRY(detail::build_model(mesh, m));
  std::vector<std::uint8_t> bytes;
  RESTITCH_TRY(detail::serialize(m, true, bytes));
  return bytes;
}

/// Saves a mesh as .glb (binary) or .gltf (JSON, embedded buffer) by the
/// path's extension; any other extension is an invalid_argument. Written to
/// a temporary file beside `path`, then renamed over it.
inline Status save_gltf(const Mesh& mesh, const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  if (ext != ".glb" && ext != ".gltf")
    return error(StatusCode::invalid_argument, path + ": the output must end in .glb or .gltf");
  tinygltf::Model m;
  RESTITCH_TRY(detail::build_model(mesh, m));
  std::vector<std::uint8_t> bytes;
  RESTITCH_TRY(detail::serialize(m, ext == ".glb", bytes));
  return detail::write_file_atomic(path, bytes.data(), bytes.size());
}

}  // namespace restitch
