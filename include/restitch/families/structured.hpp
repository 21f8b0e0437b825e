// restitch/families/structured.hpp - generated families with structure around their repeat (internal).
//
// The models restitch was first developed on are n copies of a module between two end caps. Real parts
// have more: a housing that reaches past the first pin, a key notch centred in a shroud, slots next to
// both ends, a tall drawer under short ones, a valve on one section, slats in two runs split by a rail,
// ornaments that alternate. Each family below reproduces one of these with exact ground truth: modules
// are exact translates of their template (restitch/families/builder.hpp) except where a part that occurs
// once changes them (SampleModel::parts says which), and the family generated at another count is the
// result a perfect resize gives. Lengths in block-local coordinates; see families.hpp for the contract.
// Included by generators.hpp, after the helpers it uses.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>


namespace restitch {
namespace families {
namespace detail {

/// An axis-aligned face of a box: the plane `at` along `axis`, over [u0, u1] x [v0, v1] of the other two
/// axes in order (x: y, z; y: x, z; z: x, y), facing +axis when `positive`. The same quads as
/// SampleMeshBuilder::box's faces.
template <class = void>
void face(restitch::detail::SampleMeshBuilder& B, int axis, bool positive, double at, double u0, double u1, double v0,
          double v1) {
  using V = Eigen::Vector3d;
  if (!(u0 < u1 && v0 < v1)) return;
  switch (axis) {
    case 0:
      if (positive)
        B.quad(V(at, u0, v0), V(at, u1, v0), V(at, u1, v1), V(at, u0, v1));
      else
        B.quad(V(at, u0, v0), V(at, u0, v1), V(at, u1, v1), V(at, u1, v0));
      break;
    case 1:
      if (positive)
        B.quad(V(u0, at, v0), V(u0, at, v1), V(u1, at, v1), V(u1, at, v0));
      else
        B.quad(V(u0, at, v0), V(u1, at, v0), V(u1, at, v1), V(u0, at, v1));
      break;
    default:
      if (positive)
        B.quad(V(u0, v0, at), V(u1, v0, at), V(u1, v1, at), V(u0, v1, at));
      else
        B.quad(V(u0, v0, at), V(u0, v1, at), V(u1, v1, at), V(u1, v0, at));
  }
}

/// A face with a rectangular hole: the rectangle [u0, u1] x [v0, v1] minus [h0, h1] x [g0, g1] (inside it),
/// as four quads.
template <class = void>
void face_with_hole(restitch::detail::SampleMeshBuilder& B, int axis, bool positive, double at, double u0, double u1,
                    double v0, double v1, double h0, double h1, double g0, double g1) {
  face(B, axis, positive, at, u0, u1, v0, g0);
  face(B, axis, positive, at, u0, u1, g1, v1);
  face(B, axis, positive, at, u0, h0, g0, g1);
  face(B, axis, positive, at, h1, u1, g0, g1);
}

/// A square pin along y at (x, z) of half-size a from y0 down to y1 < y0, with a tapered tip of length
/// `tip` at y1 (as the pin header's), open where it meets the body at y0.
template <class = void>
void pin_down(restitch::detail::SampleMeshBuilder& B, double x, double z, double a, double y0, double y1, double tip) {
  B.frustum_y(x, z, y1 + tip, y0, a, a, false, false);
  B.frustum_y(x, z, y1, y1 + tip, 0.5 * a, a, true, false);
}

// ---------------------------------------------------------------------------
// connector
//
// A single-row wire-to-board housing, pin 1 at the origin, pins along +x at `pitch`. x: [start cap: the
// housing from -wall to the first module] [module: one pin] x pins [end cap]; the housing reaches `wall`
// past the first and the last pin, more than half a pitch, so the origin lies in the second lattice cell
// (the start cap is its own cell). A module: the housing's box (y in [0, height], z in [-depth/2,
// depth/2]) with a square mating opening over its pin, the pin below. The first and the last module have a
// slot in the back wall (parts that occur once, kept next to their ends); the start cap carries a
// polarisation key on its back face. With `one_piece`, the housing's outer faces (front, back, top, bottom,
// ends) run whole from end to end, each tessellated evenly over its length as a CAD export is, so no vertex
// of them lies on the pitch except around the openings and slots (the openings, slots and pins stay per pin):
// the copies pair only where the pins are.

inline SampleInfo connector_info() {
  return {"connector",
          "A single-row wire-to-board connector housing: pin 1 at the origin, the housing reaching past the first "
          "and last pins, a polarisation key at the pin-1 end, a slot in the back wall next to each end. Repeats "
          "along x (pins). Millimetres.",
          "mm",
          {{"pins", 6, 1, 40, true, "pins (repeats along x)"},
           {"pitch", 2.5, 1.0, 5.0, false, "distance between pins (mm)"},
           {"wall", 3.2, 1.0, 10.0, false, "distance from the first (last) pin to the housing's end (mm)"},
           {"height", 6.0, 2.0, 20.0, false, "height of the housing (mm)"},
           {"depth", 5.2, 2.0, 20.0, false, "depth of the housing (mm)"},
           {"opening", 1.6, 0.5, 4.0, false, "side of the square mating opening over each pin (mm)"},
           {"opening_depth", 2.5, 0.5, 10.0, false, "depth of the mating openings (mm)"},
           {"slot_width", 1.2, 0.2, 4.0, false, "width of the back-wall slots (mm)"},
           {"slot_height", 2.0, 0.2, 10.0, false, "height of the back-wall slots (mm)"},
           {"slot_depth", 0.8, 0.1, 5.0, false, "depth of the back-wall slots (mm)"},
           {"pin_size", 0.64, 0.2, 2.0, false, "side of a pin's square section (mm)"},
           {"pin_below", 3.0, 0.5, 20.0, false, "length of a pin below the housing (mm)"},
           {"detail", 1, 1, 64, true, "tessellation level: edges are cut every 1 mm / detail"},
           {"one_piece", 0, 0, 1, true,
            "1: the housing's outer faces run whole from end to end, tessellated evenly over the length as a CAD "
            "export is (no vertex on the pitch but around the openings and slots); 0: one block per pin"}}};
}

template <class = void>
Status connector_check(const ParameterValues& v) {
  const double p = v["pitch"];
  if (!(v["wall"] > p / 2 + 0.1)) return constraint(false, "wall must reach at least 0.1 past half the pitch");
  if (!(v["opening"] < p - 0.4)) return constraint(false, "opening must be less than pitch - 0.4");
  if (!(v["pin_size"] < v["opening"])) return constraint(false, "pin_size must be less than opening");
  if (!(v["slot_width"] < p - 0.4)) return constraint(false, "slot_width must be less than pitch - 0.4");
  if (!(v["slot_height"] < v["height"] - 1)) return constraint(false, "slot_height must be less than height - 1");
  if (!(v["slot_depth"] < v["depth"] / 2 - 0.2)) return constraint(false, "slot_depth must be less than depth / 2 - 0.2");
  if (!(v["opening_depth"] < v["height"] - 1)) return constraint(false, "opening_depth must be less than height - 1");
  if (!(v["opening"] < v["depth"] - 2 * v["slot_depth"] - 0.4))
    return constraint(false, "opening must leave room for the slots: opening < depth - 2 slot_depth - 0.4");
  return {};
}

template <class = void>
void connector_build(const ParameterValues& v, restitch::detail::SampleMeshBuilder& B, SampleModel& out) {
  const int n = v.count("pins");
  const double p = v["pitch"], wall = v["wall"], H = v["height"], D = v["depth"], o = v["opening"],
               od = v["opening_depth"], sw = v["slot_width"], sh = v["slot_height"], sd = v["slot_depth"],
               a = v["pin_size"] / 2, below = v["pin_below"];
  const double e = wall - p / 2;  // the caps' length
  const int plastic = B.add_material(make_material("housing", 0.92f, 0.90f, 0.84f, 0.0f, 0.7f));
  const int tin = B.add_material(make_material("tin", 0.80f, 0.80f, 0.82f, 1.0f, 0.35f));
  const Blocks X{n};
  out.origin = Vec3(-p / 2, 0, 0);
  out.generators = {Vec3(p, 0, 0)};
  out.count_parameters = {"pins"};
  out.counts = {n};
  out.modules = {n};
  out.parts = {{0, 0, 0, "low end", "back-wall slot next to pin 1"}};
  if (n > 1) out.parts.push_back({0, n - 1, n - 1, "high end", "back-wall slot next to the last pin"});
  const double tip = std::min(0.3 * v["pin_size"], 0.4 * below);
  const bool one_piece = v.count("one_piece") == 1;
  const double c0 = p / 2 - o / 2, c1 = p / 2 + o / 2;                             // an opening, in its block
  const double s0 = p / 2 - sw / 2, s1 = p / 2 + sw / 2, y0 = (H - sh) / 2, y1 = y0 + sh, zb = -D / 2 + sd;  // a slot
  // The polarisation key: a rib on the back face, in the start cap's block.
  const auto key = [&] {
    B.box(Vec3(0.2 * e, 1.0, -D / 2 - 0.6), Vec3(0.8 * e, H - 1.0, -D / 2), box_all & ~box_pos_z);
  };
  if (one_piece) {
    // The housing's outer faces, their openings' and slots' walls and floors, in the start cap's block (x from
    // the housing's end): every face on one grid of break lines, so faces meet edge to edge and the housing is
    // closed. The breaks along each axis are the face's length cut evenly (cells at most the builder's cell
    // long, as a patch is cut) and the openings' and slots' edges; along x the even cuts run over the whole
    // length, so they fall on the pitch only by chance.
    B.set_material(plastic);
    B.set_block(Vec3(-wall, 0, 0), -1);
    const double L = (n - 1) * p + 2 * wall, near = 1e-6;
    const auto x_of = [&](int pin, double in_block) { return wall - p / 2 + pin * p + in_block; };  // block-local
    const auto even = [&](double a, double b) {
      std::vector<double> out;
      const int k = B.segments(b - a);  // as a patch's edge is cut
      for (int i = 0; i <= k; ++i) out.push_back(i == k ? b : a + (b - a) * i / k);
      return out;
    };
    // Breaks: the even cuts of [a, b] with the features' edges (an even cut within `near` of one gives way).
    const auto breaks = [&](double a, double b, std::vector<double> features) {
      std::vector<double> out = features;
      for (const double t : even(a, b))
        if (std::none_of(features.begin(), features.end(), [&](double f) { return std::abs(f - t) < near; }))
          out.push_back(t);
      std::sort(out.begin(), out.end());
      return out;
    };
    const auto within = [&](const std::vector<double>& b, double lo, double hi) {
      std::vector<double> out;
      for (const double t : b)
        if (t >= lo - near && t <= hi + near) out.push_back(t);
      return out;
    };
    std::vector<double> fx{0, L};
    for (int i = 0; i < n; ++i) {
      fx.insert(fx.end(), {x_of(i, c0), x_of(i, c1)});
      if (i == 0 || i == n - 1) fx.insert(fx.end(), {x_of(i, s0), x_of(i, s1)});
    }
    const std::vector<double> xs = breaks(0, L, fx), ys = breaks(0, H, {0, y0, y1, H}),
                              zs = breaks(-D / 2, D / 2, {-D / 2, -o / 2, o / 2, D / 2});
    const auto in_opening = [&](double x, double z) {
      for (int i = 0; i < n; ++i)
        if (x > x_of(i, c0) && x < x_of(i, c1) && z > -o / 2 && z < o / 2) return true;
      return false;
    };
    const auto in_slot = [&](double x, double y) {
      for (const int i : {0, n - 1})
        if (x > x_of(i, s0) && x < x_of(i, s1) && y > y0 && y < y1) return true;
      return false;
    };
    // A face on the grid us x vs (as face(): the plane `at` along `axis`), leaving out the cells `hole` says.
    const auto grid = [&](int axis, bool positive, double at, const std::vector<double>& us,
                          const std::vector<double>& vs, const auto& hole) {
      for (std::size_t i = 0; i + 1 < us.size(); ++i)
        for (std::size_t j = 0; j + 1 < vs.size(); ++j)
          if (!hole(0.5 * (us[i] + us[i + 1]), 0.5 * (vs[j] + vs[j + 1])))
            face(B, axis, positive, at, us[i], us[i + 1], vs[j], vs[j + 1]);
    };
    const auto none = [](double, double) { return false; };
    grid(1, false, 0, xs, zs, none);        // bottom
    grid(1, true, H, xs, zs, in_opening);   // top
    grid(2, true, D / 2, xs, ys, none);     // front
    grid(2, false, -D / 2, xs, ys, in_slot);  // back
    grid(0, false, 0, ys, zs, none);        // the two ends
    grid(0, true, L, ys, zs, none);
    const std::vector<double> yo = breaks(H - od, H, {H - od, H}), zo = within(zs, -o / 2, o / 2);
    const std::vector<double> yr = within(ys, y0, y1), zr = breaks(-D / 2, zb, {-D / 2, zb});
    for (int i = 0; i < n; ++i) {  // an opening's walls and floor
      const std::vector<double> xo = within(xs, x_of(i, c0), x_of(i, c1));
      grid(0, true, x_of(i, c0), yo, zo, none);
      grid(0, false, x_of(i, c1), yo, zo, none);
      grid(2, true, -o / 2, xo, yo, none);
      grid(2, false, o / 2, xo, yo, none);
      grid(1, true, H - od, xo, zo, none);
      if (i != 0 && i != n - 1) continue;
      const std::vector<double> xr = within(xs, x_of(i, s0), x_of(i, s1));  // a slot's walls and floor
      grid(0, true, x_of(i, s0), yr, zr, none);
      grid(0, false, x_of(i, s1), yr, zr, none);
      grid(1, true, y0, xr, zr, none);
      grid(1, false, y1, xr, zr, none);
      grid(2, false, zb, xr, yr, none);
    }
    key();
  }
  for (int bx = -1; bx <= X.n; ++bx) {
    B.set_material(plastic);
    if (!X.module(bx) && one_piece) continue;
    if (!X.module(bx)) {
      const bool start = X.start(bx);
      B.set_block(Vec3(start ? -wall : (n - 1) * p + p / 2, 0, 0), bx);
      B.box(Vec3(0, 0, -D / 2), Vec3(e, H, D / 2), box_all & ~(start ? box_pos_x : box_neg_x));
      if (start) key();
      continue;
    }
    B.set_block(Vec3(bx * p - p / 2, 0, 0), bx);
    if (one_piece) {  // the housing is built above; the pin alone
      B.set_material(tin);
      pin_down(B, p / 2, 0, a, 0, -below, tip);
      continue;
    }
    face_with_hole(B, 1, true, H, 0, p, -D / 2, D / 2, c0, c1, -o / 2, o / 2);  // top, around the opening
    face(B, 0, true, c0, H - od, H, -o / 2, o / 2);                              // the opening's walls
    face(B, 0, false, c1, H - od, H, -o / 2, o / 2);
    face(B, 2, true, -o / 2, c0, c1, H - od, H);
    face(B, 2, false, o / 2, c0, c1, H - od, H);
    face(B, 1, true, H - od, c0, c1, -o / 2, o / 2);  // its floor
    face(B, 1, false, 0, 0, p, -D / 2, D / 2);  // bottom
    face(B, 2, true, D / 2, 0, p, 0, H);        // front
    const bool slot = bx == 0 || bx == n - 1;
    if (slot) {  // a recess in the back wall
      face_with_hole(B, 2, false, -D / 2, 0, p, 0, H, s0, s1, y0, y1);
      face(B, 0, true, s0, y0, y1, -D / 2, zb);
      face(B, 0, false, s1, y0, y1, -D / 2, zb);
      face(B, 1, true, y0, s0, s1, -D / 2, zb);
      face(B, 1, false, y1, s0, s1, -D / 2, zb);
      face(B, 2, false, zb, s0, s1, y0, y1);
    } else {
      face(B, 2, false, -D / 2, 0, p, 0, H);
    }
    B.set_material(tin);
    pin_down(B, p / 2, 0, a, 0, -below, tip);
  }
}

// ---------------------------------------------------------------------------
// dip
//
// A dual in-line package: pin 1 at the origin, `pins` pins a side along +x in two rows (z = -+row), under
// one moulded body that ends `wall` past the first and the last pin, less than half a pitch, and a dimple
// marking pin 1 in the top. x: [start cap: the body's end and pin 1] [module: one pin of each row] x
// (pins - 2) [end cap: the last pins and the body's end]; block boundaries lie half a pitch past a pin.
// The dimple runs from `marker_x` past pin 1 over `marker_width`; where it reaches past the first
// boundary (the default) the part that occurs once spans the start cap and the next block, and a cell
// plane in the gap after pin 1 can cut it.

inline SampleInfo dip_info() {
  return {"dip",
          "A dual in-line chip package: pin 1 at the origin, two rows of pins along x under one body that ends "
          "less than half a pitch past the end pins, a dimple marking pin 1 in the top, reaching into the gap "
          "after it. Repeats along x (pins a side). Millimetres.",
          "mm",
          {{"pins", 5, 2, 40, true, "pins a side (repeats along x)"},
           {"pitch", 2.54, 1.0, 5.0, false, "distance between pins (mm)"},
           {"wall", 0.9, 0.3, 2.5, false, "distance from the first (last) pin to the body's end (mm)"},
           {"width", 6.4, 2.0, 20.0, false, "width of the body (z, mm)"},
           {"height", 3.3, 1.0, 10.0, false, "height of the body (mm)"},
           {"row", 2.5, 0.5, 10.0, false, "distance of each row of pins from the middle (z, mm)"},
           {"marker_x", 0.45, -2.0, 5.0, false, "start of the pin-1 dimple past pin 1 (x, mm)"},
           {"marker_width", 0.9, 0.2, 3.0, false, "side of the square pin-1 dimple (mm)"},
           {"marker_depth", 0.1, 0.02, 1.0, false, "depth of the pin-1 dimple (mm)"},
           {"pin_size", 0.5, 0.2, 2.0, false, "side of a pin's square section (mm)"},
           {"pin_below", 3.0, 0.5, 20.0, false, "length of a pin below the body (mm)"},
           {"detail", 1, 1, 64, true, "tessellation level: edges are cut every 1 mm / detail"}}};
}

template <class = void>
Status dip_check(const ParameterValues& v) {
  const double p = v["pitch"], w = v["wall"], mx = v["marker_x"], mw = v["marker_width"];
  if (!(w < p / 2)) return constraint(false, "wall must be less than half the pitch");
  if (!(w > v["pin_size"] / 2 + 0.1)) return constraint(false, "wall must reach at least 0.1 past a pin's side");
  if (!(v["pin_size"] < p - 0.2)) return constraint(false, "pin_size must be less than pitch - 0.2");
  if (!(v["row"] + v["pin_size"] / 2 < v["width"] / 2)) return constraint(false, "the rows of pins must lie under the body: row + pin_size / 2 < width / 2");
  if (!(mx > -w + 0.1 && mx + mw < 1.5 * p - 0.1))
    return constraint(false, "the dimple must lie between the body's end and the next gap: -wall + 0.1 < marker_x and marker_x + marker_width < 1.5 pitch - 0.1");
  if (!(mw < v["width"] / 2 - 0.2)) return constraint(false, "marker_width must be less than width / 2 - 0.2");
  if (!(v["marker_depth"] < v["height"] / 2)) return constraint(false, "marker_depth must be less than height / 2");
  return {};
}

template <class = void>
void dip_build(const ParameterValues& v, restitch::detail::SampleMeshBuilder& B, SampleModel& out) {
  const int n = v.count("pins");
  const double p = v["pitch"], wall = v["wall"], W = v["width"], H = v["height"], row = v["row"], mx = v["marker_x"],
               mw = v["marker_width"], md = v["marker_depth"], a = v["pin_size"] / 2, below = v["pin_below"];
  const int body = B.add_material(make_material("body", 0.08f, 0.08f, 0.09f, 0.0f, 0.6f));
  const int tin = B.add_material(make_material("tin", 0.80f, 0.80f, 0.82f, 1.0f, 0.35f));
  const Blocks X{n - 2};
  out.origin = Vec3(p / 2, 0, 0);
  out.generators = {Vec3(p, 0, 0)};
  out.count_parameters = {"pins"};
  out.counts = {n};
  out.modules = {n - 2};
  out.parts = {{0, -1, mx + mw > p / 2 ? 0 : -1, "low end", "pin-1 dimple"}};
  const double g0 = W / 4 - mw / 2, g1 = W / 4 + mw / 2;  // the dimple's extent along z
  for (int bx = -1; bx <= X.n; ++bx) {
    const bool start = X.start(bx), end = !start && !X.module(bx);
    const double x0 = start ? -wall : p / 2 + bx * p, x1 = end ? (n - 1) * p + wall : p / 2 + (bx + 1) * p;
    const double L = x1 - x0, pin = (start ? 0.0 : end ? (n - 1) * p : p + bx * p) - x0;
    B.set_block(Vec3(x0, 0, 0), bx);
    B.set_material(body);
    // The body's faces on one grid per block (x cut where the dimple starts and ends in it, z where it does in
    // every block), so faces meet edge to edge, across the blocks too: no T-junction, the model is closed.
    const double h0 = std::max(0.0, mx - x0), h1 = std::min(L, mx + mw - x0);  // the dimple in this block
    const bool dimple = h0 < h1;
    std::vector<double> xs{0.0};
    if (dimple && h0 > 0) xs.push_back(h0);
    if (dimple && h1 < L) xs.push_back(h1);
    xs.push_back(L);
    const double zs[4] = {-W / 2, g0, g1, W / 2};
    for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
      for (int j = 0; j < 3; ++j) {
        if (!(dimple && j == 1 && xs[i] >= h0 && xs[i + 1] <= h1)) face(B, 1, true, H, xs[i], xs[i + 1], zs[j], zs[j + 1]);
        face(B, 1, false, 0, xs[i], xs[i + 1], zs[j], zs[j + 1]);  // bottom
      }
      face(B, 2, true, W / 2, xs[i], xs[i + 1], 0, H);  // front, back
      face(B, 2, false, -W / 2, xs[i], xs[i + 1], 0, H);
    }
    for (int j = 0; j < 3; ++j) {
      if (start) face(B, 0, false, 0, 0, H, zs[j], zs[j + 1]);
      if (end) face(B, 0, true, L, 0, H, zs[j], zs[j + 1]);
    }
    if (dimple) {  // its floor and walls
      face(B, 1, true, H - md, h0, h1, g0, g1);
      face(B, 2, true, g0, h0, h1, H - md, H);
      face(B, 2, false, g1, h0, h1, H - md, H);
      if (mx >= x0) face(B, 0, true, h0, H - md, H, g0, g1);
      if (mx + mw <= x1) face(B, 0, false, h1, H - md, H, g0, g1);
    }
    B.set_material(tin);  // one closed pin of each row, touching the body
    for (const double z : {-row, row}) B.box(Vec3(pin - a, -below, z - a), Vec3(pin + a, 0, z + a), box_all);
  }
}

// ---------------------------------------------------------------------------
// box_header
//
// A shrouded two-row header: pin 1 at the origin, `columns` columns of two pins (rows at z = +-pitch/2)
// along +x. A base under a shroud of four walls; the front wall has a key notch centred on the shroud (a
// part that occurs once, kept at the centre: between the middle columns for an even count, on the middle
// column for an odd one, so a resize by an odd number of columns cannot keep it centred by whole
// columns). x: [start cap: shroud end] [module: a column] x columns [end cap].

inline SampleInfo box_header_info() {
  return {"box_header",
          "A shrouded two-row box header: pin 1 at the origin, columns of two pins along x, a base under four walls "
          "with a key notch centred in the front wall. Repeats along x (columns). Millimetres.",
          "mm",
          {{"columns", 6, 1, 40, true, "columns of two pins (repeats along x)"},
           {"pitch", 2.54, 1.0, 5.0, false, "distance between columns and between the rows (mm)"},
           {"shroud_end", 3.8, 1.5, 10.0, false, "distance from the first (last) column to the shroud's end (mm)"},
           {"width", 8.9, 4.0, 20.0, false, "outer width of the shroud (z, mm)"},
           {"height", 9.0, 3.0, 20.0, false, "height of the shroud (mm)"},
           {"base", 2.0, 0.5, 5.0, false, "height of the base (mm)"},
           {"wall", 0.9, 0.3, 2.0, false, "thickness of the walls (mm)"},
           {"notch_width", 4.5, 1.0, 10.0, false, "width of the key notch (mm)"},
           {"pin_size", 0.64, 0.2, 2.0, false, "side of a pin's square section (mm)"},
           {"pin_above", 6.0, 1.0, 20.0, false, "length of a pin above the base (mm)"},
           {"pin_below", 3.0, 0.5, 20.0, false, "length of a pin below the base (mm)"},
           {"detail", 1, 1, 64, true, "tessellation level: edges are cut every 1 mm / detail"}}};
}

template <class = void>
Status box_header_check(const ParameterValues& v) {
  const double p = v["pitch"], t = v["wall"];
  if (!(v["shroud_end"] > p / 2 + t + 0.1)) return constraint(false, "shroud_end must exceed pitch / 2 + wall");
  if (!(v["width"] > p + 2 * t + v["pin_size"] + 0.4)) return constraint(false, "width too small for two rows");
  if (!(v["base"] < v["height"] - 1)) return constraint(false, "base must be less than height - 1");
  if (!(v["notch_width"] < 2 * (v["shroud_end"] - t) - 0.2))
    return constraint(false, "notch_width must be less than 2 (shroud_end - wall) - 0.2 (it must fit one column)");
  if (!(v["pin_above"] > 0.5)) return constraint(false, "pin_above must exceed 0.5");
  return {};
}

template <class = void>
void box_header_build(const ParameterValues& v, restitch::detail::SampleMeshBuilder& B, SampleModel& out) {
  const int n = v.count("columns");
  const double p = v["pitch"], E = v["shroud_end"], W = v["width"], H = v["height"], b = v["base"], t = v["wall"],
               w = v["notch_width"], a = v["pin_size"] / 2, above = v["pin_above"], below = v["pin_below"];
  const double e = E - p / 2;                                   // the caps' length
  const double notch_lo = (n - 1) * p / 2 - w / 2, notch_hi = notch_lo + w;  // global x
  const int plastic = B.add_material(make_material("shroud", 0.05f, 0.05f, 0.05f, 0.0f, 0.6f));
  const int gold = B.add_material(make_material("gold", 1.0f, 0.77f, 0.34f, 1.0f, 0.3f));
  const Blocks X{n};
  out.origin = Vec3(-p / 2, 0, 0);
  out.generators = {Vec3(p, 0, 0)};
  out.count_parameters = {"columns"};
  out.counts = {n};
  out.modules = {n};
  const int first = std::clamp(int(std::floor((notch_lo + p / 2) / p)), 0, n - 1),
            last = std::clamp(int(std::ceil((notch_hi + p / 2) / p)) - 1, 0, n - 1);
  out.parts = {{0, first, last, "centre", "key notch"}};
  const double tip = std::min(0.3 * v["pin_size"], 0.4 * std::min(above, below));
  for (int bx = -1; bx <= X.n; ++bx) {
    const bool start = X.start(bx), end = X.end(bx);
    const double x0 = start ? -E : (end ? (n - 1) * p + p / 2 : bx * p - p / 2), len = X.module(bx) ? p : e;
    B.set_block(Vec3(x0, 0, 0), bx);
    B.set_material(plastic);
    const unsigned outer = start ? box_neg_x : (end ? box_pos_x : 0u);
    // Base: bottom, front, back and the outer end; its top inside the walls.
    B.box(Vec3(0, 0, -W / 2), Vec3(len, b, W / 2), box_neg_y | box_pos_z | box_neg_z | outer);
    const double in0 = start ? t : 0, in1 = end ? len - t : len;  // inside the end walls
    face(B, 1, true, b, in0, in1, -W / 2 + t, W / 2 - t);
    // Back wall.
    B.box(Vec3(0, b, -W / 2), Vec3(len, H, -W / 2 + t), box_pos_y | box_neg_z | box_pos_z | outer);
    // End wall.
    if (start) B.box(Vec3(0, b, -W / 2 + t), Vec3(t, H, W / 2 - t), box_neg_x | box_pos_x | box_pos_y);
    if (end) B.box(Vec3(len - t, b, -W / 2 + t), Vec3(len, H, W / 2 - t), box_neg_x | box_pos_x | box_pos_y);
    // Front wall, minus the key notch (block-local [lo, hi]).
    const double lo = std::clamp(notch_lo - x0, 0.0, len), hi = std::clamp(notch_hi - x0, 0.0, len);
    const unsigned wall_faces = box_pos_y | box_neg_z | box_pos_z;
    if (lo >= hi) {
      B.box(Vec3(0, b, W / 2 - t), Vec3(len, H, W / 2), wall_faces | outer);
    } else {
      if (lo > 0) B.box(Vec3(0, b, W / 2 - t), Vec3(lo, H, W / 2), wall_faces | box_pos_x | (start ? box_neg_x : 0u));
      if (hi < len) B.box(Vec3(hi, b, W / 2 - t), Vec3(len, H, W / 2), wall_faces | box_neg_x | (end ? box_pos_x : 0u));
    }
    if (!X.module(bx)) continue;
    B.set_material(gold);
    for (const double z : {-p / 2, p / 2}) {
      B.frustum_y(p / 2, z, b, b + above - tip, a, a, false, false);
      B.frustum_y(p / 2, z, b + above - tip, b + above, a, 0.5 * a, false, true);
      pin_down(B, p / 2, z, a, 0, -below, tip);
    }
  }
}

// ---------------------------------------------------------------------------
// cabinet
//
// A chest of drawers: short drawers stacked along y on one tall drawer over a plinth. y: [start cap:
// plinth and the tall drawer] [module: a short drawer] x drawers [end cap: the top]. The tall drawer's
// front is taller than a period and carries one handle: a part that occurs once, kept at the bottom.

inline SampleInfo cabinet_info() {
  return {"cabinet",
          "A chest of drawers: short drawers stacked on one tall drawer over a plinth, between two side panels "
          "under a top. Repeats along y (short drawers).",
          "m",
          {{"drawers", 4, 1, 30, true, "short drawers (repeats along y)"},
           {"drawer_height", 0.18, 0.08, 0.5, false, "height of a short drawer (m)"},
           {"tall_height", 0.34, 0.1, 1.0, false, "height of the tall bottom drawer (m)"},
           {"width", 0.6, 0.3, 2.0, false, "width (m)"},
           {"depth", 0.45, 0.2, 1.0, false, "depth of the carcass (m)"},
           {"panel", 0.018, 0.008, 0.05, false, "thickness of the panels (m)"},
           {"plinth", 0.08, 0.02, 0.3, false, "height of the plinth (m)"},
           {"gap", 0.004, 0.001, 0.02, false, "gap between drawer fronts (m)"},
           {"handle_width", 0.12, 0.02, 0.4, false, "width of a handle (m)"},
           {"detail", 1, 1, 64, true, "tessellation level: edges are cut every 0.1 m / detail"}}};
}

template <class = void>
Status cabinet_check(const ParameterValues& v) {
  if (!(v["handle_width"] < v["width"] - 2 * v["panel"] - 0.02)) return constraint(false, "handle_width too large");
  if (!(v["drawer_height"] > 3 * v["gap"] + 0.03)) return constraint(false, "drawer_height too small for its gap");
  if (!(v["tall_height"] > v["panel"] + 0.06)) return constraint(false, "tall_height too small");
  return {};
}

template <class = void>
void cabinet_build(const ParameterValues& v, restitch::detail::SampleMeshBuilder& B, SampleModel& out) {
  const int n = v.count("drawers");
  const double q = v["drawer_height"], T = v["tall_height"], W = v["width"], D = v["depth"], t = v["panel"],
               pl = v["plinth"], g = v["gap"], hw = v["handle_width"];
  const double ft = 0.02, hh = 0.02, hd = 0.03;  // front thickness, handle height and depth
  const int wood = B.add_material(make_material("carcass", 0.55f, 0.38f, 0.22f, 0.0f, 0.6f));
  const int paint = B.add_material(make_material("fronts", 0.85f, 0.84f, 0.80f, 0.0f, 0.5f));
  const int steel = B.add_material(make_material("handles", 0.6f, 0.6f, 0.62f, 1.0f, 0.3f));
  const Blocks Y{n};
  const double y0 = pl + T;  // the first short drawer
  out.origin = Vec3(0, y0, 0);
  out.generators = {Vec3(0, q, 0)};
  out.count_parameters = {"drawers"};
  out.counts = {n};
  out.modules = {n};
  // One drawer bay of height h: side panels, back, the rail under it, its front and a centred handle.
  const auto bay = [&](double h, unsigned side_ends) {
    B.set_material(wood);
    B.box(Vec3(0, 0, 0), Vec3(t, h, D), box_neg_x | box_pos_x | box_neg_z | box_pos_z | side_ends);
    B.box(Vec3(W - t, 0, 0), Vec3(W, h, D), box_neg_x | box_pos_x | box_neg_z | box_pos_z | side_ends);
    B.box(Vec3(t, 0, 0), Vec3(W - t, h, t), box_neg_z | box_pos_z);
    B.box(Vec3(t, 0, t), Vec3(W - t, t, D), box_neg_y | box_pos_y | box_pos_z);
    B.set_material(paint);
    B.box(Vec3(g, g / 2, D), Vec3(W - g, h - g / 2, D + ft), box_all);
    B.set_material(steel);
    B.box(Vec3(W / 2 - hw / 2, h / 2 - hh / 2, D + ft), Vec3(W / 2 + hw / 2, h / 2 + hh / 2, D + ft + hd),
          box_all & ~box_neg_z);
  };
  for (int by = -1; by <= Y.n; ++by) {
    if (Y.start(by)) {
      B.set_block(Vec3(0, 0, 0), by);
      B.set_material(wood);
      B.box(Vec3(0.03, 0, 0.03), Vec3(W - 0.03, pl, D - 0.03), box_all & ~box_pos_y);  // plinth
      B.set_block(Vec3(0, pl, 0), by);
      bay(T, box_neg_y);
      continue;
    }
    if (Y.end(by)) {
      B.set_block(Vec3(0, y0 + n * q, 0), by);
      B.set_material(wood);
      B.box(Vec3(0, 0, 0), Vec3(W, t, D + ft), box_all);  // the top
      continue;
    }
    B.set_block(Vec3(0, y0 + by * q, 0), by);
    bay(q, 0u);
  }
  out.parts = {{0, -1, -1, "low end", "tall drawer"}};
}

// ---------------------------------------------------------------------------
// radiator
//
// A sectional radiator: sections along x joined by a top and a bottom header, plugs at both ends, a valve
// under section `valve_section`, k from the left or -k from the right (a part that occurs once, kept at its
// distance from the end it is counted from). With
// `drift` > 0 the pitch grows along the row (section i at x = pitch (i + drift i (i - 1) / (2 (n - 1)))):
// no two sections are exact copies, the mean pitch is pitch (1 + drift / 2), and there is no exact
// ground truth (the family tests the fundamental period found).

inline SampleInfo radiator_info() {
  return {"radiator",
          "A sectional radiator: sections joined by top and bottom headers, end plugs, and a valve under one "
          "section. Repeats along x (sections).",
          "m",
          {{"sections", 8, 1, 60, true, "sections (repeats along x)"},
           {"pitch", 0.07, 0.03, 0.2, false, "distance between sections (m)"},
           {"height", 0.5, 0.2, 2.0, false, "height (m)"},
           {"section_width", 0.045, 0.01, 0.19, false, "width of a section (x, m)"},
           {"section_depth", 0.08, 0.02, 0.3, false, "depth of a section (z, m)"},
           {"header", 0.05, 0.02, 0.2, false, "height of the headers (m)"},
           {"valve", 1, 0, 1, true, "1: a valve under one section"},
           {"valve_section", 1, -60, 60, true,
            "the section the valve hangs under: k from the left (1: the first), -k from the right"},
           {"drift", 0, 0, 0.1, false, "growth of the pitch from the first gap to the last (relative)"},
           {"detail", 1, 1, 64, true, "tessellation level: edges are cut every 0.05 m / detail"}}};
}

template <class = void>
Status radiator_check(const ParameterValues& v) {
  if (!(v["section_width"] < v["pitch"] - 0.004)) return constraint(false, "section_width must be less than pitch");
  if (!(2 * v["header"] < v["height"] - 0.05)) return constraint(false, "headers too tall for the height");
  if (v["valve"] == 1 && (v.count("valve_section") == 0 || std::abs(v.count("valve_section")) > v.count("sections")))
    return constraint(false, "valve_section must be 1 to sections, or -1 to -sections (from the right)");
  return {};
}

template <class = void>
void radiator_build(const ParameterValues& v, restitch::detail::SampleMeshBuilder& B, SampleModel& out) {
  const int n = v.count("sections");
  const double p = v["pitch"], H = v["height"], sw = v["section_width"], sd = v["section_depth"], hh = v["header"],
               drift = v["drift"];
  const double hd = 0.6 * sd, plug = 0.012;  // header depth, plug length
  const int iron = B.add_material(make_material("radiator", 0.93f, 0.93f, 0.91f, 0.2f, 0.4f));
  const int brass = B.add_material(make_material("valve", 0.78f, 0.62f, 0.30f, 1.0f, 0.3f));
  const int vs = v.count("valve_section");
  const int valve_at = v.count("valve") == 1 ? (vs > 0 ? vs - 1 : n + vs) : -1;
  const Blocks X{n};
  const auto at = [&](int i) {  // the start of section i's module
    return p * (double(i) + (n > 1 ? drift * double(i) * double(i - 1) / (2.0 * double(n - 1)) : 0.0));
  };
  out.origin = Vec3(0, 0, 0);
  out.generators = {Vec3(p * (1 + drift / 2), 0, 0)};
  out.count_parameters = {"sections"};
  out.counts = {n};
  out.modules = {n};
  if (valve_at >= 0)
    out.parts = {{0, valve_at, valve_at, vs > 0 ? "low end" : "high end", "valve"}};
  for (int bx = -1; bx <= X.n; ++bx) {
    B.set_material(iron);
    if (!X.module(bx)) {
      const bool start = X.start(bx);
      B.set_block(Vec3(start ? -plug : at(n - 1) + p, 0, 0), bx);
      for (const double y : {0.0, H - hh})
        B.box(Vec3(0, y, -hd / 2), Vec3(plug, y + hh, hd / 2), box_all & ~(start ? box_pos_x : box_neg_x));
      continue;
    }
    const double len = bx + 1 < n ? at(bx + 1) - at(bx) : p;
    B.set_block(Vec3(at(bx), 0, 0), bx);
    for (const double y : {0.0, H - hh}) B.box(Vec3(0, y, -hd / 2), Vec3(len, y + hh, hd / 2), box_neg_y | box_pos_y | box_neg_z | box_pos_z);
    B.box(Vec3(p / 2 - sw / 2, hh, -sd / 2), Vec3(p / 2 + sw / 2, H - hh, sd / 2),
          box_neg_x | box_pos_x | box_neg_z | box_pos_z);
    if (bx == valve_at) {
      B.set_material(brass);
      B.frustum_y(p / 2, 0, -0.06, 0, 0.008, 0.008, false, false);                          // pipe
      B.box(Vec3(p / 2 - 0.018, -0.09, -0.018), Vec3(p / 2 + 0.018, -0.06, 0.018), box_all);  // body
      B.box(Vec3(p / 2 - 0.01, -0.085, 0.018), Vec3(p / 2 + 0.01, -0.065, 0.05), box_all & ~box_neg_z);  // knob
    }
  }
}

// ---------------------------------------------------------------------------
// shutter
//
// A louvred shutter panel: horizontal slats along y between two stiles, in two runs split by a middle
// rail (a part that occurs once, kept at the centre: ceil(slats / 2) slats below it), a bottom and a top
// rail. y: [start cap: bottom rail] [module: a slat] x slats [end cap: top rail], the middle rail inside
// the module after which it sits (that module is taller by the rail: the modules above it are shifted
// by the rail's height, so the lattice period is the slat pitch and the middle rail is extra length).

inline SampleInfo shutter_info() {
  return {"shutter",
          "A louvred shutter: slats in two runs split by a middle rail, between two stiles, under a top rail and "
          "over a bottom rail. Repeats along y (slats).",
          "m",
          {{"slats", 7, 1, 100, true, "slats (repeats along y), ceil(slats / 2) below the middle rail"},
           {"pitch", 0.07, 0.02, 0.2, false, "distance between slats (m)"},
           {"width", 0.5, 0.2, 2.0, false, "width of the panel (m)"},
           {"stile", 0.045, 0.02, 0.1, false, "width of the stiles (m)"},
           {"rail", 0.06, 0.03, 0.3, false, "height of the middle, top and bottom rails (m)"},
           {"slat_thickness", 0.01, 0.004, 0.03, false, "thickness of a slat (m)"},
           {"detail", 1, 1, 64, true, "tessellation level: edges are cut every 0.05 m / detail"}}};
}

template <class = void>
Status shutter_check(const ParameterValues& v) {
  if (!(v["slat_thickness"] < v["pitch"] - 0.005)) return constraint(false, "slat_thickness must be below pitch");
  if (!(2 * v["stile"] < v["width"] - 0.1)) return constraint(false, "stiles too wide for the width");
  return {};
}

template <class = void>
void shutter_build(const ParameterValues& v, restitch::detail::SampleMeshBuilder& B, SampleModel& out) {
  const int n = v.count("slats"), below = n - n / 2;
  const double q = v["pitch"], W = v["width"], s = v["stile"], r = v["rail"], st = v["slat_thickness"];
  const double d = 0.03;  // depth of stiles and rails (z in [-d/2, d/2]); slats 0.8 d deep
  const int wood = B.add_material(make_material("frame", 0.95f, 0.95f, 0.93f, 0.0f, 0.5f));
  const int slat = B.add_material(make_material("slats", 0.93f, 0.93f, 0.90f, 0.0f, 0.5f));
  const Blocks Y{n};
  const auto at = [&](int i) { return r + double(i) * q + (i >= below ? r : 0.0); };  // module i's bottom
  out.origin = Vec3(0, r, 0);
  out.generators = {Vec3(0, q, 0)};
  out.count_parameters = {"slats"};
  out.counts = {n};
  out.modules = {n};
  const auto stiles = [&](double h) {
    B.set_material(wood);
    B.box(Vec3(0, 0, -d / 2), Vec3(s, h, d / 2), box_neg_x | box_pos_x | box_neg_z | box_pos_z);
    B.box(Vec3(W - s, 0, -d / 2), Vec3(W, h, d / 2), box_neg_x | box_pos_x | box_neg_z | box_pos_z);
  };
  const auto rail_box = [&](double y, unsigned ends) {
    B.set_material(wood);
    B.box(Vec3(0, y, -d / 2), Vec3(W, y + r, d / 2), box_neg_x | box_pos_x | box_neg_z | box_pos_z | ends);
  };
  for (int by = -1; by <= Y.n; ++by) {
    if (Y.start(by)) {
      B.set_block(Vec3(0, 0, 0), by);
      rail_box(0, box_neg_y | box_pos_y);
      continue;
    }
    if (Y.end(by)) {
      B.set_block(Vec3(0, at(n - 1) + q, 0), by);
      rail_box(0, box_neg_y | box_pos_y);
      continue;
    }
    B.set_block(Vec3(0, at(by), 0), by);
    stiles(q);
    B.set_material(slat);
    B.box(Vec3(s, q / 2 - st / 2, -0.4 * d), Vec3(W - s, q / 2 + st / 2, 0.4 * d), box_neg_y | box_pos_y | box_neg_z | box_pos_z);
    if (by == below - 1 && by + 1 < n) rail_box(q, box_neg_y | box_pos_y);  // the middle rail above it
  }
  out.parts = {{0, below - 1, below - 1, "centre", "middle rail"}};
}

// ---------------------------------------------------------------------------
// railing
//
// A railing whose balusters alternate: a plain bar, then a bar with a square ring at mid-height, `spacing`
// apart. The module is the pair (period 2 x spacing); the rails and bars repeat every spacing, the rings
// every module, so a period of one spacing would cut the rhythm. x: [start cap: post] [module: two
// balusters and their rails] x modules [end cap: post].

inline SampleInfo railing_info() {
  return {"railing",
          "A railing between two posts whose balusters alternate between a plain bar and a bar with a ring. "
          "Repeats along x (pairs of balusters).",
          "m",
          {{"modules", 5, 1, 40, true, "pairs of balusters (repeats along x)"},
           {"spacing", 0.12, 0.06, 0.5, false, "distance between balusters (m); the period is twice this"},
           {"height", 0.9, 0.4, 2.0, false, "height of the top rail's top (m)"},
           {"bar", 0.02, 0.008, 0.05, false, "side of a baluster's square section (m)"},
           {"ring", 0.07, 0.03, 0.2, false, "outer side of the ring (m)"},
           {"post", 0.08, 0.04, 0.2, false, "side of the end posts (m)"},
           {"detail", 1, 1, 64, true, "tessellation level: edges are cut every 0.1 m / detail"}}};
}

template <class = void>
Status railing_check(const ParameterValues& v) {
  if (!(v["ring"] < v["spacing"] - 0.01)) return constraint(false, "ring must be less than spacing - 0.01");
  if (!(v["bar"] < v["ring"] - 0.02)) return constraint(false, "bar must be less than ring - 0.02");
  return {};
}

template <class = void>
void railing_build(const ParameterValues& v, restitch::detail::SampleMeshBuilder& B, SampleModel& out) {
  const int n = v.count("modules");
  const double u = v["spacing"], H = v["height"], bar = v["bar"], ring = v["ring"], post = v["post"];
  const double rail = 0.05, foot = 0.06, rt = 0.01;  // rail height, bottom rail's height above ground, ring bar
  const int steel = B.add_material(make_material("steel", 0.15f, 0.15f, 0.16f, 0.8f, 0.45f));
  const int posts = B.add_material(make_material("posts", 0.25f, 0.24f, 0.22f, 0.6f, 0.5f));
  const Blocks X{n};
  out.origin = Vec3(post, 0, 0);
  out.generators = {Vec3(2 * u, 0, 0)};
  out.count_parameters = {"modules"};
  out.counts = {n};
  out.modules = {n};
  for (int bx = -1; bx <= X.n; ++bx) {
    B.set_material(X.module(bx) ? steel : posts);
    if (!X.module(bx)) {
      B.set_block(Vec3(X.start(bx) ? 0.0 : post + n * 2 * u, 0, 0), bx);
      B.box(Vec3(0, 0, -post / 2), Vec3(post, H + 0.04, post / 2), box_all & ~box_neg_y);
      continue;
    }
    B.set_block(Vec3(post + bx * 2 * u, 0, 0), bx);
    for (const double y : {foot, H - rail})
      B.box(Vec3(0, y, -0.02), Vec3(2 * u, y + rail, 0.02), box_neg_y | box_pos_y | box_neg_z | box_pos_z);
    const double y0 = foot + rail, y1 = H - rail, ym = 0.5 * (y0 + y1);
    for (int k = 0; k < 2; ++k) {
      const double x = (k + 0.5) * u;
      B.box(Vec3(x - bar / 2, y0, -bar / 2), Vec3(x + bar / 2, y1, bar / 2), box_neg_x | box_pos_x | box_neg_z | box_pos_z);
      if (k == 1) {  // the ring: four bars around the baluster at mid-height
        const double r = ring / 2;
        B.box(Vec3(x - r, ym - r, -rt / 2), Vec3(x + r, ym - r + rt, rt / 2), box_all);
        B.box(Vec3(x - r, ym + r - rt, -rt / 2), Vec3(x + r, ym + r, rt / 2), box_all);
        B.box(Vec3(x - r, ym - r + rt, -rt / 2), Vec3(x - r + rt, ym + r - rt, rt / 2), box_all & ~(box_neg_y | box_pos_y));
        B.box(Vec3(x + r - rt, ym - r + rt, -rt / 2), Vec3(x + r, ym + r - rt, rt / 2), box_all & ~(box_neg_y | box_pos_y));
      }
    }
  }
}


// ---------------------------------------------------------------------------
// tube_rail
//
// A round rail carried by square posts, as towel radiators and railings have: a closed tube of `sides`
// flat faces along x, with a ring of vertices every half pitch, through a post in the middle of every
// module. A modeller's copies are rarely exact: with `jitter`, every ring's radius differs from the
// rail's by up to that fraction, and with `twist`, every ring is turned about the rail by up to that
// fraction of a side (a pseudo-random amount per ring, the same for the same ring index at every count),
// so two copies meeting at a seam are cut along lines that do not meet (docs/method.md 3, the zipper).
// With `pinch`, every other vertex of a ring keeps its exact place, so the two cut lines meet at those
// vertices and part between them (a row of slits rather than two separate loops).
// x: [start cap: the rail's end, `end` long] [module: a post, rings at 0 and half the pitch] x modules
// [end cap: the rail's end].

inline SampleInfo tube_rail_info() {
  return {"tube_rail",
          "A round rail through square posts, closed, whose rings of vertices may differ slightly from copy to "
          "copy (--jitter, --twist). Repeats along x (posts).",
          "m",
          {{"modules", 4, 1, 60, true, "posts (repeats along x)"},
           {"pitch", 0.25, 0.1, 1.0, false, "distance between posts (m)"},
           {"radius", 0.02, 0.005, 0.05, false, "the rail's radius (m)"},
           {"sides", 16, 6, 64, true, "flat faces around the rail"},
           {"post", 0.05, 0.01, 0.12, false, "side of a post's square section (m)"},
           {"height", 0.3, 0.1, 1.0, false, "height of the rail's axis above the posts' feet (m)"},
           {"end", 0.06, 0.02, 0.3, false, "length of the rail past the first and last post's module (m)"},
           {"jitter", 0, 0, 0.2, false, "each ring's radius differs by up to this fraction of the radius"},
           {"twist", 0, 0, 1, false, "each ring is turned by up to this fraction of a side"},
           {"pinch", 0, 0, 1, true, "1: every other vertex of a ring stays exact (the copies meet there)"},
           {"detail", 1, 1, 64, true, "tessellation level: edges are cut every 0.1 m / detail"}}};
}

template <class = void>
Status tube_rail_check(const ParameterValues& v) {
  RESTITCH_TRY(constraint(v["post"] > 2 * v["radius"], "post must be more than twice the radius"));
  return constraint(v["post"] < v["pitch"] / 2, "post must be less than half the pitch");
}

template <class = void>
void tube_rail_build(const ParameterValues& v, restitch::detail::SampleMeshBuilder& B, SampleModel& out) {
  const int n = v.count("modules"), sides = v.count("sides");
  const double p = v["pitch"], r = v["radius"], post = v["post"], H = v["height"], e = v["end"];
  const int steel = B.add_material(make_material("steel", 0.7f, 0.7f, 0.72f, 0.9f, 0.3f));
  const int wood = B.add_material(make_material("posts", 0.45f, 0.3f, 0.18f, 0.0f, 0.7f));
  const Blocks X{n};
  out.origin = Vec3(e, 0, 0);
  out.generators = {Vec3(p, 0, 0)};
  out.count_parameters = {"modules"};
  out.counts = {n};
  out.modules = {n};
  // Ring k (k = 0 at the start cap's inner end, 2n at the end cap's): a fixed pseudo-random amount in
  // [-1, 1] per ring and kind, so a ring index gives the same ring at every count.
  auto noise = [](int k, int kind) {
    std::uint32_t h = std::uint32_t(k) * 2654435761u + std::uint32_t(kind) * 40503u + 12345u;
    h ^= h >> 15, h *= 2246822519u, h ^= h >> 13;
    return double(h % 20001u) / 10000.0 - 1.0;
  };
  auto ring = [&](int k, bool exact) {
    std::vector<Vec3> q(static_cast<std::size_t>(sides));
    const double rk = exact ? r : r * (1 + v["jitter"] * noise(k, 0));
    const double turn = exact ? 0 : v["twist"] * noise(k, 1);
    const bool pinch = v.count("pinch") == 1;
    for (int i = 0; i < sides; ++i) {
      const bool kept = pinch && i % 2 == 0;
      const double t = 2 * M_PI * (i + (kept ? 0 : turn)) / sides, ri = kept ? r : rk;
      q[std::size_t(i)] = Vec3(0, H + ri * std::cos(t), ri * std::sin(t));
    }
    return q;
  };
  auto tube = [&](const std::vector<Vec3>& a, double xa, const std::vector<Vec3>& b, double xb) {
    for (int i = 0; i < sides; ++i) {
      const int j = (i + 1) % sides;
      const Vec3 dx(xa, 0, 0), ex(xb, 0, 0);
      B.quad(a[std::size_t(i)] + dx, a[std::size_t(j)] + dx, b[std::size_t(j)] + ex, b[std::size_t(i)] + ex);
    }
  };
  auto cap = [&](const std::vector<Vec3>& a, double x, bool low) {
    const Vec3 c(x, H, 0), dx(x, 0, 0);
    for (int i = 0; i < sides; ++i) {
      const int j = (i + 1) % sides;
      if (low)
        B.triangle(c, a[std::size_t(j)] + dx, a[std::size_t(i)] + dx);
      else
        B.triangle(c, a[std::size_t(i)] + dx, a[std::size_t(j)] + dx);
    }
  };
  for (int bx = -1; bx <= X.n; ++bx) {
    B.set_material(steel);
    if (!X.module(bx)) {  // the rail's end: from the end ring (exact) to ring 0 or 2n
      const bool low = X.start(bx);
      B.set_block(Vec3(low ? 0.0 : e + n * p, 0, 0), bx);
      const std::vector<Vec3> outer = ring(0, true), inner = ring(low ? 0 : 2 * n, false);
      if (low) {
        tube(outer, 0, inner, e);
        cap(outer, 0, true);
      } else {
        tube(inner, 0, outer, e);
        cap(outer, e, false);
      }
      continue;
    }
    B.set_block(Vec3(e + bx * p, 0, 0), bx);
    const std::vector<Vec3> a = ring(2 * bx, false), m = ring(2 * bx + 1, false), b = ring(2 * bx + 2, false);
    B.set_material(steel);
    tube(a, 0, m, p / 2);
    tube(m, p / 2, b, p);
    B.set_material(wood);
    B.box(Vec3(p / 2 - post / 2, 0, -post / 2), Vec3(p / 2 + post / 2, H + post / 2, post / 2), box_all);
  }
}

}  // namespace detail
}  // namespace families
}  // namespace restitch
