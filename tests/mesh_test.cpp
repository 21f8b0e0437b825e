// Tests for restitch/mesh.hpp: validate() on each class of bad mesh, and the
// geometric helpers (bounding_box, double_area, BoundingBox) on meshes whose
// answers are known by hand.
#include "restitch/mesh.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "support/mesh_builders.hpp"

using restitch::BoundingBox;
using restitch::Mesh;
using restitch::StatusCode;
using restitch::test::add_box;

namespace {

// Two triangles (a unit square in z = 0) with every channel filled and two groups.
Mesh good_mesh() {
  Mesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 2, 3;
  m.FG.resize(2);
  m.FG << 0, 1;
  m.N = restitch::MatrixX3f::Zero(4, 3);
  m.N.col(2).setOnes();
  m.T = restitch::MatrixX4f::Zero(4, 4);
  m.T.col(0).setOnes();
  m.T.col(3).setOnes();
  m.UV.push_back(restitch::MatrixX2f::Zero(4, 2));
  m.UV.push_back(restitch::MatrixX2f::Ones(4, 2));
  m.C = restitch::MatrixX4f::Ones(4, 4);
  m.materials.push_back(restitch::Material{});
  restitch::Group g0, g1;
  g0.material = 0;
  g1.material = -1;  // the default material
  m.groups = {g0, g1};
  return m;
}

StatusCode code_of(const Mesh& m) { return restitch::validate(m).code(); }

}  // namespace

TEST_CASE("validate: good meshes pass", "[mesh]") {
  CHECK(restitch::validate(good_mesh()).ok());
  Mesh box;
  add_box(box, {0, 0, 0}, {1, 2, 3});
  CHECK(restitch::validate(box).ok());
  // Optional channels may be absent (0 rows) while others are present.
  Mesh m = good_mesh();
  m.N.resize(0, 3);
  m.C.resize(0, 4);
  m.UV.clear();
  CHECK(restitch::validate(m).ok());
  // Unused vertices are allowed.
  m = good_mesh();
  m.V.conservativeResize(5, 3);
  m.V.row(4) << 7, 7, 7;
  m.N.resize(0, 3), m.T.resize(0, 4), m.C.resize(0, 4), m.UV.clear();
  CHECK(restitch::validate(m).ok());
}

TEST_CASE("validate: no triangles is invalid_mesh", "[mesh]") {
  CHECK(code_of(Mesh{}) == StatusCode::invalid_mesh);
  Mesh m = good_mesh();
  m.F.resize(0, 3);
  m.FG.resize(0);
  CHECK(code_of(m) == StatusCode::invalid_mesh);
  CHECK(m.empty());
  CHECK_FALSE(restitch::validate(m).message().empty());
}

TEST_CASE("validate: a non-finite position is invalid_mesh, naming the vertex", "[mesh]") {
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity()}) {
    for (int axis = 0; axis < 3; ++axis) {
      Mesh m = good_mesh();
      m.V(2, axis) = bad;
      INFO("value " << bad << " on axis " << axis);
      const restitch::Status s = restitch::validate(m);
      CHECK(s.code() == StatusCode::invalid_mesh);
      CHECK_THAT(s.message(), Catch::Contains("vertex 2"));
    }
  }
}

TEST_CASE("validate: indices out of range are invalid_mesh", "[mesh]") {
  Mesh m = good_mesh();
  m.F(1, 2) = 4;  // one past the last vertex
  CHECK(code_of(m) == StatusCode::invalid_mesh);
  m.F(1, 2) = 3;  // the last vertex: fine
  CHECK(code_of(m) == StatusCode::ok);
  m.F(0, 0) = 0xffffffffu;
  CHECK(code_of(m) == StatusCode::invalid_mesh);

  // Face groups: one per face, each naming an existing group.
  m = good_mesh();
  m.FG.resize(1);
  m.FG << 0;
  CHECK(code_of(m) == StatusCode::invalid_mesh);
  m = good_mesh();
  m.FG(1) = 2;  // two groups
  CHECK(code_of(m) == StatusCode::invalid_mesh);
  m = good_mesh();
  m.groups.clear();
  m.FG.setZero();
  CHECK(code_of(m) == StatusCode::invalid_mesh);
  // A group's material must exist (-1 is the default material).
  m = good_mesh();
  m.groups[1].material = 1;  // one material
  CHECK(code_of(m) == StatusCode::invalid_mesh);
  m.groups[1].material = 0;
  CHECK(code_of(m) == StatusCode::ok);
}

TEST_CASE("validate: every vertex channel has one entry per vertex or none", "[mesh]") {
  auto bad = [](auto&& spoil) {
    Mesh m = good_mesh();
    spoil(m);
    return code_of(m);
  };
  CHECK(bad([](Mesh& m) { m.N.conservativeResize(3, 3); }) == StatusCode::invalid_mesh);
  CHECK(bad([](Mesh& m) { m.N = restitch::MatrixX3f::Zero(5, 3); }) == StatusCode::invalid_mesh);
  CHECK(bad([](Mesh& m) { m.T.conservativeResize(3, 4); }) == StatusCode::invalid_mesh);
  CHECK(bad([](Mesh& m) { m.C.conservativeResize(1, 4); }) == StatusCode::invalid_mesh);
  CHECK(bad([](Mesh& m) { m.UV[1].conservativeResize(3, 2); }) == StatusCode::invalid_mesh);
  CHECK(bad([](Mesh& m) { m.UV.push_back(restitch::MatrixX2f::Zero(0, 2)); }) == StatusCode::invalid_mesh);
  // The same channels correctly sized are fine.
  CHECK(bad([](Mesh& m) { m.UV.push_back(restitch::MatrixX2f::Zero(4, 2)); }) == StatusCode::ok);
}

TEST_CASE("validate: a group may not claim a channel the mesh lacks, nor a material below -1", "[mesh]") {
  auto with_group = [](auto&& set) {
    Mesh m = good_mesh();
    set(m.groups[0].attributes);
    return code_of(m);
  };
  using restitch::AttributeSet;
  CHECK(with_group([](AttributeSet& a) { a.normals = true, a.tangents = true, a.uv_sets = 2, a.color_components = 4; }) ==
        StatusCode::ok);
  auto stripped = [](auto&& set) {  // the channels removed, the claim kept
    Mesh m = good_mesh();
    m.N.resize(0, 3), m.T.resize(0, 4), m.C.resize(0, 4), m.UV.clear();
    set(m.groups[1].attributes);
    return code_of(m);
  };
  CHECK(stripped([](AttributeSet&) {}) == StatusCode::ok);
  CHECK(stripped([](AttributeSet& a) { a.normals = true; }) == StatusCode::invalid_mesh);
  CHECK(stripped([](AttributeSet& a) { a.tangents = true; }) == StatusCode::invalid_mesh);
  CHECK(stripped([](AttributeSet& a) { a.uv_sets = 1; }) == StatusCode::invalid_mesh);
  CHECK(stripped([](AttributeSet& a) { a.color_components = 3; }) == StatusCode::invalid_mesh);
  CHECK(with_group([](AttributeSet& a) { a.uv_sets = 3; }) == StatusCode::invalid_mesh);  // the mesh has 2
  Mesh m = good_mesh();
  m.groups[1].material = -2;
  CHECK(code_of(m) == StatusCode::invalid_mesh);
}

TEST_CASE("validate: a mesh of degenerate triangles only has no area and is invalid_mesh", "[mesh]") {
  Mesh m = good_mesh();
  m.V.row(2) << 0.5f, 0, 0;  // collinear with 0 and 1
  m.V.row(3) << 2, 0, 0;     // collinear too
  CHECK(code_of(m) == StatusCode::invalid_mesh);
  // Repeated corners are degenerate as well.
  m = good_mesh();
  m.F << 0, 0, 1, 2, 2, 2;
  CHECK(code_of(m) == StatusCode::invalid_mesh);
  // One non-degenerate triangle among degenerate ones is enough.
  m = good_mesh();
  m.F << 0, 0, 1, 0, 2, 3;
  CHECK(code_of(m) == StatusCode::ok);
  m.F << 0, 2, 3, 1, 1, 1;
  CHECK(code_of(m) == StatusCode::ok);
}

TEST_CASE("bounding_box, double_area and BoundingBox on known meshes", "[mesh]") {
  Mesh m;
  add_box(m, {-1, 2, 0.5}, {3, 2.5, 4});
  add_box(m, {0, -1, 1}, {1, 0, 2});
  const BoundingBox b = restitch::bounding_box(m);
  REQUIRE(b.valid());
  CHECK(b.min.isApprox(Eigen::Vector3d(-1, -1, 0.5)));
  CHECK(b.max.isApprox(Eigen::Vector3d(3, 2.5, 4)));
  CHECK(b.size().isApprox(Eigen::Vector3d(4, 3.5, 3.5)));
  CHECK(b.center().isApprox(Eigen::Vector3d(1, 0.75, 2.25)));
  CHECK(m.vertex_count() == 16);
  CHECK(m.triangle_count() == 24);

  // Only vertices used by a triangle count.
  m.V.conservativeResize(m.V.rows() + 1, 3);
  m.V.row(m.V.rows() - 1) << 100, -100, 100;
  const BoundingBox b2 = restitch::bounding_box(m);
  CHECK(b2.min == b.min);
  CHECK(b2.max == b.max);

  // No triangles: an invalid box of size zero.
  const BoundingBox none = restitch::bounding_box(Mesh{});
  CHECK_FALSE(none.valid());
  CHECK(none.size() == Eigen::Vector3d::Zero());

  // A single point is a valid box of size zero.
  BoundingBox p;
  p.extend({1, 2, 3});
  CHECK(p.valid());
  CHECK(p.size() == Eigen::Vector3d::Zero());

  // double_area: twice the area of a 3-4-5 right triangle, and of a degenerate one.
  Mesh t;
  t.V.resize(4, 3);
  t.V << 1, 1, 1, 4, 1, 1, 1, 1, 5, 7, 1, 1;
  t.F.resize(2, 3);
  t.F << 0, 1, 2, 0, 1, 3;
  CHECK(restitch::double_area(t, 0) == Approx(12.0));
  CHECK(restitch::double_area(t, 1) == Approx(0.0).margin(1e-12));
  // Summed over a box's triangles: twice its surface area, 2 * 2 * (1*2 + 2*3 + 1*3).
  Mesh unit;
  add_box(unit, {0, 0, 0}, {1, 2, 3});
  double twice = 0;
  for (Eigen::Index f = 0; f < unit.F.rows(); ++f) twice += restitch::double_area(unit, f);
  CHECK(twice == Approx(2 * 2 * (1 * 2 + 2 * 3 + 1 * 3)));
}
