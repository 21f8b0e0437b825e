// Tests for restitch/io/json_report.hpp: every documented key of analysis_json
// and retarget_json carries the value of the Analysis / RetargetReport it came
// from, in model units, on hand-made inputs with distinct values (so a swapped
// or unconverted field shows) and on a real analysis and resize.
#include "restitch/io/json_report.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "restitch/analyze.hpp"
#include "restitch/families/families.hpp"
#include "restitch/retarget.hpp"

using nlohmann::json;
using restitch::Analysis;
using restitch::RetargetReport;

namespace {

void check_vec3(const json& j, const Eigen::Vector3d& v, double eps = 1e-12) {
  REQUIRE(j.is_array());
  REQUIRE(j.size() == 3);
  for (int i = 0; i < 3; ++i) CHECK(j[std::size_t(i)].get<double>() == Approx(v[i]).epsilon(eps).margin(eps));
}
void check_arr3(const json& j, const Eigen::Array3i& v) {
  REQUIRE(j.is_array());
  REQUIRE(j.size() == 3);
  for (int i = 0; i < 3; ++i) CHECK(j[std::size_t(i)].get<int>() == v[i]);
}

// An analysis with distinct values everywhere; normalization scale 0.5, so
// model-unit lengths are twice the normalized ones.
Analysis hand_analysis() {
  Analysis a;
  a.normalization.center = Eigen::Vector3d(1, 2, 3);
  a.normalization.scale = 0.5;
  a.features.points = restitch::MatrixX3f::Zero(7, 3);
  a.sampled_features = 4;
  restitch::DominantOffset d0, d1;
  d0.offset = Eigen::Vector3d(0.4, 0, 0.02);
  d0.votes = 10;
  d0.overlap = 0.8;
  d0.significant = true;
  d1.offset = Eigen::Vector3d(0, 0.3, 0.1);
  d1.votes = 3;
  d1.overlap = 0.2;
  d1.significant = false;
  a.dominant = {d0, d1};
  a.principal = {d0.offset};
  a.lattice.A.col(0) = Eigen::Vector3d(0.8, 0, 0.04);  // the principal offset in model units
  a.lattice.A.col(1) = Eigen::Vector3d(0, 0.4, 0);
  a.lattice.A.col(2) = Eigen::Vector3d(0, 0, 0.4);
  a.lattice.dummy = {{false, true, true}};
  a.lattice.cells = Eigen::Array3i(5, 1, 1);
  a.lattice.origin = Eigen::Vector3d(-1, 0.5, 2);
  a.sparsity.top7 = 0.25;
  a.sparsity.top20 = 0.5;
  a.sparsity.bins = 42;
  a.descriptor_name = "fpfh";
  a.matcher_name = "reduced";
  a.detector_name = "autocorrelation";
  a.timings_ms = {{"sampling", 1.5}, {"matching", 2.5}};
  return a;
}

}  // namespace

TEST_CASE("analysis_json: keys and values of a hand-made analysis", "[json]") {
  const Analysis a = hand_analysis();
  const json j = restitch::analysis_json(a);
  for (const char* key :
       {"scale", "features", "dominant_offsets", "principal_offsets", "dummy_directions", "lattice_axes", "resizable",
        "lattice_cells", "lattice_origin", "sparsity", "descriptor", "matcher", "detector", "timings_ms"})
    CHECK(j.contains(key));
  CHECK(j["scale"].get<double>() == 0.5);
  CHECK(j["features"].get<int>() == 7);  // all features, not only the Poisson ones

  REQUIRE(j["dominant_offsets"].size() == 2);
  check_vec3(j["dominant_offsets"][0]["offset"], {0.8, 0, 0.04});  // model units
  CHECK(j["dominant_offsets"][0]["votes"].get<int>() == 10);
  CHECK(j["dominant_offsets"][0]["overlap"].get<double>() == 0.8);
  CHECK(j["dominant_offsets"][0]["significant"].get<bool>());
  check_vec3(j["dominant_offsets"][1]["offset"], {0, 0.6, 0.2});
  CHECK(j["dominant_offsets"][1]["votes"].get<int>() == 3);
  CHECK(j["dominant_offsets"][1]["overlap"].get<double>() == 0.2);
  CHECK_FALSE(j["dominant_offsets"][1]["significant"].get<bool>());

  REQUIRE(j["principal_offsets"].size() == 1);
  check_vec3(j["principal_offsets"][0], a.principal_model_units()[0]);
  check_vec3(j["principal_offsets"][0], {0.8, 0, 0.04});
  REQUIRE(j["dummy_directions"].size() == 2);
  check_vec3(j["dummy_directions"][0], {0, 0.4, 0});
  check_vec3(j["dummy_directions"][1], {0, 0, 0.4});
  REQUIRE(j["lattice_axes"].size() == 3);
  for (int c = 0; c < 3; ++c) check_vec3(j["lattice_axes"][std::size_t(c)], a.lattice.A.col(c));
  CHECK(j["resizable"] == json::array({true, false, false}));
  check_arr3(j["lattice_cells"], {5, 1, 1});
  check_vec3(j["lattice_origin"], {-1, 0.5, 2});
  CHECK(j["sparsity"]["top7"].get<double>() == 0.25);
  CHECK(j["sparsity"]["top20"].get<double>() == 0.5);
  CHECK(j["sparsity"]["bins"].get<int>() == 42);
  CHECK(j["descriptor"] == "fpfh");
  CHECK(j["matcher"] == "reduced");
  CHECK(j["detector"] == "autocorrelation");
  CHECK(j["timings_ms"]["sampling"].get<double>() == 1.5);
  CHECK(j["timings_ms"]["matching"].get<double>() == 2.5);
  CHECK(j["timings_ms"].size() == 2);
  // What the CLI writes reads back as the same document.
  CHECK(json::parse(j.dump()) == j);
}

TEST_CASE("analysis_json: resizable follows the dummy flags; no repetition gives no principal offsets", "[json]") {
  Analysis a = hand_analysis();
  a.principal.push_back(Eigen::Vector3d(0.1, 0.2, 0));
  a.lattice.A.col(1) = Eigen::Vector3d(0.2, 0.4, 0);
  a.lattice.dummy = {{false, false, true}};
  json j = restitch::analysis_json(a);
  CHECK(j["resizable"] == json::array({true, true, false}));
  REQUIRE(j["principal_offsets"].size() == 2);
  check_vec3(j["principal_offsets"][1], {0.2, 0.4, 0});
  REQUIRE(j["dummy_directions"].size() == 1);
  check_vec3(j["dummy_directions"][0], {0, 0, 0.4});

  Analysis none;
  none.normalization.scale = 4;
  none.lattice.A = Eigen::Matrix3d::Identity() * 0.05;
  none.lattice.dummy = {{true, true, true}};
  j = restitch::analysis_json(none);
  CHECK(j["principal_offsets"].empty());
  CHECK(j["dominant_offsets"].empty());
  CHECK(j["resizable"] == json::array({false, false, false}));
  CHECK(j["dummy_directions"].size() == 3);
  CHECK(j["features"].get<int>() == 0);
}

TEST_CASE("retarget_json: keys and values of a hand-made report", "[json]") {
  RetargetReport r;
  r.steps = {2, 0, -1};
  r.grid_steps = {3, 0, -2};
  r.cells_in = {5, 2, 4};
  r.cells_out = {8, 2, 2};
  r.nodes = 32;
  r.labels = 12;
  r.edges = 123;
  r.cycles = 4;
  r.energy = 12.5;
  r.non_metric = true;
  r.triangles_in = 555;
  r.triangles_out = 777;
  r.vertices_out = 999;
  r.checked = true;
  r.open_edges.assign(2, {Eigen::Vector3f::Zero(), Eigen::Vector3f::UnitX()});
  r.warnings.push_back({"open seam", "2 edge(s) of the output are open"});
  r.boundary_edges_in = 11;
  r.boundary_edges_out = 13;
  r.weld_tolerance = 8e-6;
  r.weld_tolerance_measured = true;
  r.regions = 6;
  r.size_in = {1, 2, 3};
  r.size_out = {1.5, 2, 2.25};
  r.timings_ms = {{"energy", 0.5}, {"solve", 1.25}, {"stitch", 2}, {"total", 4}};
  r.plane_offsets[0] = {0, 0, 0.3125, 0, 0, 0, 0, 0, 0};
  r.seams_moved = 1;
  restitch::SeamReport seam;
  seam.cell_a = {1, 0, 0};
  seam.cell_b = {2, 0, 0};
  seam.offset = 0.3125;
  r.seams.push_back(seam);
  const json j = restitch::retarget_json(r);
  CHECK(j["seams_moved"].get<int>() == 1);
  REQUIRE(j["plane_offsets"].size() == 3);
  CHECK(j["plane_offsets"][0].size() == 9);
  CHECK(j["plane_offsets"][0][2].get<double>() == 0.3125);
  CHECK(j["plane_offsets"][1].empty());
  CHECK(j["seams"][0]["offset"].get<double>() == 0.3125);
  CHECK(r.plane(0, 2) == 2.3125);
  CHECK(r.plane(1, 1) == 1.0);
  CHECK((r.cell_of({2.2, 0.5, 0.5}) == Eigen::Array3i(1, 0, 0)).all());  // before the moved plane
  CHECK((r.cell_of({2.4, 0.5, 0.5}) == Eigen::Array3i(2, 0, 0)).all());
  CHECK((r.cell_of({-3, 9, 1.5}) == Eigen::Array3i(0, 1, 1)).all());     // clamped
  check_arr3(j["steps"], r.steps);
  check_arr3(j["grid_steps"], r.grid_steps);
  check_arr3(j["cells_in"], r.cells_in);
  check_arr3(j["cells_out"], r.cells_out);
  CHECK(j["nodes"].get<int>() == 32);
  CHECK(j["labels"].get<int>() == 12);
  CHECK(j["edges"].get<int>() == 123);
  CHECK(j["cycles"].get<int>() == 4);
  CHECK(j["energy"].get<double>() == 12.5);
  CHECK(j["non_metric"].get<bool>());
  check_vec3(j["size_in"], r.size_in);
  check_vec3(j["size_out"], r.size_out);
  CHECK(j["timings_ms"]["solve"].get<double>() == 1.25);
  CHECK(j["timings_ms"].size() == 4);
  CHECK(j["output"]["vertices"].get<std::size_t>() == 999);
  CHECK(j["output"]["triangles"].get<std::size_t>() == 777);
  CHECK(j["boundary_edges"]["in"].get<std::size_t>() == 11);
  CHECK(j["boundary_edges"]["out"].get<std::size_t>() == 13);
  CHECK(j["boundary_edges"]["new"].get<std::size_t>() == 2);
  CHECK(j["checked"].get<bool>());
  REQUIRE(j["warnings"].size() == 1);
  CHECK(j["warnings"][0]["check"] == "open seam");
  CHECK(j["warnings"][0]["message"] == "2 edge(s) of the output are open");
  CHECK(j["weld_tolerance"]["relative"].get<double>() == 8e-6);
  CHECK(j["weld_tolerance"]["measured"].get<bool>());
  CHECK(json::parse(j.dump()) == j);
}

TEST_CASE("analysis_json and retarget_json agree with a real analysis and resize of the pin header", "[json]") {
  auto sample = restitch::families::generate("pin_header", {{"pins", 5}});
  REQUIRE(sample.ok());
  auto a = restitch::analyze(sample->mesh);
  REQUIRE(a.ok());
  const json ja = restitch::analysis_json(*a);
  const auto principal = a->principal_model_units();
  REQUIRE(principal.size() == 1);
  REQUIRE(ja["principal_offsets"].size() == 1);
  check_vec3(ja["principal_offsets"][0], principal[0]);
  // The pitch of the generated model, in model units (mm), whatever the sign.
  CHECK(std::abs(ja["principal_offsets"][0][0].get<double>()) == Approx(sample->generators[0].x()).epsilon(1e-3));
  // lattice_axes: the principal offsets in order, then the dummy directions.
  check_vec3(ja["lattice_axes"][0], principal[0], 1e-9);
  for (int c = 0; c < 3; ++c) CHECK(ja["resizable"][std::size_t(c)].get<bool>() == !a->lattice.dummy[std::size_t(c)]);
  CHECK(ja["dummy_directions"].size() == std::size_t(3 - a->lattice.principal_count()));
  check_arr3(ja["lattice_cells"], a->lattice.cells);
  CHECK(ja["scale"].get<double>() == Approx(2.0 / restitch::bounding_box(sample->mesh).size().maxCoeff()));
  CHECK(ja["features"].get<int>() == int(a->features.size()));
  CHECK(ja["dominant_offsets"].size() == a->dominant.size());
  CHECK(ja["descriptor"] == "shot");
  CHECK(ja["matcher"] == "brute_force");

  auto steps = restitch::lattice_steps_from_principal(*a, {2});
  REQUIRE(steps.ok());
  restitch::RetargetOptions options;
  auto out = restitch::retarget(sample->mesh, *a, *steps, options);
  REQUIRE(out.ok());
  const json jr = restitch::retarget_json(out->report);
  // Not counted without the check: null.
  restitch::RetargetOptions unchecked;
  unchecked.check = false;
  CHECK(restitch::retarget_json(restitch::retarget(sample->mesh, *a, *steps, unchecked)->report)["boundary_edges"].is_null());
  check_arr3(jr["steps"], *steps);
  check_arr3(jr["cells_in"], a->lattice.cells);
  check_arr3(jr["cells_out"], a->lattice.cells + *steps);  // one cell per repeat
  CHECK(jr["nodes"].get<int>() == (a->lattice.cells + *steps).prod());
  CHECK(jr["labels"].get<int>() == 3);
  CHECK(jr["output"]["vertices"].get<std::size_t>() == out->mesh.vertex_count());
  CHECK(jr["output"]["triangles"].get<std::size_t>() == out->mesh.triangle_count());
  CHECK(jr["boundary_edges"]["in"].get<std::size_t>() == restitch::boundary_edge_count(sample->mesh));
  CHECK(jr["boundary_edges"]["out"].get<std::size_t>() == restitch::boundary_edge_count(out->mesh));
  check_vec3(jr["size_in"], restitch::bounding_box(sample->mesh).size(), 1e-9);
  check_vec3(jr["size_out"], restitch::bounding_box(out->mesh).size(), 1e-9);
  // Two more pins: the box grows by two pitches along x.
  CHECK(jr["size_out"][0].get<double>() - jr["size_in"][0].get<double>() ==
        Approx(2 * sample->generators[0].x()).epsilon(1e-3));
}
