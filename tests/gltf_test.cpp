// glTF in and out: what is read, what is carried, what is refused.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "restitch/detail/file.hpp"
#include "restitch/io/gltf.hpp"
#include "support/gltf_builder.hpp"
#include "support/boundary_length.hpp"

using namespace restitch;
using restitch::test::GltfBuilder;
using restitch::test::surface_area;

namespace {

const std::vector<std::uint8_t> kPng1x1 = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
    0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00, 0x00, 0x90, 0x77, 0x53, 0xde, 0x00, 0x00, 0x00,
    0x0c, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0xf8, 0xdf, 0xc0, 0x00, 0x00, 0x04, 0x01, 0x01, 0x80, 0xc5,
    0x2a, 0x18, 0x5d, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};

std::string tmp_path(const std::string& name) {
  std::filesystem::create_directories(RESTITCH_TEST_TMP);
  return std::string(RESTITCH_TEST_TMP) + "/" + name;
}

Result<Mesh> load_text(const std::string& text, GltfLoadReport* r = nullptr) {
  return load_gltf_from_memory(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), "", r);
}

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& b) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

// Scene with one node per mesh entry, all roots.
void add_scene(GltfBuilder& b, std::vector<nlohmann::json> nodes) {
  nlohmann::json roots = nlohmann::json::array();
  for (auto& n : nodes) {
    b.j["nodes"].push_back(n);
    roots.push_back(int(b.j["nodes"].size()) - 1);
  }
  b.j["scenes"].push_back({{"nodes", roots}});
  b.j["scene"] = 0;
}

// A textured two-material mesh built by the reader, for round trips.
Mesh textured_mesh() {
  GltfBuilder b;
  const int bv = b.view(kPng1x1.data(), kPng1x1.size());
  b.j["images"] = {{{"bufferView", bv}, {"mimeType", "image/png"}, {"name", "checker"}}};
  b.j["samplers"] = {{{"magFilter", 9728}, {"wrapS", 33648}}};
  b.j["textures"] = {{{"source", 0}, {"sampler", 0}}};
  b.j["materials"] = {
      {{"name", "painted"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.25}}}},
      {{"name", "plain"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1.0, 1.0}}}}}};
  const int m0 = restitch::test::add_quad_mesh(b, 4, true, 0);
  const int m1 = restitch::test::add_quad_mesh(b, 4, true, 1);
  add_scene(b, {{{"mesh", m0}}, {{"mesh", m1}, {"translation", {0, 0, 2}}}});
  auto m = load_gltf_from_memory(b.glb().data(), b.glb().size());
  REQUIRE(m.ok());
  return *m;
}

}  // namespace

TEST_CASE("gltf: a quad with normals and UVs loads as two triangles", "[gltf]") {
  GltfBuilder b;
  add_scene(b, {{{"mesh", restitch::test::add_quad_mesh(b)}}});
  for (const bool binary : {false, true}) {
    const std::vector<std::uint8_t> glb = b.glb();
    const std::string text = b.gltf_text();
    auto m = binary ? load_gltf_from_memory(glb.data(), glb.size()) : load_text(text);
    REQUIRE(m.ok());
    CHECK(m->triangle_count() == 2);
    CHECK(m->vertex_count() == 4);
    REQUIRE(m->groups.size() == 1);
    CHECK(m->groups[0].attributes.normals);
    CHECK(m->groups[0].attributes.uv_sets == 1);
    CHECK(m->UV[0](1, 0) == 1.0f);
    CHECK(surface_area(*m) == Approx(1.0));
  }
}

TEST_CASE("gltf: node transforms are applied in world space, mirroring flips winding back", "[gltf]") {
  GltfBuilder b;
  const int quad = restitch::test::add_quad_mesh(b);
  // parent translates by (10,0,0) and scales x by -2 (a mirror); child rotates 90 degrees about z.
  const double s = std::sqrt(0.5);
  b.j["nodes"].push_back({{"translation", {10, 0, 0}}, {"scale", {-2, 1, 1}}, {"children", {1}}});
  b.j["nodes"].push_back({{"mesh", quad}, {"rotation", {0, 0, s, s}}});
  b.j["scenes"].push_back({{"nodes", {0}}});
  auto m = load_text(b.gltf_text());
  REQUIRE(m.ok());
  // Vertex (1,0,0) -> rotated (0,1,0) -> scaled (0,1,0) -> translated (10,1,0).
  CHECK(m->V(1, 0) == Approx(10.0f));
  CHECK(m->V(1, 1) == Approx(1.0f));
  // Vertex (0,1,0) -> rotated (-1,0,0) -> scaled (2,0,0) -> (12,0,0).
  CHECK(m->V(3, 0) == Approx(12.0f));
  CHECK(surface_area(*m) == Approx(2.0));
  // The normal stays +z (rotation about z, mirror in x); the face, wound back, still faces +z.
  CHECK(m->N(0, 2) == Approx(1.0f));
  const Eigen::Vector3f a = m->V.row(m->F(0, 0)), c1 = m->V.row(m->F(0, 1)), c2 = m->V.row(m->F(0, 2));
  CHECK((c1 - a).cross(c2 - a).z() > 0);
}

TEST_CASE("gltf: a mesh instanced by several nodes is placed once per node, each with its own transform", "[gltf]") {
  // Mesh A (material 0, with tangents) is shown by three nodes, mesh B (material 1) by one in between:
  // a translation, a mirror with translation as a matrix, and a rotation with non-uniform scale.
  const double s = std::sqrt(0.5);
  const std::vector<nlohmann::json> nodes = {
      {{"translation", {1, 2, 3}}},
      {{"translation", {5, 0, 0}}},
      {{"matrix", {-2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 7, 0, 0, 1}}},
      {{"rotation", {0, 0, s, s}}, {"scale", {3, 0.5, 2}}, {"translation", {0, -4, 0}}}};
  const std::vector<int> mesh_of = {0, 1, 0, 0};
  auto build = [&](const std::vector<int>& which) {
    GltfBuilder b;
    b.j["materials"] = {{{"name", "a"}}, {{"name", "b"}}};
    const int a = restitch::test::add_quad_mesh(b, 4, true, 0);
    const int bm = restitch::test::add_quad_mesh(b, 4, true, 1);
    const std::vector<float> tan = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, -1};
    b.j["meshes"][a]["primitives"][0]["attributes"]["TANGENT"] = b.floats(tan, "VEC4", 4);
    std::vector<nlohmann::json> chosen;
    for (int k : which) {
      nlohmann::json n = nodes[k];
      n["mesh"] = mesh_of[k] == 0 ? a : bm;
      chosen.push_back(n);
    }
    add_scene(b, chosen);
    GltfLoadReport r;
    auto m = load_text(b.gltf_text(), &r);
    REQUIRE(m.ok());
    return std::make_pair(*m, r);
  };
  const auto [all, report] = build({0, 1, 2, 3});
  CHECK(report.primitives == 4);
  CHECK(all.triangle_count() == 8);  // 3 x 2 for mesh A, 2 for mesh B
  CHECK(all.vertex_count() == 16);
  REQUIRE(all.groups.size() == 2);
  CHECK(all.groups[0].material == 0);
  CHECK(all.groups[0].name == "mesh 0 primitive 0, mesh 0 primitive 0, mesh 0 primitive 0");
  CHECK(all.groups[1].material == 1);
  CHECK(all.groups[0].attributes.tangents);
  CHECK(all.FG.head(6).maxCoeff() == 0);
  CHECK(all.FG.tail(2).minCoeff() == 1);

  // Each instance equals, bit for bit, the same node loaded alone: group 0 holds
  // nodes 0, 2, 3 (depth-first order), then group 1 holds node 1.
  const std::vector<int> order = {0, 2, 3, 1};
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Mesh one = build({order[i]}).first;
    REQUIRE(one.vertex_count() == 4);
    REQUIRE(one.triangle_count() == 2);
    const Eigen::Index v0 = Eigen::Index(4 * i), f0 = Eigen::Index(2 * i);
    CHECK(all.V.middleRows(v0, 4) == one.V);
    CHECK(all.N.middleRows(v0, 4) == one.N);
    CHECK(all.UV[0].middleRows(v0, 4) == one.UV[0]);
    if (one.groups[0].attributes.tangents) CHECK(all.T.middleRows(v0, 4) == one.T);
    const MatrixX3u shifted = (one.F.array() + std::uint32_t(v0)).matrix();
    CHECK(all.F.middleRows(f0, 2) == shifted);
  }

  // And each instance is the quad under its own transform.
  const std::vector<float> quad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const Eigen::Matrix3d rot = Eigen::Quaterniond(s, 0, 0, s).normalized().toRotationMatrix();
  const std::vector<Eigen::Affine3d> xf = {
      Eigen::Affine3d(Eigen::Translation3d(1, 2, 3)),
      Eigen::Affine3d(Eigen::Translation3d(7, 0, 0) * Eigen::Scaling(-2.0, 1.0, 1.0)),
      Eigen::Affine3d(Eigen::Translation3d(0, -4, 0) * rot * Eigen::Scaling(3.0, 0.5, 2.0)),
      Eigen::Affine3d(Eigen::Translation3d(5, 0, 0))};
  for (std::size_t i = 0; i < xf.size(); ++i)
    for (int v = 0; v < 4; ++v) {
      const Eigen::Vector3d want = xf[i] * Eigen::Vector3d(quad[3 * v], quad[3 * v + 1], quad[3 * v + 2]);
      for (int c = 0; c < 3; ++c) CHECK(all.V(4 * i + v, c) == Approx(want[c]).margin(1e-6));
    }
  // The mirrored instance is wound back (faces +z like the others) and its tangents' w flipped.
  for (Eigen::Index f = 0; f < all.F.rows(); ++f) {
    const Eigen::Vector3f a = all.V.row(all.F(f, 0)), c1 = all.V.row(all.F(f, 1)), c2 = all.V.row(all.F(f, 2));
    CHECK((c1 - a).cross(c2 - a).z() > 0);
  }
  CHECK(all.T(4, 3) == -1.0f);
  CHECK(all.T(7, 3) == 1.0f);
  CHECK(all.T(0, 3) == 1.0f);
}

TEST_CASE("gltf: strips, fans and non-indexed primitives become the same triangles", "[gltf]") {
  for (int mode : {5, 6}) {
    GltfBuilder b;
    add_scene(b, {{{"mesh", restitch::test::add_quad_mesh(b, mode)}}});
    auto m = load_text(b.gltf_text());
    REQUIRE(m.ok());
    CHECK(m->triangle_count() == 2);
    CHECK(surface_area(*m) == Approx(1.0));
    for (Eigen::Index f = 0; f < m->F.rows(); ++f) {  // every triangle faces +z
      const Eigen::Vector3f a = m->V.row(m->F(f, 0)), c1 = m->V.row(m->F(f, 1)), c2 = m->V.row(m->F(f, 2));
      CHECK((c1 - a).cross(c2 - a).z() > 0);
    }
  }
  GltfBuilder b;
  add_scene(b, {{{"mesh", restitch::test::add_quad_mesh(b, 4, false)}}});
  auto m = load_text(b.gltf_text());
  REQUIRE(m.ok());
  CHECK(m->triangle_count() == 1);  // 4 vertices, no indices: one triangle, the 4th vertex unused
}

TEST_CASE("gltf: external buffers are read from beside the .gltf file", "[gltf]") {
  GltfBuilder b;
  add_scene(b, {{{"mesh", restitch::test::add_quad_mesh(b)}}});
  nlohmann::json j = b.j;
  j["buffers"] = {{{"byteLength", b.bin.size()}, {"uri", "quad.bin"}}};
  std::filesystem::create_directories(tmp_path("external"));
  write_bytes(tmp_path("external/quad.bin"), b.bin);
  std::ofstream(tmp_path("external/quad.gltf")) << j.dump();
  auto m = load_gltf(tmp_path("external/quad.gltf"));
  REQUIRE(m.ok());
  CHECK(m->triangle_count() == 2);
}

TEST_CASE("gltf: round trip keeps geometry, attributes, materials and texture bytes", "[gltf]") {
  const Mesh m = textured_mesh();
  REQUIRE(m.assets);
  for (const std::string ext : {".glb", ".gltf"}) {
    const std::string path = tmp_path("roundtrip" + ext);
    REQUIRE(save_gltf(m, path).ok());
    auto back = load_gltf(path);
    REQUIRE(back.ok());
    CHECK(back->V == m.V);
    CHECK(back->F == m.F);
    CHECK(back->FG == m.FG);
    CHECK(back->N == m.N);
    REQUIRE(back->UV.size() == 1);
    CHECK(back->UV[0] == m.UV[0]);
    REQUIRE(back->groups.size() == 2);
    CHECK(back->groups[0].material == 0);
    CHECK(back->groups[1].material == 1);
    CHECK(back->materials[0].name == "painted");
    CHECK(back->materials[0].metallic == Approx(0.25f));
    CHECK(back->materials[1].base_color[2] == Approx(1.0f));
    REQUIRE(back->assets->model.images.size() == 1);
    CHECK(back->assets->model.images[0].image == kPng1x1);
    CHECK(back->assets->model.images[0].name == "checker");
    CHECK(back->assets->model.samplers.size() == 1);
    CHECK(back->assets->model.materials[0].pbrMetallicRoughness.baseColorTexture.index == 0);
  }
}

TEST_CASE("gltf: saving is deterministic, byte for byte", "[gltf]") {
  const Mesh m = textured_mesh();
  auto a = save_glb_to_memory(m), b = save_glb_to_memory(m);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  CHECK(*a == *b);
}

TEST_CASE("gltf: tangents and vertex colours survive, attribute sets stay per group", "[gltf]") {
  GltfBuilder b;
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::vector<float> tan = {1, 0, 0, -1, 1, 0, 0, -1, 1, 0, 0, -1};
  const std::vector<float> col = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  nlohmann::json p0 = {{"attributes",
                        {{"POSITION", b.floats(pos, "VEC3", 3, true)},
                         {"TANGENT", b.floats(tan, "VEC4", 4)},
                         {"COLOR_0", b.floats(col, "VEC3", 3)}}}};
  nlohmann::json p1 = {{"attributes", {{"POSITION", b.floats(pos, "VEC3", 3, true)}}}};
  b.j["meshes"].push_back({{"primitives", {p0, p1}}});
  add_scene(b, {{{"mesh", 0}}});
  auto m = load_text(b.gltf_text());
  REQUIRE(m.ok());
  REQUIRE(m->groups.size() == 2);
  CHECK(m->groups[0].attributes.tangents);
  CHECK(m->groups[0].attributes.color_components == 3);
  CHECK_FALSE(m->groups[1].attributes.tangents);
  CHECK(m->T(0, 3) == -1.0f);
  CHECK(m->C(2, 2) == 1.0f);
  auto bytes = save_glb_to_memory(*m);
  REQUIRE(bytes.ok());
  auto back = load_gltf_from_memory(bytes->data(), bytes->size());
  REQUIRE(back.ok());
  CHECK(back->groups[0].attributes == m->groups[0].attributes);
  CHECK(back->groups[1].attributes == m->groups[1].attributes);
  CHECK(back->T.topRows(3) == m->T.topRows(3));
  CHECK(back->C.topRows(3).leftCols(3) == m->C.topRows(3).leftCols(3));
}

TEST_CASE("gltf: what cannot be carried is named in a warning, never dropped silently", "[gltf]") {
  GltfBuilder b;
  const int quad = restitch::test::add_quad_mesh(b);
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0};
  b.j["meshes"][quad]["primitives"].push_back(
      {{"attributes", {{"POSITION", b.floats(pos, "VEC3", 3, true)}}}, {"mode", 1}});
  b.j["animations"] = {{{"channels", nlohmann::json::array()}, {"samplers", nlohmann::json::array()}}};
  add_scene(b, {{{"mesh", quad}}});
  GltfLoadReport r;
  auto m = load_text(b.gltf_text(), &r);
  REQUIRE(m.ok());
  CHECK(m->triangle_count() == 2);
  bool lines = false, anim = false;
  for (const auto& w : r.warnings) {
    lines |= w.find("LINES") != std::string::npos && w.find("dropped") != std::string::npos;
    anim |= w.find("animation") != std::string::npos;
  }
  CHECK(lines);
  CHECK(anim);
}

TEST_CASE("gltf: a required compression extension is refused with its name", "[gltf]") {
  GltfBuilder b;
  add_scene(b, {{{"mesh", restitch::test::add_quad_mesh(b)}}});
  b.j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  b.j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  auto m = load_text(b.gltf_text());
  REQUIRE_FALSE(m.ok());
  CHECK(m.status().code() == StatusCode::unsupported);
  CHECK_THAT(m.status().message(), Catch::Contains("KHR_draco_mesh_compression"));
}

TEST_CASE("gltf: bad input gets an error that names the problem", "[gltf]") {
  GltfBuilder good;
  add_scene(good, {{{"mesh", restitch::test::add_quad_mesh(good)}}});
  const std::vector<std::uint8_t> glb = good.glb();

  SECTION("missing file") {
    auto m = load_gltf(tmp_path("does-not-exist.glb"));
    REQUIRE_FALSE(m.ok());
    CHECK_THAT(m.status().message(), Catch::Contains("no such file"));
  }
  SECTION("a directory") {
    auto m = load_gltf(RESTITCH_TEST_TMP);
    REQUIRE_FALSE(m.ok());
    CHECK_THAT(m.status().message(), Catch::Contains("directory"));
  }
  SECTION("truncated binary") {
    std::vector<std::uint8_t> cut(glb.begin(), glb.begin() + glb.size() / 2);
    auto m = load_gltf_from_memory(cut.data(), cut.size());
    REQUIRE_FALSE(m.ok());
    CHECK_THAT(m.status().message(), Catch::Contains("truncated"));
  }
  SECTION("wrong magic") {
    std::vector<std::uint8_t> bad = glb;
    bad[0] = 'X';
    auto m = load_gltf_from_memory(bad.data(), bad.size());
    REQUIRE_FALSE(m.ok());
    CHECK(m.status().code() == StatusCode::parse_error);
    CHECK_THAT(m.status().message(), Catch::Contains("not a glTF file"));
  }
  SECTION("broken JSON") {
    std::string text = good.gltf_text();
    text.resize(text.size() - 10);
    auto m = load_text(text);
    REQUIRE_FALSE(m.ok());
    CHECK(m.status().code() == StatusCode::parse_error);
  }
  SECTION("accessor out of range") {
    GltfBuilder b = good;
    b.j["accessors"][0]["count"] = 1000;
    auto m = load_text(b.gltf_text());
    REQUIRE_FALSE(m.ok());
    CHECK_THAT(m.status().message(), Catch::Contains("past the end"));
  }
  SECTION("an absurd count over a small buffer is refused before anything is allocated") {
    // 2^31 positions (48 GiB as doubles) declared over the quad's few bytes: a parse error, not
    // std::bad_alloc (the count is checked against the bytes that are there first). The vertex limit
    // would refuse the larger counts first (next section): it is lifted here.
    GltfLimits none;
    none.max_vertices = none.max_triangles = std::numeric_limits<std::size_t>::max();
    for (const std::int64_t count : {std::int64_t(1) << 31, (std::int64_t(1) << 31) - 1, std::int64_t(1000000)}) {
      GltfBuilder b = good;
      b.j["accessors"][0]["count"] = count;
      const std::string text = b.gltf_text();
      auto m = load_gltf_from_memory(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), "", nullptr, none);
      REQUIRE_FALSE(m.ok());
      CHECK(m.status().code() == StatusCode::parse_error);
      CHECK_THAT(m.status().message(), Catch::Contains("past the end"));
    }
  }
  SECTION("an absurd count with no bufferView (zeros) is refused by the vertex limit before it is allocated") {
    GltfBuilder b = good;
    b.j["accessors"][0].erase("bufferView");
    b.j["accessors"][0]["count"] = std::int64_t(1) << 31;  // 48 GiB of doubles if it were decoded
    auto m = load_text(b.gltf_text());
    REQUIRE_FALSE(m.ok());
    CHECK(m.status().code() == StatusCode::too_large);
    CHECK_THAT(m.status().message(), Catch::Contains("2147483648 vertices"));
    CHECK_THAT(m.status().message(), Catch::Contains("GltfLimits::max_vertices"));
    CHECK_THAT(m.status().message(), Catch::Contains("--max-vertices"));
  }
  SECTION("an attribute whose count differs from POSITION is refused before it is read") {
    GltfBuilder b = good;
    const int n = b.floats(std::vector<float>(12, 0.5f), "VEC3", 3);
    b.j["accessors"][std::size_t(n)].erase("bufferView");
    b.j["accessors"][std::size_t(n)]["count"] = std::int64_t(1) << 31;
    b.j["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = n;
    auto m = load_text(b.gltf_text());
    REQUIRE_FALSE(m.ok());
    CHECK_THAT(m.status().message(), Catch::Contains("NORMAL has a different count from POSITION"));
  }
  SECTION("the vertex and triangle limits, per primitive and over the scene's instances") {
    GltfLimits tight;
    tight.max_triangles = 3;  // the quad has 2 triangles: one instance passes, two do not
    auto one = load_gltf_from_memory(glb.data(), glb.size(), "", nullptr, tight);
    REQUIRE(one.ok());
    GltfBuilder b = good;
    b.j["nodes"].push_back({{"mesh", 0}, {"translation", {2.0, 0.0, 0.0}}});
    b.j["scenes"][0]["nodes"].push_back(int(b.j["nodes"].size()) - 1);
    const std::string text = b.gltf_text();
    REQUIRE(load_text(text).ok());
    auto two = load_gltf_from_memory(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), "", nullptr,
                                     tight);
    REQUIRE_FALSE(two.ok());
    CHECK(two.status().code() == StatusCode::too_large);
    CHECK_THAT(two.status().message(), Catch::Contains("4 triangles, more than the limit of 3"));
    CHECK_THAT(two.status().message(), Catch::Contains("--max-triangles"));
    GltfLimits few_vertices;
    few_vertices.max_vertices = 3;  // the quad has 4
    auto v = load_gltf_from_memory(glb.data(), glb.size(), "", nullptr, few_vertices);
    REQUIRE_FALSE(v.ok());
    CHECK(v.status().code() == StatusCode::too_large);
    CHECK_THAT(v.status().message(), Catch::Contains("4 vertices, more than the limit of 3"));
  }
  SECTION("index out of range") {
    GltfBuilder b;
    const int q = restitch::test::add_quad_mesh(b, 4, false);
    b.j["meshes"][q]["primitives"][0]["indices"] = b.indices({0, 1, 9});
    add_scene(b, {{{"mesh", q}}});
    auto m = load_text(b.gltf_text());
    REQUIRE_FALSE(m.ok());
    CHECK_THAT(m.status().message(), Catch::Contains("out of range"));
  }
  SECTION("NaN positions") {
    GltfBuilder b;
    const std::vector<float> pos = {0, 0, 0, NAN, 0, 0, 0, 1, 0};
    b.j["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", b.floats(pos, "VEC3", 3)}}}}}}});
    add_scene(b, {{{"mesh", 0}}});
    auto m = load_text(b.gltf_text());
    REQUIRE_FALSE(m.ok());
    CHECK(m.status().code() == StatusCode::invalid_mesh);
    CHECK_THAT(m.status().message(), Catch::Contains("NaN"));
  }
  SECTION("empty scene") {
    GltfBuilder b = good;
    b.j["scenes"] = {{{"nodes", nlohmann::json::array()}}};
    auto m = load_text(b.gltf_text());
    REQUIRE_FALSE(m.ok());
    CHECK_THAT(m.status().message(), Catch::Contains("no triangles"));
  }
  SECTION("only degenerate triangles") {
    GltfBuilder b;
    const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 2, 0, 0};
    b.j["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", b.floats(pos, "VEC3", 3)}}}}}}});
    add_scene(b, {{{"mesh", 0}}});
    auto m = load_text(b.gltf_text());
    REQUIRE_FALSE(m.ok());
    CHECK_THAT(m.status().message(), Catch::Contains("degenerate"));
  }
}

TEST_CASE("gltf: a failed save leaves no file behind", "[gltf]") {
  const Mesh m = textured_mesh();
  const std::string bad_ext = tmp_path("out.obj");
  CHECK_FALSE(save_gltf(m, bad_ext).ok());
  CHECK_FALSE(std::filesystem::exists(bad_ext));
  const std::string no_dir = tmp_path("no/such/dir/out.glb");
  const Status s = save_gltf(m, no_dir);
  CHECK_FALSE(s.ok());
  CHECK(s.code() == StatusCode::io_error);
  CHECK_FALSE(std::filesystem::exists(no_dir));
  Mesh empty;
  const std::string empty_path = tmp_path("empty.glb");
  std::filesystem::remove(empty_path);
  CHECK_FALSE(save_gltf(empty, empty_path).ok());
  CHECK_FALSE(std::filesystem::exists(empty_path));
}

TEST_CASE("gltf: the real models load with the MANIFEST's triangle counts and round-trip", "[gltf][models]") {
  const std::string dir = RESTITCH_SHARED_MODELS;
  std::ifstream manifest(dir + "/MANIFEST.tsv");
  if (!manifest) {
    WARN("../shared/models is absent: real-model checks skipped");
    return;
  }
  std::string line;
  std::getline(manifest, line);  // header
  int checked = 0;
  while (std::getline(manifest, line)) {
    std::vector<std::string> cols;
    std::size_t start = 0, tab;
    while ((tab = line.find('\t', start)) != std::string::npos)
      cols.push_back(line.substr(start, tab - start)), start = tab + 1;
    cols.push_back(line.substr(start));
    if (cols.size() < 12) continue;
    INFO(cols[0]);
    GltfLoadReport r;
    auto m = load_gltf(dir + "/" + cols[0], &r);
    REQUIRE(m.ok());
    CHECK(m->triangle_count() == std::stoul(cols[4]));
    CHECK(r.textures == std::stoul(cols[11]));
    // bbox_size "a x b x c" (4 significant digits)
    double sx, sy, sz;
    REQUIRE(std::sscanf(cols[5].c_str(), "%lf x %lf x %lf", &sx, &sy, &sz) == 3);
    const Eigen::Vector3d size = bounding_box(*m).size();
    CHECK(size.x() == Approx(sx).epsilon(2e-3));
    CHECK(size.y() == Approx(sy).epsilon(2e-3));
    CHECK(size.z() == Approx(sz).epsilon(2e-3));
    auto bytes = save_glb_to_memory(*m);
    REQUIRE(bytes.ok());
    auto back = load_gltf_from_memory(bytes->data(), bytes->size());
    REQUIRE(back.ok());
    REQUIRE(back->triangle_count() == m->triangle_count());
    bool same_corners = true;  // vertices are compacted on save, so compare triangle corners
    for (Eigen::Index f = 0; f < m->F.rows(); ++f)
      for (int c = 0; c < 3; ++c) same_corners &= back->V.row(back->F(f, c)) == m->V.row(m->F(f, c));
    CHECK(same_corners);
    CHECK(back->groups.size() == m->groups.size());
    if (m->assets) {
      REQUIRE(back->assets->model.images.size() == m->assets->model.images.size());
      for (std::size_t i = 0; i < m->assets->model.images.size(); ++i)
        CHECK(back->assets->model.images[i].image == m->assets->model.images[i].image);
    }
    ++checked;
  }
  CHECK(checked == 14);
}
