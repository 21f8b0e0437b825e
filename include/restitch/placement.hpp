// restitch/placement.hpp - where a resized model sits, and exact sizes (docs/method.md 2.7).
//
// The stitched result keeps the input's canonical cell 0 in place and grows
// at the far end of every lattice axis. `place` turns that into what a
// modeller expects: a *pivot* stays put and growth goes away from it. The
// pivot is chosen per world axis x, y, z:
//
//   origin  (default) the model's origin (0,0,0), clamped into its bounding
//           box: the content there stays where it is. Along a lattice axis,
//           with the model's structure (restitch/lattice/structure.hpp): at
//           the model's centre (a quarter period) the centre stays unless a
//           centred part holds the origin; otherwise in
//           a part that occurs once, that part stays (a part at an end keeps
//           that end fixed, a centred one takes its centring shift); in repeated
//           content, the end of the model nearer to it stays fixed, and growth
//           splits evenly when it lies at the model's centre (within a
//           quarter period: halfway to where pin 1 of a two-pin part lies),
//           or within half a period of it in a module that is not the first
//           or the last that repeats. So a connector whose housing reaches past pin 1
//           at the origin keeps pin 1 where it was, whatever the grid phase.
//           Without the structure (RetargetOptions::keep_parts off, the
//           regular baseline), or along an axis where no cell repeats, the
//           cell holding it decides: the first cell
//           keeps that end, the last cell the other, any other splits evenly
//           (the centre staying when the origin is at the box's centre).
//           A single-cell axis keeps the end of the half the origin lies in.
//   min     the end at the bounding box's minimum stays fixed.
//   max     the end at the bounding box's maximum stays fixed.
//   center  growth is split evenly between both ends.
//
// An even split of an odd count puts the odd cell on the max side: +3 adds 1
// cell at the min end and 2 at the max end, -3 removes 1 and 2. A lattice
// axis takes the pivot of the world axis it runs along (world_axis_of).
// Growth is in whole lattice cells, so the translation applied is a whole
// number of periods along every principal offset: -(cells added at the low
// end) * v_a, summed over the axes, and repeated parts of the result lie
// exactly where the input's lie; except where the centre stays (`center`,
// or `origin` at the model's centre): there the translation is -(k_a / 2)
// v_a, half a period more at an odd k_a, so the result is centred where the
// input was (a package built about its centre, 7 pins a side from 6). The
// pivot *point* reported (per world axis: the clamped origin, the box
// minimum, centre or maximum) is where the pivot is; with an odd split of
// `origin` in a middle cell away from the centre the content there moves by
// half a period, since a cell cannot be split.
//
// Exact sizes: `scale_about` scales a mesh along the world axes about a
// point (positions, normals by the inverse transpose, tangents), which the
// retargeter uses to bring the nearest whole-repeat result to an asked size.
//
// Cost: O(1) for `place`, O(#V) for `scale_about`. Nothing throws.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "restitch/analysis.hpp"
#include "restitch/lattice/lattice.hpp"
#include "restitch/mesh.hpp"
#include "restitch/lattice/structure.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// What stays put along one world axis when a model is resized (see the file comment).
enum class Pivot { origin, min, center, max };
/// One pivot per world axis x, y, z.
using Pivots = std::array<Pivot, 3>;

template <class = void>
const char* pivot_name(Pivot p) {
  switch (p) {
    case Pivot::origin: return "origin";
    case Pivot::min: return "min";
    case Pivot::center: return "center";
    case Pivot::max: return "max";
  }
  return "origin";
}

/// "origin", "min", "center" or "max" for all three axes, or three of them comma-separated for x,y,z.
template <class = void>
Result<Pivots> parse_pivots(const std::string& text) {
  auto one = [](const std::string& s, Pivot& out) {
    for (Pivot p : {Pivot::origin, Pivot::min, Pivot::center, Pivot::max})
      if (s == pivot_name(p)) return out = p, true;
    return false;
  };
  std::array<std::string, 3> parts;
  int n = 0;
  std::string cur;
  for (const char c : text + ",") {
    if (c != ',') {
      cur += c;
      continue;
    }
    if (n == 3) return error(StatusCode::invalid_argument, "pivot '" + text + "': give one value or three (x,y,z)");
    parts[std::size_t(n++)] = cur;
    cur.clear();
  }
  if (n != 1 && n != 3) return error(StatusCode::invalid_argument, "pivot '" + text + "': give one value or three (x,y,z)");
  Pivots out{};
  for (int a = 0; a < 3; ++a) {
    const std::string& s = parts[std::size_t(n == 1 ? 0 : a)];
    if (!one(s, out[std::size_t(a)]))
      return error(StatusCode::invalid_argument, "pivot '" + s + "'" + (n == 3 ? std::string(" for ") + "xyz"[a] : "") +
                                                     ": known are origin, min, center, max");
  }
  return out;
}

/// Where a resize puts its result (model units unless said otherwise).
struct Placement {
  Pivots modes{{Pivot::origin, Pivot::origin, Pivot::origin}};
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();        ///< the pivot point, per world axis (file comment)
  Eigen::Array3i low_cells = Eigen::Array3i::Zero();      ///< cells added (< 0: removed) at each lattice axis's low end
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();  ///< applied to the stitched result: -A * low_cells, or -A * steps / 2 where the centre stays
};

/// The placement of a resize by lattice `steps` (per axis of `L`, the analysis lattice) of a model whose
/// bounding box is `box`, with `modes` per world axis. `structure` (on the cells of L; null: none) places
/// by content for the `origin` mode (see the file comment).
template <class = void>
Placement place(const Lattice& L, const BoundingBox& box, const Eigen::Array3i& steps, const Pivots& modes,
                const CellStructure* structure = nullptr) {
  Placement out;
  out.modes = modes;
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero().cwiseMax(box.min).cwiseMin(box.max);
  for (int w = 0; w < 3; ++w) switch (modes[std::size_t(w)]) {
      case Pivot::origin: out.pivot[w] = origin[w]; break;
      case Pivot::min: out.pivot[w] = box.min[w]; break;
      case Pivot::center: out.pivot[w] = box.center()[w]; break;
      case Pivot::max: out.pivot[w] = box.max[w]; break;
    }
  const Eigen::Vector3d c = L.to_canonical(origin);
  for (int a = 0; a < 3; ++a) {
    const int k = steps[a];
    if (L.dummy[a] || k == 0) continue;
    const int w = world_axis_of(L.A.col(a));
    const bool low_is_min = L.A(w, a) > 0;  // the sign rule of docs/method.md 1.6 makes this the usual case
    const int keep_low = 0, keep_high = k;
    const int split = low_is_min ? k / 2 : k - k / 2;  // k / 2 truncates: the odd cell goes to the max side
    int low = keep_low;
    bool centred = false;  // the model's centre stays put: an odd count is placed half a period off the cells
    switch (modes[std::size_t(w)]) {
      case Pivot::min: low = low_is_min ? keep_low : keep_high; break;
      case Pivot::max: low = low_is_min ? keep_high : keep_low; break;
      case Pivot::center: low = split, centred = true; break;
      case Pivot::origin: {
        const int n = L.cells[a];
        const int j = std::clamp(int(std::floor(c[a])), 0, n - 1);
        // By content where the structure says what repeats along a (not along an undecided axis, or one too
        // short to compare: there the cells decide, as without it).
        const std::vector<int>* copies = structure && n > 1 ? &structure->copy_of[std::size_t(a)] : nullptr;
        if (copies && std::any_of(copies->begin(), copies->end(), [](int i) { return i >= 0; })) {
          // Within a quarter period of the centre: split (a package built about its centre, whose key or
          // marker at one end moves the box's centre a little), also where the cell there belongs to a part
          // at an end (the marker of a 3-pin package reaching into the middle pin's cell). Otherwise in a
          // part: the part stays where it is (a centred one too, at the centre: it stays whole cells where
          // it was). In the first or last module that repeats (pin 1 of a two-pin
          // part, half a period from its centre): the nearer end. Elsewhere within half a period of the
          // centre: split.
          const double to_low = c[a] - structure->extent_low[a], to_high = structure->extent_high[a] - c[a];
          const double off = std::abs(to_low - to_high) / 2;
          centred = off <= structure->centre_near(a);
          const SingularPart* p = structure->part_of(a, j);
          if (p && centred && p->anchor != PartAnchor::centre) p = nullptr;
          if (p) {
            centred = false;
            low = CellStructure::shift_of(*p, k);  // the part stays where it is
          } else {
            int first = 0, last = n - 1;
            while (first < n - 1 && !structure->repeats(a, first)) ++first;
            while (last > 0 && !structure->repeats(a, last)) --last;
            const bool next_to_end = j <= first || j >= last;
            low = centred || (!next_to_end && off <= structure->centre_band(a)) ? split
                  : to_low < to_high                                            ? keep_low
                                                                                : keep_high;
          }
        } else if (n == 1)
          low = c[a] < 0.5 ? keep_low : keep_high;
        else if (j == 0)
          low = keep_low;
        else if (j == n - 1)
          low = keep_high;
        else {  // a middle cell splits; at the box's centre (a quarter period, as above) the centre stays
          low = split;
          centred = std::abs(c[a] - L.to_canonical(box.center())[a]) <= CellStructure::centre_quarter;
        }
        break;
      }
    }
    out.low_cells[a] = low;
    // Half of the growth at each end: k / 2 periods, a half period more than the whole cells at an odd k.
    out.translation -= (centred ? 0.5 * double(k) : double(low)) * L.A.col(a);
  }
  return out;
}

/// Scales `m` by `factors` along the world axes about `pivot`: positions, normals (inverse transpose,
/// renormalised) and tangents (xyz scaled and renormalised, w kept). Factors must be positive.
template <class = void>
void scale_about(Mesh& m, const Eigen::Vector3d& factors, const Eigen::Vector3d& pivot) {
  for (Eigen::Index v = 0; v < m.V.rows(); ++v)
    for (int i = 0; i < 3; ++i) m.V(v, i) = float(pivot[i] + (double(m.V(v, i)) - pivot[i]) * factors[i]);
  auto rescale = [](float* p, const Eigen::Vector3d& f) {
    Eigen::Vector3d q(double(p[0]) * f[0], double(p[1]) * f[1], double(p[2]) * f[2]);
    const double n = q.norm();
    if (!(n > 0)) return;
    q /= n;
    for (int i = 0; i < 3; ++i) p[i] = float(q[i]);
  };
  const Eigen::Vector3d inverse = factors.cwiseInverse();
  for (Eigen::Index v = 0; v < m.N.rows(); ++v) rescale(&m.N(v, 0), inverse);
  for (Eigen::Index v = 0; v < m.T.rows(); ++v) rescale(&m.T(v, 0), factors);
}

/// Translates every vertex of `m` by `t`.
template <class = void>
void translate(Mesh& m, const Eigen::Vector3d& t) {
  if (t.isZero()) return;
  for (Eigen::Index v = 0; v < m.V.rows(); ++v)
    for (int i = 0; i < 3; ++i) m.V(v, i) = float(double(m.V(v, i)) + t[i]);
}

}  // namespace restitch
