// Tests of restitch/families/families.hpp (the generated families: parametric sample models) and of
// the test-only surface distance oracle in tests/support/surface_distance.hpp.
#include "restitch/families/families.hpp"
#include "restitch/mesh_boundary.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include "support/sampled_shapes.hpp"
#include "support/surface_distance.hpp"

using restitch::Mesh;
using restitch::StatusCode;
using restitch::families::generate;
using restitch::families::SampleModel;
using restitch::test::symmetric_surface_distance;
using restitch::test::unit;
using Vec3 = Eigen::Vector3d;

namespace {

const std::vector<std::string> kNames = {"bookshelf", "box_header", "cabinet",  "connector", "dip",
                                         "facade",    "facade_sheared", "fence", "pin_header", "radiator",
                                         "railing",   "shutter",    "tube_rail"};

SampleModel make(const std::string& name, const std::map<std::string, double>& o = {}) {
  auto r = generate(name, o);
  INFO(name << ": " << r.status().message());
  REQUIRE(r.ok());
  return std::move(*r);
}

double param_default(const std::string& sample, const std::string& param) {
  for (const auto& s : restitch::families::catalog())
    if (s.name == sample)
      for (const auto& p : s.parameters)
        if (p.name == param) return p.value;
  FAIL("no parameter " << param << " in " << sample);
  return 0;
}

double longest_side(const Mesh& m) { return restitch::bounding_box(m).size().maxCoeff(); }

Vec3 vertex(const Mesh& m, Eigen::Index f, int k) { return m.V.row(m.F(f, k)).transpose().cast<double>(); }

// The faces of `m` whose block along generator g satisfies `pick`, translated by `shift`, appended to `out`.
template <class Pick>
void append_faces(const SampleModel& m, int g, Pick pick, const Vec3& shift, Mesh& out) {
  std::vector<Eigen::Index> faces;
  for (Eigen::Index f = 0; f < m.mesh.F.rows(); ++f)
    if (pick(m.face_block[std::size_t(g)](f))) faces.push_back(f);
  const Eigen::Index v0 = out.V.rows(), f0 = out.F.rows();
  out.V.conservativeResize(v0 + 3 * Eigen::Index(faces.size()), 3);
  out.F.conservativeResize(f0 + Eigen::Index(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Index v = v0 + 3 * Eigen::Index(i) + k;
      out.V.row(v) = (vertex(m.mesh, faces[i], k) + shift).cast<float>().transpose();
      out.F(f0 + Eigen::Index(i), k) = static_cast<std::uint32_t>(v);
    }
}

// What a perfect resize of `m` by one step along generator g produces: the
// start cap and module 0 where they are, and module 0 .. end cap moved by the generator.
Mesh grown_by_one(const SampleModel& m, int g, const Vec3& shift) {
  Mesh out;
  out.V.resize(0, 3);
  out.F.resize(0, 3);
  append_faces(
      m, g, [](int b) { return b <= 0; }, Vec3::Zero(), out);
  append_faces(
      m, g, [](int b) { return b >= 0; }, shift, out);
  return out;
}

// The faces of block `b` along generator g, corners in order.
std::vector<Eigen::Index> faces_of_block(const SampleModel& m, int g, int b) {
  std::vector<Eigen::Index> out;
  for (Eigen::Index f = 0; f < m.mesh.F.rows(); ++f)
    if (m.face_block[std::size_t(g)](f) == b) out.push_back(f);
  return out;
}

// Faces fa of a and fb of b correspond: positions b = a + shift (tolerance tol), normals and UVs bit-identical.
void require_translated(const Mesh& a, const std::vector<Eigen::Index>& fa, const Mesh& b,
                        const std::vector<Eigen::Index>& fb, const Vec3& shift, double tol) {
  REQUIRE(fa.size() == fb.size());
  REQUIRE(!fa.empty());
  double worst = 0;
  bool attributes_equal = true;
  for (std::size_t i = 0; i < fa.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const auto va = a.F(fa[i], k), vb = b.F(fb[i], k);
      worst = std::max(worst, (vertex(a, fa[i], k) + shift - vertex(b, fb[i], k)).cwiseAbs().maxCoeff());
      attributes_equal = attributes_equal && a.N.row(va) == b.N.row(vb) && a.UV[0].row(va) == b.UV[0].row(vb) &&
                         a.FG(fa[i]) == b.FG(fb[i]);
    }
  CHECK(worst <= tol);
  CHECK(attributes_equal);
}

bool bit_equal(const Mesh& a, const Mesh& b) {
  auto same = [](const auto& x, const auto& y) {
    return x.rows() == y.rows() && x.cols() == y.cols() &&
           std::memcmp(x.data(), y.data(), sizeof(*x.data()) * std::size_t(x.size())) == 0;
  };
  return same(a.V, b.V) && same(a.F, b.F) && same(a.FG, b.FG) && same(a.N, b.N) && a.UV.size() == b.UV.size() &&
         same(a.UV[0], b.UV[0]) && a.groups.size() == b.groups.size() && a.materials.size() == b.materials.size();
}

}  // namespace

TEST_CASE("catalog lists every sample in a fixed order with sane parameters", "[samples]") {
  const auto& cat = restitch::families::catalog();
  REQUIRE(cat.size() == kNames.size());
  for (std::size_t i = 0; i < cat.size(); ++i) {
    CHECK(cat[i].name == kNames[i]);
    CHECK(!cat[i].description.empty());
    CHECK((cat[i].units == "m" || cat[i].units == "mm"));
    std::set<std::string> names;
    bool has_detail = false;
    for (const auto& p : cat[i].parameters) {
      INFO(cat[i].name << "." << p.name);
      CHECK(names.insert(p.name).second);
      CHECK(p.min <= p.value);
      CHECK(p.value <= p.max);
      CHECK(!p.help.empty());
      if (p.integer) {
        CHECK(p.value == std::floor(p.value));
        // Counts, detail and a 1-based index are >= 1 (families.hpp); the other integer kinds are a 0/1
        // switch (pin_header's `closed`, radiator's `valve`) and an index counted from either end, whose
        // range is symmetric: 0 for none (bookshelf's `door_column`, `door_shelf`) or the first from the
        // left (radiator's `valve_section`).
        CHECK((p.min >= 1 || (p.min == 0 && p.max == 1) || (p.min == -p.max && (p.value == 0 || p.value == 1))));
      }
      has_detail = has_detail || (p.name == "detail" && p.integer);
    }
    CHECK(has_detail);
  }
  CHECK(&restitch::families::catalog() == &cat);
}

TEST_CASE("every sample generates with its defaults: valid, attributed, 1k-5k triangles", "[samples]") {
  for (const auto& name : kNames) {
    INFO(name);
    const SampleModel s = make(name);
    const Mesh& m = s.mesh;
    const auto st = restitch::validate(m);
    INFO(st.message());
    REQUIRE(st.ok());
    CHECK(m.triangle_count() >= 1000);
    CHECK(m.triangle_count() <= 5000);
    CHECK(m.materials.size() >= 2);
    CHECK(m.materials.size() <= 4);
    REQUIRE(m.groups.size() == m.materials.size());
    for (std::size_t g = 0; g < m.groups.size(); ++g) {
      CHECK(m.groups[g].material == int(g));
      CHECK(m.groups[g].attributes.normals);
      CHECK(m.groups[g].attributes.uv_sets == 1);
    }
    REQUIRE(m.N.rows() == m.V.rows());
    REQUIRE(m.UV.size() == 1);
    REQUIRE(m.UV[0].rows() == m.V.rows());
    CHECK(m.UV[0].allFinite());
    // Every group is used, and a vertex belongs to faces of one group only.
    std::vector<int> group_of_vertex(m.vertex_count(), -1);
    std::set<std::uint32_t> used;
    bool one_group = true;
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      used.insert(m.FG(f));
      for (int k = 0; k < 3; ++k) {
        int& g = group_of_vertex[m.F(f, k)];
        one_group = one_group && (g < 0 || g == int(m.FG(f)));
        g = int(m.FG(f));
      }
    }
    CHECK(one_group);
    CHECK(used.size() == m.groups.size());
    // Normals are unit, flat, and agree with the winding (counter-clockwise = front).
    int bad_normals = 0, degenerate = 0;
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      const Vec3 c = (vertex(m, f, 1) - vertex(m, f, 0)).cross(vertex(m, f, 2) - vertex(m, f, 0));
      if (c.norm() == 0) {
        ++degenerate;
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        const Vec3 n = m.N.row(m.F(f, k)).transpose().cast<double>();
        if (std::abs(n.norm() - 1) > 1e-6 || n.dot(c.normalized()) < 0.999) ++bad_normals;
      }
    }
    CHECK(bad_normals == 0);
    CHECK(degenerate == 0);
    // Ground truth: generators, counts, blocks; at least 3 repeats, each generator
    // clearly longer than tau = 0.15 in normalized units.
    const std::size_t ng = (name == "bookshelf" || name == "facade" || name == "facade_sheared") ? 2 : 1;
    REQUIRE(s.generators.size() == ng);
    REQUIRE(s.count_parameters.size() == ng);
    REQUIRE(s.counts.size() == ng);
    REQUIRE(s.modules.size() == ng);
    REQUIRE(s.face_block.size() == ng);
    const double scale = 2.0 / longest_side(m);
    for (std::size_t g = 0; g < ng; ++g) {
      CHECK(s.counts[g] >= 3);
      CHECK(s.counts[g] == int(param_default(name, s.count_parameters[g])));
      // The bookshelf's end caps hold a compartment, the DIP's each hold a pin (of each row).
      CHECK(s.modules[g] == s.counts[g] - (name == "bookshelf" ? 1 : name == "dip" ? 2 : 0));
      CHECK(s.generators[g].norm() * scale > 0.2);
      REQUIRE(s.face_block[g].size() == m.F.rows());
      CHECK(s.face_block[g].minCoeff() == -1);
      CHECK(s.face_block[g].maxCoeff() == s.modules[g]);
    }
    // `origin` is the low corner of module 0 (along every generator) in the generators' directions.
    Vec3 low = Vec3::Constant(INFINITY);
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      bool module0 = true;
      for (std::size_t g = 0; g < ng; ++g) module0 = module0 && s.face_block[g](f) == 0;
      if (module0)
        for (int k = 0; k < 3; ++k) low = low.cwiseMin(vertex(m, f, k));
    }
    CHECK(std::abs(low.x() - s.origin.x()) < 1e-6);
    if (ng == 2) CHECK(std::abs(low.y() - s.origin.y()) < 1e-6);
  }
}

TEST_CASE("bounding boxes agree with the parameters", "[samples]") {
  const double tol = 1e-5;
  SECTION("bookshelf") {
    const auto s =
        make("bookshelf", {{"columns", 3}, {"shelves", 5}, {"column_pitch", 0.5}, {"board_thickness", 0.03}});
    const auto b = restitch::bounding_box(s.mesh);
    CHECK(b.min.isApprox(Vec3(0, 0, -0.005), tol));
    CHECK(b.size().isApprox(Vec3(0.03 + 3 * 0.5, 0.03 + 5 * 0.35, 0.3 + 0.005), tol));
    CHECK(s.generators[0] == Vec3(0.5, 0, 0));
    CHECK(s.generators[1] == Vec3(0, 0.35, 0));
    CHECK(s.counts == std::vector<int>{3, 5});
  }
  SECTION("facade") {
    const auto s = make("facade", {{"columns", 6}, {"floors", 3}});
    const auto b = restitch::bounding_box(s.mesh);
    CHECK(std::abs(b.size().x() - (2 * 1.0 + 6 * 3.0)) < tol);
    CHECK(std::abs(b.size().y() - (0.8 + 3 * 3.2 + 0.9)) < tol);
    CHECK(std::abs(b.min.z() + 0.3) < tol);              // wall back
    CHECK(std::abs(b.max.z() - 0.15) < tol);             // cornice front
    CHECK(s.generators[0].dot(s.generators[1]) == 0.0);  // orthogonal without shear
  }
  SECTION("facade_sheared: the bounding box reflects the shear, the generators are not orthogonal") {
    const auto plain = make("facade", {{"floors", 3}});
    const auto s = make("facade_sheared", {{"floors", 3}});
    const double shear = param_default("facade_sheared", "shear");
    REQUIRE(shear > 0);
    const auto b = restitch::bounding_box(s.mesh), bp = restitch::bounding_box(plain.mesh);
    CHECK(std::abs(b.size().x() - (bp.size().x() + 4 * shear)) < tol);  // plinth at -shear, parapet at +3 shear
    CHECK(std::abs(b.min.x() + shear) < tol);
    CHECK(std::abs(b.size().y() - bp.size().y()) < tol);
    CHECK(s.generators[1] == Vec3(shear, 3.2, 0));
    const double cosine = s.generators[0].normalized().dot(s.generators[1].normalized());
    CHECK(std::abs(cosine) > 0.2);
  }
  SECTION("fence") {
    const auto s = make("fence", {{"pickets", 11}, {"picket_pitch", 0.12}});
    const auto b = restitch::bounding_box(s.mesh);
    CHECK(std::abs(b.size().x() - (2 * 0.1 + 11 * 0.12)) < tol);
    CHECK(std::abs(b.max.y() - (1.15 + 0.4 * 0.1)) < tol);  // post cap apex
    CHECK(b.min.y() == 0.0);
    CHECK(s.generators[0] == Vec3(0.12, 0, 0));
  }
  SECTION("dip: the body ends wall past the end pins, the pins hang below it, closed") {
    const auto s = make("dip", {{"pins", 6}, {"wall", 0.8}});
    const auto b = restitch::bounding_box(s.mesh);
    CHECK(b.min.isApprox(Vec3(-0.8, -3.0, -3.2), tol));
    CHECK(b.max.isApprox(Vec3(5 * 2.54 + 0.8, 3.3, 3.2), tol));
    CHECK(s.generators[0] == Vec3(2.54, 0, 0));
    CHECK(s.modules[0] == 4);
    CHECK(restitch::boundary_edge_count(s.mesh) == 0);
    // The dimple reaches past the first block boundary (half a pitch past pin 1): the part spans the start
    // cap and module 0; kept inside the start cap, it is the start cap's alone.
    REQUIRE(s.parts.size() == 1);
    CHECK((s.parts[0].first == -1 && s.parts[0].last == 0 && s.parts[0].anchor == "low end"));
    CHECK(make("dip", {{"marker_x", 0.0}}).parts[0].last == -1);
  }
  SECTION("pin_header") {
    const auto s = make("pin_header", {{"pins", 5}});
    const auto b = restitch::bounding_box(s.mesh);
    CHECK(std::abs(b.size().x() - (2 * 0.3 + 5 * 2.54)) < 1e-4);
    CHECK(std::abs(b.min.y() + 3.0) < 1e-5);
    CHECK(std::abs(b.max.y() - (2.5 + 6.0)) < 1e-5);
    CHECK(std::abs(b.size().z() - 2.5) < 1e-5);
    CHECK(s.generators[0] == Vec3(2.54, 0, 0));
  }
}

namespace {

// generate(n + 1) is exactly generate(n) grown by one module along each generator.
// Needs at least one module along each generator (module 0 is what the new one copies).
void check_one_more_repeat(const std::string& name, const std::map<std::string, double>& base) {
  const SampleModel small = make(name, base);
  for (std::size_t g = 0; g < small.generators.size(); ++g) {
    INFO(name << " generator " << g << " (" << small.count_parameters[g] << ")");
    auto params = base;
    params[small.count_parameters[g]] += 1;
    const SampleModel big = make(name, params);
    REQUIRE(small.modules[g] >= 1);
    const Vec3 gen = small.generators[g];
    REQUIRE(big.generators[g] == gen);
    REQUIRE(big.counts[g] == small.counts[g] + 1);
    REQUIRE(big.modules[g] == small.modules[g] + 1);
    const double size = longest_side(big.mesh), tol = 1e-6 * size;

    // The bounding box grows by exactly the generator, on the side it points to.
    const auto b0 = restitch::bounding_box(small.mesh), b1 = restitch::bounding_box(big.mesh);
    CHECK((b1.min - b0.min - gen.cwiseMin(0)).cwiseAbs().maxCoeff() <= tol);
    CHECK((b1.max - b0.max - gen.cwiseMax(0)).cwiseAbs().maxCoeff() <= tol);
    CHECK(((b1.size() - b0.size()) - gen.cwiseAbs()).cwiseAbs().maxCoeff() <= tol);

    // Caps: the start cap is unchanged bit for bit, the end cap moved by the generator.
    require_translated(small.mesh, faces_of_block(small, int(g), -1), big.mesh, faces_of_block(big, int(g), -1),
                       Vec3::Zero(), 0.0);
    require_translated(small.mesh, faces_of_block(small, int(g), small.modules[g]), big.mesh,
                       faces_of_block(big, int(g), big.modules[g]), gen, tol);
    // Modules are translates of module 0 within one model.
    for (int i = 1; i < big.modules[g]; ++i)
      require_translated(big.mesh, faces_of_block(big, int(g), 0), big.mesh, faces_of_block(big, int(g), i),
                         double(i) * gen, tol);

    // Vertices: the start cap and modules of the small model are on the big
    // surface where they were; its modules and end cap are on it moved by the
    // generator. (End-cap vertices where they were are not: the new module sits there.)
    const restitch::test::TriangleSurface surface(big.mesh);
    double worst_stay = 0, worst_moved = 0;
    for (Eigen::Index f = 0; f < small.mesh.F.rows(); ++f) {
      const int b = small.face_block[g](f);
      for (int k = 0; k < 3; ++k) {
        const Vec3 p = vertex(small.mesh, f, k);
        if (b < small.modules[g]) worst_stay = std::max(worst_stay, surface.distance(p));
        if (b >= 0) worst_moved = std::max(worst_moved, surface.distance(p + gen));
      }
    }
    CHECK(worst_stay <= tol);
    CHECK(worst_moved <= tol);

    // Surfaces: the big model equals [start cap, module 0] + [module 0 .. end cap moved by the generator].
    const double spacing = size / 40;
    const double d = symmetric_surface_distance(grown_by_one(small, int(g), gen), big.mesh, spacing);
    CHECK(d <= 1e-6 * size);
    // Negative control: a wrong shift is seen (one direction suffices).
    const double wrong =
        restitch::test::one_sided_surface_distance(grown_by_one(small, int(g), 0.5 * gen), big.mesh, spacing);
    CHECK(wrong >= 0.05 * gen.norm());
  }
}

}  // namespace

TEST_CASE("bookshelf: one more column or shelf is the model grown by one module", "[samples][ground_truth]") {
  check_one_more_repeat("bookshelf", {{"columns", 3}, {"shelves", 3}});
  check_one_more_repeat("bookshelf", {{"columns", 2}, {"shelves", 2}});
}

TEST_CASE("facade: one more column or floor is the model grown by one module", "[samples][ground_truth]") {
  check_one_more_repeat("facade", {{"columns", 3}, {"floors", 3}});
}

TEST_CASE("facade_sheared: one more floor moves the top by (shear, floor_height, 0)", "[samples][ground_truth]") {
  check_one_more_repeat("facade_sheared", {{"columns", 3}, {"floors", 3}});
  check_one_more_repeat("facade_sheared", {{"columns", 2}, {"floors", 2}, {"shear", -0.5}});
}

TEST_CASE("fence: one more picket is the model grown by one module", "[samples][ground_truth]") {
  check_one_more_repeat("fence", {{"pickets", 4}});
  check_one_more_repeat("fence", {{"pickets", 1}, {"detail", 3}});
}

TEST_CASE("pin_header: one more pin is the model grown by one module", "[samples][ground_truth]") {
  check_one_more_repeat("pin_header", {{"pins", 4}, {"detail", 3}});
}

TEST_CASE("dip: one more pin a side is the package grown by one module", "[samples][ground_truth]") {
  check_one_more_repeat("dip", {{"pins", 3}, {"marker_x", 0.0}});  // the dimple inside the start cap
}

TEST_CASE("generation is deterministic", "[samples]") {
  for (const auto& name : kNames) {
    INFO(name);
    const auto a = make(name, {{"detail", 3}}), b = make(name, {{"detail", 3}});
    CHECK(bit_equal(a.mesh, b.mesh));
    CHECK(a.generators == b.generators);
    for (std::size_t g = 0; g < a.face_block.size(); ++g) CHECK(a.face_block[g] == b.face_block[g]);
  }
}

TEST_CASE("bad requests get invalid_argument naming what is wrong", "[samples]") {
  auto fails = [](const std::string& name, const std::map<std::string, double>& o, StatusCode code,
                  std::vector<std::string> words) {
    const auto r = generate(name, o);
    REQUIRE(!r.ok());
    CHECK(r.status().code() == code);
    for (const auto& w : words) {
      INFO("message: " << r.status().message() << " / expected word: " << w);
      CHECK(r.status().message().find(w) != std::string::npos);
    }
  };
  fails("bookcase", {}, StatusCode::invalid_argument, {"bookcase", "bookshelf", "pin_header"});
  fails("bookshelf", {{"colums", 3}}, StatusCode::invalid_argument, {"colums", "columns", "shelves"});
  fails("bookshelf", {{"columns", 0}}, StatusCode::invalid_argument, {"columns", "[1, 64]"});
  fails("bookshelf", {{"columns", 65}}, StatusCode::invalid_argument, {"columns"});
  fails("bookshelf", {{"columns", 2.5}}, StatusCode::invalid_argument, {"columns", "integer"});
  fails("fence", {{"detail", 1.5}}, StatusCode::invalid_argument, {"detail", "integer"});
  fails("fence", {{"picket_pitch", std::nan("")}}, StatusCode::invalid_argument, {"picket_pitch"});
  fails("pin_header", {{"pitch", 0.5}}, StatusCode::invalid_argument, {"pitch"});
  fails("facade", {{"window_width", 2.9}}, StatusCode::invalid_argument, {"window_width", "bay_width"});
  fails("facade_sheared", {{"shear", 1.2}}, StatusCode::invalid_argument, {"shear", "margin"});
  fails("fence", {{"picket_width", 0.2}}, StatusCode::invalid_argument, {"picket_width", "picket_pitch"});
  fails("pin_header", {{"notch", 0.5}}, StatusCode::invalid_argument, {"notch"});
  fails("bookshelf", {{"columns", 64}, {"shelves", 64}, {"detail", 64}}, StatusCode::too_large, {"detail"});
  fails("bookshelf", {{"door_column", 2}}, StatusCode::invalid_argument, {"door_column", "door_shelf"});
  fails("bookshelf", {{"door_column", -5}, {"door_shelf", 1}}, StatusCode::invalid_argument, {"door_column", "columns"});
  fails("bookshelf", {{"door_column", 1}, {"door_shelf", 5}}, StatusCode::invalid_argument, {"door_shelf", "shelves"});
  fails("radiator", {{"valve_section", 0}}, StatusCode::invalid_argument, {"valve_section", "sections"});
  fails("radiator", {{"sections", 8}, {"valve_section", -9}}, StatusCode::invalid_argument, {"valve_section"});
  // Boundary values are accepted.
  CHECK(generate("radiator", {{"sections", 8}, {"valve_section", -8}}).ok());
  CHECK(generate("radiator", {{"valve", 0}, {"valve_section", 0}}).ok());  // no valve: its section is not read
  CHECK(generate("bookshelf", {{"columns", 1}, {"shelves", 1}}).ok());
  CHECK(generate("bookshelf", {{"columns", 1}, {"shelves", 1}, {"door_column", -1}, {"door_shelf", 1}}).ok());
  CHECK(generate("fence", {{"pickets", 1}}).ok());
  CHECK(generate("pin_header", {{"pins", 1}}).ok());
  CHECK(generate("facade", {{"columns", 1}, {"floors", 1}}).ok());
}

TEST_CASE("a radiator's valve counted from the right is the one counted from the left, kept at the right", "[samples]") {
  for (const int n : {1, 2, 5, 8})
    for (int k = 1; k <= n; ++k) {
      INFO(n << " sections, valve " << k << " from the right");
      const auto right = make("radiator", {{"sections", n}, {"valve_section", -k}});
      const auto left = make("radiator", {{"sections", n}, {"valve_section", n + 1 - k}});
      CHECK(right.mesh.V == left.mesh.V);
      CHECK(right.mesh.F == left.mesh.F);
      REQUIRE(right.parts.size() == 1);
      CHECK(right.parts[0].first == n - k);
      CHECK(right.parts[0].anchor == "high end");
      CHECK(left.parts[0].anchor == "low end");
    }
}

TEST_CASE("detail scales the triangle count up to about 200k triangles", "[samples]") {
  for (const auto& name : kNames) {
    INFO(name);
    std::size_t previous = 0;
    for (int d : {1, 2, 4}) {
      const auto s = make(name, {{"detail", d}});
      CHECK(s.mesh.triangle_count() > previous);
      if (d == 4) CHECK(s.mesh.triangle_count() > 2 * previous);
      previous = s.mesh.triangle_count();
    }
  }
  const auto big = make("bookshelf", {{"detail", 9}});
  CHECK(big.mesh.triangle_count() >= 150000);
  CHECK(big.mesh.triangle_count() <= 300000);
  CHECK(restitch::validate(big.mesh).ok());
  CHECK(big.face_block[0].size() == big.mesh.F.rows());
}

// ---------------------------------------------------------------------------
// The surface distance oracle.

namespace {

Mesh box_mesh(const Vec3& lo, const Vec3& hi, double cell, unsigned faces = restitch::detail::box_all) {
  restitch::detail::SampleMeshBuilder b(cell, 1.0, 1, false);
  b.add_material(restitch::Material{});
  b.box(lo, hi, faces);
  Mesh m;
  std::vector<Eigen::VectorXi> blocks;
  b.finish("test", m, blocks);
  return m;
}


}  // namespace

TEST_CASE("closest point on a triangle matches a brute-force search", "[surface_distance]") {
  std::mt19937_64 rng(12345);
  auto rnd = [&]() -> Vec3 {  // coordinates drawn in a fixed order
    const double x = unit(rng), y = unit(rng), z = unit(rng);
    return Vec3(2 * x - 1, 2 * y - 1, 2 * z - 1);
  };
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a = rnd(), b = rnd(), c = rnd(), p = 2.0 * rnd();
    const Vec3 q = restitch::test::closest_point_on_triangle(p, a, b, c);
    // q lies in the triangle's plane.
    const Vec3 n = (b - a).cross(c - a);
    CHECK(std::abs((q - a).dot(n.normalized())) < 1e-9);
    // No point of a fine barycentric grid is nearer.
    double brute = INFINITY;
    const int m = 200;
    for (int j = 0; j <= m; ++j)
      for (int i = 0; i + j <= m; ++i)
        brute = std::min(brute, (a + (double(i) / m) * (b - a) + (double(j) / m) * (c - a) - p).norm());
    const double d = (q - p).norm();
    CHECK(d <= brute + 1e-12);
    CHECK(d >= brute - 0.02);  // the grid's own resolution
  }
  // A degenerate triangle is its segment.
  const Vec3 q =
      restitch::test::closest_point_on_triangle(Vec3(0.5, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0));
  CHECK((q - Vec3(0.5, 0, 0)).norm() < 1e-12);
}

TEST_CASE("symmetric surface distance: retriangulated ~0, shifted ~delta, missing panel large", "[surface_distance]") {
  const Vec3 lo(0, 0, 0), hi(1.0, 0.6, 0.4);
  const Mesh coarse = box_mesh(lo, hi, 10.0);  // 12 triangles
  const Mesh fine = box_mesh(lo, hi, 0.07);    // the same surface, many more triangles
  REQUIRE(coarse.triangle_count() == 12);
  REQUIRE(fine.triangle_count() > 200);
  CHECK(symmetric_surface_distance(coarse, fine, 0.05) < 1e-6);
  CHECK(symmetric_surface_distance(fine, fine, 0.05) == 0.0);

  for (double delta : {0.003, 0.05}) {
    const Mesh shifted = box_mesh(lo + Vec3(delta, 0, 0), hi + Vec3(delta, 0, 0), 0.1);
    CHECK(std::abs(symmetric_surface_distance(fine, shifted, 0.05) - delta) < 1e-6);
    const Mesh diagonal = box_mesh(lo + Vec3(delta, delta, 0), hi + Vec3(delta, delta, 0), 0.1);
    CHECK(std::abs(symmetric_surface_distance(fine, diagonal, 0.05) - std::sqrt(2.0) * delta) < 1e-6);
  }

  // Without the +z panel the panel's centre is 0.3 from the side faces and 0.4 from the bottom.
  const Mesh open = box_mesh(lo, hi, 0.07, restitch::detail::box_all & ~restitch::detail::box_pos_z);
  const double d = symmetric_surface_distance(fine, open, 0.02);
  CHECK(d > 0.28);
  CHECK(d <= 0.3 + 1e-6);
  // One direction only sees it: every point of the open box is on the closed one.
  CHECK(restitch::test::one_sided_surface_distance(open, fine, 0.02) < 1e-6);
}
