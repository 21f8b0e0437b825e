// restitch/stitch/detail/output.hpp - the stitched output while it is built, and its assembly into a Mesh.
//
// An output vertex is a recipe: an input vertex copied by a region (its
// values are read from the input when the mesh is written, its position
// translated by the region's A d), or a cut vertex whose values sit in `cut`
// (position already translated, then the attribute channels, as floats).
// VertexLayout says where each attribute channel sits in a clip vertex
// (canonical xyz, model xyz, then N, T, the UV sets, C as doubles) and in a
// cut vertex. `assemble` writes the Mesh: faces remapped through the weld
// map, collapsed faces dropped, faces ordered by group (stable), vertices
// numbered by first use. Cost O(output vertices + faces).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "restitch/mesh.hpp"
#include "restitch/stitch/detail/cache.hpp"

namespace restitch::detail {

/// Where each channel sits in a clip vertex (doubles) and in a cut vertex (floats).
struct VertexLayout {
  int stride = 6, off_n = -1, off_t = -1, off_uv = -1, off_c = -1, uv_sets = 0;
  bool has_n = false, has_t = false, has_c = false;
  int cut_stride = 3, cut_n = 0, cut_t = 0, cut_uv = 0, cut_c = 0;  // offsets unused when a channel is absent

  template <class = void>
  explicit VertexLayout(const Mesh& in) {
    has_n = in.N.rows() > 0;
    has_t = in.T.rows() > 0;
    has_c = in.C.rows() > 0;
    uv_sets = int(in.UV.size());
    if (has_n) off_n = stride, stride += 3;
    if (has_t) off_t = stride, stride += 4;
    if (uv_sets) off_uv = stride, stride += 2 * uv_sets;
    if (has_c) off_c = stride, stride += 4;
    // A cut vertex keeps the same channels as floats, without the canonical coordinates.
    cut_n = 3 + (off_n - 6);
    cut_t = 3 + (off_t - 6);
    cut_uv = 3 + (off_uv - 6);
    cut_c = 3 + (off_c - 6);
    cut_stride = stride - 3;
  }

  /// Clip vertex of input vertex v: canonical xyz, model xyz, channels.
  template <class = void>
  void load(const Mesh& in, const ClipStitchCache& cache, std::uint32_t v, double* x) const {
    const double* c = cache.canonical(v);
    for (int a = 0; a < 3; ++a) x[a] = c[a];
    for (int a = 0; a < 3; ++a) x[3 + a] = in.V(Eigen::Index(v), a);
    if (has_n)
      for (int a = 0; a < 3; ++a) x[off_n + a] = in.N(Eigen::Index(v), a);
    if (has_t)
      for (int a = 0; a < 4; ++a) x[off_t + a] = in.T(Eigen::Index(v), a);
    for (int s = 0; s < uv_sets; ++s)
      for (int a = 0; a < 2; ++a) x[off_uv + 2 * s + a] = in.UV[std::size_t(s)](Eigen::Index(v), a);
    if (has_c)
      for (int a = 0; a < 4; ++a) x[off_c + a] = in.C(Eigen::Index(v), a);
  }
};

/// The output being built (see the file comment).
class StitchOutput {
 public:
  static constexpr std::uint32_t cut_bit = 0x80000000u;

  template <class = void>
  StitchOutput(const Mesh& in, const VertexLayout& layout, const std::vector<Eigen::Vector3d>& region_translation)
      : in_(in), L_(layout), region_t_(region_translation), vstamp_(in.vertex_count(), -1), vmap_(in.vertex_count(), 0) {}

  template <class = void>
  void reserve(std::size_t faces, std::size_t vertices) {
    faces_.reserve(3 * faces);
    fgroup_.reserve(faces);
    vsrc_.reserve(vertices);
    vregion_.reserve(vertices);
    vgroup_.reserve(vertices);
  }

  /// Input vertex v copied by `region` (one output vertex per region and input vertex).
  template <class = void>
  std::uint32_t copy_vertex(std::uint32_t v, std::uint32_t group, std::int32_t region) {
    if (vstamp_[v] == region) return vmap_[v];
    const std::uint32_t id = std::uint32_t(vsrc_.size());
    vstamp_[v] = region;
    vmap_[v] = id;
    push(v, group, region);
    return id;
  }

  /// A cut point x (a clip vertex) made by `region`, translated by its A d.
  template <class = void>
  std::uint32_t cut_vertex(const double* x, std::uint32_t group, std::int32_t region) {
    const std::uint32_t id = std::uint32_t(vsrc_.size());
    push(std::uint32_t(cut_.size() / std::size_t(L_.cut_stride)) | cut_bit, group, region);
    const Eigen::Vector3d& t = region_t_[std::size_t(region)];
    for (int a = 0; a < 3; ++a) cut_.push_back(float(x[3 + a] + t(a)));
    if (L_.has_n) push_unit(x + L_.off_n);
    if (L_.has_t) {
      push_unit(x + L_.off_t);
      cut_.push_back(x[L_.off_t + 3] >= 0 ? 1.0f : -1.0f);
    }
    for (int a = 0; a < 2 * L_.uv_sets; ++a) cut_.push_back(float(x[L_.off_uv + a]));
    if (L_.has_c)
      for (int a = 0; a < 4; ++a) cut_.push_back(float(x[L_.off_c + a]));
    return id;
  }

  template <class = void>
  void add_face(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t group) {
    faces_.push_back(a);
    faces_.push_back(b);
    faces_.push_back(c);
    fgroup_.push_back(group);
  }

  /// A new cut vertex on the segment from output vertex a to b, at parameter t
  /// (0 at a), with position p exactly (floats, already translated): the
  /// attributes are interpolated with the clipping rules (normals and tangent
  /// xyz re-normalised, tangent w the sign of the interpolated w, UVs and
  /// colours linear). It takes a's group and region.
  template <class = void>
  std::uint32_t interpolated_vertex(std::uint32_t a, std::uint32_t b, double t, const float* p) {
    double x[4 + 4 + 2 * max_uv_sets + 4];  // channels first, as doubles: the cut store may grow below
    int n = 0;
    auto lerp = [&](const float* u, const float* v, int k) {
      for (int i = 0; i < k; ++i) x[n++] = double(u[i]) + t * (double(v[i]) - double(u[i]));
    };
    if (L_.has_n) lerp(normal(a), normal(b), 3);
    if (L_.has_t) lerp(tangent(a), tangent(b), 4);
    for (int s = 0; s < L_.uv_sets; ++s) lerp(texcoord(a, s), texcoord(b, s), 2);
    if (L_.has_c) lerp(color(a), color(b), 4);
    const std::uint32_t id = std::uint32_t(vsrc_.size());
    push(std::uint32_t(cut_.size() / std::size_t(L_.cut_stride)) | cut_bit, vgroup_[a], vregion_[a]);
    for (int i = 0; i < 3; ++i) cut_.push_back(p[i]);
    int k = 0;
    if (L_.has_n) push_unit(x + k), k += 3;
    if (L_.has_t) {
      push_unit(x + k);
      cut_.push_back(x[k + 3] >= 0 ? 1.0f : -1.0f);
      k += 4;
    }
    for (int i = 0; i < 2 * L_.uv_sets; ++i) cut_.push_back(float(x[k++]));
    if (L_.has_c)
      for (int i = 0; i < 4; ++i) cut_.push_back(float(x[k++]));
    return id;
  }

  /// From now on vertex i takes the position of vertex at[i] (at[i] == i: its own; at[at[i]] == at[i]);
  /// vertices added later keep their own. The weld's geometric part (weld_map).
  void snap_positions(std::vector<std::uint32_t>&& at) { at_ = std::move(at); }

  // Faces as built: 3 corners each (output vertex ids, not yet welded), and their groups.
  std::size_t face_count() const { return fgroup_.size(); }
  const std::uint32_t* face(std::size_t f) const { return &faces_[3 * f]; }
  std::uint32_t face_group(std::size_t f) const { return fgroup_[f]; }
  /// Replaces every face (the T-junction repair's rebuilt list, same layout).
  template <class = void>
  void replace_faces(std::vector<std::uint32_t>&& faces, std::vector<std::uint32_t>&& groups) {
    faces_ = std::move(faces);
    fgroup_ = std::move(groups);
  }

  // Values of output vertex i: position (translated) and attribute channels.
  std::size_t vertex_count() const { return vsrc_.size(); }
  std::int32_t region(std::uint32_t i) const { return vregion_[i]; }
  std::uint32_t group(std::uint32_t i) const { return vgroup_[i]; }
  bool is_cut(std::uint32_t i) const { return (vsrc_[i] & cut_bit) != 0; }
  /// The input vertex an uncut output vertex copies.
  std::uint32_t source(std::uint32_t i) const { return vsrc_[i]; }
  template <class = void>
  void position(std::uint32_t i, float* p) const {
    if (i < at_.size()) i = at_[i];  // snapped onto another vertex's position (snap_positions)
    if (is_cut(i)) {
      std::copy(cut_data(i), cut_data(i) + 3, p);
      return;
    }
    const Eigen::Vector3d& t = region_t_[std::size_t(vregion_[i])];
    for (int a = 0; a < 3; ++a) p[a] = float(double(in_.V(Eigen::Index(vsrc_[i]), a)) + t(a));
  }
  template <class = void>
  const float* normal(std::uint32_t i) const {
    return is_cut(i) ? cut_data(i) + L_.cut_n : in_.N.data() + 3 * std::size_t(vsrc_[i]);
  }
  template <class = void>
  const float* tangent(std::uint32_t i) const {
    return is_cut(i) ? cut_data(i) + L_.cut_t : in_.T.data() + 4 * std::size_t(vsrc_[i]);
  }
  template <class = void>
  const float* texcoord(std::uint32_t i, int set) const {
    return is_cut(i) ? cut_data(i) + L_.cut_uv + 2 * set
                     : in_.UV[std::size_t(set)].data() + 2 * std::size_t(vsrc_[i]);
  }
  template <class = void>
  const float* color(std::uint32_t i) const {
    return is_cut(i) ? cut_data(i) + L_.cut_c : in_.C.data() + 4 * std::size_t(vsrc_[i]);
  }

  /// Writes the mesh: every vertex i replaced by rep_of[i] (the weld map).
  template <class = void>
  void assemble(const std::vector<std::uint32_t>& rep_of, Mesh& out) {
    const std::vector<std::uint32_t> order = kept_faces_by_group(rep_of);
    // Vertices: numbered by first use.
    const std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> newid(vsrc_.size(), none), old;
    old.reserve(vsrc_.size());
    Mesh m;
    m.F.resize(Eigen::Index(order.size()), 3);
    m.FG.resize(Eigen::Index(order.size()));
    std::uint32_t* F = m.F.data();
    for (std::size_t r = 0; r < order.size(); ++r) {
      const std::size_t f = order[r];
      for (std::size_t k = 0; k < 3; ++k) {
        std::uint32_t& id = newid[faces_[3 * f + k]];
        if (id == none) {
          id = std::uint32_t(old.size());
          old.push_back(faces_[3 * f + k]);
        }
        F[3 * r + k] = id;
      }
      m.FG(Eigen::Index(r)) = fgroup_[f];
    }
    write_vertices(old, m);
    m.groups = in_.groups;
    m.materials = in_.materials;
    m.assets = in_.assets;
    out = std::move(m);
  }

 private:
  template <class = void>
  void push(std::uint32_t src, std::uint32_t group, std::int32_t region) {
    vsrc_.push_back(src);
    vregion_.push_back(region);
    vgroup_.push_back(group);
  }
  template <class = void>
  void push_unit(const double* v) {  // xyz re-normalised
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const double s = len > 0 ? 1.0 / len : 1.0;
    for (int a = 0; a < 3; ++a) cut_.push_back(float(v[a] * s));
  }
  template <class = void>
  const float* cut_data(std::uint32_t i) const {
    return cut_.data() + std::size_t(vsrc_[i] & ~cut_bit) * std::size_t(L_.cut_stride);
  }

  // Faces remapped through rep_of, collapsed ones dropped, stable counting sort by group.
  template <class = void>
  std::vector<std::uint32_t> kept_faces_by_group(const std::vector<std::uint32_t>& rep_of) {
    const std::size_t nf = fgroup_.size(), ng = in_.groups.size();
    std::vector<std::uint32_t> gstart(ng + 1, 0);
    for (std::size_t f = 0; f < nf; ++f) {
      std::uint32_t* c = &faces_[3 * f];
      for (int k = 0; k < 3; ++k) c[k] = rep_of[c[k]];
      if (c[0] != c[1] && c[1] != c[2] && c[2] != c[0])
        ++gstart[fgroup_[f] + 1];
      else
        fgroup_[f] = std::uint32_t(ng);  // dropped
    }
    for (std::size_t g = 0; g < ng; ++g) gstart[g + 1] += gstart[g];
    std::vector<std::uint32_t> order(gstart[ng]);
    for (std::size_t f = 0; f < nf; ++f)
      if (fgroup_[f] < ng) order[gstart[fgroup_[f]]++] = std::uint32_t(f);
    return order;
  }

  template <class = void>
  void write_vertices(const std::vector<std::uint32_t>& old, Mesh& m) const {
    const Eigen::Index nv = Eigen::Index(old.size());
    m.V.resize(nv, 3);
    if (L_.has_n) m.N.resize(nv, 3);
    if (L_.has_t) m.T.resize(nv, 4);
    if (L_.has_c) m.C.resize(nv, 4);
    m.UV.assign(std::size_t(L_.uv_sets), MatrixX2f(nv, 2));
    for (std::size_t v = 0; v < std::size_t(nv); ++v) {
      const std::uint32_t s = old[v];
      position(s, m.V.data() + 3 * v);
      if (L_.has_n) std::copy(normal(s), normal(s) + 3, m.N.data() + 3 * v);
      if (L_.has_t) std::copy(tangent(s), tangent(s) + 4, m.T.data() + 4 * v);
      for (int u = 0; u < L_.uv_sets; ++u)
        std::copy(texcoord(s, u), texcoord(s, u) + 2, m.UV[std::size_t(u)].data() + 2 * v);
      if (L_.has_c) std::copy(color(s), color(s) + 4, m.C.data() + 4 * v);
    }
  }

  const Mesh& in_;
  const VertexLayout& L_;
  const std::vector<Eigen::Vector3d>& region_t_;
  std::vector<std::int32_t> vstamp_;  // per input vertex: the region that last copied it
  std::vector<std::uint32_t> vmap_;   // per input vertex: its copy in that region
  std::vector<std::uint32_t> vsrc_;   // input vertex, or cut index | cut_bit
  std::vector<std::int32_t> vregion_;
  std::vector<std::uint32_t> vgroup_;
  std::vector<float> cut_;
  std::vector<std::uint32_t> at_;  // snap_positions; empty: every vertex at its own position
  std::vector<std::uint32_t> faces_;  // 3 per face
  std::vector<std::uint32_t> fgroup_;
};

}  // namespace restitch::detail
