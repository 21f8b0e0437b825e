// Tests for restitch/mesh_boundary.hpp (boundary edges with positions welded) and
// for the stitcher's T-junction repair (restitch/stitch/detail/tjunction.hpp).
#include "restitch/mesh_boundary.hpp"

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cstring>
#include <vector>

#include "restitch/stitch/stitch.hpp"

using restitch::Mesh;

namespace {

// A mesh of one group (normals and one UV set) from triangles given by corner positions,
// every triangle with its own three vertices (so nothing is shared by index).
struct Soup {
  std::vector<Eigen::Vector3d> pos;
  std::vector<std::array<std::uint32_t, 3>> tri;
  std::uint32_t vertex(const Eigen::Vector3d& p) {
    pos.push_back(p);
    return std::uint32_t(pos.size() - 1);
  }
  void triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    tri.push_back({vertex(a), vertex(b), vertex(c)});
  }
  void quad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
    triangle(a, b, c);
    triangle(a, c, d);
  }
  Mesh mesh() const {
    Mesh m;
    const Eigen::Index nv = Eigen::Index(pos.size()), nf = Eigen::Index(tri.size());
    m.V.resize(nv, 3);
    m.N.resize(nv, 3);
    m.UV.assign(1, restitch::MatrixX2f(nv, 2));
    for (Eigen::Index v = 0; v < nv; ++v) {
      const Eigen::Vector3d& p = pos[std::size_t(v)];
      m.V.row(v) = p.cast<float>().transpose();
      // Affine in y and z, the same in every cell along x (as a texture per module would be).
      m.UV[0].row(v) << float(0.25 * p.y() + 0.1 * p.z()), float(p.z() - 0.5 * p.y());
    }
    m.F.resize(nf, 3);
    m.FG.setZero(nf);
    for (Eigen::Index f = 0; f < nf; ++f) {
      const auto& t = tri[std::size_t(f)];
      for (int k = 0; k < 3; ++k) m.F(f, k) = t[std::size_t(k)];
      const Eigen::Vector3d n =
          (pos[t[1]] - pos[t[0]]).cross(pos[t[2]] - pos[t[0]]).normalized();  // flat: one normal per face
      for (int k = 0; k < 3; ++k) m.N.row(t[std::size_t(k)]) = n.cast<float>().transpose();
    }
    restitch::Group g;
    g.attributes.normals = true;
    g.attributes.uv_sets = 1;
    m.groups.push_back(g);
    return m;
  }
};

// Axis-aligned box [lo, hi], outward, every face its own vertices; `skip` leaves one face out (0..5, -1 none).
void box(Soup& s, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int skip = -1) {
  auto P = [&](int i, int j, int k) {
    return Eigen::Vector3d(i ? hi.x() : lo.x(), j ? hi.y() : lo.y(), k ? hi.z() : lo.z());
  };
  const std::array<std::array<Eigen::Vector3d, 4>, 6> q = {{{P(0, 0, 0), P(0, 1, 0), P(1, 1, 0), P(1, 0, 0)},
                                                             {P(0, 0, 1), P(1, 0, 1), P(1, 1, 1), P(0, 1, 1)},
                                                             {P(0, 0, 0), P(1, 0, 0), P(1, 0, 1), P(0, 0, 1)},
                                                             {P(0, 1, 0), P(0, 1, 1), P(1, 1, 1), P(1, 1, 0)},
                                                             {P(0, 0, 0), P(0, 0, 1), P(0, 1, 1), P(0, 1, 0)},
                                                             {P(1, 0, 0), P(1, 1, 0), P(1, 1, 1), P(1, 0, 1)}}};
  for (int f = 0; f < 6; ++f)
    if (f != skip) s.quad(q[std::size_t(f)][0], q[std::size_t(f)][1], q[std::size_t(f)][2], q[std::size_t(f)][3]);
}

// A closed bar along x over 3 cells of pitch 1 (y, z in [0, 1]) whose +z face
// is tessellated differently at its two ends inside cell 1: at x = 1 the face
// has corners at y = 0 and 1 only, at x = 2 (and in cell 2) also at y = 0.5.
// The input is closed. Stitching output cells {0, 1} from input cells {0, 1}
// and output cells {2, 3} from input cells {1, 2} joins the x = 2 end of cell 1
// (split at y = 0.5) to the x = 1 end of cell 1 (not split): a T-junction.
Mesh t_bar() {
  Soup s;
  using V = Eigen::Vector3d;
  for (int side = 0; side < 4; ++side) {  // -y, +y, -z faces (plain quads per cell); +z below
    if (side == 3) continue;
    for (int c = 0; c < 3; ++c) {
      const double x0 = c, x1 = c + 1;
      if (side == 0) s.quad(V(x0, 0, 0), V(x1, 0, 0), V(x1, 0, 1), V(x0, 0, 1));
      if (side == 1) s.quad(V(x0, 1, 0), V(x0, 1, 1), V(x1, 1, 1), V(x1, 1, 0));
      if (side == 2) s.quad(V(x0, 0, 0), V(x0, 1, 0), V(x1, 1, 0), V(x1, 0, 0));
    }
  }
  // +z face (z = 1), counter-clockwise seen from +z.
  s.quad(V(0, 0, 1), V(1, 0, 1), V(1, 1, 1), V(0, 1, 1));  // cell 0: corners only
  s.triangle(V(1, 0, 1), V(2, 0, 1), V(2, 0.5, 1));        // cell 1: a fan from x = 1 to the split end x = 2
  s.triangle(V(1, 0, 1), V(2, 0.5, 1), V(1, 1, 1));
  s.triangle(V(1, 1, 1), V(2, 0.5, 1), V(2, 1, 1));
  s.quad(V(2, 0, 1), V(3, 0, 1), V(3, 0.5, 1), V(2, 0.5, 1));  // cell 2: split at y = 0.5 along its length
  s.quad(V(2, 0.5, 1), V(3, 0.5, 1), V(3, 1, 1), V(2, 1, 1));
  s.quad(V(0, 0, 0), V(0, 0, 1), V(0, 1, 1), V(0, 1, 0));  // end cap x = 0
  const V m(3, 0.5, 1);                                     // end cap x = 3: fanned from the split point
  s.triangle(m, V(3, 0, 1), V(3, 0, 0));
  s.triangle(m, V(3, 0, 0), V(3, 1, 0));
  s.triangle(m, V(3, 1, 0), V(3, 1, 1));
  return s.mesh();
}

// t_bar with two materials on cell 1's +z face, fanned from its centre c = (1.5, 0.5, 1): the triangle
// on the x = 1 end in material 0, the four that reach the x = 2 end (and its split point) in material 1.
// The T-junction the stitch makes at x = 2 then has its long edge in material 0 and its T-vertex in
// material 1 only.
Mesh t_bar_two_materials() {
  Mesh plain = t_bar();
  Soup s;
  using V = Eigen::Vector3d;
  std::vector<std::uint8_t> material;
  const V c(1.5, 0.5, 1);
  for (Eigen::Index f = 0; f < plain.F.rows(); ++f) {
    V p[3];
    for (int k = 0; k < 3; ++k) p[k] = plain.V.row(plain.F(f, k)).cast<double>().transpose();
    const bool cell1_top = p[0].z() == 1 && p[1].z() == 1 && p[2].z() == 1 &&
                           std::min({p[0].x(), p[1].x(), p[2].x()}) == 1 && std::max({p[0].x(), p[1].x(), p[2].x()}) == 2;
    if (cell1_top) continue;
    s.triangle(p[0], p[1], p[2]);
    material.push_back(0);
  }
  s.triangle(V(1, 0, 1), c, V(1, 1, 1));  // counter-clockwise seen from +z, as the face it replaces
  material.push_back(0);
  for (const auto& [a, b] : {std::pair<V, V>{V(1, 0, 1), V(2, 0, 1)}, {V(2, 0, 1), V(2, 0.5, 1)},
                             {V(2, 0.5, 1), V(2, 1, 1)}, {V(2, 1, 1), V(1, 1, 1)}}) {
    s.triangle(a, b, c);
    material.push_back(1);
  }
  Mesh m = s.mesh();
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) m.FG(f) = material[std::size_t(f)];
  m.groups.push_back(m.groups[0]);
  return m;
}

restitch::Lattice lattice_x3() {
  restitch::Lattice l;
  l.A = Eigen::Matrix3d::Identity();
  l.cells = Eigen::Array3i(3, 1, 1);
  l.dummy = {{false, true, true}};
  return l;
}

bool same_bits(const Mesh& a, const Mesh& b) {
  auto eq = [](const auto& x, const auto& y) {
    return x.rows() == y.rows() && x.cols() == y.cols() &&
           (x.size() == 0 || std::memcmp(x.data(), y.data(), sizeof(*x.data()) * std::size_t(x.size())) == 0);
  };
  return eq(a.V, b.V) && eq(a.F, b.F) && eq(a.FG, b.FG) && eq(a.N, b.N) && eq(a.UV[0], b.UV[0]);
}

}  // namespace

TEST_CASE("boundary edges: a closed box has none, an open one four, whatever the vertex sharing", "[mesh]") {
  Soup closed;
  box(closed, {0, 0, 0}, {1, 2, 3});
  const Mesh m = closed.mesh();
  CHECK(restitch::boundary_edge_count(m) == 0);
  // Every triangle has its own vertices: by index alone all 3 edges of each of the 12 triangles are open.
  CHECK(restitch::boundary_edge_count_at(m, 0.0) == 36);
  Soup open;
  box(open, {0, 0, 0}, {1, 2, 3}, 5);
  CHECK(restitch::boundary_edge_count(open.mesh()) == 4);
  // A gap wider than the tolerance is open; one within it is welded.
  Soup moved;
  box(moved, {0, 0, 0}, {1, 2, 3}, 5);
  moved.quad({1 + 1e-3, 0, 0}, {1 + 1e-3, 2, 0}, {1 + 1e-3, 2, 3}, {1 + 1e-3, 0, 3});
  CHECK(restitch::boundary_edge_count(moved.mesh()) == 8);
  Soup near;
  box(near, {0, 0, 0}, {1, 2, 3}, 5);
  const double d = 0.2 * 1e-6 * std::sqrt(14.0);  // a fifth of the weld tolerance
  near.quad({1 + d, 0, 0}, {1 + d, 2, 0}, {1 + d, 2, 3}, {1 + d, 0, 3});
  CHECK(restitch::boundary_edge_count(near.mesh()) == 0);
}

TEST_CASE("boundary edges: a T-junction is open; the bar's input is closed", "[mesh]") {
  Soup t;  // two triangles of one square, one edge split by a vertex of the neighbour: 3 open edges there
  t.quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
  t.triangle({1, 0, 0}, {2, 0, 0}, {1, 0.5, 0});
  t.triangle({1, 0.5, 0}, {2, 0, 0}, {1, 1, 0});
  // Open: the square's 4 outer edges (its x = 1 edge is not shared: the
  // neighbour has two halves), the neighbour's 2 halves and its 2 outer edges.
  CHECK(restitch::boundary_edge_count(t.mesh()) == 4 + 2 + 2);
  CHECK(restitch::boundary_edge_count(t_bar()) == 0);
}

TEST_CASE("stitch: a T-junction on a seam is split, so a closed input stays closed", "[stitch]") {
  const Mesh in = t_bar();
  REQUIRE(restitch::boundary_edge_count(in) == 0);
  const restitch::Lattice lat = lattice_x3();
  // Output cells 0, 1 copy input 0, 1; output cells 2, 3 copy input 1, 2.
  const std::vector<Eigen::Array3i> labels = {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  restitch::ClipStitcher with, without;
  without.repair_t_junctions = false;
  without.zip_seams = false;  // the strips would close it too, with a triangle of no area
  Mesh out, out_plain, again;
  restitch::StitchReport rep, rep_plain, rep_again;
  REQUIRE(without.stitch(in, lat, {4, 1, 1}, labels, out_plain, rep_plain).ok());
  REQUIRE(with.stitch(in, lat, {4, 1, 1}, labels, out, rep).ok());
  // Without the repair: the unsplit edge (2,0,1)-(2,1,1) and the two halves across it are open.
  CHECK(restitch::boundary_edge_count(out_plain) == 3);
  CHECK(rep_plain.t_junction_edges_split == 0);
  CHECK(restitch::boundary_edge_count(out) == 0);
  CHECK(rep.t_junction_edges_split == 1);
  CHECK(out.triangle_count() == out_plain.triangle_count() + 1);  // one face fanned into two
  CHECK(restitch::validate(out).ok());
  // The new corner got the T-vertex's attributes (UVs affine, normals of one plane): it welded to it,
  // so no vertex was added: the mesh is closed by index along that seam too.
  CHECK(out.vertex_count() == out_plain.vertex_count());
  // Area is kept (the fan covers the face exactly).
  double a0 = 0, a1 = 0;
  for (Eigen::Index f = 0; f < out.F.rows(); ++f) a1 += restitch::double_area(out, f);
  for (Eigen::Index f = 0; f < out_plain.F.rows(); ++f) a0 += restitch::double_area(out_plain, f);
  CHECK(a1 == Approx(a0).epsilon(1e-9));
  // Deterministic.
  REQUIRE(with.stitch(in, lat, {4, 1, 1}, labels, again, rep_again).ok());
  CHECK(same_bits(out, again));
}

TEST_CASE("stitch: a T-vertex whose attributes differ gets its own vertex (texture seams stay split)", "[stitch]") {
  Mesh in = t_bar();
  // Shift the UVs of the cell-1 and cell-2 +z triangles that touch (2, 0.5, 1): the T-vertex's UV no
  // longer matches the interpolation along the other side's edge.
  for (Eigen::Index v = 0; v < in.V.rows(); ++v)
    if (std::abs(in.V(v, 0) - 2) < 1e-6 && std::abs(in.V(v, 1) - 0.5) < 1e-6) in.UV[0](v, 0) += 0.25f;
  const std::vector<Eigen::Array3i> labels = {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  restitch::ClipStitcher with, without;
  without.repair_t_junctions = false;
  Mesh out, out_plain;
  restitch::StitchReport rep, rep_plain;
  REQUIRE(without.stitch(in, lattice_x3(), {4, 1, 1}, labels, out_plain, rep_plain).ok());
  REQUIRE(with.stitch(in, lattice_x3(), {4, 1, 1}, labels, out, rep).ok());
  CHECK(restitch::boundary_edge_count(out) == 0);  // closed geometrically
  CHECK(rep.t_junction_edges_split == 1);
  CHECK(out.vertex_count() == out_plain.vertex_count() + 1);  // but the new corner stays its own vertex
}

TEST_CASE("stitch: a T-vertex of another material closes the edge it lies on", "[stitch]") {
  // Where two materials meet, the input's faces share positions, not vertices: the only vertex that can
  // close the long edge is the other material's. The new corner gets the long edge's material (its own
  // vertex: vertices of two materials are never welded).
  const Mesh in = t_bar_two_materials();
  REQUIRE(restitch::boundary_edge_count(in) == 0);
  const std::vector<Eigen::Array3i> labels = {{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  restitch::ClipStitcher with, without;
  without.repair_t_junctions = false;
  without.zip_seams = false;
  Mesh out, out_plain;
  restitch::StitchReport rep, rep_plain;
  REQUIRE(without.stitch(in, lattice_x3(), {4, 1, 1}, labels, out_plain, rep_plain).ok());
  REQUIRE(with.stitch(in, lattice_x3(), {4, 1, 1}, labels, out, rep).ok());
  CHECK(restitch::boundary_edge_count(out_plain) == 3);
  CHECK(restitch::boundary_edge_count(out) == 0);
  CHECK(rep.t_junction_edges_split == 1);
  CHECK(out.vertex_count() == out_plain.vertex_count() + 1);
  CHECK(restitch::validate(out).ok());
  // The fanned face keeps material 0: each material's area is what it was.
  for (std::uint32_t g = 0; g < 2; ++g) {
    double a0 = 0, a1 = 0;
    for (Eigen::Index f = 0; f < out.F.rows(); ++f)
      if (out.FG(f) == g) a1 += restitch::double_area(out, f);
    for (Eigen::Index f = 0; f < out_plain.F.rows(); ++f)
      if (out_plain.FG(f) == g) a0 += restitch::double_area(out_plain, f);
    CHECK(a1 == Approx(a0).epsilon(1e-9));
  }
}
