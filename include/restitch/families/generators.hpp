// restitch/families/generators.hpp - the generated families (internal): parameters, checks, builders.
//
// Each family has an `_info()` (its catalogue entry: parameters with defaults
// and ranges), a `_check()` (constraints between parameters, as Status) and a
// `_build()` (the mesh and its ground truth). The contract they fulfil is in
// restitch/families/families.hpp.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "restitch/families/builder.hpp"
#include "restitch/families/model.hpp"
#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch {
namespace families {

namespace detail {

/// Validated parameter values by name.
class ParameterValues {
 public:
  explicit ParameterValues(std::map<std::string, double> v) : v_(std::move(v)) {}
  template <class = void>
  double operator[](const char* name) const {
    const auto it = v_.find(name);
    RESTITCH_ASSERT(it != v_.end(), "sample family reads a parameter it did not declare");
    return it->second;
  }
  int count(const char* name) const { return static_cast<int>((*this)[name]); }

 private:
  std::map<std::string, double> v_;
};

using restitch::detail::box_all;
using restitch::detail::box_neg_x;
using restitch::detail::box_neg_y;
using restitch::detail::box_neg_z;
using restitch::detail::box_pos_x;
using restitch::detail::box_pos_y;
using restitch::detail::box_pos_z;
using restitch::detail::SampleMeshBuilder;
using Vec3 = Eigen::Vector3d;

template <class = void>
Material make_material(const char* name, float r, float g, float b, float metallic, float roughness) {
  Material m;
  m.name = name;
  m.base_color = Eigen::Vector4f(r, g, b, 1.0f);
  m.metallic = metallic;
  m.roughness = roughness;
  return m;
}

template <class = void>
std::string format_number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

inline Status constraint(bool ok, const std::string& what) {
  return ok ? Status() : error(StatusCode::invalid_argument, "parameters do not fit together: " + what);
}

// Block kinds along one generator: index -1 = start cap, 0..n-1 = module, n = end cap.
struct Blocks {
  int n;
  bool start(int b) const { return b < 0; }
  bool end(int b) const { return b >= n; }
  bool module(int b) const { return b >= 0 && b < n; }
};

// ---------------------------------------------------------------------------
// bookshelf
//
// x: [left panel t] [compartment p-t, divider t] x (columns-1) [compartment p-t, right panel t]
// y: [bottom board t] [compartment q-t, shelf board t] x (shelves-1) [compartment q-t, top board t]
// z: back panel [-b, 0], everything else [0, depth].
// Width t + columns * p, height t + shelves * q. Dividers run from the bottom
// board to the top board; shelf boards sit between dividers; the top and
// bottom boards run between the side panels. Faces in contact are left out.

template <class = void>
SampleInfo bookshelf_info() {
  return {"bookshelf",
          "A bookshelf: columns x shelves compartments between two side panels, top and bottom boards, vertical "
          "dividers, shelf boards and a back panel; optionally a door over one compartment. Repeats along x "
          "(columns) and y (shelves).",
          "m",
          {{"columns", 4, 1, 64, true, "compartments side by side (repeats along x)"},
           {"shelves", 4, 1, 64, true, "compartments stacked (repeats along y)"},
           {"column_pitch", 0.4, 0.15, 2.0, false, "distance between dividers (m)"},
           {"shelf_pitch", 0.35, 0.15, 2.0, false, "distance between shelf boards (m)"},
           {"depth", 0.3, 0.1, 1.0, false, "depth of the boards (m)"},
           {"board_thickness", 0.02, 0.005, 0.05, false, "thickness of panels, boards and dividers (m)"},
           {"back_thickness", 0.005, 0.002, 0.02, false, "thickness of the back panel (m)"},
           {"door_column", 0, -64, 64, true,
            "column of the compartment a door closes: k from the left, -k from the right; 0: no door"},
           {"door_shelf", 0, -64, 64, true, "shelf of the door's compartment: k from the bottom, -k from the top"},
           {"detail", 1, 1, 64, true, "tessellation level: edges are cut every 0.1 m / detail"}}};
}

template <class = void>
Status bookshelf_check(const ParameterValues& v) {
  const int i = v.count("door_column"), j = v.count("door_shelf");
  if ((i == 0) != (j == 0)) return constraint(false, "door_column and door_shelf are both 0 (no door) or neither");
  if (std::abs(i) > v.count("columns")) return constraint(false, "door_column must be at most columns");
  if (std::abs(j) > v.count("shelves")) return constraint(false, "door_shelf must be at most shelves");
  return {};
}

template <class = void>
void bookshelf_build(const ParameterValues& P, SampleMeshBuilder& B, SampleModel& out) {
  const int c = P.count("columns"), r = P.count("shelves");
  const double p = P["column_pitch"], q = P["shelf_pitch"], D = P["depth"], t = P["board_thickness"],
               bk = P["back_thickness"];
  const int wood = B.add_material(make_material("wood", 0.55f, 0.36f, 0.20f, 0.0f, 0.6f));
  const int shelf = B.add_material(make_material("shelf", 0.62f, 0.43f, 0.26f, 0.0f, 0.55f));
  const int back = B.add_material(make_material("back_panel", 0.85f, 0.80f, 0.70f, 0.0f, 0.9f));
  const Blocks X{c - 1}, Y{r - 1};
  // The door's compartment (0-based; compartment i lives in block i, the last in the end block), and the
  // parts it makes, kept at the end it is counted from.
  const int di = P.count("door_column"), dj = P.count("door_shelf");
  const int door_x = di > 0 ? di - 1 : c + di, door_y = dj > 0 ? dj - 1 : r + dj;
  const int door = di != 0 ? B.add_material(make_material("door", 0.80f, 0.78f, 0.72f, 0.0f, 0.5f)) : -1;
  if (door >= 0)
    out.parts = {{0, door_x, door_x, di > 0 ? "low end" : "high end", "door"},
                 {1, door_y, door_y, dj > 0 ? "low end" : "high end", "door"}};
  out.origin = Vec3(t, t, 0);
  out.generators = {Vec3(p, 0, 0), Vec3(0, q, 0)};
  out.count_parameters = {"columns", "shelves"};
  out.counts = {c, r};
  out.modules = {X.n, Y.n};
  auto offset = [&](int b, double pitch, const Blocks& K) {
    return K.start(b) ? 0.0 : (K.end(b) ? t + K.n * pitch : t + b * pitch);
  };
  for (int by = -1; by <= Y.n; ++by)
    for (int bx = -1; bx <= X.n; ++bx) {
      B.set_block(Vec3(offset(bx, p, X), offset(by, q, Y), 0), bx, by);
      const double wx = X.start(bx) ? t : p, wy = Y.start(by) ? t : q;
      const unsigned x_ends = (X.start(bx) ? box_neg_x : 0u) | (X.end(bx) ? box_pos_x : 0u);
      const unsigned y_ends = (Y.start(by) ? box_neg_y : 0u) | (Y.end(by) ? box_pos_y : 0u);
      // Back panel, cut per block; its rim only at the outer ends.
      B.set_material(back);
      B.box(Vec3(0, 0, -bk), Vec3(wx, wy, 0), box_neg_z | box_pos_z | x_ends | y_ends);
      B.set_material(wood);
      // Side panels: full height, cut per row.
      if (X.start(bx)) B.box(Vec3(0, 0, 0), Vec3(t, wy, D), box_neg_x | box_pos_x | box_neg_z | box_pos_z | y_ends);
      if (X.end(bx)) B.box(Vec3(p - t, 0, 0), Vec3(p, wy, D), box_neg_x | box_pos_x | box_neg_z | box_pos_z | y_ends);
      if (X.start(bx)) continue;
      // Bottom and top boards: between the side panels, continuous over the dividers.
      const double board_x1 = X.end(bx) ? p - t : p;
      const unsigned board = box_neg_y | box_pos_y | box_neg_z | box_pos_z;
      if (Y.start(by)) B.box(Vec3(0, 0, 0), Vec3(board_x1, t, D), board);
      if (Y.end(by)) B.box(Vec3(0, q - t, 0), Vec3(board_x1, q, D), board);
      B.set_material(shelf);
      // Shelf boards between dividers.
      if (Y.module(by)) B.box(Vec3(0, q - t, 0), Vec3(p - t, q, D), board);
      // Dividers: from the bottom board to the top board, cut per row.
      if (X.module(bx) && !Y.start(by))
        B.box(Vec3(p - t, 0, 0), Vec3(p, Y.end(by) ? q - t : q, D), box_neg_x | box_pos_x | box_neg_z | box_pos_z);
      if (door >= 0 && bx == door_x && by == door_y) {  // a door panel in front of the compartment, a knob
        const double gap = 0.004, w = p - t, h = q - t;
        const unsigned all = box_neg_x | box_pos_x | box_neg_y | box_pos_y | box_neg_z | box_pos_z;
        B.set_material(door);
        B.box(Vec3(gap, gap, D), Vec3(w - gap, h - gap, D + t), all);
        B.box(Vec3(w - 0.06, h / 2 - 0.03, D + t), Vec3(w - 0.04, h / 2 + 0.03, D + t + 0.025), all);
      }
    }
}

// ---------------------------------------------------------------------------
// facade (and facade_sheared)
//
// x: [margin] [bay] x columns [margin];  y: [plinth] [floor] x floors [parapet].
// The wall is a slab z in [-wall_thickness, 0]. Row (block along y) j is
// shifted sideways by j * shear (the plinth by -shear, the parapet by
// floors * shear), so the generators are (bay, 0, 0) and (shear, floor, 0);
// the wall's exposed steps between shifted rows are closed by ledge faces
// in the caps. Each bay holds an opening with reveals, a frame of four boxes
// on the wall, a recessed glass pane and a sill.

template <class = void>
std::vector<Parameter> facade_parameters(double shear) {
  return {{"columns", 5, 1, 64, true, "window bays side by side (repeats along x)"},
          {"floors", 4, 1, 64, true, "floors (repeats along y)"},
          {"bay_width", 3.0, 1.0, 10.0, false, "width of one window bay (m)"},
          {"floor_height", 3.2, 1.5, 10.0, false, "height of one floor (m)"},
          {"window_width", 1.4, 0.3, 8.0, false, "width of the window opening (m)"},
          {"window_height", 1.6, 0.3, 8.0, false, "height of the window opening (m)"},
          {"sill_height", 0.9, 0.2, 5.0, false, "height of the opening's bottom above the floor (m)"},
          {"wall_thickness", 0.3, 0.1, 1.0, false, "thickness of the wall (m)"},
          {"frame_width", 0.08, 0.02, 0.3, false, "width of the window frame (m)"},
          {"frame_depth", 0.06, 0.01, 0.3, false, "how far the frame stands out of the wall (m)"},
          {"glass_recess", 0.1, 0.0, 0.9, false, "depth of the glass behind the wall's front (m)"},
          {"margin", 1.0, 0.3, 5.0, false, "wall left and right of the outer bays (m)"},
          {"plinth_height", 0.8, 0.2, 3.0, false, "height of the stone plinth below the first floor (m)"},
          {"parapet_height", 0.9, 0.3, 3.0, false, "height of the parapet above the top floor (m)"},
          {"shear", shear, -3.0, 3.0, false, "sideways shift of each floor against the one below (m)"},
          {"detail", 1, 1, 64, true, "tessellation level: edges are cut every 1 m / detail"}};
}

template <class = void>
SampleInfo facade_info() {
  return {"facade",
          "A building facade: a wall with columns x floors windows (frame, recessed glass, sill), a plinth and a "
          "parapet with a cornice. Repeats along x (columns) and y (floors).",
          "m", facade_parameters(0.0)};
}

template <class = void>
SampleInfo facade_sheared_info() {
  return {"facade_sheared",
          "The facade with every floor shifted sideways by `shear`: the lattice generators are (bay_width, 0, 0) "
          "and (shear, floor_height, 0), not orthogonal; the building is a stepped parallelogram in the wall plane.",
          "m", facade_parameters(0.75)};
}

constexpr double facade_sill_overhang = 0.05, facade_sill_thickness = 0.06, facade_sill_depth = 0.08,
                 facade_glass_thickness = 0.02, facade_cornice_depth = 0.15, facade_plinth_depth = 0.04;

template <class = void>
Status facade_check(const ParameterValues& P) {
  const double pw = P["bay_width"], ph = P["floor_height"], ww = P["window_width"], wh = P["window_height"],
               sh = P["sill_height"], f = P["frame_width"], T = P["wall_thickness"], gr = P["glass_recess"];
  RESTITCH_TRY(constraint(
      ww + 2 * f + 2 * facade_sill_overhang < pw,
      "window_width + 2 * frame_width + 0.1 (sill overhang) = " + format_number(ww + 2 * f + 2 * facade_sill_overhang) +
          " must be less than bay_width = " + format_number(pw)));
  RESTITCH_TRY(constraint(sh - f - facade_sill_thickness > 0,
                          "sill_height - frame_width - 0.06 (sill) must be positive; sill_height = " +
                              format_number(sh) + ", frame_width = " + format_number(f)));
  RESTITCH_TRY(
      constraint(sh + wh + f < ph, "sill_height + window_height + frame_width = " + format_number(sh + wh + f) +
                                       " must be less than floor_height = " + format_number(ph)));
  RESTITCH_TRY(constraint(gr + facade_glass_thickness < T,
                          "glass_recess + 0.02 (glass) must be less than "
                          "wall_thickness = " +
                              format_number(T)));
  RESTITCH_TRY(
      constraint(std::abs(P["shear"]) < P["margin"], "|shear| = " + format_number(std::abs(P["shear"])) +
                                                         " must be less than margin = " + format_number(P["margin"])));
  return {};
}

template <class = void>
void facade_build(const ParameterValues& P, SampleMeshBuilder& B, SampleModel& out) {
  const int c = P.count("columns"), r = P.count("floors");
  const double pw = P["bay_width"], ph = P["floor_height"], ww = P["window_width"], wh = P["window_height"],
               sh = P["sill_height"], T = P["wall_thickness"], f = P["frame_width"], fd = P["frame_depth"],
               gr = P["glass_recess"], m = P["margin"], plinth = P["plinth_height"], parapet = P["parapet_height"],
               s = P["shear"];
  const int wall = B.add_material(make_material("wall", 0.80f, 0.74f, 0.64f, 0.0f, 0.9f));
  const int stone = B.add_material(make_material("stone", 0.45f, 0.44f, 0.42f, 0.0f, 0.8f));
  const int frame = B.add_material(make_material("frame", 0.92f, 0.92f, 0.90f, 0.0f, 0.4f));
  const int glass = B.add_material(make_material("glass", 0.25f, 0.40f, 0.50f, 0.0f, 0.05f));
  const Blocks X{c}, Y{r};
  out.origin = Vec3(m, plinth, 0);
  out.generators = {Vec3(pw, 0, 0), Vec3(s, ph, 0)};
  out.count_parameters = {"columns", "floors"};
  out.counts = {c, r};
  out.modules = {c, r};
  const double ox0 = (pw - ww) / 2, ox1 = (pw + ww) / 2, oy0 = sh, oy1 = sh + wh;
  for (int by = -1; by <= Y.n; ++by)
    for (int bx = -1; bx <= X.n; ++bx) {
      const double xo = X.start(bx) ? 0.0 : (X.end(bx) ? m + X.n * pw : m + bx * pw);
      const double yo = Y.start(by) ? 0.0 : (Y.end(by) ? plinth + Y.n * ph : plinth + by * ph);
      const int row = Y.start(by) ? -1 : by;  // the parapet's row index is floors
      B.set_block(Vec3(xo + row * s, yo, 0), bx, by);
      const double wx = X.module(bx) ? pw : m, wy = Y.module(by) ? ph : (Y.start(by) ? plinth : parapet);
      B.set_material(Y.start(by) ? stone : wall);
      // Wall front (z = 0) and back (z = -T); a bay cuts the opening out of both.
      if (X.module(bx) && Y.module(by)) {
        const double xs[4][4] = {{0, pw, 0, oy0}, {0, pw, oy1, ph}, {0, ox0, oy0, oy1}, {ox1, pw, oy0, oy1}};
        for (const auto& q : xs) {
          B.rect_z(q[0], q[1], q[2], q[3], 0, true);
          B.rect_z(q[0], q[1], q[2], q[3], -T, false);
        }
        // Reveals: the opening's sides through the wall, facing into the opening.
        B.quad(Vec3(ox0, oy0, -T), Vec3(ox0, oy0, 0), Vec3(ox1, oy0, 0), Vec3(ox1, oy0, -T));  // +y
        B.quad(Vec3(ox0, oy1, -T), Vec3(ox1, oy1, -T), Vec3(ox1, oy1, 0), Vec3(ox0, oy1, 0));  // -y
        B.quad(Vec3(ox0, oy0, -T), Vec3(ox0, oy1, -T), Vec3(ox0, oy1, 0), Vec3(ox0, oy0, 0));  // +x
        B.quad(Vec3(ox1, oy0, -T), Vec3(ox1, oy0, 0), Vec3(ox1, oy1, 0), Vec3(ox1, oy1, -T));  // -x
        B.set_material(frame);
        const unsigned out_faces = box_all & ~box_neg_z;
        B.box(Vec3(ox0 - f, oy0 - f, 0), Vec3(ox0, oy1 + f, fd), out_faces);
        B.box(Vec3(ox1, oy0 - f, 0), Vec3(ox1 + f, oy1 + f, fd), out_faces);
        B.box(Vec3(ox0, oy0 - f, 0), Vec3(ox1, oy0, fd), box_neg_y | box_pos_y | box_pos_z);
        B.box(Vec3(ox0, oy1, 0), Vec3(ox1, oy1 + f, fd), box_neg_y | box_pos_y | box_pos_z);
        B.set_material(glass);
        B.box(Vec3(ox0, oy0, -gr - facade_glass_thickness), Vec3(ox1, oy1, -gr), box_neg_z | box_pos_z);
        B.set_material(stone);
        B.box(Vec3(ox0 - f - facade_sill_overhang, oy0 - f - facade_sill_thickness, 0),
              Vec3(ox1 + f + facade_sill_overhang, oy0 - f, fd + facade_sill_depth), out_faces);
        continue;
      }
      B.rect_z(0, wx, 0, wy, 0, true);
      B.rect_z(0, wx, 0, wy, -T, false);
      // The wall's rim at the outer ends.
      if (X.start(bx)) B.quad(Vec3(0, 0, -T), Vec3(0, 0, 0), Vec3(0, wy, 0), Vec3(0, wy, -T));
      if (X.end(bx)) B.quad(Vec3(wx, 0, -T), Vec3(wx, wy, -T), Vec3(wx, wy, 0), Vec3(wx, 0, 0));
      auto top = [&](double x0, double x1) {
        B.quad(Vec3(x0, wy, -T), Vec3(x0, wy, 0), Vec3(x1, wy, 0), Vec3(x1, wy, -T));
      };
      auto bottom = [&](double x0, double x1) {
        B.quad(Vec3(x0, 0, -T), Vec3(x1, 0, -T), Vec3(x1, 0, 0), Vec3(x0, 0, 0));
      };
      if (Y.start(by)) bottom(0, wx);
      if (Y.end(by)) top(0, wx);
      // Ledges where a row sticks out past the row above or below (shear only).
      const double a = std::abs(s);
      if (a > 0) {
        const bool above = !Y.end(by), below = !Y.start(by);
        if (above && s > 0 && X.start(bx)) top(0, a);
        if (above && s < 0 && X.end(bx)) top(m - a, m);
        if (below && s > 0 && X.end(bx)) bottom(m - a, m);
        if (below && s < 0 && X.start(bx)) bottom(0, a);
      }
      const unsigned x_ends = (X.start(bx) ? box_neg_x : 0u) | (X.end(bx) ? box_pos_x : 0u);
      if (Y.start(by))  // a stone band in front of the plinth
        B.box(Vec3(0, 0, 0), Vec3(wx, wy, facade_plinth_depth), box_neg_y | box_pos_y | box_pos_z | x_ends);
      if (Y.end(by)) {  // the cornice on the parapet
        const double ch = std::min(0.25, wy / 2);
        B.box(Vec3(0, wy - ch, 0), Vec3(wx, wy, facade_cornice_depth), box_neg_y | box_pos_y | box_pos_z | x_ends);
      }
    }
}

// ---------------------------------------------------------------------------
// fence
//
// x: [post] [picket module] x pickets [post]. A module holds one picket
// (a pentagonal prism with a pointed top, z in [0, picket_thickness]) and its
// share of the two rails (z in [-rail_thickness, 0], centred at 20% and 75%
// of the picket height). Posts are centred on the rails' mid-plane and carry
// a pyramid cap.

template <class = void>
SampleInfo fence_info() {
  return {"fence",
          "A picket fence: pickets with pointed tops on two horizontal rails between two posts. Repeats along x "
          "(pickets) only.",
          "m",
          {{"pickets", 8, 1, 500, true, "pickets (repeats along x)"},
           {"picket_pitch", 0.15, 0.05, 1.0, false, "distance between pickets (m)"},
           {"picket_width", 0.09, 0.02, 0.9, false, "width of a picket (m)"},
           {"picket_height", 1.0, 0.3, 3.0, false, "height of a picket, tip included (m)"},
           {"picket_thickness", 0.02, 0.005, 0.1, false, "thickness of a picket (m)"},
           {"point_height", 0.06, 0.01, 0.5, false, "height of a picket's pointed top (m)"},
           {"post_width", 0.1, 0.03, 0.5, false, "width and depth of a post (m)"},
           {"post_height", 1.15, 0.3, 3.5, false, "height of a post without its cap (m)"},
           {"rail_height", 0.07, 0.02, 0.3, false, "height of a rail (m)"},
           {"rail_thickness", 0.03, 0.01, 0.2, false, "thickness of a rail (m)"},
           {"detail", 2, 1, 64, true, "tessellation level: edges are cut every 0.1 m / detail"}}};
}

template <class = void>
Status fence_check(const ParameterValues& P) {
  const double p = P["picket_pitch"], w = P["picket_width"], h = P["picket_height"], tip = P["point_height"],
               rh = P["rail_height"], ph = P["post_height"];
  RESTITCH_TRY(constraint(
      w < p, "picket_width = " + format_number(w) + " must be less than picket_pitch = " + format_number(p)));
  RESTITCH_TRY(constraint(0.2 * h - rh / 2 > 0,
                          "the lower rail (centred at 0.2 * picket_height) must clear the "
                          "ground: rail_height must be less than 0.4 * picket_height"));
  RESTITCH_TRY(constraint(0.75 * h + rh / 2 < h - tip,
                          "the upper rail (centred at 0.75 * picket_height) must end "
                          "below the point: 0.75 * picket_height + rail_height / 2 < "
                          "picket_height - point_height"));
  RESTITCH_TRY(constraint(0.75 * h + rh / 2 < ph,
                          "the upper rail must end below the top of the posts: "
                          "0.75 * picket_height + rail_height / 2 < post_height"));
  return {};
}

template <class = void>
void fence_build(const ParameterValues& P, SampleMeshBuilder& B, SampleModel& out) {
  const int n = P.count("pickets");
  const double p = P["picket_pitch"], w = P["picket_width"], h = P["picket_height"], pt = P["picket_thickness"],
               tip = P["point_height"], pw = P["post_width"], ph = P["post_height"], rh = P["rail_height"],
               rt = P["rail_thickness"];
  const int paint = B.add_material(make_material("picket_paint", 0.90f, 0.90f, 0.86f, 0.0f, 0.7f));
  const int wood = B.add_material(make_material("post_wood", 0.42f, 0.30f, 0.20f, 0.0f, 0.85f));
  const Blocks X{n};
  out.origin = Vec3(pw, 0, 0);
  out.generators = {Vec3(p, 0, 0)};
  out.count_parameters = {"pickets"};
  out.counts = {n};
  out.modules = {n};
  const double rail_y[2] = {0.2 * h, 0.75 * h};
  const double post_z = -rt / 2;
  for (int bx = -1; bx <= X.n; ++bx) {
    B.set_block(Vec3(X.start(bx) ? 0.0 : (X.end(bx) ? pw + X.n * p : pw + bx * p), 0, 0), bx);
    if (!X.module(bx)) {
      B.set_material(wood);
      B.box(Vec3(0, 0, post_z - pw / 2), Vec3(pw, ph, post_z + pw / 2), box_all & ~box_pos_y);
      B.frustum_y(pw / 2, post_z, ph, ph + 0.4 * pw, pw / 2, 0.0, false, false);
      continue;
    }
    B.set_material(wood);
    for (double y : rail_y)
      B.box(Vec3(0, y - rh / 2, -rt), Vec3(p, y + rh / 2, 0), box_neg_y | box_pos_y | box_neg_z | box_pos_z);
    B.set_material(paint);
    const double x0 = (p - w) / 2, x1 = (p + w) / 2;
    const std::vector<Eigen::Vector2d> profile = {{x0, 0}, {x1, 0}, {x1, h - tip}, {p / 2, h}, {x0, h - tip}};
    B.prism_z(profile, {{0, 1, 2, 4}, {2, 3, 4, -1}}, 0, pt, 0x1fu, true, true);
  }
}

// ---------------------------------------------------------------------------
// pin_header
//
// x: [body end e] [segment with one pin] x pins [body end e], millimetres.
// A body segment is a hexagonal prism (its top edges chamfered, so
// neighbouring segments form a V notch), z in [-depth/2, depth/2]; the
// faces between segments are left out, so the body's surface is one piece.
// A pin is a square post with tapered tips, above and below the body. With
// closed = 1 each pin also gets the square where it meets the body, and the
// end cap's face is cut so that its edges at x = 0 match the last segment's,
// so every part (body, pins) is a closed surface and the model has no boundary
// edges (positions welded: each face has its own vertices).

template <class = void>
SampleInfo pin_header_info() {
  return {"pin_header",
          "A single-row pin header: square pins at a 2.54 mm pitch through a plastic body made of one notched "
          "segment per pin. Repeats along x (pins) only. Millimetres.",
          "mm",
          {{"pins", 8, 1, 100, true, "pins (repeats along x)"},
           {"pitch", 2.54, 1.0, 5.0, false, "distance between pins (mm)"},
           {"body_height", 2.5, 0.5, 10.0, false, "height of the plastic body (mm)"},
           {"body_depth", 2.5, 0.5, 10.0, false, "depth of the plastic body (mm)"},
           {"end_length", 0.3, 0.1, 2.0, false, "length of the body beyond the outer segments (mm)"},
           {"notch", 0.2, 0.05, 1.0, false, "size of the chamfer on the body's top edges (mm)"},
           {"pin_size", 0.64, 0.2, 2.0, false, "side of a pin's square section (mm)"},
           {"pin_above", 6.0, 0.5, 30.0, false, "length of a pin above the body (mm)"},
           {"pin_below", 3.0, 0.5, 30.0, false, "length of a pin below the body (mm)"},
           {"detail", 1, 1, 64, true, "tessellation level: edges are cut every 1 mm / detail"},
           {"closed", 0, 0, 1, true,
            "1: cap the pins where they meet the body, so every part is a closed surface (0 boundary edges)"}}};
}

template <class = void>
Status pin_header_check(const ParameterValues& P) {
  const double p = P["pitch"], H = P["body_height"], e = P["end_length"], c = P["notch"], a = P["pin_size"];
  RESTITCH_TRY(
      constraint(c < e, "notch = " + format_number(c) + " must be less than end_length = " + format_number(e)));
  RESTITCH_TRY(constraint(
      c < H / 2, "notch = " + format_number(c) + " must be less than body_height / 2 = " + format_number(H / 2)));
  RESTITCH_TRY(constraint(a + 2 * c < p, "pin_size + 2 * notch = " + format_number(a + 2 * c) +
                                             " must be less than pitch = " + format_number(p)));
  RESTITCH_TRY(constraint(a < P["body_depth"], "pin_size must be less than body_depth"));
  return {};
}

template <class = void>
void pin_header_build(const ParameterValues& P, SampleMeshBuilder& B, SampleModel& out) {
  const int n = P.count("pins");
  const double p = P["pitch"], H = P["body_height"], d = P["body_depth"], e = P["end_length"], c = P["notch"],
               a = P["pin_size"] / 2, above = P["pin_above"], below = P["pin_below"];
  const int plastic = B.add_material(make_material("plastic", 0.03f, 0.03f, 0.03f, 0.0f, 0.6f));
  const int gold = B.add_material(make_material("gold", 1.0f, 0.77f, 0.34f, 1.0f, 0.3f));
  const Blocks X{n};
  out.origin = Vec3(e, 0, 0);
  out.generators = {Vec3(p, 0, 0)};
  out.count_parameters = {"pins"};
  out.counts = {n};
  out.modules = {n};
  const double tip = std::min(0.3 * P["pin_size"], 0.4 * std::min(above, below));
  const bool closed = P.count("closed") == 1;  // the pins' ends on the body get caps: each pin a closed box
  for (int bx = -1; bx <= X.n; ++bx) {
    B.set_block(Vec3(X.start(bx) ? 0.0 : (X.end(bx) ? e + X.n * p : e + bx * p), 0, 0), bx);
    B.set_material(plastic);
    if (X.start(bx)) {
      // (0,0) (e,0) (e,H-c) (e-c,H) (0,H): the face at x = e touches segment 0 and is left out.
      B.prism_z({{0, 0}, {e, 0}, {e, H - c}, {e - c, H}, {0, H}}, {{0, 1, 2, 4}, {2, 3, 4, -1}}, -d / 2, d / 2, 0x1du,
                true, true);
      continue;
    }
    if (X.end(bx)) {
      // (0,0) (e,0) (e,H) (c,H) (0,H-c): the face at x = 0 touches the last segment and is left out.
      // The open variant's patches cut the end face along (0,0)-(c,H), so its triangle's chamfer edge is
      // subdivided where the segment's is not (a T-junction: 8 open edges); the closed variant cuts along
      // (0,H-c)-(e,H), mirroring the start cap, so the edges at x = 0 match the segment's.
      const std::vector<std::array<int, 4>> patches =
          closed ? std::vector<std::array<int, 4>>{{0, 1, 2, 4}, {4, 2, 3, -1}}
                 : std::vector<std::array<int, 4>>{{0, 1, 2, 3}, {0, 3, 4, -1}};
      B.prism_z({{0, 0}, {e, 0}, {e, H}, {c, H}, {0, H - c}}, patches, -d / 2, d / 2, 0x0fu, true, true);
      continue;
    }
    // Segment: (0,0) (p,0) (p,H-c) (p-c,H) (c,H) (0,H-c); sides 1 (x = p) and 5 (x = 0) are contact faces.
    B.prism_z({{0, 0}, {p, 0}, {p, H - c}, {p - c, H}, {c, H}, {0, H - c}}, {{0, 1, 2, 5}, {5, 2, 3, 4}}, -d / 2, d / 2,
              0x1du, true, true);
    B.set_material(gold);
    const double x = p / 2;
    B.frustum_y(x, 0, H, H + above - tip, a, a, closed, false);
    B.frustum_y(x, 0, H + above - tip, H + above, a, 0.5 * a, false, true);
    B.frustum_y(x, 0, -below + tip, 0, a, a, false, closed);
    B.frustum_y(x, 0, -below, -below + tip, 0.5 * a, a, true, false);
  }
}

}  // namespace detail
}  // namespace families
}  // namespace restitch

#include "restitch/families/structured.hpp"

namespace restitch {
namespace families {
namespace detail {

// ---------------------------------------------------------------------------

struct SampleFamily {
  SampleInfo (*info)();
  Status (*check)(const ParameterValues&);
  void (*build)(const ParameterValues&, SampleMeshBuilder&, SampleModel&);
  double cell;     ///< subdivision edge length at detail 1 (model units)
  double uv_unit;  ///< model units per texture repeat
};

template <class = void>
const std::vector<SampleFamily>& families() {
  static const std::vector<SampleFamily> f = {
      {bookshelf_info, bookshelf_check, bookshelf_build, 0.1, 1.0},
      {box_header_info, box_header_check, box_header_build, 1.0, 10.0},
      {cabinet_info, cabinet_check, cabinet_build, 0.1, 1.0},
      {connector_info, connector_check, connector_build, 1.0, 10.0},
      {dip_info, dip_check, dip_build, 1.0, 10.0},
      {facade_info, facade_check, facade_build, 1.0, 1.0},
      {facade_sheared_info, facade_check, facade_build, 1.0, 1.0},
      {fence_info, fence_check, fence_build, 0.1, 1.0},
      {pin_header_info, pin_header_check, pin_header_build, 1.0, 10.0},
      {radiator_info, radiator_check, radiator_build, 0.05, 1.0},
      {railing_info, railing_check, railing_build, 0.1, 1.0},
      {shutter_info, shutter_check, shutter_build, 0.05, 1.0},
      {tube_rail_info, tube_rail_check, tube_rail_build, 0.05, 1.0},
  };
  return f;
}

}  // namespace detail

}  // namespace families
}  // namespace restitch
