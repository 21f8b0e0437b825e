// The result check (restitch/retarget/check.hpp, docs/method.md 2.11): known answers on small meshes, and
// measured as a detector on the generated families, exact results and results broken on purpose.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <string>

#include "restitch/families/families.hpp"
#include "restitch/restitch.hpp"
#include "support/mesh_builders.hpp"
#include "restitch/mesh_boundary.hpp"
#include "support/surface_distance.hpp"

using namespace restitch;

namespace {

Mesh two_triangles(const Eigen::Vector3f& o) {  // an open unit square in the z = o.z plane
  Mesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  m.V.rowwise() += o.transpose();
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 2, 3;
  m.FG = VectorXu::Zero(2);
  m.groups.resize(1);
  return m;
}

Mesh joined(const Mesh& a, const Mesh& b) {
  Mesh m = a;
  m.V.conservativeResize(a.V.rows() + b.V.rows(), 3);
  m.V.bottomRows(b.V.rows()) = b.V;
  m.F.conservativeResize(a.F.rows() + b.F.rows(), 3);
  m.F.bottomRows(b.F.rows()) = b.F.array() + std::uint32_t(a.V.rows());
  m.FG = VectorXu::Zero(m.F.rows());
  return m;
}

// Solves, then relabels every output cell x with `relabel(problem, x, label)`: a wrong labelling forced.
template <class Relabel>
struct RelabelSolver {
  Relabel relabel;
  template <class P>
  Status solve(const P& problem, std::vector<int>& labels, SolveReport& report, const Progress& progress) const {
    RESTITCH_TRY(AlphaExpansion<>().solve(problem, labels, report, progress));
    for (std::int64_t x = 0; x < problem.out_grid().size(); ++x)
      labels[std::size_t(x)] = relabel(problem, x, labels[std::size_t(x)]);
    return {};
  }
};

// Every output cell of the middle slab along `axis` gets the label farthest from its own.
struct FarthestInMiddle {
  int axis = 0;
  template <class P>
  int operator()(const P& problem, std::int64_t x, int label) const {
    if (problem.out_grid().cell(x)[axis] != problem.out_grid().dims[axis] / 2) return label;
    const int d = problem.labels()[std::size_t(label)][axis];
    int best = label;
    for (int l = 0; l < problem.label_count(); ++l)
      if (std::abs(problem.labels()[std::size_t(l)][axis] - d) > std::abs(problem.labels()[std::size_t(best)][axis] - d))
        best = l;
    return best;
  }
};
using WrongLabelSolver = RelabelSolver<FarthestInMiddle>;

// The nearer end along `axis`: the smallest shift in the low half of the output, the largest in the high
// half, whatever the energy: a grown model as two copies of the input end to end.
struct NearerEnd {
  int axis = 0;
  template <class P>
  int operator()(const P& problem, std::int64_t x, int) const {
    const bool low_half = 2 * problem.out_grid().cell(x)[axis] < problem.out_grid().dims[axis];
    int pick = 0;
    for (int l = 1; l < problem.label_count(); ++l) {
      const int d = problem.labels()[std::size_t(l)][axis], best = problem.labels()[std::size_t(pick)][axis];
      if (low_half ? d < best : d > best) pick = l;
    }
    return pick;
  }
};
using EndToEndSolver = RelabelSolver<NearerEnd>;

// The default stitcher on a grid whose planes lie `offset` of a cell further along `axis`: every seam off its
// plane.
struct MovedSeamStitcher {
  int axis = 0;
  double offset = 0.37;
  Status stitch(const Mesh& in, const Lattice& lattice, const Eigen::Array3i& out_cells,
                const std::vector<Eigen::Array3i>& shift, Mesh& out, StitchReport& report) const {
    Lattice moved = lattice;
    moved.origin += offset * lattice.A.col(axis);
    return ClipStitcher().stitch(in, moved, out_cells, shift, out, report);
  }
};

// Flagged by the result check (the planned warnings aside); `open_seams`: count open seams too.
bool flagged(const RetargetReport& r, bool open_seams = true) {
  for (const ResultWarning& w : r.warnings)
    if (!w.planned() && (open_seams || w.check != "open seam"))
      return true;
  return false;
}

// Whether report r holds warnings, all of check `check`.
bool only_check(const RetargetReport& r, const std::string& check) {
  return !r.warnings.empty() &&
         std::all_of(r.warnings.begin(), r.warnings.end(), [&](const ResultWarning& w) { return w.check == check; });
}

bool exact(const Mesh& out, const Mesh& truth) {
  const BoundingBox bt = bounding_box(truth), bo = bounding_box(out);
  const double size = bt.size().norm();
  return (bt.min - bo.min).norm() < 1e-4 * size && (bt.max - bo.max).norm() < 1e-4 * size &&
         test::symmetric_surface_distance(out, truth, 0.004 * size) < 1e-4 * size;
}

}  // namespace

TEST_CASE("check: open edges of the input and their copies are told from new ones", "[check]") {
  const Mesh sheet = two_triangles(Eigen::Vector3f::Zero());
  InputShape in(sheet, 1e-6);
  REQUIRE(in.edge_a.size() == 4);
  // A piece of an edge, moved back onto the sheet, lies on an open edge; a diagonal and a segment beside
  // the sheet do not.
  CHECK(in.on_open_edge(Eigen::Vector3d(0.2, 0, 0), Eigen::Vector3d(0.7, 0, 0)));
  CHECK(in.on_open_edge(Eigen::Vector3d(1, 0.1, 0), Eigen::Vector3d(1, 0.9, 0)));
  CHECK_FALSE(in.on_open_edge(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 0)));
  CHECK_FALSE(in.on_open_edge(Eigen::Vector3d(0.2, 0.01, 0), Eigen::Vector3d(0.7, 0.01, 0)));
  CHECK_FALSE(in.on_open_edge(Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(1.5, 0, 0)));  // runs past its end
}

TEST_CASE("check: pieces that touch are one group, a piece apart is its own", "[check]") {
  const Mesh a = two_triangles(Eigen::Vector3f::Zero());
  const Mesh touching = joined(a, two_triangles(Eigen::Vector3f(1, 0, 0)));  // shares the edge x = 1, not welded
  CHECK(detail::touching_groups(touching, 1e-6, 1e-3).size() == 1);
  const Mesh apart = joined(a, two_triangles(Eigen::Vector3f(1.5, 0, 0)));
  const std::vector<BoundingBox> g = detail::touching_groups(apart, 1e-6, 1e-3);
  REQUIRE(g.size() == 2);
  CHECK(g[0].size().isApprox(Eigen::Vector3d(1, 1, 0)));
  CHECK(g[1].min.isApprox(Eigen::Vector3d(1.5, 0, 0)));
}

// The detector, measured: every structured family at every count resized to every other count of its
// sweep, as solved and broken on purpose (the middle slab given the label farthest from its own; every seam
// moved 0.37 of a cell off its plane). Each result is compared in place with the family generated at the
// count asked (exact: boxes and surfaces within 1e-4 of the diagonal). Every result that is not exact is
// flagged, unless the report said beforehand that whole periods cannot do it (a centred part half a period
// off, an undecided axis), or a seam moved off its plane that the stitcher closed (below). A solved result
// that is exact is flagged by no check but "open seam", which flags exact results whose seams the stitcher
// leaves open (docs/results.md). The counts are printed (docs/method.md 2.11).
TEST_CASE("check: flags the broken results and none of the exact ones on the generated families",
          "[check][samples][slow]") {
  struct Sweep {
    std::string name;
    std::vector<int> counts;
    std::map<std::string, double> params;
  };
  std::map<std::string, std::array<int, 4>> tally;  // per variant: exact, exact flagged, broken, broken flagged
  for (const Sweep& s : {Sweep{"connector", {4, 5, 6, 8}, {}}, Sweep{"cabinet", {3, 4, 6}, {}},
                         Sweep{"radiator", {3, 5, 8}, {}}, Sweep{"box_header", {6, 8, 10}, {}},
                         Sweep{"shutter", {7, 9}, {}}, Sweep{"railing", {3, 5}, {}},
                         Sweep{"pin_header", {2, 4, 7}, {{"closed", 1}}}, Sweep{"fence", {4, 7}, {}}}) {
    const std::string count = families::generate(s.name)->count_parameters[0];
    for (const int n : s.counts) {
      std::map<std::string, double> params = s.params;
      params[count] = n;
      auto sample = families::generate(s.name, params);
      REQUIRE(sample.ok());
      auto a = analyze(sample->mesh);
      REQUIRE(a.ok());
      int axis = -1;
      for (int b = 0; b < 3; ++b)
        if (!a->lattice.dummy[b] &&
            std::abs(a->lattice.A.col(b).normalized().dot(sample->generators[0].normalized())) > std::cos(M_PI / 180))
          axis = b;
      REQUIRE(axis >= 0);
      Retargeter<> solved(sample->mesh, *a);
      Retargeter<LatticeLabels, WrongLabelSolver> wrong(sample->mesh, *a, {}, {}, WrongLabelSolver{FarthestInMiddle{axis}});
      Retargeter<LatticeLabels, AlphaExpansion<>, MovedSeamStitcher> moved(sample->mesh, *a, {}, {}, {},
                                                                           MovedSeamStitcher{axis});
      for (const int m : s.counts) {
        if (m == n) continue;
        INFO(s.name << " " << n << " to " << m);
        params[count] = m;
        auto truth = families::generate(s.name, params);
        REQUIRE(truth.ok());
        Eigen::Array3i steps = Eigen::Array3i::Zero();
        steps[axis] = m - n;
        auto judge = [&](const std::string& variant, const Result<RetargetResult>& out) {
          REQUIRE(out.ok());
          CHECK(out->report.checked);
          const RetargetReport& r = out->report;
          std::array<int, 4>& t = tally[variant];
          bool known = false;  // the report said whole periods cannot do it
          for (const ResultWarning& w : r.warnings)
            known = known || w.planned();
          std::string said;
          for (const ResultWarning& w : r.warnings) said += w.check + ": " + w.message + "; ";
          INFO(variant << ": " << said);
          if (exact(out->mesh, truth->mesh)) {
            ++t[0];
            t[1] += flagged(r);
            if (variant == "solved") CHECK_FALSE(flagged(r, false));
            CHECK((std::any_of(r.warnings.begin(), r.warnings.end(),
                               [](const ResultWarning& w) { return w.check == "open seam"; }) ==
                   (r.boundary_edges_new() > 0)));
          } else if (!known) {
            ++t[2];
            t[3] += flagged(r);
            // A seam moved off its plane where both copies' walls lie in that plane, tessellated differently,
            // is closed by the T-junction repair: a closed surface cut elsewhere than the report says, which
            // no check reads (the library's stitcher cuts where the report says). Counted, not required.
            if (variant == "moved seams" && r.boundary_edges_new() == 0) return;
            CHECK(flagged(r));
          }
        };
        judge("solved", solved.retarget(steps));
        judge("wrong label", wrong.retarget(steps));
        judge("moved seams", moved.retarget(steps));
      }
    }
  }
  for (const auto& [variant, t] : tally)
    std::printf("check %-12s exact %3d (flagged %d), not exact %3d (flagged %d)\n", variant.c_str(), t[0], t[1], t[2],
                t[3]);
}

// Two copies with nothing in common glued together close every edge, so only the seam measure sees them:
// the 2-section radiator grown by 2 as two 2-section radiators end to end (labels 0 0 2 2), their end plugs
// face to face. Solved, grown by 1 it is exact and passes.
TEST_CASE("check: copies glued end cap to end cap are an unmatched seam; an exact grow is not", "[check][samples]") {
  auto two = families::generate("radiator", {{"sections", 2}});
  REQUIRE(two.ok());
  auto a = analyze(two->mesh);
  REQUIRE(a.ok());
  auto steps = lattice_steps_from_world(*a, {2, 0, 0});
  REQUIRE(steps.ok());
  int axis = 0;
  while (axis < 2 && (*steps)[axis] == 0) ++axis;
  Retargeter<LatticeLabels, EndToEndSolver> glued(two->mesh, *a, {}, {}, EndToEndSolver{NearerEnd{axis}});
  Retargeter<> r(two->mesh, *a);
  auto out = glued.retarget(*steps);
  REQUIRE(out.ok());
  auto four = families::generate("radiator", {{"sections", 4}});
  REQUIRE(four.ok());
  CHECK_FALSE(exact(out->mesh, four->mesh));
  CHECK(out->report.boundary_edges_new() == 0);
  std::set<std::string> checks;
  for (const ResultWarning& w : out->report.warnings) checks.insert(w.check);
  // Each radiator holds the valve, which the input holds once: counted too (method.md 2.11, Content once).
  CHECK(checks == std::set<std::string>{"part count", "unmatched seam"});
  auto one = lattice_steps_from_world(*a, {1, 0, 0});
  REQUIRE(one.ok());
  auto three = r.retarget(*one);
  REQUIRE(three.ok());
  auto truth = families::generate("radiator", {{"sections", 3}});
  REQUIRE(truth.ok());
  CHECK(exact(three->mesh, truth->mesh));
  CHECK(three->report.warnings.empty());
}

// A package of 2 pins a side whose pin-1 dimple lies in one of its two modules has no repeat; with the pitch
// typed (promote_offsets, as --offsets) each of its two cells holds an end, and grown by 2 it comes out as two
// 2-pin packages end to end: closed, each a piece of the input moved by whole periods, no seam joining
// surface to none (the cell planes lie past the bodies' ends). The input is one piece over its whole box and
// the output is not: "side by side"; and the pin-1 dimple is in both: "part count". The 3-pin package grown by
// 2, one piece, passes.
TEST_CASE("check: copies of a whole one-piece model next to each other are side by side", "[check][samples]") {
  for (const int n : {2, 3}) {
    INFO(n << " pins a side");
    auto in = families::generate("dip", {{"pins", n}});
    REQUIRE(in.ok());
    auto a = analyze(in->mesh);
    REQUIRE(a.ok());
    REQUIRE(promote_offsets(in->mesh, AnalysisOptions<>{}, {Eigen::Vector3d(2.54, 0, 0)}, *a).ok());
    auto steps = lattice_steps_from_world(*a, {2, 0, 0});
    REQUIRE(steps.ok());
    Retargeter<> r(in->mesh, *a);
    auto out = r.retarget(*steps);
    REQUIRE(out.ok());
    auto truth = families::generate("dip", {{"pins", n + 2}});
    REQUIRE(truth.ok());
    std::set<std::string> checks;
    for (const ResultWarning& w : out->report.warnings) checks.insert(w.check);
    if (n == 2) {
      CHECK_FALSE(exact(out->mesh, truth->mesh));
      CHECK(boundary_edge_count(out->mesh) == 0);
      // Each package holds the dimple, which the input holds once: counted too (method.md 2.11, Content once).
      CHECK(checks == std::set<std::string>{"part count", "side by side"});
    } else {
      CHECK(exact(out->mesh, truth->mesh));
      CHECK(checks.empty());
    }
  }
}

// "size" for a request by size: the shutter of 3 slats (2 + rail + 1) has two slats with the rail (0.2) as
// its period (a run of one slat above the rail has no copy at the slat pitch), so a height of 0.6 (from 0.39)
// is no whole number of periods away: the nearest (0.59) is given and warned. A size that whole periods
// reach, the same size typed as printed, or the exact scale is not.
TEST_CASE("check: a size asked that whole periods do not reach is warned; one they reach is not", "[check][samples]") {
  const auto size_warnings = [](const RetargetReport& rep) {
    return std::count_if(rep.warnings.begin(), rep.warnings.end(), [](const ResultWarning& w) { return w.check == "size"; });
  };
  auto three = families::generate("shutter", {{"slats", 3}});
  REQUIRE(three.ok());
  auto a = analyze(three->mesh);
  REQUIRE(a.ok());
  REQUIRE(a->principal.size() == 1);
  const double period = a->principal_model_units()[0].y();
  REQUIRE(period == Approx(0.2).margin(1e-4));  // what makes 0.6 unreachable; if the period changes, so must this
  Retargeter<> r(three->mesh, *a);
  auto six = r.retarget_to_size(Eigen::Vector3d(0, 0.6, 0), false);
  REQUIRE(six.ok());
  CHECK(six->report.size_out.y() == Approx(0.59).margin(1e-4));
  CHECK(size_warnings(six->report) == 1);
  auto reach = r.retarget_to_size(Eigen::Vector3d(0, 0.59, 0), false);
  REQUIRE(reach.ok());
  CHECK(size_warnings(reach->report) == 0);
  // The size is right; what the period copies is not: the middle rail, which the input holds once, comes out
  // twice (2 + rail + 2 + rail + 1 slats), and the count of what occurs once says so, and nothing else does.
  CHECK(only_check(reach->report, "part count"));
  auto typed = r.retarget_to_size(Eigen::Vector3d(0, 0.5900004, 0), false);  // 0.59 as a viewer might show it
  REQUIRE(typed.ok());
  CHECK(size_warnings(typed->report) == 0);
  auto scaled = r.retarget_to_size(Eigen::Vector3d(0, 0.6, 0), true);
  REQUIRE(scaled.ok());
  CHECK(scaled->report.size_out.y() == Approx(0.6).margin(1e-6));
  CHECK(size_warnings(scaled->report) == 0);
  // Asked too little to change by one period: the input is given back, and that too misses the size.
  auto same = r.retarget_to_size(Eigen::Vector3d(0, 0.45, 0), false);
  REQUIRE(same.ok());
  CHECK(same->report.size_out.y() == Approx(0.39).margin(1e-6));
  CHECK(size_warnings(same->report) == 1);
  // An exact resize by size elsewhere: the pin header's 6-pin length from 3 pins.
  auto h3 = families::generate("pin_header", {{"pins", 3}}), h6 = families::generate("pin_header", {{"pins", 6}});
  REQUIRE(h3.ok());
  REQUIRE(h6.ok());
  auto ah = analyze(h3->mesh);
  REQUIRE(ah.ok());
  Retargeter<> rh(h3->mesh, *ah);
  auto grown = rh.retarget_to_size(Eigen::Vector3d(bounding_box(h6->mesh).size().x(), 0, 0), false);
  REQUIRE(grown.ok());
  CHECK(exact(grown->mesh, h6->mesh));
  CHECK(grown->report.warnings.empty());
}

namespace {
// Every edge of m (positions welded at `tol`) is run once each way by its two faces: closed and
// consistently oriented. Returns the edges that are not.
std::size_t badly_oriented_edges(const Mesh& m, double tol) {
  const std::vector<std::uint32_t> rep = weld_positions(m, tol);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> run;  // directed edge -> times run
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const std::uint32_t c[3] = {rep[m.F(f, 0)], rep[m.F(f, 1)], rep[m.F(f, 2)]};
    if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) continue;
    for (int k = 0; k < 3; ++k) ++run[{c[k], c[(k + 1) % 3]}];
  }
  std::size_t bad = 0;
  for (const auto& [e, n] : run) {
    const auto back = run.find({e.second, e.first});
    bad += n != 1 || back == run.end() || back->second != 1;
  }
  return bad;
}
}  // namespace

// The zipper (restitch/stitch/detail/zipper.hpp): a closed round rail whose copies differ slightly (every
// ring's radius by up to 5%, turned by up to half a side) opens every seam it is cut at, unless the two
// cut lines are joined by a strip. With the strip every resize is closed, consistently oriented, passes
// the check, and lies within the copies' differences of the exact rail at that count.
TEST_CASE("check: a closed rail whose copies differ slightly stays closed at every count, zipped",
          "[check][stitch][samples]") {
  // Rings jittered and turned: two cut lines apart all round. Pinched: every other vertex exact, so the
  // welded cut lines touch there and run as one chain out along one side and back along the other.
  for (const int n : {3, 5})  // at 2, two copies that differ are no repeat: no principal offset
  for (const double pinch : {0.0, 1.0}) {
    std::map<std::string, double> params = {{"jitter", 0.05}, {"twist", 0.5}, {"pinch", pinch}};
    params["modules"] = n;
    INFO("pinch " << pinch);
    auto sample = families::generate("tube_rail", params);
    REQUIRE(sample.ok());
    REQUIRE(boundary_edge_count(sample->mesh) == 0);
    auto a = analyze(sample->mesh);
    REQUIRE(a.ok());
    REQUIRE(a->principal.size() == 1);
    Retargeter<> zipped(sample->mesh, *a);
    ClipStitcher unzipped_stitcher;
    unzipped_stitcher.zip_seams = false;
    Retargeter<> unzipped(sample->mesh, *a, {}, {}, {}, unzipped_stitcher);
    for (const int m : {1, 2, 4, 6}) {
      if (m == n) continue;
      INFO(n << " to " << m);
      auto steps = lattice_steps_from_principal(*a, {m - n});
      REQUIRE(steps.ok());
      auto out = zipped.retarget(*steps);
      REQUIRE(out.ok());
      CHECK(out->report.boundary_edges_out == 0);
      CHECK(out->report.warnings.empty());
      const double tol = weld_tolerance_of(out->mesh);
      CHECK(badly_oriented_edges(out->mesh, tol) == 0);
      auto exact = families::generate("tube_rail", {{"modules", m}});
      REQUIRE(exact.ok());
      const double size = bounding_box(exact->mesh).size().norm();
      // Rings differ by up to 5% of the 0.02 radius plus the sagitta of half a side: 1.4 mm.
      CHECK(test::symmetric_surface_distance(out->mesh, exact->mesh, 0.004 * size) < 0.0014);
      auto open = unzipped.retarget(*steps);
      REQUIRE(open.ok());
      CHECK(open->report.boundary_edges_new() > 0);  // what the strips close
    }
  }
}
