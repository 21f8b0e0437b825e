// restitch/io/detail/gltf_primitives.hpp - a glTF mesh's primitives decoded once, placed per instance.
//
// Part of restitch/io/gltf.hpp, which includes it after configuring and
// including tinygltf and after declaring GltfAssets; do not include it on its
// own.
//
// `decode_mesh` decodes every triangle primitive of one glTF mesh, in file
// order, in the mesh's own space: POSITION (VEC3, finite), NORMAL, TANGENT,
// TEXCOORD_0..(max_uv_sets-1) (contiguous from 0), COLOR_0, indices (or
// 0..n-1), triangulated per mode (TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN).
// What it cannot carry (POINTS and LINES, morph targets, primitive
// extensions, colour sets past COLOR_0, skinning and custom attributes, UV
// sets after a gap) is dropped with a warning naming it; bad data (counts,
// types, indices, NaNs, a material out of range) is an error naming the
// primitive. `place_primitive` appends a decoded primitive to a group's data
// transformed by one instance's world matrix, with the very arithmetic of a
// decode-per-instance reader, so instancing changes no bit of the output.
//
// Also here: the file-level extension checks and warnings (`check_model`),
// the deduplicated warning list (`add_warning`), and the materials and
// pass-through assets a loaded Mesh carries. Never throws.
//
// Cost: linear in the primitive's vertex and index counts.
#pragma once

#ifndef RESTITCH_GLTF_PARTS
#error "include restitch/io/gltf.hpp, not its detail parts"
#endif

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "restitch/io/detail/gltf_accessor.hpp"
#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch::detail {

// Adds `w` to `warnings` unless it is there already (first occurrence keeps its place).
inline void add_warning(std::vector<std::string>& warnings, std::string w) {
  if (std::find(warnings.begin(), warnings.end(), w) == warnings.end()) warnings.push_back(std::move(w));
}

// Extensions restitch decodes or passes through untouched with the materials.
template <class = void>
bool extension_is_carried(const std::string& e) {
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

// File-level checks: a required extension restitch cannot decode is an error;
// extensions not carried, animations, skins and cameras are warnings.
template <class = void>
Status check_model(const tinygltf::Model& model, std::vector<std::string>& warnings) {
  for (const std::string& e : model.extensionsRequired)
    if (!extension_is_carried(e))
      return error(StatusCode::unsupported, "the file requires the extension " + e +
                                                ", which restitch cannot decode (re-export the model without it)");
  for (const std::string& e : model.extensionsUsed)
    if (!extension_is_carried(e)) add_warning(warnings, "extension " + e + " is not carried: what it adds is dropped");
  if (!model.animations.empty())
    add_warning(warnings, std::to_string(model.animations.size()) + " animation(s) dropped: the output is static");
  if (!model.skins.empty())
    add_warning(warnings, std::to_string(model.skins.size()) + " skin(s) dropped: the output is not skinned");
  if (!model.cameras.empty()) add_warning(warnings, std::to_string(model.cameras.size()) + " camera(s) dropped");
  return {};
}

template <class = void>
const char* mode_name(int mode) {
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

// Turns a primitive's index list (or implicit 0..n-1) into triangles per its mode.
template <class = void>
void triangulate(int mode, const std::vector<std::uint32_t>& idx, std::vector<std::uint32_t>& tris) {
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

// Vertex data of one primitive (or of a whole group), as doubles.
struct PrimitiveData {
  std::vector<double> pos, nrm, tan, col;
  std::vector<std::vector<double>> uv;
  int col_components = 0;
  std::vector<std::uint32_t> tris;  // corner indices into these vertices
};

// One triangle primitive of a glTF mesh, decoded in the mesh's own space.
struct DecodedPrimitive {
  std::string where;  // "mesh 0 'Shelf' primitive 1": for messages and group names
  int material = -1;
  AttributeSet attributes;
  PrimitiveData data;  // tris wound as in the file
};

// A mesh's triangle primitives in file order (the dropped ones left out).
using DecodedMesh = std::vector<DecodedPrimitive>;

// Reads POSITION (VEC3, finite coordinates).
template <class = void>
Status read_positions(const tinygltf::Model& model, int accessor, const std::string& where,
                             std::vector<double>& pos) {
  int comps = 0;
  RESTITCH_TRY(read_accessor(model, accessor, pos, comps, where + " POSITION"));
  if (comps != 3) return gltf_error(StatusCode::parse_error, where, "POSITION is not VEC3");
  for (std::size_t i = 0; i < pos.size(); ++i)
    if (!std::isfinite(pos[i]))
      return gltf_error(StatusCode::invalid_mesh, where,
                        "POSITION has a NaN or infinite coordinate at vertex " + std::to_string(i / 3));
  return {};
}

// Reads vertex attribute `name` (one value set per vertex, all finite).
template <class = void>
Status read_vertex_attribute(const tinygltf::Model& model, int accessor, const std::string& where,
                                    const std::string& name, std::size_t nv, std::vector<double>& values, int& comps) {
  // Before reading: a count the positions do not have is refused without decoding (or allocating) it.
  if (accessor >= 0 && accessor < int(model.accessors.size()) && model.accessors[std::size_t(accessor)].count != nv)
    return gltf_error(StatusCode::parse_error, where, name + " has a different count from POSITION");
  RESTITCH_TRY(read_accessor(model, accessor, values, comps, where + " " + name));
  if (values.size() / std::max(comps, 1) != nv)
    return gltf_error(StatusCode::parse_error, where, name + " has a different count from POSITION");
  for (double v : values)
    if (!std::isfinite(v)) return gltf_error(StatusCode::invalid_mesh, where, name + " has a NaN or infinite value");
  return {};
}

// Keeps attribute `name` (already read as `values`, `comps` per vertex) in
// `d` and `attrs` if restitch carries it, else warns that it is dropped.
template <class = void>
Status keep_attribute(const std::string& name, std::vector<double>& values, int comps, const std::string& where,
                             PrimitiveData& d, AttributeSet& attrs, std::vector<std::string>& warnings) {
  if (name == "NORMAL") {
    if (comps != 3) return gltf_error(StatusCode::parse_error, where, "NORMAL is not VEC3");
    d.nrm = std::move(values), attrs.normals = true;
  } else if (name == "TANGENT") {
    if (comps != 4) return gltf_error(StatusCode::parse_error, where, "TANGENT is not VEC4");
    d.tan = std::move(values), attrs.tangents = true;
  } else if (name.rfind("TEXCOORD_", 0) == 0) {
    if (comps != 2) return gltf_error(StatusCode::parse_error, where, name + " is not VEC2");
    const int set = std::atoi(name.c_str() + 9);
    if (set < 0 || set >= int(max_uv_sets))
      return gltf_error(StatusCode::unsupported, where,
                        name + " is past the " + std::to_string(max_uv_sets) + " UV sets restitch carries");
    if (int(d.uv.size()) <= set) d.uv.resize(set + 1);
    d.uv[set] = std::move(values);
  } else if (name == "COLOR_0") {
    if (comps != 3 && comps != 4) return gltf_error(StatusCode::parse_error, where, "COLOR_0 is neither VEC3 nor VEC4");
    d.col = std::move(values), d.col_components = comps, attrs.color_components = comps;
  } else if (name.rfind("JOINTS_", 0) == 0 || name.rfind("WEIGHTS_", 0) == 0) {
    add_warning(warnings, where + ": skinning attribute " + name + " dropped");
  } else {
    add_warning(warnings,
                where + ": attribute " + name + " dropped (restitch carries normals, tangents, UVs and COLOR_0)");
  }
  return {};
}

// Reads every attribute but POSITION, in the file's (name) order.
template <class = void>
Status read_attributes(const tinygltf::Model& model, const tinygltf::Primitive& prim, const std::string& where,
                              std::size_t nv, PrimitiveData& d, AttributeSet& attrs,
                              std::vector<std::string>& warnings) {
  for (const auto& kv : prim.attributes) {
    const std::string& name = kv.first;
    std::vector<double> values;
    int comps = 0;
    if (name == "POSITION") continue;
    if (name == "NORMAL" || name == "TANGENT" || name.rfind("TEXCOORD_", 0) == 0 || name.rfind("COLOR_", 0) == 0) {
      if (name.rfind("COLOR_", 0) == 0 && name != "COLOR_0") {
        add_warning(warnings, where + ": vertex colour set " + name + " dropped (only COLOR_0 is carried)");
        continue;
      }
      RESTITCH_TRY(read_vertex_attribute(model, kv.second, where, name, nv, values, comps));
    }
    RESTITCH_TRY(keep_attribute(name, values, comps, where, d, attrs, warnings));
  }
  // UV sets must be contiguous from 0 to be written back as TEXCOORD_0..k.
  int uv_sets = 0;
  while (uv_sets < int(d.uv.size()) && !d.uv[uv_sets].empty()) ++uv_sets;
  if (uv_sets < int(d.uv.size())) {
    add_warning(warnings, where + ": UV sets after a missing TEXCOORD_" + std::to_string(uv_sets) + " dropped");
    d.uv.resize(uv_sets);
  }
  attrs.uv_sets = uv_sets;
  return {};
}

// The primitive's vertex indices (unsigned integers below `nv`), or 0..nv-1.
template <class = void>
Status read_indices(const tinygltf::Model& model, const tinygltf::Primitive& prim, const std::string& where,
                           std::size_t nv, std::vector<std::uint32_t>& idx) {
  if (prim.indices < 0) {
    idx.resize(nv);
    for (std::size_t i = 0; i < nv; ++i) idx[i] = std::uint32_t(i);
    return {};
  }
  std::vector<double> iv;
  int comps = 0;
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
  return {};
}

// The count of accessor `index` when it exists (0 otherwise: read_accessor reports the error).
inline std::size_t accessor_count(const tinygltf::Model& model, int index) {
  return index >= 0 && index < int(model.accessors.size()) ? model.accessors[std::size_t(index)].count : 0;
}

// too_large: `n` `what` ("vertices" or "triangles") past the limit GltfLimits::max_<what>.
template <class = void>
Status over_limit(const std::string& where, std::uint64_t n, const std::string& what, std::size_t limit) {
  return gltf_error(StatusCode::too_large, where,
                    "has " + std::to_string(n) + " " + what + ", more than the limit of " + std::to_string(limit) +
                        " (GltfLimits::max_" + what + "; --max-" + what + " on the command line)");
}

// Decodes primitive `pi` of mesh `mi`; appends it to `out` unless it is
// dropped (with a warning). Counts past `limits` are refused before their data is read.
template <class = void>
Status decode_primitive(const tinygltf::Model& model, int mi, std::size_t pi, DecodedMesh& out,
                               std::vector<std::string>& warnings, const GltfLimits& limits) {
  const tinygltf::Mesh& gm = model.meshes[mi];
  const tinygltf::Primitive& prim = gm.primitives[pi];
  const std::string where =
      "mesh " + std::to_string(mi) + (gm.name.empty() ? "" : " '" + gm.name + "'") + " primitive " + std::to_string(pi);
  const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    add_warning(warnings, where + " is " + mode_name(mode) + ", not triangles: dropped");
    return {};
  }
  if (!prim.targets.empty())
    add_warning(warnings, where + ": " + std::to_string(prim.targets.size()) + " morph target(s) dropped");
  for (const auto& ext : prim.extensions)
    if (!extension_is_carried(ext.first))
      add_warning(warnings, where + ": primitive extension " + ext.first + " dropped");
  auto pos_it = prim.attributes.find("POSITION");
  if (pos_it == prim.attributes.end()) {
    add_warning(warnings, where + " has no POSITION attribute: dropped");
    return {};
  }
  const std::size_t declared_vertices = accessor_count(model, pos_it->second);
  if (declared_vertices > limits.max_vertices)
    return over_limit(where, declared_vertices, "vertices", limits.max_vertices);
  const std::uint64_t corners = prim.indices >= 0 ? accessor_count(model, prim.indices) : declared_vertices;
  const std::uint64_t declared_triangles =
      mode == TINYGLTF_MODE_TRIANGLES ? corners / 3 : (corners > 2 ? corners - 2 : 0);
  if (declared_triangles > limits.max_triangles)
    return over_limit(where, declared_triangles, "triangles", limits.max_triangles);
  DecodedPrimitive p;
  PrimitiveData& d = p.data;
  RESTITCH_TRY(read_positions(model, pos_it->second, where, d.pos));
  const std::size_t nv = d.pos.size() / 3;
  RESTITCH_TRY(read_attributes(model, prim, where, nv, d, p.attributes, warnings));
  std::vector<std::uint32_t> idx;
  RESTITCH_TRY(read_indices(model, prim, where, nv, idx));
  triangulate(mode, idx, d.tris);
  if (prim.material >= int(model.materials.size()))
    return gltf_error(StatusCode::parse_error, where,
                      "refers to material " + std::to_string(prim.material) + ", which does not exist");
  p.where = where;
  p.material = prim.material;
  out.push_back(std::move(p));
  return {};
}

// Decodes every primitive of mesh `mi` (a valid index), in file order.
template <class = void>
Status decode_mesh(const tinygltf::Model& model, int mi, DecodedMesh& out, std::vector<std::string>& warnings,
                          const GltfLimits& limits) {
  out.clear();
  for (std::size_t pi = 0; pi < model.meshes[mi].primitives.size(); ++pi)
    RESTITCH_TRY(decode_primitive(model, mi, pi, out, warnings, limits));
  return {};
}

// One instance's transform: positions by `world`, normals by `Ln` (the
// inverse transpose of `L`), tangents by `L` (its linear part); a mirror
// (`mirrored`, det L < 0) flips the winding and the tangents' w back.
struct InstanceTransform {
  Eigen::Matrix4d world;
  Eigen::Matrix3d L, Ln;
  bool mirrored = false;
};

// Appends `d` transformed by `xf` to the group data `gd`, indices offset by
// the vertices already there. The arithmetic (doubles, Eigen's fixed-size
// products, normalize when the norm is positive) is that of a reader that
// decodes per instance: the output is the same to the bit.
template <class = void>
void place_primitive(const PrimitiveData& d, const InstanceTransform& xf, PrimitiveData& gd) {
  const std::size_t nv = d.pos.size() / 3;
  const std::uint32_t base = std::uint32_t(gd.pos.size() / 3);
  for (std::size_t i = 0; i < nv; ++i) {
    Eigen::Vector4d p(d.pos[3 * i], d.pos[3 * i + 1], d.pos[3 * i + 2], 1.0);
    const Eigen::Vector4d w = xf.world * p;
    for (int c = 0; c < 3; ++c) gd.pos.push_back(w[c]);
  }
  for (std::size_t i = 0; i < nv && !d.nrm.empty(); ++i) {
    Eigen::Vector3d n = xf.Ln * Eigen::Vector3d(d.nrm[3 * i], d.nrm[3 * i + 1], d.nrm[3 * i + 2]);
    if (n.norm() > 0) n.normalize();
    for (int c = 0; c < 3; ++c) gd.nrm.push_back(n[c]);
  }
  for (std::size_t i = 0; i < nv && !d.tan.empty(); ++i) {
    Eigen::Vector3d t = xf.L * Eigen::Vector3d(d.tan[4 * i], d.tan[4 * i + 1], d.tan[4 * i + 2]);
    if (t.norm() > 0) t.normalize();
    for (int c = 0; c < 3; ++c) gd.tan.push_back(t[c]);
    gd.tan.push_back(xf.mirrored ? -d.tan[4 * i + 3] : d.tan[4 * i + 3]);
  }
  gd.col.insert(gd.col.end(), d.col.begin(), d.col.end());
  gd.col_components = d.col_components;
  gd.uv.resize(d.uv.size());
  for (std::size_t s = 0; s < d.uv.size(); ++s) gd.uv[s].insert(gd.uv[s].end(), d.uv[s].begin(), d.uv[s].end());
  for (std::size_t t = 0; t < d.tris.size(); t += 3) {
    gd.tris.push_back(base + d.tris[t]);
    gd.tris.push_back(base + d.tris[xf.mirrored ? t + 2 : t + 1]);
    gd.tris.push_back(base + d.tris[xf.mirrored ? t + 1 : t + 2]);
  }
}

// Plain material descriptions (for reports and for writers without the assets).
template <class = void>
std::vector<Material> plain_materials(const tinygltf::Model& model) {
  std::vector<Material> out;
  for (const tinygltf::Material& gm : model.materials) {
    Material mat;
    mat.name = gm.name;
    const auto& bc = gm.pbrMetallicRoughness.baseColorFactor;
    if (bc.size() == 4) mat.base_color = Eigen::Vector4f(float(bc[0]), float(bc[1]), float(bc[2]), float(bc[3]));
    mat.metallic = float(gm.pbrMetallicRoughness.metallicFactor);
    mat.roughness = float(gm.pbrMetallicRoughness.roughnessFactor);
    mat.double_sided = gm.doubleSided;
    out.push_back(mat);
  }
  return out;
}

// The file's materials, textures, images (bytes kept), samplers, asset
// info and the carried extensions other than KHR_mesh_quantization (the
// geometry is written back as floats).
template <class = void>
std::shared_ptr<GltfAssets> pass_through_assets(const tinygltf::Model& model) {
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
  return assets;
}

}  // namespace restitch::detail
