// restitch/mesh_arrays.hpp - a Mesh from flat arrays, as bindings and other libraries hold meshes.
//
//   MeshArrays a;
//   a.positions = {...};             // x, y, z per vertex (world space, model units)
//   a.indices = {...};               // 3 per triangle, counter-clockwise = front
//   a.groups = {{0, 36, 0, "wood"}}; // ranges of `indices` in order, covering them; none: one group
//   Result<Mesh> m = mesh_from_arrays(a);
//
// Optional channels: normals (3 per vertex), uvs (sets of 2 per vertex, glTF convention: v down), colors
// (RGBA per vertex, linear). Every group carries the channels given. A vertex used by faces of two groups
// is copied into each (a Mesh keeps groups apart: restitch/mesh.hpp). A group's material is an index into
// `Mesh::materials`, which gets plain materials named "material K" up to the largest index (-1: none).
// Errors (invalid_argument) name the array and what is wrong with it; the result is validated
// (restitch::validate). Cost: O(#groups * #vertices + #indices).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// A mesh as flat arrays (see the file comment).
struct MeshArrays {
  struct Range {
    std::size_t start = 0;  ///< first index (a multiple of 3)
    std::size_t count = 0;  ///< number of indices (a multiple of 3)
    int material = -1;      ///< index into the mesh's materials; -1: none
    std::string name;       ///< where it came from (Group::name)
  };
  std::vector<float> positions;
  std::vector<std::uint32_t> indices;
  std::vector<float> normals;
  std::vector<std::vector<float>> uvs;
  std::vector<float> colors;
  std::vector<Range> groups;
};

/// The Mesh the arrays describe, or invalid_argument / invalid_mesh saying what is wrong.
template <class = void>
Result<Mesh> mesh_from_arrays(const MeshArrays& a) {
  auto bad = [](const std::string& what) { return error(StatusCode::invalid_argument, what); };
  const std::size_t nv = a.positions.size() / 3;
  if (a.positions.size() % 3) return bad("positions: the length is not a multiple of 3");
  if (a.indices.empty() || a.indices.size() % 3) return bad("indices: the length is not a positive multiple of 3");
  if (!a.normals.empty() && a.normals.size() != 3 * nv) return bad("normals: not 3 numbers per vertex");
  if (!a.colors.empty() && a.colors.size() != 4 * nv) return bad("colors: not 4 numbers (RGBA) per vertex");
  if (a.uvs.size() > max_uv_sets) return bad("uvs: at most " + std::to_string(max_uv_sets) + " sets");
  for (std::size_t k = 0; k < a.uvs.size(); ++k)
    if (a.uvs[k].size() != 2 * nv) return bad("uvs[" + std::to_string(k) + "]: not 2 numbers per vertex");
  for (const std::uint32_t i : a.indices)
    if (i >= nv) return bad("indices: index " + std::to_string(i) + " is past the last vertex");
  std::vector<MeshArrays::Range> ranges = a.groups;
  if (ranges.empty()) ranges.push_back({0, a.indices.size(), -1, "arrays"});
  std::size_t next = 0;
  for (std::size_t g = 0; g < ranges.size(); ++g) {
    const MeshArrays::Range& r = ranges[g];
    if (r.start != next || r.count % 3 || r.start + r.count > a.indices.size())
      return bad("groups[" + std::to_string(g) +
                 "]: groups must follow each other from index 0, each a multiple of 3 indices long");
    if (r.material < -1) return bad("groups[" + std::to_string(g) + "]: material must be -1 (none) or an index");
    next += r.count;
  }
  if (next != a.indices.size())
    return bad("groups: they cover " + std::to_string(next) + " of " + std::to_string(a.indices.size()) + " indices");

  Mesh m;
  int materials = 0;
  for (const MeshArrays::Range& r : ranges) materials = std::max(materials, r.material + 1);
  for (int k = 0; k < materials; ++k) m.materials.push_back(Material{"material " + std::to_string(k)});
  std::vector<std::uint32_t> source;  // new vertex -> given vertex
  std::vector<std::uint32_t> faces, face_group;
  std::vector<std::int64_t> local(nv, -1);
  for (std::size_t g = 0; g < ranges.size(); ++g) {
    const MeshArrays::Range& r = ranges[g];
    std::fill(local.begin(), local.end(), -1);
    for (std::size_t q = r.start; q < r.start + r.count; ++q) {
      const std::uint32_t v = a.indices[q];
      if (local[v] < 0) {
        local[v] = std::int64_t(source.size());
        source.push_back(v);
      }
      faces.push_back(std::uint32_t(local[v]));
      if ((q - r.start) % 3 == 2) face_group.push_back(std::uint32_t(g));
    }
    Group group;
    group.material = r.material;
    group.name = r.name.empty() ? "group " + std::to_string(g) : r.name;
    group.attributes.normals = !a.normals.empty();
    group.attributes.uv_sets = int(a.uvs.size());
    group.attributes.color_components = a.colors.empty() ? 0 : 4;
    m.groups.push_back(group);
  }
  const Eigen::Index n = Eigen::Index(source.size());
  m.V.resize(n, 3);
  if (!a.normals.empty()) m.N.resize(n, 3);
  if (!a.colors.empty()) m.C.resize(n, 4);
  m.UV.assign(a.uvs.size(), MatrixX2f(n, 2));
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::size_t s = source[std::size_t(i)];
    for (int k = 0; k < 3; ++k) m.V(i, k) = a.positions[3 * s + std::size_t(k)];
    for (int k = 0; k < 3 && !a.normals.empty(); ++k) m.N(i, k) = a.normals[3 * s + std::size_t(k)];
    for (int k = 0; k < 4 && !a.colors.empty(); ++k) m.C(i, k) = a.colors[4 * s + std::size_t(k)];
    for (std::size_t u = 0; u < a.uvs.size(); ++u)
      for (int k = 0; k < 2; ++k) m.UV[u](i, k) = a.uvs[u][2 * s + std::size_t(k)];
  }
  m.F = Eigen::Map<const MatrixX3u>(faces.data(), Eigen::Index(faces.size() / 3), 3);
  m.FG = Eigen::Map<const VectorXu>(face_group.data(), Eigen::Index(face_group.size()));
  RESTITCH_TRY(validate(m));
  return m;
}

}  // namespace restitch
