// restitch/mesh.hpp - the one mesh type of the whole pipeline.
//
// A `Mesh` is an indexed triangle soup in world space (node transforms of a
// glTF file already applied), in the model's own units, with every per-vertex
// attribute a resize must carry, and faces grouped by material.
//
//   V   #V by 3  positions
//   F   #F by 3  triangle corner indices into V (counter-clockwise = front)
//   FG  #F       group of each face, an index into `groups`
//   N   #V by 3  normals            (0 rows when no group has normals)
//   T   #V by 4  tangents, w = +-1  (0 rows when no group has tangents)
//   UV  k sets of #V by 2 texture coordinates, glTF convention (v down)
//   C   #V by 4  vertex colours RGBA, linear, in [0, 1] (0 rows when none)
//
// A *group* is what one glTF primitive was: one material and one set of
// attributes. Channels are sized for all vertices as soon as one group has
// them; `Group::attributes` says which channels the group really carries, so
// saving writes each primitive with exactly the attributes it came with.
// A vertex is used by faces of one group only (loading and stitching keep
// that), so per-group attribute sets never conflict.
//
// Materials: `materials` are restitch's own plain description (used by the
// sample generator and written when there is nothing better). A mesh loaded
// from glTF also holds `assets`, an opaque copy of the file's materials,
// textures, images, samplers and extensions; saving writes those unchanged,
// so textures survive a resize byte for byte.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "restitch/status.hpp"

namespace restitch {

using MatrixX2f = Eigen::Matrix<float, Eigen::Dynamic, 2, Eigen::RowMajor>;
using MatrixX3f = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;
using MatrixX4f = Eigen::Matrix<float, Eigen::Dynamic, 4, Eigen::RowMajor>;
using MatrixX3u = Eigen::Matrix<std::uint32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;
using VectorXu = Eigen::Matrix<std::uint32_t, Eigen::Dynamic, 1>;

/// The most texture-coordinate sets (TEXCOORD_0 .. TEXCOORD_7) a Mesh carries
/// through restitch; the glTF reader refuses TEXCOORD_8 and beyond, the
/// stitcher a mesh with more sets.
inline constexpr std::size_t max_uv_sets = 8;

/// A plain PBR material (glTF metallic-roughness).
struct Material {
  std::string name;
  Eigen::Vector4f base_color = Eigen::Vector4f::Ones();  ///< linear RGBA
  float metallic = 0.0f;
  float roughness = 1.0f;
  bool double_sided = false;
};

/// Which optional per-vertex channels a group carries.
struct AttributeSet {
  bool normals = false;
  bool tangents = false;
  int uv_sets = 0;           ///< TEXCOORD_0 .. TEXCOORD_{uv_sets-1}
  int color_components = 0;  ///< 0 (none), 3 (RGB) or 4 (RGBA)
  template <class = void>
  bool operator==(const AttributeSet& o) const {
    return normals == o.normals && tangents == o.tangents && uv_sets == o.uv_sets &&
           color_components == o.color_components;
  }
  bool operator!=(const AttributeSet& o) const { return !(*this == o); }
};

/// One material's share of the faces (what one glTF primitive was).
struct Group {
  int material = -1;  ///< index into Mesh::materials (and into the glTF assets' materials); -1 = default
  AttributeSet attributes;
  std::string name;  ///< where it came from, e.g. "mesh 'Shelf' primitive 2"
};

/// Opaque pass-through of a glTF file's materials, textures, images, samplers
/// and extensions; defined in restitch/io/gltf.hpp.
struct GltfAssets;

struct Mesh {
  MatrixX3f V;
  MatrixX3u F;
  VectorXu FG;
  MatrixX3f N;
  MatrixX4f T;
  std::vector<MatrixX2f> UV;
  MatrixX4f C;
  std::vector<Group> groups;
  std::vector<Material> materials;
  std::shared_ptr<const GltfAssets> assets;

  std::size_t vertex_count() const { return static_cast<std::size_t>(V.rows()); }
  std::size_t triangle_count() const { return static_cast<std::size_t>(F.rows()); }
  bool empty() const { return F.rows() == 0; }
};

/// Axis-aligned bounding box. `valid()` is false for an empty box.
struct BoundingBox {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(INFINITY);
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-INFINITY);
  bool valid() const { return (min.array() <= max.array()).all(); }
  Eigen::Vector3d size() const { return valid() ? Eigen::Vector3d(max - min) : Eigen::Vector3d::Zero(); }
  Eigen::Vector3d center() const { return 0.5 * (min + max); }
  template <class = void>
  void extend(const Eigen::Vector3d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

/// Bounding box of the vertices referenced by faces. Cost O(#F).
template <class = void>
BoundingBox bounding_box(const Mesh& m) {
  BoundingBox b;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) b.extend(m.V.row(m.F(f, k)).transpose().template cast<double>());
  return b;
}

/// The largest |coordinate| of the vertices the faces use (0 without faces). Vertices no face uses are
/// not geometry (glTF allows them anywhere): tolerances derived from coordinates ignore them, as
/// bounding_box does.
template <class = void>
double max_abs_coordinate(const Mesh& m) {
  double out = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) out = std::max(out, double(m.V.row(m.F(f, k)).cwiseAbs().maxCoeff()));
  return out;
}

/// Twice the area of face f (the norm of the cross product of two edges).
template <class = void>
double double_area(const Mesh& m, Eigen::Index f) {
  const Eigen::Vector3d a = m.V.row(m.F(f, 0)).template cast<double>(), b = m.V.row(m.F(f, 1)).template cast<double>(),
                        c = m.V.row(m.F(f, 2)).template cast<double>();
  return (b - a).cross(c - a).norm();
}

/// Checks the structural invariants above and that the geometry is usable:
/// at least one triangle, finite positions, indices and groups in range,
/// channel sizes consistent, and a non-zero surface area. Degenerate
/// (zero-area) triangles are allowed as long as some triangle is not.
/// Cost O(#V + #F).
template <class = void>
Status validate(const Mesh& m) {
  const Eigen::Index nv = m.V.rows();
  if (m.F.rows() == 0) return error(StatusCode::invalid_mesh, "the mesh has no triangles");
  for (Eigen::Index i = 0; i < nv; ++i)
    if (!m.V.row(i).allFinite())
      return error(StatusCode::invalid_mesh,
                   "vertex " + std::to_string(i) + " has a non-finite coordinate (NaN or infinity)");
  if (m.F.size() && m.F.maxCoeff() >= static_cast<std::uint32_t>(nv))
    return error(StatusCode::invalid_mesh, "a triangle refers to a vertex index past the end of the vertex list");
  if (m.FG.rows() != m.F.rows())
    return error(StatusCode::invalid_mesh, "the face-group list does not have one entry per triangle");
  if (m.groups.empty() || (m.FG.size() && m.FG.maxCoeff() >= m.groups.size()))
    return error(StatusCode::invalid_mesh, "a triangle refers to a group that does not exist");
  for (const Group& g : m.groups) {
    if (g.material < -1 || g.material >= static_cast<int>(m.materials.size()))
      return error(StatusCode::invalid_mesh, "group '" + g.name + "' refers to a material that does not exist");
    const AttributeSet& at = g.attributes;
    if ((at.normals && m.N.rows() == 0) || (at.tangents && m.T.rows() == 0) || (at.color_components > 0 && m.C.rows() == 0) ||
        at.uv_sets < 0 || at.uv_sets > static_cast<int>(m.UV.size()) || at.color_components < 0 || at.color_components > 4)
      return error(StatusCode::invalid_mesh,
                   "group '" + g.name + "' carries a vertex channel (normals, tangents, UVs or colours) the mesh does not have");
  }
  auto sized = [nv](Eigen::Index rows) { return rows == 0 || rows == nv; };
  bool uv_ok = true;
  for (const auto& uv : m.UV) uv_ok = uv_ok && uv.rows() == nv;
  if (!sized(m.N.rows()) || !sized(m.T.rows()) || !sized(m.C.rows()) || !uv_ok)
    return error(StatusCode::invalid_mesh, "a vertex attribute channel does not have one entry per vertex");
  double area = 0;
  for (Eigen::Index f = 0; f < m.F.rows() && area == 0; ++f) area += double_area(m, f);
  if (!(area > 0)) return error(StatusCode::invalid_mesh, "every triangle is degenerate: the mesh has no surface area");
  return {};
}

}  // namespace restitch
