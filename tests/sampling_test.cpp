// Tests of restitch/sampling/poisson_disk.hpp and restitch/sampling/features.hpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "restitch/sampling/features.hpp"
#include "restitch/sampling/poisson_disk.hpp"

using restitch::Mesh;
using restitch::Normalization;
using restitch::PointSet;

namespace {

// A triangle soup from corner positions; one group. Faces get their own
// vertices (flat shading) when `shared` is false.
Mesh make_mesh(const std::vector<Eigen::Vector3f>& corners, const std::vector<std::array<int, 3>>& tris) {
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(corners.size()), 3);
  for (std::size_t i = 0; i < corners.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = corners[i].transpose();
  m.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t f = 0; f < tris.size(); ++f)
    for (int k = 0; k < 3; ++k) m.F(static_cast<Eigen::Index>(f), k) = static_cast<std::uint32_t>(tris[f][k]);
  m.FG = restitch::VectorXu::Zero(m.F.rows());
  m.groups.resize(1);
  return m;
}

// Axis-aligned box [lo, hi], outward-facing triangles, 8 shared corners.
Mesh make_box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  std::vector<Eigen::Vector3f> c;
  for (int i = 0; i < 8; ++i)
    c.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z());
  // Quads as corner bit patterns, then oriented outward by the centroid test.
  const int quads[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  const Eigen::Vector3f mid = 0.5f * (lo + hi);
  std::vector<std::array<int, 3>> t;
  for (const auto& q : quads)
    for (const std::array<int, 3>& tri : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
      const Eigen::Vector3f n = (c[tri[1]] - c[tri[0]]).cross(c[tri[2]] - c[tri[0]]);
      if (n.dot(c[tri[0]] - mid) < 0)
        t.push_back({tri[0], tri[2], tri[1]});
      else
        t.push_back(tri);
    }
  return make_mesh(c, t);
}

double min_pair_distance_squared(const PointSet& s) {
  double best = INFINITY;
  for (Eigen::Index i = 0; i < s.size(); ++i)
    for (Eigen::Index j = i + 1; j < s.size(); ++j)
      best = std::min(best, (s.points.row(i).cast<double>() - s.points.row(j).cast<double>()).squaredNorm());
  return best;
}

Normalization identity() { return Normalization{}; }

}  // namespace

TEST_CASE("poisson_disk_sample respects the spacing, covers the surface and keeps face normals", "[sampling]") {
  const Mesh box = make_box({-1, -1, -1}, {1, 1, 1});  // area 24, normalization = identity
  const Normalization norm = Normalization::of(restitch::bounding_box(box));
  REQUIRE(norm.scale == 1.0);
  const double s = 0.1;
  auto r = restitch::poisson_disk_sample(box, norm, s, 7);
  REQUIRE(r.ok());
  const PointSet& p = *r;
  REQUIRE(p.normals.rows() == p.size());

  // Spacing, by brute force over all pairs.
  CHECK(min_pair_distance_squared(p) >= s * s);

  // Count ~ area / spacing^2 (random close packing gives ~0.7 per spacing^2).
  const double per_area = double(p.size()) * s * s / 24.0;
  CHECK(per_area > 0.5);
  CHECK(per_area < 1.16);

  // Points on the surface; normal = outward axis of the face the point lies on.
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    const Eigen::Vector3f q = p.points.row(i), n = p.normals.row(i);
    CHECK(q.cwiseAbs().maxCoeff() <= 1.0f + 1e-6f);
    Eigen::Index axis;
    n.cwiseAbs().maxCoeff(&axis);
    CHECK(std::abs(n[axis]) == Approx(1.0).margin(1e-6));
    CHECK(n.norm() == Approx(1.0).margin(1e-6));
    CHECK(std::abs(q[axis]) == Approx(1.0).margin(1e-6));
    CHECK(n[axis] * q[axis] > 0);
  }

  // Coverage: every point of a 0.1 grid on every face is within 2 spacings of a sample.
  double worst = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = -1; side <= 1; side += 2)
      for (int u = 0; u <= 20; ++u)
        for (int v = 0; v <= 20; ++v) {
          Eigen::Vector3d g;
          g[axis] = side;
          g[(axis + 1) % 3] = -1 + 0.1 * u;
          g[(axis + 2) % 3] = -1 + 0.1 * v;
          double best = INFINITY;
          for (Eigen::Index i = 0; i < p.size(); ++i)
            best = std::min(best, (p.points.row(i).transpose().cast<double>() - g).squaredNorm());
          worst = std::max(worst, std::sqrt(best));
        }
  CHECK(worst <= 2 * s);
  // Near-maximal: in practice the largest gap is about one spacing.
  CHECK(worst <= 1.3 * s);
}

TEST_CASE("poisson_disk_sample count scales with area / spacing^2", "[sampling]") {
  const Mesh box = make_box({-1, -1, -1}, {1, 1, 1});
  auto a = restitch::poisson_disk_sample(box, identity(), 0.1, 1);
  auto b = restitch::poisson_disk_sample(box, identity(), 0.05, 1);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  const double ratio = double(b->size()) / double(a->size());
  CHECK(ratio > 3.5);
  CHECK(ratio < 4.5);
  // A box of two thirds of the cube's area at the same spacing (faces farther
  // apart than the spacing: Poisson-disk distance is 3-D, not geodesic).
  const Mesh slab = make_box({-1, -1, -0.5f}, {1, 1, 0.5f});  // area 8 + 8
  auto c = restitch::poisson_disk_sample(slab, identity(), 0.1, 1);
  REQUIRE(c.ok());
  CHECK(double(c->size()) / double(a->size()) == Approx(16.0 / 24.0).epsilon(0.05));
}

TEST_CASE("poisson_disk_sample is deterministic per seed and normalizes first", "[sampling]") {
  const Mesh box = make_box({-1, -1, -1}, {1, 1, 1});
  auto a = restitch::poisson_disk_sample(box, identity(), 0.1, 42);
  auto b = restitch::poisson_disk_sample(box, identity(), 0.1, 42);
  auto c = restitch::poisson_disk_sample(box, identity(), 0.1, 43);
  REQUIRE((a.ok() && b.ok() && c.ok()));
  CHECK(a->points == b->points);
  CHECK(a->normals == b->normals);
  CHECK(!(a->points.rows() == c->points.rows() && a->points == c->points));

  // A box in model units [10, 30] x [0, 4] x [5, 6]: samples land in the normalized frame.
  const Mesh big = make_box({10, 0, 5}, {30, 4, 6});
  const Normalization norm = Normalization::of(restitch::bounding_box(big));
  auto d = restitch::poisson_disk_sample(big, norm, 0.05, 3);
  REQUIRE(d.ok());
  REQUIRE(d->size() > 100);
  CHECK(d->points.col(0).minCoeff() >= -1.0f - 1e-6f);
  CHECK(d->points.col(0).maxCoeff() <= 1.0f + 1e-6f);
  CHECK(d->points.col(1).cwiseAbs().maxCoeff() <= 0.2f + 1e-6f);
  CHECK(d->points.col(2).cwiseAbs().maxCoeff() <= 0.05f + 1e-6f);
  CHECK(d->points.col(0).maxCoeff() > 0.95f);
  CHECK(d->points.col(0).minCoeff() < -0.95f);
}

TEST_CASE("poisson_disk_sample ignores zero-area triangles", "[sampling]") {
  // Unit square of two triangles; then the same with degenerate triangles appended.
  std::vector<Eigen::Vector3f> c = {{0, 0, 0},    {1, 0, 0},    {1, 1, 0},   {0, 1, 0},
                                    {0, 0, 0.5f}, {0, 0, 0.7f}, {0, 0, 0.9f}};
  const Mesh square = make_mesh(c, {{0, 1, 2}, {0, 2, 3}});
  const Mesh with_degenerate = make_mesh(c, {{0, 1, 2}, {4, 5, 6}, {0, 2, 3}, {4, 4, 5}, {6, 6, 6}});
  auto a = restitch::poisson_disk_sample(square, identity(), 0.05, 9);
  auto b = restitch::poisson_disk_sample(with_degenerate, identity(), 0.05, 9);
  REQUIRE((a.ok() && b.ok()));
  CHECK(a->points == b->points);
  CHECK(a->normals == b->normals);
  CHECK(b->points.col(2).cwiseAbs().maxCoeff() == 0.0f);
  for (Eigen::Index i = 0; i < b->size(); ++i) CHECK(b->normals.row(i) == Eigen::RowVector3f(0, 0, 1));

  const Mesh only_degenerate = make_mesh(c, {{4, 5, 6}, {0, 0, 1}});
  auto d = restitch::poisson_disk_sample(only_degenerate, identity(), 0.05, 9);
  REQUIRE(!d.ok());
  CHECK(d.status().code() == restitch::StatusCode::invalid_mesh);
}

TEST_CASE("poisson_disk_sample rejects bad input and honours cancellation", "[sampling]") {
  const Mesh box = make_box({-1, -1, -1}, {1, 1, 1});
  CHECK(restitch::poisson_disk_sample(box, identity(), 0.0, 1).status().code() ==
        restitch::StatusCode::invalid_argument);
  CHECK(restitch::poisson_disk_sample(box, identity(), NAN, 1).status().code() ==
        restitch::StatusCode::invalid_argument);
  CHECK(restitch::poisson_disk_sample(box, identity(), 1e-6, 1).status().code() == restitch::StatusCode::too_large);
  CHECK(restitch::poisson_disk_sample(Mesh{}, identity(), 0.1, 1).status().code() ==
        restitch::StatusCode::invalid_mesh);
  Mesh bad = box;
  bad.F(3, 1) = 99;
  CHECK(restitch::poisson_disk_sample(bad, identity(), 0.1, 1).status().code() == restitch::StatusCode::invalid_mesh);
  Mesh nan = box;
  nan.V(2, 0) = NAN;
  CHECK(restitch::poisson_disk_sample(nan, identity(), 0.1, 1).status().code() == restitch::StatusCode::invalid_mesh);

  std::vector<std::string> stages;
  restitch::Progress stop([&](std::string_view stage, double) {
    stages.emplace_back(stage);
    return false;
  });
  CHECK(restitch::poisson_disk_sample(box, identity(), 0.1, 1, stop).status().code() ==
        restitch::StatusCode::cancelled);
  REQUIRE(!stages.empty());
  CHECK(stages[0] == "sampling");
}

TEST_CASE("vertex_features merges duplicates and averages face normals by area", "[sampling]") {
  // Flat-shaded octahedron: 8 faces with their own 3 vertices each, plus an unreferenced vertex.
  const Eigen::Vector3f ax[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<Eigen::Vector3f> c = {{5, 5, 5}};  // index 0: unreferenced
  std::vector<std::array<int, 3>> t;
  for (int sx : {0, 1})
    for (int sy : {2, 3})
      for (int sz : {4, 5}) {
        std::array<Eigen::Vector3f, 3> tri = {ax[sx], ax[sy], ax[sz]};
        if ((tri[1] - tri[0]).cross(tri[2] - tri[0]).dot(tri[0] + tri[1] + tri[2]) < 0) std::swap(tri[1], tri[2]);
        const int base = static_cast<int>(c.size());
        for (const auto& p : tri) c.push_back(p);
        t.push_back({base, base + 1, base + 2});
      }
  const Mesh oct = make_mesh(c, t);
  auto r = restitch::vertex_features(oct, identity());
  REQUIRE(r.ok());
  REQUIRE(r->size() == 6);
  // Order: by the lowest index of each position; the first face is (+x, +y, +z) up to orientation.
  std::vector<int> first_index;
  for (Eigen::Index i = 0; i < r->size(); ++i) {
    const Eigen::Vector3f p = r->points.row(i);
    CHECK(p.norm() == Approx(1.0));
    CHECK((r->normals.row(i) - r->points.row(i)).norm() < 1e-6f);  // normal = direction of the vertex
    int k = 1;
    while (c[static_cast<std::size_t>(k)] != p) ++k;
    first_index.push_back(k);
  }
  CHECK(std::is_sorted(first_index.begin(), first_index.end()));
  CHECK(first_index[0] == 1);

  // Area weighting: an L-shaped pair of faces, one 4x larger: normal leans to the larger one.
  const Mesh ell = make_mesh({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 1}, {0, 1, 0}},
                             {{0, 1, 2}, {0, 4, 3}});  // +z face area 2, -x... face area 0.5
  auto e = restitch::vertex_features(ell, identity());
  REQUIRE(e.ok());
  const Eigen::Vector3d n0 = Eigen::Vector3d(0, 0, 4) + Eigen::Vector3d(1, 0, 0);  // cross products
  CHECK((e->normals.row(0).cast<double>().transpose() - n0.normalized()).norm() < 1e-6);

  // Opposite coincident faces: the sum is zero; fallback gives a finite unit normal.
  const Mesh two_sided = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 1}});
  auto d = restitch::vertex_features(two_sided, identity());
  REQUIRE(d.ok());
  REQUIRE(d->size() == 3);
  for (Eigen::Index i = 0; i < 3; ++i) {
    CHECK(d->normals.row(i).allFinite());
    CHECK(d->normals.row(i).norm() == Approx(1.0));
    CHECK(std::abs(d->normals(i, 2)) == Approx(1.0));
  }
}

TEST_CASE("vertex_features respects the cap deterministically", "[sampling]") {
  // A 60 x 60 vertex grid on [-1, 1]^2 (pitch ~0.034), shared vertices. Flat: its inner vertices are
  // shape-neutral, so the cap is tested with keep_flat (the last argument).
  const int g = 60;
  std::vector<Eigen::Vector3f> c;
  std::vector<std::array<int, 3>> t;
  for (int y = 0; y < g; ++y)
    for (int x = 0; x < g; ++x) c.emplace_back(-1 + 2.0f * x / (g - 1), -1 + 2.0f * y / (g - 1), 0);
  for (int y = 0; y + 1 < g; ++y)
    for (int x = 0; x + 1 < g; ++x) {
      const int a = y * g + x;
      t.push_back({a, a + 1, a + g + 1});
      t.push_back({a, a + g + 1, a + g});
    }
  const Mesh grid = make_mesh(c, t);
  const Normalization norm = Normalization::of(restitch::bounding_box(grid));

  auto all = restitch::vertex_features(grid, norm, 20000, 0.02, 1, true);
  REQUIRE(all.ok());
  CHECK(all->size() == g * g);

  // Spacing 0.1 thins below the cap: a Poisson-disk subset.
  auto thin = restitch::vertex_features(grid, norm, 1000, 0.1, 5, true);
  REQUIRE(thin.ok());
  CHECK(thin->size() < 1000);
  CHECK(thin->size() > 200);
  CHECK(min_pair_distance_squared(*thin) >= 0.01);
  auto again = restitch::vertex_features(grid, norm, 1000, 0.1, 5, true);
  REQUIRE(again.ok());
  CHECK(again->points == thin->points);

  // Spacing below the pitch removes nothing: the strided subset makes exactly `cap`.
  auto capped = restitch::vertex_features(grid, norm, 500, 0.02, 5, true);
  REQUIRE(capped.ok());
  CHECK(capped->size() == 500);
  for (Eigen::Index i = 0; i < capped->size(); ++i) CHECK(capped->normals.row(i) == Eigen::RowVector3f(0, 0, 1));

  auto none = restitch::vertex_features(grid, norm, 0);
  REQUIRE(none.ok());
  CHECK(none->size() == 0);
  CHECK(restitch::vertex_features(grid, norm, 10, -1.0).status().code() == restitch::StatusCode::invalid_argument);

  const PointSet both = restitch::concat(*thin, *capped);
  REQUIRE(both.size() == thin->size() + capped->size());
  CHECK(both.points.topRows(thin->size()) == thin->points);
  CHECK(both.normals.bottomRows(capped->size()) == capped->normals);
}

TEST_CASE("vertex_features leaves out shape-neutral vertices: inside flat regions and straight edges", "[sampling]") {
  // A 61 x 61 grid on [-1, 1]^2 folded into a roof z = 0.3 |x| (one column of vertices on the ridge x = 0).
  const int g = 61;
  auto roof = [&](bool fold) {
    std::vector<Eigen::Vector3f> c;
    std::vector<std::array<int, 3>> t;
    for (int y = 0; y < g; ++y)
      for (int x = 0; x < g; ++x) {
        const float u = -1 + 2.0f * x / (g - 1);
        c.emplace_back(u, -1 + 2.0f * y / (g - 1), fold ? 0.3f * std::abs(u) : 0.0f);
      }
    for (int y = 0; y + 1 < g; ++y)
      for (int x = 0; x + 1 < g; ++x) {
        const int a = y * g + x;
        t.push_back({a, a + 1, a + g + 1});
        t.push_back({a, a + g + 1, a + g});
      }
    return make_mesh(c, t);
  };
  const Mesh flat = roof(false), folded = roof(true);
  // Flat: inside the square and along its straight open edges every vertex is neutral; the 4 corners stay.
  auto f = restitch::vertex_features(flat, Normalization::of(restitch::bounding_box(flat)));
  REQUIRE(f.ok());
  CHECK(f->size() == 4);
  // Folded: the ridge is a straight crease, neutral inside too; its two ends (a crease meeting the open
  // edge) and the 4 corners stay.
  auto r = restitch::vertex_features(folded, Normalization::of(restitch::bounding_box(folded)));
  REQUIRE(r.ok());
  CHECK(r->size() == 6);
  for (Eigen::Index i = 0; i < r->size(); ++i) {
    const Eigen::Vector3f p = r->points.row(i);
    CHECK(std::abs(std::abs(p.y()) - 1) < 1e-6f);  // on the open edges y = +-1
    CHECK((std::abs(p.x()) < 1e-6f || std::abs(std::abs(p.x()) - 1) < 1e-6f));
  }
  // A bent line is no straight crease: fold the ridge's middle vertex up, and it and its neighbours stay.
  Mesh kinked = folded;
  kinked.V(((g - 1) / 2) * g + (g - 1) / 2, 2) += 0.05f;
  auto k = restitch::vertex_features(kinked, Normalization::of(restitch::bounding_box(kinked)));
  REQUIRE(k.ok());
  CHECK(k->size() > 6);
  // The same square flat-shaded (every triangle with its own three vertices, as glTF exports often are):
  // positions merge first, so the same 4 corners remain; a zero-area triangle's vertex is kept.
  {
    std::vector<Eigen::Vector3f> c;
    std::vector<std::array<int, 3>> t;
    for (Eigen::Index f = 0; f < flat.F.rows(); ++f) {
      const int base = int(c.size());
      for (int k = 0; k < 3; ++k) c.push_back(flat.V.row(flat.F(f, k)).transpose());
      t.push_back({base, base + 1, base + 2});
    }
    const Mesh split = make_mesh(c, t);
    auto sf = restitch::vertex_features(split, Normalization::of(restitch::bounding_box(split)));
    REQUIRE(sf.ok());
    CHECK(sf->size() == 4);
    const int centre = (g / 2) * g + g / 2;  // an inner vertex of the shared grid
    Mesh sliver = flat;
    sliver.F.conservativeResize(sliver.F.rows() + 1, 3);
    sliver.F.row(sliver.F.rows() - 1) << std::uint32_t(centre), std::uint32_t(centre + 1), std::uint32_t(centre + 2);
    auto zf = restitch::vertex_features(sliver, Normalization::of(restitch::bounding_box(sliver)));
    REQUIRE(zf.ok());
    CHECK(zf->size() == 4 + 3);  // the collinear triangle's three corners stay
  }
  // Two coincident sheets facing opposite ways (a board resting on another, vertices at the same
  // positions): the flat square plus a reversed copy of the grid's vertex range [lo, hi]^2 with its own
  // vertices. Inside the overlap every edge has two faces along +z and two along -z: neutral. The copy's
  // straight sides lying on the square are neutral too; its 4 corners and the square's stay.
  auto double_sheet = [&](int lo, int hi) {
    std::vector<Eigen::Vector3f> c;
    std::vector<std::array<int, 3>> t;
    for (Eigen::Index v = 0; v < flat.V.rows(); ++v) c.push_back(flat.V.row(v).transpose());
    for (Eigen::Index f = 0; f < flat.F.rows(); ++f) t.push_back({int(flat.F(f, 0)), int(flat.F(f, 1)), int(flat.F(f, 2))});
    const int base = int(c.size()), w = hi - lo + 1;
    for (int y = lo; y <= hi; ++y)
      for (int x = lo; x <= hi; ++x) c.push_back(flat.V.row(y * g + x).transpose());
    for (int y = 0; y + 1 < w; ++y)
      for (int x = 0; x + 1 < w; ++x) {
        const int a = base + y * w + x;
        t.push_back({a, a + w + 1, a + 1});  // reversed winding: normal -z
        t.push_back({a, a + w, a + w + 1});
      }
    return make_mesh(c, t);
  };
  const Mesh both = double_sheet(0, g - 1), board = double_sheet(10, 40);
  auto bf = restitch::vertex_features(both, Normalization::of(restitch::bounding_box(both)));
  REQUIRE(bf.ok());
  CHECK(bf->size() == 4);
  auto of = restitch::vertex_features(board, Normalization::of(restitch::bounding_box(board)));
  REQUIRE(of.ok());
  CHECK(of->size() == 4 + 4);
  // But four faces along +-z on ONE side of an edge are a stack ending there, not two sheets passing
  // through: a double-sided triangle card stacked twice keeps its 3 corners.
  {
    std::vector<Eigen::Vector3f> c;
    std::vector<std::array<int, 3>> t;
    for (int copy = 0; copy < 4; ++copy) {
      const int base = int(c.size());
      c.emplace_back(0.0f, 0.0f, 0.0f);
      c.emplace_back(1.0f, 0.0f, 0.0f);
      c.emplace_back(0.0f, 1.0f, 0.0f);
      if (copy % 2 == 0)
        t.push_back({base, base + 1, base + 2});
      else
        t.push_back({base, base + 2, base + 1});
    }
    const Mesh stack = make_mesh(c, t);
    auto sf = restitch::vertex_features(stack, Normalization::of(restitch::bounding_box(stack)));
    REQUIRE(sf.ok());
    CHECK(sf->size() == 3);
  }
  // keep_flat: every vertex.
  auto all = restitch::vertex_features(folded, Normalization::of(restitch::bounding_box(folded)), 20000, 0.02, 1, true);
  REQUIRE(all.ok());
  CHECK(all->size() == g * g);
  // A closed flat-faced solid (the octahedron of the test above, shared vertices): every vertex bends.
  const Eigen::Vector3f ax[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<Eigen::Vector3f> c(ax, ax + 6);
  std::vector<std::array<int, 3>> t;
  for (int sx : {0, 1})
    for (int sy : {2, 3})
      for (int sz : {4, 5}) t.push_back({sx, sy, sz});
  auto o = restitch::vertex_features(make_mesh(c, t), identity());
  REQUIRE(o.ok());
  CHECK(o->size() == 6);
}
