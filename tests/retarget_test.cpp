// Retargeting: resized samples equal the samples generated with more repeats;
// the energy, label spaces and limits behave as documented.
#include <catch2/catch.hpp>

#include <array>
#include <map>
#include <set>

#include "restitch/families/families.hpp"
#include "restitch/io/gltf.hpp"
#include "restitch/io/json_report.hpp"
#include "restitch/restitch.hpp"
#include "support/boundary_length.hpp"
#include "support/components.hpp"
#include "support/mesh_builders.hpp"
#include "support/surface_distance.hpp"

using namespace restitch;

namespace {

struct Prepared {
  families::SampleModel sample;
  Analysis analysis;
};

// One analysis per family, shared by the test cases (analysis is the slow part).
const Prepared& prepared(const std::string& name) {
  static std::map<std::string, Prepared> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  auto s = families::generate(name);
  REQUIRE(s.ok());
  auto a = analyze(s->mesh);
  REQUIRE(a.ok());
  return cache.emplace(name, Prepared{std::move(*s), std::move(*a)}).first->second;
}

// The lattice axis parallel to a generator (within 1 degree), or -1.
int axis_of(const Lattice& L, const Eigen::Vector3d& g) {
  for (int a = 0; a < 3; ++a)
    if (!L.dummy[a] && std::abs(L.A.col(a).normalized().dot(g.normalized())) > std::cos(M_PI / 180.0)) return a;
  return -1;
}

// `out` equals `truth` in place: bounding boxes, and the symmetric surface distance, within 1e-4 of the
// diagonal.
// In place (the generators' origin is the pivot), within 1e-4 of the size, and no more open than the
// generated model: no more open edges (positions welded), except where a seam plane cuts an edge the
// input already had open in two (the facades' window reveals), so also no more open length.
enum class Open { edges, length };
void check_same_model(const Mesh& out, const Mesh& truth, Open open_check = Open::edges) {
  const BoundingBox bt = bounding_box(truth), bo = bounding_box(out);
  const double size = bt.size().norm();
  CHECK((bt.min - bo.min).norm() < 1e-4 * size);
  CHECK((bt.max - bo.max).norm() < 1e-4 * size);
  CHECK(restitch::test::symmetric_surface_distance(out, truth, 0.004 * size) < 1e-4 * size);
  const double open = restitch::test::open_boundary_length(truth);
  CHECK(restitch::test::open_boundary_length(out) <= open + 1e-6 * (1 + open));
  if (open_check == Open::edges) CHECK(boundary_edge_count(out) <= boundary_edge_count(truth));
}
// The facades' seam planes cut edges their inputs have open (window reveals) in two: more open edges
// than the generated model, no more open length.
Open open_check_of(const std::string& family) { return family.rfind("facade", 0) == 0 ? Open::length : Open::edges; }

// Steps of `k` along sample generator `g` (the lattice axis parallel to it).
Eigen::Array3i steps_along(const Prepared& p, std::size_t g, int k) {
  const int axis = axis_of(p.analysis.lattice, p.sample.generators[g]);
  REQUIRE(axis >= 0);
  Eigen::Array3i steps = Eigen::Array3i::Zero();
  steps[axis] = k;
  return steps;
}

}  // namespace

TEST_CASE("retarget: each sample family resized by k steps equals the family generated with k more repeats",
          "[retarget][samples]") {
  for (const families::SampleInfo& info : families::catalog()) {
    if (!families::generate(info.name)->parts.empty()) continue;  // the structured ones: structure_test.cpp
    const Prepared& p = prepared(info.name);
    RetargetOptions options;
    Retargeter<> r(p.sample.mesh, p.analysis, options);
    REQUIRE(r.status().ok());
    for (std::size_t g = 0; g < p.sample.generators.size(); ++g) {
      INFO(info.name << " generator " << g);
      for (const int k : {2, -1}) {
        INFO("steps " << k);
        auto out = r.retarget(steps_along(p, g, k));
        REQUIRE(out.ok());
        auto truth = families::generate(info.name, {{p.sample.count_parameters[g], p.sample.counts[g] + k}});
        REQUIRE(truth.ok());
        check_same_model(out->mesh, truth->mesh, open_check_of(info.name));
        CHECK(out->report.labels == std::abs(k) + 1);
        CHECK(out->report.nodes == out->report.cells_out.prod());
        CHECK(validate(out->mesh).ok());
        // No more open edges than the generated model has (the samples' parts touch without sharing
        // vertices, so they have some): stitching opens nothing.
        CHECK(out->report.boundary_edges_in == boundary_edge_count(p.sample.mesh));
        CHECK(out->report.boundary_edges_out == boundary_edge_count(out->mesh));
        // The facades have more open edges than their generated twins (2162 against 2113 at +2 along
        // the columns): the seam planes cut edges the input already had open (window reveals against
        // the wall) in two. By length the result opens nothing: no more open length than the twin.
        if (info.name.rfind("facade", 0) != 0)
          CHECK(out->report.boundary_edges_out <= boundary_edge_count(truth->mesh));
        const double open = restitch::test::open_boundary_length(truth->mesh);
        CHECK(restitch::test::open_boundary_length(out->mesh) <= open + 1e-6 * (1 + open));
      }
    }
  }
}

// Down to ONE pin too: before end caps that gave 3.49 mm, not the 1-pin model's 3.14 mm, with 28 open
// edges (one output cell could carry only one end).
TEST_CASE("retarget: the closed pin header stays closed, grown, shrunk and down to one pin", "[retarget][samples]") {
  for (const int pins : {3, 6}) {
    INFO("pins " << pins);
    auto s = families::generate("pin_header", {{"pins", pins}, {"closed", 1}});
    REQUIRE(s.ok());
    REQUIRE(boundary_edge_count(s->mesh) == 0);
    // The open variant is not closed: the pins' ends on the body are open squares (4 edges each, 2 per
    // pin), and its end cap's face meets the last segment with a T-junction (3 + 1 edges, front and back).
    auto open = families::generate("pin_header", {{"pins", pins}});
    REQUIRE(open.ok());
    CHECK(boundary_edge_count(open->mesh) == std::size_t(8 * pins + 8));
    auto a = analyze(s->mesh);
    REQUIRE(a.ok());
    const Prepared p{std::move(*s), std::move(*a)};
    RetargetOptions options;
    Retargeter<> r(p.sample.mesh, p.analysis, options);
    REQUIRE(r.status().ok());
    for (const int k : {1, 3, -1, 1 - pins}) {  // the last: down to one pin (end caps)
      INFO("steps " << k);
      auto out = r.retarget(steps_along(p, 0, k));
      REQUIRE(out.ok());
      CHECK(out->report.boundary_edges_in == 0);
      CHECK(out->report.boundary_edges_out == 0);
      CHECK(boundary_edge_count(out->mesh) == 0);
      auto truth = families::generate("pin_header", {{"pins", pins + k}, {"closed", 1}});
      REQUIRE(truth.ok());
      check_same_model(out->mesh, truth->mesh);
    }
  }
}

TEST_CASE("retarget: copies that differ by less than the weld tolerance are welded closed; out of range refused",
          "[retarget][samples]") {
  // The closed 4-pin header with every vertex moved by up to 1e-5 of the diagonal per coordinate (a
  // deterministic function of its position): the input stays closed (indexed), but copies meeting at a seam differ by up
  // to 2 sqrt(3) 1e-5 = 3.5e-5 of the diagonal. Stitched with the clean model's analysis (so only the
  // weld differs): open at the stitcher's 1e-6 without the strips between cut lines and closed with them,
  // closed at 1e-4 (RetargetOptions::weld_tolerance), and
  // closed by default, where the copies' precision is measured (RetargetOptions::measure_weld_tolerance):
  // their vertex pairs all lie within 6.4e-5, and within it the tolerance is measured.
  auto s = families::generate("pin_header", {{"pins", 4}, {"closed", 1}});
  REQUIRE(s.ok());
  auto a = analyze(s->mesh);
  REQUIRE(a.ok());
  const Prepared p{std::move(*s), std::move(*a)};
  Mesh noisy = p.sample.mesh;
  const double diag = bounding_box(noisy).size().norm();
  for (Eigen::Index v = 0; v < noisy.V.rows(); ++v) {  // a function of the position: coincident vertices stay so
    const Eigen::Vector3d q = p.sample.mesh.V.row(v).cast<double>().transpose();
    for (int c = 0; c < 3; ++c)
      noisy.V(v, c) += float(1e-5 * diag * std::sin(129.898 * q.x() + 782.33 * q.y() + 377.19 * q.z() + 1.7 * c));
  }
  REQUIRE(boundary_edge_count(noisy) == 0);
  for (const int k : {1, -1}) {
    INFO("steps " << k);
    RetargetOptions options;
    options.measure_weld_tolerance = false;
    ClipStitcher unzipped;  // the strips between cut lines (zipper.hpp) would close it at any weld
    unzipped.zip_seams = false;
    auto open = Retargeter<>(noisy, p.analysis, options, {}, {}, unzipped).retarget(steps_along(p, 0, k));
    REQUIRE(open.ok());
    CHECK(open->report.boundary_edges_out > 0);
    auto zipped = Retargeter<>(noisy, p.analysis, options).retarget(steps_along(p, 0, k));
    REQUIRE(zipped.ok());
    CHECK(zipped->report.boundary_edges_out == 0);
    CHECK(open->report.weld_tolerance == 1e-6);
    CHECK(!open->report.weld_tolerance_measured);
    options.measure_weld_tolerance = true;
    auto measured = Retargeter<>(noisy, p.analysis, options).retarget(steps_along(p, 0, k));
    REQUIRE(measured.ok());
    CHECK(measured->report.weld_tolerance_measured);
    CHECK(measured->report.weld_tolerance > 2 * std::sqrt(3.0) * 1e-5);
    CHECK(measured->report.weld_tolerance <= 6.4e-5);
    CHECK(measured->report.boundary_edges_out == 0);
    // The clean model's copies are exact: the stitcher's own tolerance stays.
    auto clean = Retargeter<>(p.sample.mesh, p.analysis, options).retarget(steps_along(p, 0, k));
    REQUIRE(clean.ok());
    CHECK(clean->report.weld_tolerance == 1e-6);
    CHECK(!clean->report.weld_tolerance_measured);
    CHECK(clean->report.boundary_edges_out == 0);
    options.weld_tolerance = 1e-4;
    auto closed = Retargeter<>(noisy, p.analysis, options).retarget(steps_along(p, 0, k));
    REQUIRE(closed.ok());
    CHECK(closed->report.boundary_edges_out == 0);
    auto truth = families::generate("pin_header", {{"pins", 4 + k}, {"closed", 1}});
    REQUIRE(truth.ok());
    CHECK(test::symmetric_surface_distance(closed->mesh, truth->mesh, 0.004 * diag) < 1e-4 * diag);
  }
  for (const double bad : {-1e-6, 0.02, double(NAN)}) {
    RetargetOptions options;
    options.weld_tolerance = bad;
    Retargeter<> r(p.sample.mesh, p.analysis, options);
    CHECK(r.status().code() == StatusCode::invalid_argument);
    CHECK(r.status().message().find("weld tolerance") != std::string::npos);
  }
}

TEST_CASE("retarget: the bookshelf keeps both side panels; the sheared facade stays sheared", "[retarget][samples]") {
  {
    const Prepared& p = prepared("bookshelf");
    Eigen::Array3i steps = steps_along(p, 0, 3);
    auto out = retarget(p.sample.mesh, p.analysis, steps);
    REQUIRE(out.ok());
    // The outer faces of both side panels (area lying in the planes x = min and
    // x = max) are there as in the input: each panel's area grows by nothing,
    // since the shelf grew along x only.
    auto end_areas = [](const Mesh& m) {
      const BoundingBox b = bounding_box(m);
      double low = 0, high = 0;
      for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
        double xmin = 1e9, xmax = -1e9;
        for (int c = 0; c < 3; ++c)
          xmin = std::min(xmin, double(m.V(m.F(f, c), 0))), xmax = std::max(xmax, double(m.V(m.F(f, c), 0)));
        if (xmax < b.min.x() + 1e-4) low += 0.5 * double_area(m, f);
        if (xmin > b.max.x() - 1e-4) high += 0.5 * double_area(m, f);
      }
      return std::make_pair(low, high);
    };
    const auto [in_low, in_high] = end_areas(p.sample.mesh);
    const auto [out_low, out_high] = end_areas(out->mesh);
    CHECK(in_low > 0.1);  // a real panel, not a sliver (0.3 m deep, over 1 m tall)
    CHECK(out_low == Approx(in_low).epsilon(1e-4));
    CHECK(out_high == Approx(in_high).epsilon(1e-4));
  }
  {
    const Prepared& p = prepared("facade_sheared");
    const int axis = axis_of(p.analysis.lattice, p.sample.generators[1]);
    REQUIRE(axis >= 0);
    // The lattice itself is sheared: its axes are not orthogonal.
    const Eigen::Vector3d u =
        p.analysis.lattice.A.col(axis_of(p.analysis.lattice, p.sample.generators[0])).normalized();
    CHECK(std::abs(u.dot(p.analysis.lattice.A.col(axis).normalized())) > 0.05);
    Eigen::Array3i steps = Eigen::Array3i::Zero();
    steps[axis] = 2;
    auto out = retarget(p.sample.mesh, p.analysis, steps);
    REQUIRE(out.ok());
    // Two more floors move the top right by 2 * shear: the box grows along the shear too.
    const Eigen::Vector3d grow = bounding_box(out->mesh).size() - bounding_box(p.sample.mesh).size();
    const Eigen::Vector3d want = 2 * p.sample.generators[1].cwiseAbs();
    CHECK((grow - want).norm() < 1e-3 * want.norm());
  }
}

// Grown along both principal offsets at once, cells of one label form regions that are no box (an L of
// cells): a face clipped to the region's boxes is cut on the plane between two of them while the next face
// of the same copy keeps its edge across it, a T-junction with no seam vertex on its long edge (method.md 3).
TEST_CASE("retarget: the bookshelf grown or shrunk along both offsets at once opens no edge", "[retarget][samples]") {
  const Prepared& p = prepared("bookshelf");
  const int columns = axis_of(p.analysis.lattice, p.sample.generators[0]);
  const int shelves = axis_of(p.analysis.lattice, p.sample.generators[1]);
  REQUIRE(columns >= 0);
  REQUIRE(shelves >= 0);
  for (const auto& [dc, ds] : {std::pair{1, 1}, std::pair{-1, 1}, std::pair{1, -1}, std::pair{2, 2}}) {
    INFO(dc << " columns, " << ds << " shelves");
    Eigen::Array3i steps = Eigen::Array3i::Zero();
    steps[columns] = dc;
    steps[shelves] = ds;
    auto out = retarget(p.sample.mesh, p.analysis, steps);
    REQUIRE(out.ok());
    CHECK(out->report.boundary_edges_new() == 0);
    CHECK(out->report.warnings.empty());
    auto truth = families::generate("bookshelf", {{"columns", 4 + dc}, {"shelves", 4 + ds}});
    REQUIRE(truth.ok());
    const double open = test::open_boundary_length(truth->mesh);
    CHECK(test::open_boundary_length(out->mesh) <= open + 1e-6 * (1 + open));
  }
}

TEST_CASE("retarget: materials, groups and attribute values survive a resize", "[retarget][samples]") {
  const Prepared& p = prepared("bookshelf");
  Eigen::Array3i steps = steps_along(p, 0, 2);
  RetargetOptions options;
  options.face_labels = true;
  auto out = retarget(p.sample.mesh, p.analysis, steps, options);
  REQUIRE(out.ok());
  const Mesh& in = p.sample.mesh;
  const Mesh& m = out->mesh;
  REQUIRE(m.groups.size() == in.groups.size());
  CHECK(m.materials.size() == in.materials.size());
  for (std::size_t g = 0; g < in.groups.size(); ++g) CHECK(m.groups[g].attributes == in.groups[g].attributes);
  REQUIRE(m.UV.size() == in.UV.size());
  REQUIRE(out->face_labels.size() == m.triangle_count());
  // Every output vertex that maps back (by its face's shift) onto an input
  // vertex carries exactly the attributes of an input vertex at that spot.
  std::multimap<std::tuple<float, float, float>, Eigen::Index> at;
  for (Eigen::Index v = 0; v < in.V.rows(); ++v) at.emplace(std::make_tuple(in.V(v, 0), in.V(v, 1), in.V(v, 2)), v);
  int matched = 0, equal = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d shift = out->grid.shift(out->labels[std::size_t(out->face_labels[std::size_t(f)])]);
    for (int c = 0; c < 3; ++c) {
      const Eigen::Index v = m.F(f, c);
      const Eigen::Vector3d q = m.V.row(v).cast<double>().transpose() - shift;
      // nearest input vertex position within float noise
      for (auto it = at.lower_bound(std::make_tuple(float(q.x() - 1e-5), -1e30f, -1e30f));
           it != at.end() && std::get<0>(it->first) <= q.x() + 1e-5; ++it) {
        const Eigen::Index w = it->second;
        if ((in.V.row(w).cast<double>().transpose() - q).norm() > 1e-5) continue;
        ++matched;
        if ((in.UV[0].row(w) - m.UV[0].row(v)).norm() < 1e-6f && (in.N.row(w) - m.N.row(v)).norm() < 1e-6f) {
          ++equal;
          break;
        }
      }
    }
  }
  CHECK(matched > int(m.V.rows()) / 2);
  CHECK(equal > 0.95 * double(m.F.rows() * 3));
}

TEST_CASE("retarget: zero steps return the input unchanged", "[retarget]") {
  const Prepared& p = prepared("pin_header");
  auto out = retarget(p.sample.mesh, p.analysis, Eigen::Array3i::Zero());
  REQUIRE(out.ok());
  CHECK(out->mesh.V == p.sample.mesh.V);
  CHECK(out->mesh.F == p.sample.mesh.F);
  CHECK(out->report.labels == 1);
}

TEST_CASE("retarget: refused requests say why", "[retarget]") {
  const Prepared& p = prepared("pin_header");
  const Lattice& L = p.analysis.lattice;
  int real = -1, dummy = -1;
  for (int a = 0; a < 3; ++a) (L.dummy[a] ? dummy : real) = a;
  REQUIRE(real >= 0);
  REQUIRE(dummy >= 0);
  Eigen::Array3i steps = Eigen::Array3i::Zero();
  steps[dummy] = 1;
  auto r1 = retarget(p.sample.mesh, p.analysis, steps);
  REQUIRE_FALSE(r1.ok());
  CHECK_THAT(r1.status().message(), Catch::Contains("dummy"));
  steps = Eigen::Array3i::Zero();
  steps[real] = -L.cells[real];
  auto r2 = retarget(p.sample.mesh, p.analysis, steps);
  REQUIRE_FALSE(r2.ok());
  CHECK_THAT(r2.status().message(), Catch::Contains("cannot shrink"));
  RetargetOptions small;
  small.max_problem_size = 50;
  steps = Eigen::Array3i::Zero();
  steps[real] = 5;
  auto r3 = retarget(p.sample.mesh, p.analysis, steps, small);
  REQUIRE_FALSE(r3.ok());
  CHECK(r3.status().code() == StatusCode::too_large);
  CHECK_THAT(r3.status().message(), Catch::Contains("max_problem_size"));
}

TEST_CASE("retarget: repeated requests on one Retargeter are deterministic and reuse the cache", "[retarget]") {
  const Prepared& p = prepared("fence");
  Retargeter<> r(p.sample.mesh, p.analysis);
  Eigen::Array3i steps = steps_along(p, 0, 3);
  auto a = r.retarget(steps);
  steps = steps_along(p, 0, -2);
  auto b = r.retarget(steps);
  steps = steps_along(p, 0, 3);
  auto c = r.retarget(steps);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  REQUIRE(c.ok());
  CHECK(a->mesh.V == c->mesh.V);
  CHECK(a->mesh.F == c->mesh.F);
  CHECK(a->report.energy == c->report.energy);
  auto fresh = retarget(p.sample.mesh, p.analysis, steps);
  REQUIRE(fresh.ok());
  CHECK(fresh->mesh.V == a->mesh.V);
  auto glb1 = save_glb_to_memory(a->mesh), glb2 = save_glb_to_memory(fresh->mesh);
  CHECK(*glb1 == *glb2);
}

TEST_CASE("retarget: steps_for_size picks the nearest achievable size", "[retarget]") {
  const Prepared& p = prepared("pin_header");
  Retargeter<> r(p.sample.mesh, p.analysis);
  const int axis = axis_of(p.analysis.lattice, p.sample.generators[0]);
  REQUIRE(axis >= 0);
  const Eigen::Vector3d size = bounding_box(p.sample.mesh).size();
  const Eigen::Vector3d pitch = p.sample.generators[0];
  auto s = r.steps_for_size(size + 3.3 * pitch.cwiseAbs());
  REQUIRE(s.ok());
  CHECK((*s)[axis] == 3);
  auto shrink = r.steps_for_size(size - 1.8 * pitch.cwiseAbs());
  REQUIRE(shrink.ok());
  CHECK((*shrink)[axis] == -2);
}

TEST_CASE("retarget: the regular-grid baseline needs more labels for the same request", "[retarget]") {
  const Prepared& p = prepared("pin_header");
  Eigen::Array3i steps = steps_along(p, 0, 1);
  Retargeter<LatticeLabels> lattice(p.sample.mesh, p.analysis);
  Retargeter<RegularLabels> regular(p.sample.mesh, p.analysis);
  auto a = lattice.retarget(steps);
  auto b = regular.retarget(steps);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  CHECK(a->report.labels == 2);
  // One pitch of 2.54 mm is about 2 cells of 0.1 normalized units.
  const double cells = p.analysis.normalization.to_normalized_offset(p.sample.generators[0]).norm() / 0.1;
  CHECK(b->report.labels == int(std::lround(cells)) + 1);
  CHECK(b->report.labels > a->report.labels);
  // The baseline grows the model by the snapped length.
  const double grow = bounding_box(b->mesh).size()[0] - bounding_box(p.sample.mesh).size()[0];
  CHECK(grow == Approx(std::lround(cells) * regular.grid().A(0, 0)).epsilon(1e-3));
}

TEST_CASE("retarget: the solver's threads change nothing but the time; out of range refused", "[retarget][threads]") {
  // RetargetOptions::threads reaches AlphaExpansion::threads; the descriptor energy's terms are tables, so
  // the regular-grid baseline's large problems are solved with moves proposed side by side: the same
  // labels, energy, cycles and output bytes. The geometric energy fills its terms on first use and says
  // so (terms_thread_safe), so its moves stay on the calling thread.
  const Prepared& p = prepared("pin_header");
  const Eigen::Array3i steps = steps_along(p, 0, 2);
  RetargetOptions one, four;
  four.threads = 4;
  Retargeter<RegularLabels> a(p.sample.mesh, p.analysis, one), b(p.sample.mesh, p.analysis, four);
  auto problem = b.labelling_problem(steps);
  REQUIRE(problem.ok());
  CHECK(problem->terms_thread_safe());
  CHECK(problem->node_count() + problem->edge_count() >= AlphaExpansion<>().min_parallel_size);
  auto x = a.retarget(steps), y = b.retarget(steps);
  REQUIRE(x.ok());
  REQUIRE(y.ok());
  CHECK(x->cell_labels == y->cell_labels);
  CHECK(x->report.energy == y->report.energy);
  CHECK(x->report.cycles == y->report.cycles);
  CHECK(*save_glb_to_memory(x->mesh) == *save_glb_to_memory(y->mesh));
  RetargetOptions geometric = four;
  geometric.seam_energy = SeamEnergy::geometry;
  Retargeter<RegularLabels> g(p.sample.mesh, p.analysis, geometric);
  auto gp = g.labelling_problem(steps);
  REQUIRE(gp.ok());
  CHECK_FALSE(gp->terms_thread_safe());
  RetargetOptions bad;
  bad.threads = -1;
  Retargeter<> refused(p.sample.mesh, p.analysis, bad);
  CHECK(refused.status().code() == StatusCode::invalid_argument);
  CHECK_THAT(refused.status().message(), Catch::Contains("threads"));
}

TEST_CASE("seam energy: the labelling problem is metric for Hausdorff and the solver never ends above the start",
          "[retarget][energy]") {
  const Prepared& p = prepared("bookshelf");
  CellDescriptors cells(p.analysis, p.analysis.lattice, SetDistance::hausdorff);
  Eigen::Array3i k = Eigen::Array3i::Zero();
  const int axis = axis_of(p.analysis.lattice, p.sample.generators[0]);
  REQUIRE(axis >= 0);
  k[axis] = 2;
  SeamMrf mrf(cells, k, Neighbourhood::n26);
  CHECK(check_metric(mrf).ok);
  std::vector<int> labels = mrf.initial_labels();
  const double start = energy(mrf, labels);
  SolveReport report;
  REQUIRE(AlphaExpansion<>().solve(mrf, labels, report, {}).ok());
  CHECK(report.energy <= start);
  CHECK(report.energy == Approx(energy(mrf, labels)));
  // Every node copies a cell inside the input: no forbidden label is used.
  CHECK(report.energy < mrf.forbidden());
  // The 6-neighbourhood has fewer edges.
  SeamMrf six(cells, k, Neighbourhood::n6);
  CHECK(six.edge_count() < mrf.edge_count());
}

namespace {
// A solver that labels every cell with the last label (the whole shift k): for a grown model the low end
// then copies cells from outside the input (nothing), so its outer seam mismatches by a missing surface.
// The report's warnings, one "check: message" per line ("" when the result passed every check).
std::string said(const RetargetReport& r) {
  std::string s;
  for (const ResultWarning& w : r.warnings) s += w.check + ": " + w.message + "\n";
  return s;
}

struct LastLabelSolver {
  template <class P>
  Status solve(const P& problem, std::vector<int>& labels, SolveReport& report, const Progress&) const {
    labels.assign(std::size_t(problem.node_count()), problem.label_count() - 1);
    report.energy = 0;
    return {};
  }
};
}  // namespace

TEST_CASE("retarget: with either seam energy the sample families at 3, 4 and 5 repeats grown by 1 and 3, "
          "shrunk by 1 and down to one repeat equal the family generated at that count",
          "[retarget][samples][slow]") {
  CHECK(RetargetOptions().seam_energy == SeamEnergy::descriptor);  // the default (docs/cli.md, Seam energy)
  for (const families::SampleInfo& info : families::catalog()) {
    auto base = families::generate(info.name);
    REQUIRE(base.ok());
    if (!base->parts.empty()) continue;  // the structured ones: structure_test.cpp
    for (std::size_t g = 0; g < base->generators.size(); ++g)
      for (const int n : {3, 4, 5}) {
        INFO(info.name << " generator " << g << " at " << n << " repeats");
        auto s = families::generate(info.name, {{base->count_parameters[g], n}});
        REQUIRE(s.ok());
        auto a = analyze(s->mesh);
        REQUIRE(a.ok());
        // Every family finds its generator itself from 3 repeats on (the fence at 3 pickets since the drift
        // at 2t is also measured on the vertices, docs/method.md 1.5).
        const int axis = axis_of(a->lattice, s->generators[g]);
        REQUIRE(axis >= 0);
        for (const SeamEnergy energy : {SeamEnergy::descriptor, SeamEnergy::geometry}) {
          INFO(seam_energy_name(energy) << " energy");
          RetargetOptions options;
          options.seam_energy = energy;
          Retargeter<> r(s->mesh, *a, options);
          for (const int k : {1, 3, -1, 1 - n}) {
            INFO("steps " << k);
            Eigen::Array3i steps = Eigen::Array3i::Zero();
            steps[axis] = k;
            auto out = r.retarget(steps);
            REQUIRE(out.ok());
            auto truth = families::generate(info.name, {{s->count_parameters[g], s->counts[g] + k}});
            REQUIRE(truth.ok());
            check_same_model(out->mesh, truth->mesh, open_check_of(info.name));
            // An exact result has no seam over the tolerance. (The fence shrunk to one picket warned until
            // the seam measure left out the part of a face an end cap covers: its post tops take the other
            // end's label and get their post from the cap; docs/method.md 2.8.)
            CHECK(said(out->report) == "");
          }
        }
      }
  }
}

TEST_CASE("retarget: families at 2 repeats, along the generator promoted when it is only a pair candidate, equal "
          "the family generated at 1, 3, 4 and 5 repeats",
          "[retarget][samples][slow]") {
  // With two input cells every label change compares a source with a cell outside the input (empty), so
  // every labelling pays one such seam; what decides is that an interior copy of an end cell whose end
  // lies inside it pays too (SeamMrf::penalise_inner_ends). The fence's 2 pickets are not a candidate
  // along x: its pitch is typed, and stands because it maps vertices onto vertices (promote_offsets).
  struct Case {
    const char* family;
    const char* count;
    Eigen::Vector3d generator;
    std::vector<int> steps;
  };
  const Case cases[] = {
      {"bookshelf", "columns", {0.4, 0, 0}, {1, 2, 3, -1}},
      {"bookshelf", "shelves", {0, 0.35, 0}, {1, 2, 3, -1}},
      {"facade", "columns", {3, 0, 0}, {1, 2, 3, -1}},
      {"facade", "floors", {0, 3.2, 0}, {1, 2, 3, -1}},
      {"facade_sheared", "columns", {3, 0, 0}, {1, 2, 3, -1}},
      {"pin_header", "pins", {2.54, 0, 0}, {1, 2, 3, -1}},
      {"fence", "pickets", {0.15, 0, 0}, {1, 2, 3, -1}},
  };
  for (const Case& c : cases) {
    INFO(c.family << " " << c.count << " at 2");
    auto s = families::generate(c.family, {{c.count, 2}});
    REQUIRE(s.ok());
    auto a = analyze(s->mesh);
    REQUIRE(a.ok());
    int axis = axis_of(a->lattice, c.generator);
    if (axis < 0) {  // a pair: promoted, as `restitch resize --offsets` does
      REQUIRE(promote_offsets(s->mesh, AnalysisOptions<>{}, {c.generator}, *a).ok());
      axis = axis_of(a->lattice, c.generator);
    }
    REQUIRE(axis >= 0);
    Retargeter<> r(s->mesh, *a);
    for (const int k : c.steps) {
      INFO("steps " << k);
      Eigen::Array3i steps = Eigen::Array3i::Zero();
      steps[axis] = k;
      auto out = r.retarget(steps);
      REQUIRE(out.ok());
      auto truth = families::generate(c.family, {{c.count, 2 + k}});
      REQUIRE(truth.ok());
      check_same_model(out->mesh, truth->mesh, open_check_of(c.family));
      CHECK(said(out->report) == "");
    }
    // Shrunk to one cell with the geometric energy: both ends' caps meet in that cell; no seam may be
    // reported as a missing surface (empty_mismatch) on this exact result (it was 4840 model units once),
    // nor warned: the 2-pin header's seams between its two labels, measured over the whole face, compared
    // one pin's end segment with the other's middle (3.14 model units) where the caps put the same end.
    RetargetOptions geometric;
    geometric.seam_energy = SeamEnergy::geometry;
    Retargeter<> g(s->mesh, *a, geometric);
    Eigen::Array3i one = Eigen::Array3i::Zero();
    one[axis] = -1;
    auto out = g.retarget(one);
    REQUIRE(out.ok());
    auto truth = families::generate(c.family, {{c.count, 1}});
    REQUIRE(truth.ok());
    // No more open edges either: the geometric energy gave the 2-pin header shrunk to one pin one cell of
    // the other label (its low end from the cap), whose cap met its neighbours at T-junctions on the
    // body's ends (40 open edges where the 1-pin part has 16), until the anchored ends stopped counting
    // on an output one cell long (SeamMrf::build_unary: both ends are capped whatever the label).
    check_same_model(out->mesh, truth->mesh, open_check_of(c.family));
    CHECK(out->report.max_seam_mismatch < bounding_box(truth->mesh).size().norm());
    CHECK(said(out->report) == "");
  }
}

TEST_CASE("retarget: every seam is measured on the geometry and reported; one over the tolerance is a warning",
          "[retarget][samples]") {
  const Prepared& p = prepared("bookshelf");
  const Eigen::Array3i steps = steps_along(p, 0, 2);
  for (const SeamEnergy energy : {SeamEnergy::geometry, SeamEnergy::descriptor}) {
    INFO(seam_energy_name(energy));
    RetargetOptions options;
    options.seam_energy = energy;
    Retargeter<> r(p.sample.mesh, p.analysis, options);
    auto out = r.retarget(steps);
    REQUIRE(out.ok());
    const RetargetReport& rep = out->report;
    CHECK(rep.seam_energy == energy);
    // The spacing is the analysis' dense spacing (0.02 normalized) in model units, as a median nearest
    // distance of Poisson-disk samples: between the spacing and twice it.
    const double spacing = 0.02 / p.analysis.normalization.scale;
    CHECK(rep.sample_spacing >= spacing);
    CHECK(rep.sample_spacing < 2 * spacing);
    CHECK(rep.seam_tolerance == Approx(3 * rep.sample_spacing));
    // The seams are exactly the face neighbours with different labels (plus ends off their anchor).
    const CellGrid grid(rep.cells_out);
    std::size_t inner = 0;
    for (std::int64_t x = 0; x < grid.size(); ++x)
      for (int a = 0; a < 3; ++a) {
        Eigen::Array3i y = grid.cell(x);
        y[a] += 1;
        if (grid.inside(y) && out->cell_labels[std::size_t(x)] != out->cell_labels[std::size_t(grid.index(y))])
          ++inner;
      }
    std::size_t listed_inner = 0;
    double worst = 0;
    for (const SeamReport& s : rep.seams) {
      listed_inner += s.outer ? 0 : 1;
      CHECK((s.label_a != s.label_b).any());
      CHECK((s.cell_b - s.cell_a).abs().sum() == 1);
      CHECK(s.mismatch >= 0);
      worst = std::max(worst, s.mismatch);
    }
    CHECK(listed_inner == inner);
    CHECK(rep.seams.size() > 0);
    CHECK(rep.max_seam_mismatch == worst);
    CHECK(rep.max_seam_mismatch <= rep.seam_tolerance);  // the result is exact
    CHECK(rep.warnings.empty());
    CHECK(retarget_json(rep)["warnings"].empty());
    CHECK(retarget_json(rep)["seams"].size() == rep.seams.size());
  }
  // A tolerance below the sampling noise puts seams over it, but the seam estimate warns of nothing: the
  // result check looks at the result, which is exact.
  RetargetOptions tight;
  tight.seam_tolerance = 1e-9;
  auto out = retarget(p.sample.mesh, p.analysis, steps, tight);
  REQUIRE(out.ok());
  std::size_t over = 0;
  for (const SeamReport& s : out->report.seams) over += s.mismatch > 1e-9;
  CHECK(over > 0);
  CHECK(said(out->report) == "");
  // A labelling that leaves the low end empty: its outer seam misses the side panel, the largest mismatch,
  // and the check finds the output short of the size asked and its cut boards open.
  Retargeter<LatticeLabels, LastLabelSolver> bad(p.sample.mesh, p.analysis);
  auto b = bad.retarget(steps);
  REQUIRE(b.ok());
  CHECK(b->report.max_seam_mismatch == bad.slabs().empty_mismatch());
  std::set<std::string> checks;
  for (const ResultWarning& w : b->report.warnings) checks.insert(w.check);
  CHECK(checks.count("size") == 1);
  CHECK(checks.count("open seam") == 1);
}

namespace {
// A row of 6 posts (pitch 1, at k + 0.5) on a rail, with a plaque of width 0.4 centred on every integer
// x, each at its own height: nothing repeats across an integer plane, but the copies of the row one
// period apart continue each other between a plaque and a post (relative x 0.28 to 0.37 and 0.63 to
// 0.72, a sample spacing being about 0.06). `rise[k]`: plaque k's bottom above 1.1 (default 0.15 k).
Mesh plaque_row(const std::array<double, 7>& rise = {0, 0.15, 0.3, 0.45, 0.6, 0.75, 0.9}) {
  Mesh m;
  test::add_box(m, {-0.2, -0.1, 0}, {6.2, 0, 0.1});
  for (int k = 0; k < 6; ++k) test::add_box(m, {k + 0.45, 0.05, 0}, {k + 0.55, 1.0, 0.1});
  for (int k = 0; k <= 6; ++k) {
    const double h = rise[std::size_t(k)];
    test::add_box(m, {k - 0.2, 1.1 + h, 0}, {k + 0.2, 1.2 + h, 0.1});
  }
  return m;
}

// The row's analysis with its cell planes at the integers along axis a: every one crosses a plaque.
Analysis planes_on_plaques(Analysis an, int a) {
  an.lattice.origin[0] = 0;
  an.lattice.cells[a] = 6;
  an.lattice.end_low[a] = 0;
  an.lattice.end_high[a] = 1;
  return an;
}

// The row grown by `steps` along axis a with seams moved off the cell planes (first) and on them (second).
std::pair<RetargetResult, RetargetResult> moved_and_on_planes(const Mesh& m, const Analysis& an, int a, int steps) {
  Eigen::Array3i k = Eigen::Array3i::Zero();
  k[a] = steps;
  RetargetOptions on, off;
  off.move_seams = false;
  Retargeter<> r_on(m, an, on), r_off(m, an, off);
  Result<RetargetResult> x = r_on.retarget(k), y = r_off.retarget(k);
  REQUIRE(x.ok());
  REQUIRE(y.ok());
  return {std::move(*x), std::move(*y)};
}
}  // namespace

TEST_CASE("retarget: a seam moves off its cell plane to where the two copies continue each other, so no part is "
          "cut (docs/method.md 2.9)",
          "[retarget]") {
  const Mesh m = plaque_row();
  Result<Analysis> found = analyze(m);
  REQUIRE(found.ok());
  REQUIRE(found->principal.size() == 1);
  const int a = axis_of(found->lattice, Eigen::Vector3d::UnitX());
  REQUIRE(a >= 0);
  REQUIRE(std::abs(found->lattice.A.col(a).norm() - 1.0) < 1e-3);
  const auto is_rail = [](const test::Piece& p) { return p.lo.y() < -0.05; };
  const std::vector<test::Piece> pieces_in = test::welded_components(m);

  SECTION("with the analysis' own grid phase the seams already continue: moving changes nothing") {
    for (const int steps : {1, 2, -1}) {
      Eigen::Array3i k = Eigen::Array3i::Zero();
      k[a] = steps;
      RetargetOptions on, off;
      off.move_seams = false;
      Retargeter<> r_on(m, *found, on), r_off(m, *found, off);
      Result<RetargetResult> x = r_on.retarget(k), y = r_off.retarget(k);
      REQUIRE(x.ok());
      REQUIRE(y.ok());
      CHECK(x->report.seams_moved == 0);
      CHECK(x->mesh.V == y->mesh.V);
      CHECK(x->mesh.F == y->mesh.F);
      CHECK(test::unmatched_pieces(test::welded_components(x->mesh), pieces_in, 1e-3, is_rail) == 0);
    }
  }

  SECTION("with every cell plane on a plaque, the seams on cell planes cut plaques and the moved ones do not") {
    const Analysis an = planes_on_plaques(*found, a);
    // The candidates of the seam between the copy of input cell 2 and the copy one period on, in the
    // row of the plaque at x = 3 (known answer).
    CellSlabs slabs(an, an.lattice);
    Eigen::Array3i s = CellGrid(an.lattice.cells).cell_of(an.lattice.to_canonical({2.5, 1.6, 0.05}));
    Eigen::Array3i delta = Eigen::Array3i::Zero();
    s[a] = 2;
    delta[a] = 1;
    const CellSlabs::SeamPositions& p = slabs.seam_positions(s, a, delta, 16);
    REQUIRE(p.fail.size() == 15);
    for (int j = -7; j <= 7; ++j) {
      INFO("position " << j << "/16: fail " << p.fail[std::size_t(j + 7)] << ", cut " << p.cut[std::size_t(j + 7)]);
      CHECK(p.valid[std::size_t(j + 7)]);
      if (std::abs(j) <= 3) CHECK(p.fail[std::size_t(j + 7)] > 0);         // the plaques at 0 +- 0.2
      if (std::abs(j) >= 5) CHECK(p.fail[std::size_t(j + 7)] == 0);        // between a plaque and a post
      if (std::abs(j) <= 3) CHECK(p.cut[std::size_t(j + 7)] >= p.fail[std::size_t(j + 7)]);
    }
    for (const int steps : {1, 2}) {
      INFO("steps " << steps);
      const auto [moved, planes] = moved_and_on_planes(m, an, a, steps);
      const RetargetResult *x = &moved, *y = &planes;
      // On cell planes some plaque is cut (or spliced from two): the test means something.
      REQUIRE(test::unmatched_pieces(test::welded_components(y->mesh), pieces_in, 1e-3, is_rail) > 0);
      CHECK(y->report.seams_moved == 0);
      CHECK(x->report.seams_moved > 0);
      CHECK(test::unmatched_pieces(test::welded_components(x->mesh), pieces_in, 1e-3, is_rail) == 0);
      // The rail is one piece, one period longer per step; the row has 6 + steps posts.
      int rails = 0, posts = 0;
      for (const test::Piece& c : test::welded_components(x->mesh)) {
        if (is_rail(c)) {
          ++rails;
          CHECK(c.size().x() == Approx(6.4 + steps).margin(1e-3));
        }
        posts += std::abs(c.size().y() - 0.95) < 1e-3;
      }
      CHECK(rails == 1);
      CHECK(posts == 6 + steps);
      // Every moved seam lies off its cell plane and is measured there.
      for (const SeamReport& seam : x->report.seams)
        if (!seam.outer) {
          CHECK(seam.offset != 0);
          CHECK(seam.mismatch <= x->report.seam_tolerance);
        }
      CHECK(x->report.plane_offsets[std::size_t(a)].size() == std::size_t(x->report.cells_out[a] + 1));
    }
  }
}

// The same row with plaques that differ by less than the samples can tell apart and more than the stitcher
// closes: plaque k at height 1.1 + 0.01 {0, 2, 1, 4, 3, 5, 6}[k] (no two alike: two alike farther apart
// would repeat around the plaques between them, docs/method.md 2.10), so the copies of a plaque one or two
// periods apart lie 0.01 to 0.03 apart, under 1.5 sample spacings (about 0.09), over the zipper's gap (1e-3
// of the diagonal, 0.0065), wherever the labelling puts the seam. Judged on the
// samples, a cell plane across the plaques is continued and stays, and the seams open; judged on the
// surface (CellSlabs::set_surface, as the Retargeter does) it fails and moves between a plaque and a post,
// and every seam closes (the BlendSwap radiator's sections, 0.2 to 0.7 apart at s = 1.5, were this case).
TEST_CASE("retarget: a seam plane where the copies differ by more than the stitcher closes moves, however "
          "close the samples (docs/method.md 2.9)",
          "[retarget]") {
  const Mesh m = plaque_row({0, 0.02, 0.01, 0.04, 0.03, 0.05, 0.06});
  Result<Analysis> found = analyze(m);
  REQUIRE(found.ok());
  REQUIRE(found->principal.size() == 1);
  const int a = axis_of(found->lattice, Eigen::Vector3d::UnitX());
  REQUIRE(a >= 0);
  REQUIRE(std::abs(found->lattice.A.col(a).norm() - 1.0) < 1e-3);
  const Analysis an = planes_on_plaques(*found, a);
  const double gap = 1e-3 * bounding_box(m).size().norm();
  Eigen::Array3i s = CellGrid(an.lattice.cells).cell_of(an.lattice.to_canonical({2.5, 1.6, 0.05}));
  Eigen::Array3i delta = Eigen::Array3i::Zero();
  s[a] = 2;
  delta[a] = 1;
  CellSlabs samples(an, an.lattice), surface(an, an.lattice);
  surface.set_surface(m, gap);
  REQUIRE(0.01 > gap);
  REQUIRE(0.03 < 1.5 * samples.spacing());  // the samples alone take the copies for continued
  const CellSlabs::SeamPositions &by_samples = samples.seam_positions(s, a, delta, 16),
                                 &by_surface = surface.seam_positions(s, a, delta, 16);
  CHECK(by_samples.fail[7] == 0);  // the cell plane, j = 0
  CHECK(by_surface.fail[7] > 0);
  for (int j = -7; j <= 7; ++j) {
    INFO("position " << j << "/16: fail " << by_surface.fail[std::size_t(j + 7)]);
    CHECK(by_surface.cut[std::size_t(j + 7)] == by_samples.cut[std::size_t(j + 7)]);
    if (std::abs(j) <= 3) CHECK(by_surface.fail[std::size_t(j + 7)] > 0);   // the plaques at 0 +- 0.2
    if (std::abs(j) >= 5) CHECK(by_surface.fail[std::size_t(j + 7)] == 0);  // between a plaque and a post
  }
  for (const int steps : {1, 2}) {
    INFO("steps " << steps);
    const auto [moved, planes] = moved_and_on_planes(m, an, a, steps);
    const RetargetResult *x = &moved, *y = &planes;
    REQUIRE(y->report.boundary_edges_new() > 0);  // on the cell planes the plaques' seams are open
    CHECK(x->report.seams_moved > 0);
    CHECK(x->report.boundary_edges_new() == 0);
    CHECK(x->report.boundary_edges_out == 0);
    // No plaque repeats: said before the resize; and the plaque of the cell the resize copies, each one of a
    // kind, is then in the output twice, which the count of what occurs once says (method.md 2.11).
    for (const ResultWarning& w : x->report.warnings) {
      INFO(w.check << ": " << w.message);
      CHECK((w.check == "undecided axis" || w.check == "part count"));
    }
  }
}

TEST_CASE("retarget: a vertex no face uses, however far away, changes nothing (found by fuzz_pipeline)",
          "[retarget]") {
  // glTF allows unused positions anywhere. One at 3.7e19 made the snapping's hash-grid cell overflow a
  // 64-bit integer (undefined behaviour, UBSan) and the weld tolerance (8 ulps of the largest
  // coordinate) 3.5e13, which welds a whole model into a point. Tolerances and snapping now read only
  // the vertices the faces use.
  Mesh m = plaque_row();
  Mesh far = m;
  far.V.conservativeResize(far.V.rows() + 1, 3);
  far.V.row(far.V.rows() - 1) << 3.68946e19f, -1.8e-22f, 5.6e-45f;
  REQUIRE(validate(far).ok());
  CHECK(max_abs_coordinate(far) == max_abs_coordinate(m));
  CHECK(weld_tolerance_of(far) == weld_tolerance_of(m));
  Result<Analysis> a = analyze(m), b = analyze(far);
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  REQUIRE(a->principal.size() == b->principal.size());
  for (std::size_t i = 0; i < a->principal.size(); ++i) CHECK((a->principal[i] - b->principal[i]).norm() == 0);
  RetargetOptions o;
  Eigen::Array3i k = Eigen::Array3i::Zero();
  k[axis_of(a->lattice, Eigen::Vector3d::UnitX())] = 1;
  Result<RetargetResult> x = Retargeter<>(m, *a, o).retarget(k), y = Retargeter<>(far, *b, o).retarget(k);
  REQUIRE(x.ok());
  REQUIRE(y.ok());
  CHECK(x->mesh.V == y->mesh.V);
  CHECK(x->mesh.F == y->mesh.F);
  CHECK(x->report.boundary_edges_in == y->report.boundary_edges_in);
  CHECK(x->report.boundary_edges_out == y->report.boundary_edges_out);
}

TEST_CASE("lattice: the fence's end posts lie wholly in the end caps at every picket count; a pitch typed "
          "exactly stands",
          "[retarget][lattice][samples][slow]") {
  // Posts 0.1 wide and pickets 0.15 apart: no phase keeps both posts off the cell planes, so one end
  // joins its neighbour cell (lattice/fit.hpp, ends reaching across a plane) and its end plane lies past
  // the post. Every post vertex must lie beyond its end plane (in the cap), and no picket may straddle
  // an end plane (the cap may hold the first picket whole: both gaps beside it are periodic).
  for (const int n : {2, 3, 4, 5, 6, 7}) {
    INFO(n << " pickets");
    auto s = families::generate("fence", {{"pickets", n}});
    REQUIRE(s.ok());
    auto a = analyze(s->mesh);
    REQUIRE(a.ok());
    int axis = axis_of(a->lattice, s->generators[0]);
    if (axis < 0) {  // 2 pickets (no repeat at 2t): typed, as `--offsets 0.15,0,0`
      REQUIRE(n == 2);
      REQUIRE(promote_offsets(s->mesh, AnalysisOptions<>{}, {s->generators[0]}, *a).ok());
      axis = axis_of(a->lattice, s->generators[0]);
    }
    REQUIRE(axis >= 0);
    const Lattice& L = a->lattice;
    // The pitch is exact (snapped onto the vertices), also where it was typed: at 2 pickets ICP from 0.15
    // slides to 0.125 (rails and posts), where no vertex repeats.
    CHECK(std::abs(L.A.col(axis).norm() - 0.15) < 1e-6);
    const double post = 0.1, right = 0.1 + 0.15 * n;  // the posts' inner faces (generator: post_width 0.1)
    const double low_plane = L.end_low[axis], high_plane = double(L.cells[axis] - 1) + L.end_high[axis];
    const Eigen::Matrix3d Ainv = L.A.inverse();
    std::vector<double> lo(std::size_t(n), INFINITY), hi(std::size_t(n), -INFINITY);  // per picket
    for (Eigen::Index v = 0; v < s->mesh.V.rows(); ++v) {
      const Eigen::Vector3d p = s->mesh.V.row(v).cast<double>().transpose();
      const double c = (Ainv * (p - L.origin))[axis];
      if (p.x() < post - 1e-6) {
        CHECK(c < low_plane);
      } else if (p.x() > right + 1e-6) {
        CHECK(c >= high_plane);
      } else if (p.z() > 0 && p.x() > post + 1e-6 && p.x() < right - 1e-6) {  // a picket (rails: z < 0)
        const std::size_t i = std::size_t(std::floor((p.x() - post) / 0.15));
        lo[i] = std::min(lo[i], c), hi[i] = std::max(hi[i], c);
      }
    }
    for (int i = 0; i < n; ++i) {
      INFO("picket " << i);
      CHECK_FALSE((lo[std::size_t(i)] < low_plane && hi[std::size_t(i)] > low_plane));
      CHECK_FALSE((lo[std::size_t(i)] < high_plane && hi[std::size_t(i)] > high_plane));
    }
    CHECK(low_plane < high_plane);
  }
}

TEST_CASE("SeamMrf::separable_labels: the best straight-seam labelling (brute force on one axis), never worse "
          "than the first start on two, and the Retargeter keeps the better of its two solves",
          "[retarget][energy][samples]") {
  for (const char* name : {"pin_header", "bookshelf", "fence"}) {
    INFO(name);
    const Prepared& p = prepared(name);
    RetargetOptions options;
    for (const SeamEnergy energy : {SeamEnergy::descriptor, SeamEnergy::geometry}) {
      INFO(seam_energy_name(energy));
      options.seam_energy = energy;
      Retargeter<> r(p.sample.mesh, p.analysis, options);
      for (const int k : {2, -2}) {
        INFO("steps " << k);
        const Eigen::Array3i steps = steps_along(p, 0, k);
        auto problem = r.labelling_problem(steps);
        REQUIRE(problem.ok());
        const SeamMrf& P = *problem;
        const int a = steps[0] != 0 ? 0 : steps[1] != 0 ? 1 : 2;
        const int U = P.out_grid().dims[a], M = std::abs(k) + 1;
        // Every f: {0..U-1} -> {0..M-1}, label of cell x = the shift f(x_a) along a.
        double best = INFINITY;
        std::vector<int> f(std::size_t(U), 0), lab(std::size_t(P.node_count()));
        REQUIRE(std::pow(double(M), double(U)) < 1e6);
        for (;;) {
          for (int x = 0; x < P.node_count(); ++x) {
            Eigen::Array3i d = Eigen::Array3i::Zero();
            d[a] = (k < 0 ? -1 : 1) * f[std::size_t(P.out_grid().cell(x)[a])];
            lab[std::size_t(x)] = P.label_of(d);
          }
          best = std::min(best, restitch::energy(P, lab));
          int i = 0;
          while (i < U && ++f[std::size_t(i)] == M) f[std::size_t(i++)] = 0;
          if (i == U) break;
        }
        const std::vector<int> straight = P.separable_labels();
        CHECK(restitch::energy(P, straight) == Approx(best).epsilon(1e-12));
        // The Retargeter solves from the first start, and again from the straight one where that already
        // beats the first result; it keeps the lower energy.
        std::vector<int> first = P.initial_labels(), second = straight;
        SolveReport r1, r2;
        REQUIRE(AlphaExpansion<>{}.solve(P, first, r1).ok());
        REQUIRE(AlphaExpansion<>{}.solve(P, second, r2).ok());
        auto out = r.retarget(steps);
        REQUIRE(out.ok());
        const bool second_run = restitch::energy(P, straight) < r1.energy;
        CHECK(out->report.energy == (second_run ? std::min(r1.energy, r2.energy) : r1.energy));
        CHECK(out->report.energy <= std::min(r1.energy, restitch::energy(P, straight)));
      }
    }
  }
  // Two resized axes: coordinate descent from the initial labelling never ends above it.
  const Prepared& p = prepared("bookshelf");
  Retargeter<> r(p.sample.mesh, p.analysis);
  const Eigen::Array3i steps = steps_along(p, 0, 2) + steps_along(p, 1, -1);
  auto problem = r.labelling_problem(steps);
  REQUIRE(problem.ok());
  CHECK(restitch::energy(*problem, problem->separable_labels()) <= restitch::energy(*problem, problem->initial_labels()));
}

TEST_CASE("retarget: steps along the world axes and along the principal offsets reach the same lattice steps",
          "[retarget][samples]") {
  auto s = families::generate("bookshelf", {{"columns", 3}, {"shelves", 2}});
  REQUIRE(s.ok());
  auto a = analyze(s->mesh);
  REQUIRE(a.ok());
  REQUIRE(a->principal.size() == 2);
  // Which principal offset runs along x, by its direction; the helpers must agree with it.
  const int px = std::abs(a->principal[0].x()) > std::abs(a->principal[0].y()) ? 0 : 1;
  std::vector<int> along(2, 0);
  along[std::size_t(px)] = 2, along[std::size_t(1 - px)] = -1;  // +2 along x, -1 along y
  auto world = lattice_steps_from_world(*a, Eigen::Array3i(2, -1, 0));
  auto principal = lattice_steps_from_principal(*a, along);
  REQUIRE(world.ok());
  REQUIRE(principal.ok());
  CHECK((*world == *principal).all());
  for (int l = 0; l < 3; ++l)  // and each value sits on the lattice axis along that world axis
    if ((*world)[l] != 0) CHECK(world_axis_of(a->lattice.A.col(l)) == ((*world)[l] == 2 ? 0 : 1));
  auto z = lattice_steps_from_world(*a, Eigen::Array3i(0, 0, 1));
  REQUIRE_FALSE(z.ok());
  CHECK(z.status().code() == StatusCode::invalid_argument);
  CHECK_THAT(z.status().message(), Catch::Contains("along z"));
}
