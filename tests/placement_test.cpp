// Placement and exact sizes (restitch/placement.hpp, docs/method.md 2.7): the pivot stays put, growth goes
// away from it in whole periods; a pin header whose pin 1 sits at the origin, resized, is the real part.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <functional>
#include <map>
#include <utility>

#include "restitch/families/families.hpp"
#include "restitch/io/json_report.hpp"
#include "restitch/restitch.hpp"
#include "support/boundary_length.hpp"

using namespace restitch;
using restitch::test::surface_area;

namespace {

const double pitch = 2.54, end_length = 0.3;  // the pin header's defaults (families/generators.hpp)

// A rigid motion applied to a mesh: positions, normals and tangents (R is a rotation).
Mesh moved(Mesh m, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    const Eigen::Vector3d p = R * m.V.row(v).cast<double>().transpose() + t;
    m.V.row(v) = p.cast<float>().transpose();
  }
  for (Eigen::Index v = 0; v < m.N.rows(); ++v)
    m.N.row(v) = (R * m.N.row(v).cast<double>().transpose()).cast<float>().transpose();
  for (Eigen::Index v = 0; v < m.T.rows(); ++v)
    m.T.row(v).head<3>() = (R * m.T.row(v).head<3>().cast<double>().transpose()).cast<float>().transpose();
  return m;
}

Mesh pin_header(int pins) {
  auto s = families::generate("pin_header", {{"pins", pins}});
  REQUIRE(s.ok());
  return s->mesh;
}

// The largest distance from a vertex of `truth` to the nearest vertex of `out` (brute force).
double worst_vertex_distance(const Mesh& truth, const Mesh& out) {
  double worst = 0;
  for (Eigen::Index i = 0; i < truth.V.rows(); ++i) {
    const Eigen::Vector3d p = truth.V.row(i).cast<double>();
    double best = INFINITY;
    for (Eigen::Index j = 0; j < out.V.rows() && best > 0; ++j)
      best = std::min(best, (out.V.row(j).cast<double>().transpose() - p).squaredNorm());
    worst = std::max(worst, std::sqrt(best));
  }
  return worst;
}

// `out` coincides with `truth` as placed: equal boxes and every vertex of truth on a vertex of out.
void check_coincide(const Mesh& out, const Mesh& truth) {
  const BoundingBox bo = bounding_box(out), bt = bounding_box(truth);
  INFO("out box " << bo.min.transpose() << " .. " << bo.max.transpose());
  INFO("truth box " << bt.min.transpose() << " .. " << bt.max.transpose());
  CHECK((bo.min - bt.min).cwiseAbs().maxCoeff() < 1e-4);
  CHECK((bo.max - bt.max).cwiseAbs().maxCoeff() < 1e-4);
  CHECK(worst_vertex_distance(truth, out) < 1e-4);
}

// `m` with a closed box [lo, hi] of 12 triangles added to its first group (normals per face; every other
// channel the group has gets zeros): a key or a marker on one end of a part, or a whole body.
Mesh with_box(Mesh m, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  REQUIRE(!m.groups.empty());
  const AttributeSet& has = m.groups.front().attributes;
  const Eigen::Index v0 = m.V.rows(), f0 = m.F.rows();
  m.V.conservativeResize(v0 + 24, 3);
  m.F.conservativeResize(f0 + 12, 3);
  m.FG.conservativeResize(f0 + 12);
  if (has.normals) m.N.conservativeResize(v0 + 24, 3);
  if (has.tangents) m.T.conservativeResize(v0 + 24, 4), m.T.bottomRows(24).setZero();
  if (has.color_components > 0) m.C.conservativeResize(v0 + 24, 4), m.C.bottomRows(24).setZero();
  for (MatrixX2f& uv : m.UV) uv.conservativeResize(v0 + 24, 2), uv.bottomRows(24).setZero();
  Eigen::Index v = v0, f = f0;
  for (int axis = 0; axis < 3; ++axis)
    for (const int side : {0, 1}) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n[axis] = side ? 1 : -1;
      for (const auto& [a, b] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
        Eigen::Vector3d p;
        p[axis] = side ? hi[axis] : lo[axis], p[u] = a ? hi[u] : lo[u], p[w] = b ? hi[w] : lo[w];
        m.V.row(v) = p.cast<float>().transpose();
        if (m.N.rows() == m.V.rows()) m.N.row(v) = n.cast<float>().transpose();
        ++v;
      }
      const std::uint32_t c = std::uint32_t(v - 4);  // (u, w) corners counter-clockwise about +axis
      const std::array<std::uint32_t, 6> t = side ? std::array<std::uint32_t, 6>{c, c + 1, c + 2, c, c + 2, c + 3}
                                                  : std::array<std::uint32_t, 6>{c, c + 2, c + 1, c, c + 3, c + 2};
      for (int k = 0; k < 2; ++k, ++f) m.F.row(f) << t[std::size_t(3 * k)], t[std::size_t(3 * k + 1)], t[std::size_t(3 * k + 2)];
    }
  m.FG.tail(12).setZero();
  return m;
}

// A dual in-line package as CAD exports it: the body one box of 12 triangles over every pin, `n` pins a side
// (boxes below the body at z = +-3.81), a key on the body's pin-1 end and a pin-1 marker on its top above pin
// 1. Pin 1 at the origin, pins along +x at the header's pitch; `centred`: the origin at the centre of the
// row of pins instead (a chip package's convention).
Mesh dip_package(int n, bool centred, double marker_x = -0.4) {
  Mesh m;
  m.materials = {Material{}};
  m.groups = {Group{0, AttributeSet{true, false, 0, 0}, "package"}};
  const double wall = 0.9, length = (n - 1) * pitch;
  m = with_box(m, Eigen::Vector3d(-wall, 0.5, -3.2), Eigen::Vector3d(length + wall, 3.8, 3.2));
  m = with_box(m, Eigen::Vector3d(-wall - 0.3, 2.0, -0.8), Eigen::Vector3d(-wall, 3.4, 0.8));
  m = with_box(m, Eigen::Vector3d(marker_x, 3.8, 2.0), Eigen::Vector3d(marker_x + 0.8, 3.9, 2.8));
  for (int i = 0; i < n; ++i)
    for (const double z : {-3.81, 3.81})
      m = with_box(m, Eigen::Vector3d(i * pitch - 0.25, -3.0, z - 0.3), Eigen::Vector3d(i * pitch + 0.25, 0.5, z + 0.3));
  return centred ? moved(m, Eigen::Matrix3d::Identity(), Eigen::Vector3d(-length / 2, 0, 0)) : m;
}

// The one non-dummy lattice axis, with steps k along it.
Eigen::Array3i steps_of(const Analysis& a, int k) {
  Eigen::Array3i s = Eigen::Array3i::Zero();
  for (int i = 0; i < 3; ++i)
    if (!a.lattice.dummy[i]) s[i] = k;
  return s;
}

// Resizes the n-pin part of `place` by k and checks it against the (n + k)-pin part placed by `truth_place`.
void check_resize(const std::function<Mesh(int)>& place, int n, int k, const std::function<Mesh(int)>& truth_place,
                  const Pivots& pivots = {{Pivot::origin, Pivot::origin, Pivot::origin}},
                  const Eigen::Vector3d& want_translation = Eigen::Vector3d::Constant(NAN)) {
  const Mesh in = place(n);
  auto a = analyze(in);
  REQUIRE(a.ok());
  REQUIRE(a->principal.size() == 1);
  RetargetOptions options;
  options.pivot = pivots;
  Retargeter<> r(in, *a, options);
  REQUIRE(r.status().ok());
  for (const int step : {k, -1}) {
    INFO("pins " << n << " steps " << step);
    auto out = r.retarget(steps_of(*a, step));
    REQUIRE(out.ok());
    check_coincide(out->mesh, truth_place(n + step));
    if (step == k && std::isfinite(want_translation.x()))
      CHECK((out->report.placement.translation - want_translation).norm() < 1e-5);
  }
}

}  // namespace

TEST_CASE("placement: parse_pivots takes one mode or three", "[placement]") {
  auto one = parse_pivots("max");
  REQUIRE(one.ok());
  CHECK((*one == Pivots{{Pivot::max, Pivot::max, Pivot::max}}));
  auto three = parse_pivots("min,origin,center");
  REQUIRE(three.ok());
  CHECK((*three == Pivots{{Pivot::min, Pivot::origin, Pivot::center}}));
  CHECK_FALSE(parse_pivots("min,max").ok());
  CHECK_FALSE(parse_pivots("min,max,min,max").ok());
  auto bad = parse_pivots("min,middle,max");
  REQUIRE_FALSE(bad.ok());
  CHECK_THAT(bad.status().message(), Catch::Contains("middle") && Catch::Contains("for y"));
}

TEST_CASE("placement: place() keeps the pivot's end, splits evenly with the odd cell at the max side",
          "[placement]") {
  Lattice L;  // 5 cells of 2 along x from 0; y and z dummies
  L.A = Eigen::Vector3d(2, 1, 1).asDiagonal();
  L.cells = Eigen::Array3i(5, 1, 1);
  L.dummy = {{false, true, true}};
  BoundingBox box;
  box.extend(Eigen::Vector3d(0, -1, -1)), box.extend(Eigen::Vector3d(10, 1, 1));
  auto low = [&](Pivot p, int k, const Lattice& lat = {}) {
    const Lattice& use = lat.cells.prod() > 1 ? lat : L;
    return place(use, box, Eigen::Array3i(k, 0, 0), {{p, Pivot::origin, Pivot::origin}}).low_cells[0];
  };
  CHECK(low(Pivot::min, 3) == 0);
  CHECK(low(Pivot::max, 3) == 3);
  CHECK(low(Pivot::center, 3) == 1);   // 1 cell at the min end, 2 at the max end
  CHECK(low(Pivot::center, -3) == -1); // 1 removed at the min end, 2 at the max end
  CHECK(low(Pivot::center, 4) == 2);
  CHECK(low(Pivot::max, -2) == -2);
  // The origin at x = 0 lies in the first cell: that end stays.
  CHECK(low(Pivot::origin, 3) == 0);
  const Placement p = place(L, box, Eigen::Array3i(3, 0, 0), {{Pivot::max, Pivot::min, Pivot::center}});
  CHECK((p.translation - Eigen::Vector3d(-6, 0, 0)).norm() == 0);
  CHECK((p.pivot - Eigen::Vector3d(10, -1, 0)).norm() == 0);
  // The origin in a middle cell (x in [4, 6)) splits; in the last cell keeps the max end.
  Lattice mid = L;
  mid.origin = Eigen::Vector3d(-5, 0, 0);
  CHECK(low(Pivot::origin, 3, mid) == 1);
  Lattice last = L;
  last.origin = Eigen::Vector3d(-9, 0, 0);
  CHECK(low(Pivot::origin, 3, last) == 3);
  // A lattice axis pointing to -x: its low end is the max end.
  Lattice flipped = L;
  flipped.A(0, 0) = -2;
  flipped.origin = Eigen::Vector3d(10, 0, 0);
  CHECK(low(Pivot::min, 3, flipped) == 3);
  CHECK(low(Pivot::max, 3, flipped) == 0);
  CHECK(low(Pivot::center, 3, flipped) == 2);  // 2 cells at the low (max) end: still the odd one at max
  CHECK(low(Pivot::origin, 3, flipped) == 3);  // the origin is in the last cell, at the min end
  // Dummy axes and zero steps never move.
  CHECK(place(L, box, Eigen::Array3i(0, 0, 0), {{Pivot::max, Pivot::max, Pivot::max}}).translation.isZero());
}

TEST_CASE("placement: pin 1 at the origin, pins toward -y or -x: resized, it is the real part, untranslated",
          "[placement][samples]") {
  // Pin 1's axis runs through the origin (x = end_length + pitch / 2 of the generated part, z = 0), at the
  // body's underside (y = 0); the pins run toward negative coordinates.
  const double pin1 = end_length + pitch / 2;
  Eigen::Matrix3d to_minus_y;  // (x, y, z) -> (y, -x, z): the row of pins runs along -y
  to_minus_y << 0, 1, 0, -1, 0, 0, 0, 0, 1;
  Eigen::Matrix3d to_minus_x;  // (x, y, z) -> (-x, y, -z): a half turn about y
  to_minus_x << -1, 0, 0, 0, 1, 0, 0, 0, -1;
  const auto along_minus_y = [&](int n) { return moved(pin_header(n), to_minus_y, Eigen::Vector3d(0, pin1, 0)); };
  const auto along_minus_x = [&](int n) { return moved(pin_header(n), to_minus_x, Eigen::Vector3d(pin1, 0, 0)); };
  {
    INFO("along -y");
    const Mesh six = along_minus_y(6);
    // Pin 1 is at the origin and the part lies at y <= 0.
    CHECK(bounding_box(six).max.y() == Approx(pin1).margin(1e-5));
    check_resize(along_minus_y, 6, 3, along_minus_y, {{Pivot::origin, Pivot::origin, Pivot::origin}},
                 Eigen::Vector3d(0, -3 * pitch, 0));
  }
  {
    INFO("along -x");
    check_resize(along_minus_x, 6, 2, along_minus_x);
  }
  {
    INFO("along -y, --pivot min keeps the far end instead");
    const auto truth = [&](int n) {  // the far end (y = min) stays: the part moves up by the pins added
      const Mesh m = along_minus_y(n);
      return moved(m, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, (n - 6) * pitch, 0));
    };
    check_resize(along_minus_y, 6, 3, truth, {{Pivot::origin, Pivot::min, Pivot::origin}},
                 Eigen::Vector3d::Zero());
  }
}

TEST_CASE("placement: an origin in the middle grows both ways, split evenly", "[placement][samples]") {
  // 8 pins with the origin on the axis of pin 4 (index 3, an interior cell).
  const auto centred_on = [&](int n, int index) {
    return moved(pin_header(n), Eigen::Matrix3d::Identity(), Eigen::Vector3d(-(end_length + (index + 0.5) * pitch), 0, 0));
  };
  const Mesh in = centred_on(8, 3);
  auto a = analyze(in);
  REQUIRE(a.ok());
  Retargeter<> r(in, *a);
  // +2: one pin at each end; the pin at the origin is now index 4.
  auto grow2 = r.retarget(steps_of(*a, 2));
  REQUIRE(grow2.ok());
  check_coincide(grow2->mesh, centred_on(10, 4));
  CHECK((grow2->report.placement.low_cells == Eigen::Array3i(1, 0, 0)).all());
  CHECK(grow2->report.placement.translation.x() == Approx(-pitch));
  // +3: odd, the extra pin goes to the max end: 1 at the min end, 2 at the max end.
  auto grow3 = r.retarget(steps_of(*a, 3));
  REQUIRE(grow3.ok());
  check_coincide(grow3->mesh, centred_on(11, 4));
  // -2: one pin off each end; the pin at the origin is now index 2.
  auto shrink2 = r.retarget(steps_of(*a, -2));
  REQUIRE(shrink2.ok());
  check_coincide(shrink2->mesh, centred_on(6, 2));
  // -3: 1 off the min end, 2 off the max end.
  auto shrink3 = r.retarget(steps_of(*a, -3));
  REQUIRE(shrink3.ok());
  check_coincide(shrink3->mesh, centred_on(5, 2));
}

TEST_CASE("placement: a part built about its centre stays centred, also at an odd change, whatever key or marker "
          "sits at one end", "[placement][samples]") {
  // A pin header of n pins with its origin at the centre of the row of pins (a chip package's or an SMD
  // connector's convention) and a key on its low end face 0.6 long: the box's centre lies 0.3 (0.12 of a
  // pitch) off the origin, more than a sample spacing, less than a quarter of a pitch. Resized, it is the
  // part of n + k pins with its key, centred the same way: one pin at each end for k = 2, half a pin at each
  // for k = 1. At 2 pins the origin lies in the last module that repeats, where an origin half a pitch off
  // the centre (pin 1) keeps its end; this one is at the centre.
  const double key = 0.6;
  const auto centred = [&](int n) {
    const Mesh m = with_box(pin_header(n), Eigen::Vector3d(-key, 0.5, -0.6), Eigen::Vector3d(0, 2.0, 0.6));
    return moved(m, Eigen::Matrix3d::Identity(), Eigen::Vector3d(-(end_length + n * pitch / 2), 0, 0));
  };
  for (const int n : {2, 3, 4, 5}) {
    const Mesh in = centred(n);
    auto a = analyze(in);
    REQUIRE(a.ok());
    REQUIRE(a->principal.size() == 1);
    Retargeter<> r(in, *a);
    for (const int k : {2, 1, 3, -1}) {
      if (n + k < 2) continue;
      INFO(n << " pins, steps " << k);
      auto out = r.retarget(steps_of(*a, k));
      REQUIRE(out.ok());
      check_coincide(out->mesh, centred(n + k));
      CHECK(out->report.placement.translation.x() == Approx(-0.5 * k * pitch).margin(1e-9));
    }
  }
}

TEST_CASE("placement: a package whose body is one box over every pin, pin 1 or its centre at the origin, is "
          "the package of the other size in place, closed", "[placement][samples]") {
  // The body's 12 triangles cross every cell plane, so every copy of it is clipped (restitch/stitch); the
  // key and the pin-1 marker occur once; the pins below touch the body. From 3 to 6 pins a side, to every
  // other count of 2 to 7. The marker 0.1 high over pin 1, or from 0.5 past it into the gap after it, past
  // the gap's middle, where a cell plane may cut it (its few samples do not weigh in the grid phase); then a
  // shrink to 2 pins a side may be refused or warned (the cells holding the marker and the end cell do not
  // fit in two), never silently wrong.
  for (const double marker_x : {-0.4, 0.5})
  for (const bool centred : {false, true})
    for (int n = 3; n <= 6; ++n) {
      const Mesh in = dip_package(n, centred, marker_x);
      REQUIRE(boundary_edge_count(in) == 0);
      auto a = analyze(in);
      REQUIRE(a.ok());
      REQUIRE(a->principal.size() == 1);
      Retargeter<> r(in, *a);
      for (int m = 2; m <= 7; ++m) {
        if (m == n) continue;
        INFO((centred ? "centred, " : "pin 1 at the origin, ") << n << " pins a side to " << m << ", marker from "
                                                                  << marker_x);
        auto out = r.retarget(steps_of(*a, m - n));
        if (marker_x > 0 && m == 2) {  // 2 pins a side: the marker's cells and the end may not fit in two cells
          if (!out.ok()) {  // refused, saying how far it can shrink
            CHECK(out.status().code() == StatusCode::invalid_argument);
            continue;
          }
          if (!out->report.warnings.empty()) continue;  // or warned; never silently wrong
        }
        REQUIRE(out.ok());
        const Mesh truth = dip_package(m, centred, marker_x);
        check_coincide(out->mesh, truth);
        CHECK(surface_area(out->mesh) == Approx(surface_area(truth)).epsilon(1e-5));  // nothing more: no piece of a marker
        CHECK(boundary_edge_count(out->mesh) == 0);
        CHECK(out->report.warnings.empty());
      }
    }
}

TEST_CASE("placement: min, center and max on the plain pin header", "[placement][samples]") {
  const auto plain = [](int n) { return pin_header(n); };
  const auto shifted = [](double dx) {
    return [dx](int n) { return moved(pin_header(n), Eigen::Matrix3d::Identity(), Eigen::Vector3d(dx, 0, 0)); };
  };
  const Mesh in = plain(8);
  auto a = analyze(in);
  REQUIRE(a.ok());
  const Pivot o = Pivot::origin;
  for (const int k : {3, -3, 2}) {
    INFO("steps " << k);
    {
      INFO("min");
      Retargeter<> r(in, *a, {});
      r.set_pivot({{Pivot::min, o, o}});
      auto out = r.retarget(steps_of(*a, k));
      REQUIRE(out.ok());
      check_coincide(out->mesh, plain(8 + k));
      CHECK(out->report.placement.translation.isZero());
    }
    {
      INFO("max");
      RetargetOptions opt;
      opt.pivot = {{Pivot::max, o, o}};
      Retargeter<> r(in, *a, opt);
      auto out = r.retarget(steps_of(*a, k));
      REQUIRE(out.ok());
      check_coincide(out->mesh, shifted(-k * pitch)(8 + k));
      CHECK(bounding_box(out->mesh).max.x() == Approx(bounding_box(in).max.x()).margin(1e-5));
    }
    {
      INFO("center");
      RetargetOptions opt;
      opt.pivot = {{Pivot::center, o, o}};
      Retargeter<> r(in, *a, opt);
      auto out = r.retarget(steps_of(*a, k));
      REQUIRE(out.ok());
      // The centre stays: k / 2 pins at each end, half a pin more at an odd k (the cells split with the odd
      // one at the max end, then the whole moved half a pitch back).
      check_coincide(out->mesh, shifted(-0.5 * k * pitch)(8 + k));
      CHECK(out->report.placement.low_cells.x() == k / 2);  // k / 2 truncates: the odd cell at max
      CHECK(out->report.placement.pivot.x() == Approx(bounding_box(in).center().x()));
      CHECK(bounding_box(out->mesh).center().x() == Approx(bounding_box(in).center().x()).margin(1e-5));
    }
  }
  // The label grid reported is the output's: the translation moved it too.
  RetargetOptions opt;
  opt.pivot = {{Pivot::max, o, o}};
  Retargeter<> r(in, *a, opt);
  auto out = r.retarget(steps_of(*a, 2));
  REQUIRE(out.ok());
  CHECK((out->grid.origin - (a->lattice.origin + out->report.placement.translation)).norm() < 1e-12);
}

TEST_CASE("exact sizes: sizes are checked, 0 keeps an axis, and --exact scales about the pivot",
          "[placement][exact]") {
  const Mesh in = pin_header(8);
  auto a = analyze(in);
  REQUIRE(a.ok());
  Retargeter<> r(in, *a);
  const Eigen::Vector3d size = bounding_box(in).size();
  // Negative and non-finite sizes are refused, naming the axis.
  auto neg = r.steps_for_size(Eigen::Vector3d(30, -1, 0));
  REQUIRE_FALSE(neg.ok());
  CHECK(neg.status().code() == StatusCode::invalid_argument);
  CHECK_THAT(neg.status().message(), Catch::Contains("along y"));
  CHECK_FALSE(r.steps_for_size(Eigen::Vector3d(NAN, 0, 0)).ok());
  // A change along y, where no repeat runs, is an error naming y, not a silent copy.
  auto no_repeat = r.retarget_to_size(Eigen::Vector3d(0, size.y() * 2, 0), true);
  REQUIRE_FALSE(no_repeat.ok());
  CHECK(no_repeat.status().code() == StatusCode::invalid_argument);
  CHECK_THAT(no_repeat.status().message(), Catch::Contains("no repeat runs along y"));
  // 0 keeps an axis; the current size (or one typed from it) is no change.
  auto keep = r.steps_for_size(Eigen::Vector3d(0, 0, 0));
  REQUIRE(keep.ok());
  CHECK((*keep == 0).all());
  auto same = r.steps_for_size(Eigen::Vector3d(size.x() * (1 + 2e-6), size.y(), 0));
  REQUIRE(same.ok());
  CHECK((*same == 0).all());
  // A size typed as a viewer shows it, rounded to 3 to 6 significant digits, is no change along an axis
  // without a repeat; one off in the last place typed is a change, refused as above (to 5 digits: at 6 one in
  // the last place is within the 1e-5 that is always no change).
  const auto rounded = [](double x, int digits, int off) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.*e", digits - 1, x);  // d.ddd...e+XX: digits significant digits
    const int exponent = int(std::floor(std::log10(std::abs(std::strtod(buf, nullptr)))));
    return std::strtod(buf, nullptr) + off * std::pow(10.0, exponent - (digits - 1));
  };
  for (const int digits : {3, 4, 5, 6}) {
    INFO(digits << " digits: " << rounded(size.y(), digits, 0) << " for " << size.y());
    CHECK(r.steps_for_size(Eigen::Vector3d(0, rounded(size.y(), digits, 0), rounded(size.z(), digits, 0))).ok());
    if (digits > 5) continue;
    CHECK_FALSE(r.steps_for_size(Eigen::Vector3d(0, rounded(size.y(), digits, 1), 0)).ok());
    CHECK_FALSE(r.steps_for_size(Eigen::Vector3d(0, 0, rounded(size.z(), digits, -1))).ok());
  }
  // Under 3 significant digits a typed number is no measurement: the nearest whole number is refused.
  CHECK_FALSE(r.steps_for_size(Eigen::Vector3d(0, 0, std::round(size.z()) + (std::round(size.z()) == size.z()))).ok());
  // Nearest: 30 mm is between 11 pins (28.54) and 12 (31.08): 12 pins, unscaled.
  auto nearest = r.retarget_to_size(Eigen::Vector3d(30, 0, 0), false);
  REQUIRE(nearest.ok());
  CHECK(nearest->report.size_out.x() == Approx(size.x() + 4 * pitch).epsilon(1e-6));
  CHECK_FALSE(nearest->report.exact);
  CHECK(nearest->report.scale == Eigen::Vector3d::Ones());
  // Exact: the nearest result scaled along x about the pivot (here the origin, the min end).
  for (const double want : {30.0, 26.0, 33.3}) {
    INFO("size " << want);
    auto exact = r.retarget_to_size(Eigen::Vector3d(want, 0, 0), true);
    REQUIRE(exact.ok());
    const RetargetReport& rep = exact->report;
    const BoundingBox box = bounding_box(exact->mesh);
    CHECK(std::abs(box.size().x() - want) < 1e-6 * want);
    CHECK(box.size().y() == Approx(size.y()).epsilon(1e-9));
    CHECK(box.min.x() == Approx(0).margin(1e-6));  // the pivot (origin at the min end) stays
    CHECK(rep.exact);
    CHECK(rep.scale.x() == Approx(want / rep.size_nearest.x()).epsilon(1e-12));
    CHECK(rep.scale.y() == 1);
    CHECK(std::abs(rep.scale.x() - 1) <= 0.5 * pitch / rep.size_nearest.x() + 1e-12);  // at most half a pin
    CHECK(validate(exact->mesh).ok());
    // Normals stay unit length.
    for (Eigen::Index v = 0; v < exact->mesh.N.rows(); ++v) REQUIRE(exact->mesh.N.row(v).norm() == Approx(1).epsilon(1e-5));
    const nlohmann::json j = retarget_json(rep);
    CHECK(j["exact"]["applied"] == true);
    CHECK(j["exact"]["scale"][0].get<double>() == Approx(rep.scale.x()));
    CHECK(j["pivot"]["modes"][0] == "origin");
    CHECK(j["pivot"]["translation"].size() == 3);
  }
  // About the centre: the centre of the box stays where the pivot is, for an even number of pins added.
  r.set_pivot({{Pivot::center, Pivot::origin, Pivot::origin}});
  auto centred = r.retarget_to_size(Eigen::Vector3d(26.2, 0, 0), true);  // nearest: +2 pins (26.0)
  REQUIRE(centred.ok());
  const BoundingBox cb = bounding_box(centred->mesh);
  CHECK(std::abs(cb.size().x() - 26.2) < 1e-6 * 26.2);
  CHECK(cb.center().x() == Approx(bounding_box(in).center().x()).margin(1e-5));
}
