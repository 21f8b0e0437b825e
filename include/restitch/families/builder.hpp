// restitch/families/builder.hpp - the flat-shaded mesh builder behind the sample models (internal).
//
// `detail::SampleMeshBuilder` appends planar patches (subdivided quads and
// triangles, and boxes, prisms and square frusta made of them) to a mesh that
// carries one normal and one UV pair per vertex. Every patch gets its own
// vertices, so normals are flat per face side.
//
// Blocks. The sample models are made of blocks (a start cap, modules, an end
// cap along each lattice generator). Geometry is always given in
// BLOCK-LOCAL coordinates (double precision); `set_block` fixes the block's
// model-space offset and its index along each generator. A vertex's position
// is float(local + offset), computed once from the local template, never by
// accumulation, so two modules are translates of each other to float
// rounding. Normals and UVs depend on the local coordinates only, so every
// module carries bit-identical normals and UVs, like a copied module would.
//
// Subdivision. An edge of length L is cut into max(1, ceil(L / cell))
// segments; a quad patch is an nu x nv grid of bilinear cells (two triangles
// each), a triangle patch an m x m barycentric grid (m^2 triangles).
//
// UVs (set 0): a box mapping of the block-local position, chosen by the
// dominant axis of the face normal: +-z faces (x, -y), +-x faces (z, -y),
// +-y faces (x, -z), divided by `uv_unit` (model units per texture repeat).
//
// Counting mode (`count_only`): nothing is stored, only triangles and
// vertices are counted, in O(1) per patch, so a caller can refuse a request
// that would be too large before allocating it.
//
// Cost: O(#V + #F) time and memory.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch {
namespace detail {

/// Face mask bits of an axis-aligned box.
enum BoxFaces : unsigned {
  box_neg_x = 1u,
  box_pos_x = 2u,
  box_neg_y = 4u,
  box_pos_y = 8u,
  box_neg_z = 16u,
  box_pos_z = 32u,
  box_all = 63u,
};

class SampleMeshBuilder {
 public:
  using Vec3 = Eigen::Vector3d;

  /// cell: target edge length of the subdivision (model units, > 0);
  /// uv_unit: model units per texture repeat (> 0); generators: 1 or 2.
  template <class = void>
  SampleMeshBuilder(double cell, double uv_unit, int generators, bool count_only)
      : cell_(cell), uv_unit_(uv_unit), generators_(generators), count_only_(count_only) {
    RESTITCH_ASSERT(cell > 0 && uv_unit > 0, "the sample builder needs a positive cell size and UV unit");
    RESTITCH_ASSERT(generators >= 1 && generators <= 2, "the sample builder tags faces with 1 or 2 block indices");
  }

  /// Adds a material; returns its index. Groups are made per used material at `finish`.
  template <class = void>
  int add_material(const Material& m) {
    materials_.push_back(m);
    return static_cast<int>(materials_.size()) - 1;
  }
  template <class = void>
  void set_material(int m) {
    RESTITCH_ASSERT(m >= 0 && m < static_cast<int>(materials_.size()), "set_material: no such material");
    material_ = m;
  }
  /// The block that following patches belong to: its model-space offset and
  /// its index along generator 0 and 1 (-1 start cap, 0.. modules, n end cap).
  template <class = void>
  void set_block(const Vec3& offset, int block0, int block1 = 0) {
    offset_ = offset;
    block_ = {block0, block1};
  }

  /// The segments an edge of `length` is cut into: max(1, ceil(length / cell)).
  int segments(double length) const {
    const double s = std::ceil(length / cell_ - 1e-9);
    return s < 1 ? 1 : (s > 1e9 ? 1000000000 : static_cast<int>(s));
  }
  std::uint64_t triangle_count() const { return triangles_; }
  std::uint64_t vertex_count() const { return vertices_; }

  /// A planar quad p0 p1 p2 p3, counter-clockwise seen from its front.
  /// p3 == p2 is allowed (a triangle given as a quad) but `triangle` is better.
  template <class = void>
  void quad(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3) {
    const int nu = segments(std::max((p1 - p0).norm(), (p2 - p3).norm()));
    const int nv = segments(std::max((p3 - p0).norm(), (p2 - p1).norm()));
    const std::uint64_t nvert = std::uint64_t(nu + 1) * std::uint64_t(nv + 1);
    const std::uint64_t ntri = 2ull * std::uint64_t(nu) * std::uint64_t(nv);
    vertices_ += nvert;
    triangles_ += ntri;
    if (count_only_) return;
    const Vec3 n = face_normal((p2 - p0).cross(p3 - p1));
    const std::uint32_t base = static_cast<std::uint32_t>(V_.size() / 3);
    for (int j = 0; j <= nv; ++j) {
      const double t = double(j) / double(nv);
      for (int i = 0; i <= nu; ++i) {
        const double s = double(i) / double(nu);
        const Vec3 p = (1 - s) * (1 - t) * p0 + s * (1 - t) * p1 + s * t * p2 + (1 - s) * t * p3;
        push_vertex(p, n);
      }
    }
    const std::uint32_t row = static_cast<std::uint32_t>(nu + 1);
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        const std::uint32_t a = base + std::uint32_t(j) * row + std::uint32_t(i), b = a + 1, c = a + 1 + row,
                            d = a + row;
        push_triangle(a, b, c);
        push_triangle(a, c, d);
      }
  }

  /// A triangle p0 p1 p2, counter-clockwise seen from its front.
  template <class = void>
  void triangle(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    const int m = segments(std::max({(p1 - p0).norm(), (p2 - p1).norm(), (p0 - p2).norm()}));
    vertices_ += std::uint64_t(m + 1) * std::uint64_t(m + 2) / 2;
    triangles_ += std::uint64_t(m) * std::uint64_t(m);
    if (count_only_) return;
    const Vec3 n = face_normal((p1 - p0).cross(p2 - p0));
    const std::uint32_t base = static_cast<std::uint32_t>(V_.size() / 3);
    // Vertex (i, j), i + j <= m, is stored row by row (j outer): index of row j starts at
    // sum_{k<j} (m + 1 - k).
    auto index = [&](int i, int j) { return base + static_cast<std::uint32_t>(j * (m + 1) - j * (j - 1) / 2 + i); };
    for (int j = 0; j <= m; ++j)
      for (int i = 0; i + j <= m; ++i) {
        const Vec3 p = p0 + (double(i) / m) * (p1 - p0) + (double(j) / m) * (p2 - p0);
        push_vertex(p, n);
      }
    for (int j = 0; j < m; ++j)
      for (int i = 0; i + j < m; ++i) {
        push_triangle(index(i, j), index(i + 1, j), index(i, j + 1));
        if (i + j < m - 1) push_triangle(index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
      }
  }

  /// An axis-aligned box [lo, hi] with the faces in `faces` (BoxFaces bits), normals outward.
  template <class = void>
  void box(const Vec3& lo, const Vec3& hi, unsigned faces) {
    RESTITCH_ASSERT((lo.array() < hi.array()).all(), "box: lo must be below hi on every axis");
    const double lx = lo.x(), ly = lo.y(), lz = lo.z(), hx = hi.x(), hy = hi.y(), hz = hi.z();
    if (faces & box_neg_x) quad({lx, ly, lz}, {lx, ly, hz}, {lx, hy, hz}, {lx, hy, lz});
    if (faces & box_pos_x) quad({hx, ly, lz}, {hx, hy, lz}, {hx, hy, hz}, {hx, ly, hz});
    if (faces & box_neg_y) quad({lx, ly, lz}, {hx, ly, lz}, {hx, ly, hz}, {lx, ly, hz});
    if (faces & box_pos_y) quad({lx, hy, lz}, {lx, hy, hz}, {hx, hy, hz}, {hx, hy, lz});
    if (faces & box_neg_z) quad({lx, ly, lz}, {lx, hy, lz}, {hx, hy, lz}, {hx, ly, lz});
    if (faces & box_pos_z) quad({lx, ly, hz}, {hx, ly, hz}, {hx, hy, hz}, {lx, hy, hz});
  }

  /// A rectangle in the plane z = const, facing +z (front) or -z.
  template <class = void>
  void rect_z(double x0, double x1, double y0, double y1, double z, bool front) {
    if (front)
      quad({x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z});
    else
      quad({x0, y0, z}, {x0, y1, z}, {x1, y1, z}, {x1, y0, z});
  }

  /// A prism: the convex profile (x, y), counter-clockwise seen from +z,
  /// extruded over z in [z0, z1]. `patches` cut the profile into quads and
  /// triangles (indices into the profile, counter-clockwise; a 4th index of
  /// -1 marks a triangle) for the two end faces. Side k joins profile
  /// vertex k to k+1 and is emitted when bit k of `sides` is set.
  template <class = void>
  void prism_z(const std::vector<Eigen::Vector2d>& profile, const std::vector<std::array<int, 4>>& patches, double z0,
               double z1, unsigned sides, bool front, bool back) {
    RESTITCH_ASSERT(profile.size() >= 3 && z0 < z1, "prism_z: needs a polygon and z0 < z1");
    auto at = [&](int k, double z) { return Vec3(profile[std::size_t(k)].x(), profile[std::size_t(k)].y(), z); };
    for (const auto& q : patches) {
      if (front) {
        if (q[3] < 0)
          triangle(at(q[0], z1), at(q[1], z1), at(q[2], z1));
        else
          quad(at(q[0], z1), at(q[1], z1), at(q[2], z1), at(q[3], z1));
      }
      if (back) {
        if (q[3] < 0)
          triangle(at(q[0], z0), at(q[2], z0), at(q[1], z0));
        else
          quad(at(q[0], z0), at(q[3], z0), at(q[2], z0), at(q[1], z0));
      }
    }
    const int n = static_cast<int>(profile.size());
    for (int k = 0; k < n; ++k)
      if (sides & (1u << k)) {
        const int k1 = (k + 1) % n;
        quad(at(k, z0), at(k1, z0), at(k1, z1), at(k, z1));
      }
  }

  /// A square frustum along y: cross-section centred at (cx, cz), half-size
  /// h0 at y0 and h1 at y1 (y0 < y1; one of h0, h1 may be 0: a pyramid).
  /// Four sides, plus the bottom (-y) and top (+y) squares when asked.
  template <class = void>
  void frustum_y(double cx, double cz, double y0, double y1, double h0, double h1, bool bottom, bool top) {
    RESTITCH_ASSERT(y0 < y1 && h0 >= 0 && h1 >= 0 && (h0 > 0 || h1 > 0), "frustum_y: bad extent");
    const double dirs[4][2] = {{0, 1}, {1, 0}, {0, -1}, {-1, 0}};  // outward (x, z): +z, +x, -z, -x
    for (const auto& d : dirs) {
      const double tx = d[1], tz = -d[0];  // tangent so that the side faces outward
      const Vec3 p0(cx + h0 * (d[0] - tx), y0, cz + h0 * (d[1] - tz));
      const Vec3 p1(cx + h0 * (d[0] + tx), y0, cz + h0 * (d[1] + tz));
      const Vec3 p2(cx + h1 * (d[0] + tx), y1, cz + h1 * (d[1] + tz));
      const Vec3 p3(cx + h1 * (d[0] - tx), y1, cz + h1 * (d[1] - tz));
      if (h1 == 0)
        triangle(p0, p1, p2);
      else if (h0 == 0)
        triangle(p0, p2, p3);
      else
        quad(p0, p1, p2, p3);
    }
    if (bottom && h0 > 0) box_square(cx, cz, y0, h0, false);
    if (top && h1 > 0) box_square(cx, cz, y1, h1, true);
  }

  /// Moves the result into `mesh` (one group per used material, normals and
  /// one UV set) and the per-generator block index of every face into
  /// `face_block`. Unused materials are dropped.
  template <class = void>
  void finish(const std::string& sample_name, Mesh& mesh, std::vector<Eigen::VectorXi>& face_block) {
    RESTITCH_ASSERT(!count_only_, "finish: a counting builder holds no mesh");
    const Eigen::Index nv = static_cast<Eigen::Index>(V_.size() / 3), nf = static_cast<Eigen::Index>(F_.size() / 3);
    std::vector<int> remap(materials_.size(), -1);
    mesh = Mesh();
    for (std::uint32_t m : FG_)
      if (remap[m] < 0) remap[m] = 0;
    for (std::size_t m = 0; m < materials_.size(); ++m)
      if (remap[m] == 0) {
        remap[m] = static_cast<int>(mesh.materials.size());
        Group g;
        g.material = remap[m];
        g.attributes.normals = true;
        g.attributes.uv_sets = 1;
        g.name = "sample '" + sample_name + "' material '" + materials_[m].name + "'";
        mesh.materials.push_back(materials_[m]);
        mesh.groups.push_back(g);
      }
    mesh.V = Eigen::Map<const MatrixX3f>(V_.data(), nv, 3);
    mesh.N = Eigen::Map<const MatrixX3f>(N_.data(), nv, 3);
    mesh.UV.push_back(Eigen::Map<const MatrixX2f>(UV_.data(), nv, 2));
    mesh.F = Eigen::Map<const MatrixX3u>(F_.data(), nf, 3);
    mesh.FG.resize(nf);
    for (Eigen::Index f = 0; f < nf; ++f) mesh.FG(f) = static_cast<std::uint32_t>(remap[FG_[std::size_t(f)]]);
    face_block.assign(std::size_t(generators_), Eigen::VectorXi(nf));
    for (int g = 0; g < generators_; ++g)
      for (Eigen::Index f = 0; f < nf; ++f)
        face_block[std::size_t(g)](f) = block_of_face_[std::size_t(f) * 2 + std::size_t(g)];
  }

 private:
  template <class = void>
  static Vec3 face_normal(const Vec3& c) {
    const double l = c.norm();
    return l > 0 ? Vec3(c / l) : Vec3(0, 0, 1);
  }

  template <class = void>
  void box_square(double cx, double cz, double y, double h, bool up) {
    if (up)
      quad({cx - h, y, cz - h}, {cx - h, y, cz + h}, {cx + h, y, cz + h}, {cx + h, y, cz - h});
    else
      quad({cx - h, y, cz - h}, {cx + h, y, cz - h}, {cx + h, y, cz + h}, {cx - h, y, cz + h});
  }

  template <class = void>
  void push_vertex(const Vec3& local, const Vec3& n) {
    const Vec3 p = local + offset_;
    V_.insert(V_.end(), {float(p.x()), float(p.y()), float(p.z())});
    N_.insert(N_.end(), {float(n.x()), float(n.y()), float(n.z())});
    const Eigen::Vector3d a = n.cwiseAbs();
    double u, v;
    if (a.z() >= a.x() && a.z() >= a.y()) {
      u = local.x(), v = -local.y();
    } else if (a.x() >= a.y()) {
      u = local.z(), v = -local.y();
    } else {
      u = local.x(), v = -local.z();
    }
    UV_.insert(UV_.end(), {float(u / uv_unit_), float(v / uv_unit_)});
  }

  template <class = void>
  void push_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    F_.insert(F_.end(), {a, b, c});
    FG_.push_back(static_cast<std::uint32_t>(material_));
    block_of_face_.insert(block_of_face_.end(), {block_[0], block_[1]});
  }

  double cell_, uv_unit_;
  int generators_;
  bool count_only_;
  int material_ = 0;
  Vec3 offset_ = Vec3::Zero();
  std::array<int, 2> block_{{0, 0}};
  std::uint64_t triangles_ = 0, vertices_ = 0;
  std::vector<Material> materials_;
  std::vector<float> V_, N_, UV_;
  std::vector<std::uint32_t> F_, FG_;
  std::vector<int> block_of_face_;
};

}  // namespace detail
}  // namespace restitch
