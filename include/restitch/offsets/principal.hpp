// restitch/offsets/principal.hpp - principal offsets from dominant offsets, and dummy directions.
//
// docs/method.md 1.6 (the paper's Sec. V). Greedy over the dominant offsets in
// their ranked order: v1 = the first; v2 = the first with
// |cos angle(v1, v2)| <= cos(min_angle); v3 = the first that passes that test
// against both v1 and v2. At most three. min_angle is pi/3 (60 degrees); an
// offset exactly at 60 degrees passes (the paper's <=), with 1e-12 of slack on
// the cosine so rounding cannot decide the boundary case. Zero-length or
// non-finite offsets are skipped.
//
// Sign convention (for reporting and for the lattice): every principal offset
// and dummy direction is flipped so that its largest-magnitude component is
// positive; between components of equal magnitude the lowest axis (x, then y,
// then z) decides. A lattice generator and its negative are the same lattice,
// so this only makes the output stable.
//
// Dummy directions (never resized along; they only discretise space), of
// length `dummy_length` (0.2 normalized):
//  * 2 real offsets: the direction of v1 x v2.
//  * 1 real offset v: the world axes other than the one most aligned with v
//    (largest |component|, lowest axis on a tie), in axis order a < b:
//    d1 = e_a made orthogonal to v (Gram-Schmidt), d2 = v x d1 normalized.
//    When v lies along a world axis the dummies are exactly the other two
//    world axes.
//  * 0 real offsets: the three world axes.
// Then the sign convention above is applied to each dummy.
//
// Fundamentals (restitch's addition, `reduce_to_fundamentals`, applied by the
// analysis before the greedy selection): once sampling noise breaks the exact
// descriptor ties, a pin matches its neighbours one, two and three pitches
// away about equally well, so the most-voted offset can be twice the period.
// Each offset d that is, within `tolerance`, an integer multiple k*e
// (|k| >= 2) of a shorter offset e of the same list is replaced by the
// shortest such e (with the sign of d). The list keeps its order; the greedy
// then skips the repeated entries because they are parallel.
//
// Units: whatever the offsets are in (the analysis passes normalized ones).
// Cost: O(#dominant) for the selection, O(#dominant^2) for the fundamentals.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/QR>
#include <array>
#include <cmath>
#include <vector>

namespace restitch {

/// Up to three principal offsets, completed to a basis by dummy directions.
struct PrincipalOffsets {
  std::array<Eigen::Vector3d, 3> axes{{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}};
  std::array<bool, 3> dummy{{true, true, true}};  ///< axes[a] is a dummy direction
  int real_count = 0;                             ///< axes[0 .. real_count) are real, in selection order
  std::array<int, 3> source{
      {-1, -1, -1}};  ///< index in the input list of the offset that gave each real axis; -1: dummy
};

/// Flips v so that its largest-magnitude component (lowest axis on ties) is positive.
template <class = void>
Eigen::Vector3d canonical_sign(const Eigen::Vector3d& v) {
  int k = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(v[a]) > std::abs(v[k])) k = a;
  return v[k] < 0 ? Eigen::Vector3d(-v) : v;
}

/// True when the angle between a and b is at least `min_angle` (up to sign):
/// |cos| <= cos(min_angle) + 1e-12.
template <class = void>
bool far_enough_apart(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double min_angle) {
  const double c = std::abs(a.dot(b)) / (a.norm() * b.norm());
  return c <= std::cos(min_angle) + 1e-12;
}

/// True when `v` is, within `tolerance`, a non-zero integer combination of the linearly independent
/// `basis` (the principal offsets), or k times `other` for an integer |k| >= 1.
template <class = void>
bool is_lattice_vector(const Eigen::Vector3d& v, const std::vector<Eigen::Vector3d>& basis,
                              const Eigen::Vector3d* other, double tolerance) {
  if (other && other->squaredNorm() > 0) {
    const double k = std::round(v.dot(*other) / other->squaredNorm());
    if (std::abs(k) >= 1 && (v - k * *other).norm() <= tolerance) return true;
  }
  if (basis.empty()) return false;
  Eigen::MatrixXd B(3, Eigen::Index(basis.size()));
  for (std::size_t k = 0; k < basis.size(); ++k) B.col(Eigen::Index(k)) = basis[k];
  const Eigen::VectorXd c = B.colPivHouseholderQr().solve(v).array().round().matrix();
  return c.cwiseAbs().maxCoeff() >= 1 && (B * c - v).norm() <= tolerance;
}

/// A linearly independent subset of `offsets`, taken greedily in their order: each offset joins when
/// it is longer than `tolerance` and farther than `tolerance` from the span of those already taken
/// (at most three). A basis for is_lattice_vector.
template <class = void>
std::vector<Eigen::Vector3d> independent_offsets(const std::vector<Eigen::Vector3d>& offsets,
                                                        double tolerance) {
  std::vector<Eigen::Vector3d> basis;
  for (const Eigen::Vector3d& v : offsets) {
    if (basis.size() == 3 || !v.allFinite() || !(v.norm() > tolerance)) continue;
    Eigen::Vector3d rest = v;  // v minus its projection on the span (Gram-Schmidt on the taken ones)
    std::vector<Eigen::Vector3d> q;
    for (const Eigen::Vector3d& b : basis) {
      Eigen::Vector3d u = b;
      for (const Eigen::Vector3d& e : q) u -= u.dot(e) * e;
      q.push_back(u.normalized());
    }
    for (const Eigen::Vector3d& e : q) rest -= rest.dot(e) * e;
    if (rest.norm() > tolerance) basis.push_back(v);
  }
  return basis;
}

/// Replaces each offset that is an integer multiple (|k| >= 2, within
/// `tolerance`) of a shorter offset of the list by the shortest such one, with
/// d's sign (see header). Order and length are kept.
template <class = void>
std::vector<Eigen::Vector3d> reduce_to_fundamentals(const std::vector<Eigen::Vector3d>& ranked,
                                                           double tolerance) {
  std::vector<Eigen::Vector3d> out = ranked;
  for (std::size_t i = 0; i < ranked.size(); ++i) {
    const Eigen::Vector3d& d = ranked[i];
    double best = d.norm();
    for (const Eigen::Vector3d& e : ranked) {
      const double le = e.norm();
      if (!(le > 0) || !(le < best) || !e.allFinite()) continue;
      const double k = std::round(d.dot(e) / (le * le));
      if (std::abs(k) < 2) continue;
      if ((d - k * e).norm() <= tolerance) {
        best = le;
        out[i] = k > 0 ? e : Eigen::Vector3d(-e);
      }
    }
  }
  return out;
}

template <class = void>
void complete_with_dummies(PrincipalOffsets& p, double dummy_length = 0.2);

/// The greedy selection and the dummies (see header). `dominant` in ranked order.
template <class = void>
PrincipalOffsets select_principal_offsets(const std::vector<Eigen::Vector3d>& dominant,
                                                 double min_angle = 3.14159265358979323846 / 3,
                                                 double dummy_length = 0.2) {
  PrincipalOffsets p;
  for (std::size_t i = 0; i < dominant.size() && p.real_count < 3; ++i) {
    const Eigen::Vector3d& v = dominant[i];
    if (!v.allFinite() || !(v.norm() > 0)) continue;
    bool ok = true;
    for (int k = 0; k < p.real_count && ok; ++k) ok = far_enough_apart(p.axes[std::size_t(k)], v, min_angle);
    if (!ok) continue;
    p.axes[std::size_t(p.real_count)] = canonical_sign(v);
    p.dummy[std::size_t(p.real_count)] = false;
    p.source[std::size_t(p.real_count)] = int(i);
    ++p.real_count;
  }
  complete_with_dummies(p, dummy_length);
  return p;
}

/// Sets the dummy directions of p (axes[real_count ..]) from its real axes, as the header says. The
/// analysis calls it again once the real axes are snapped onto the vertices: dummies made orthogonal to
/// an offset before it was snapped keep its noise (a drawer pitch 1e-4 off the y axis tilted every cell
/// plane across the dresser by as much, so each seam cut its boards on a slant).
template <class>
void complete_with_dummies(PrincipalOffsets& p, double dummy_length) {
  const auto dummy = [&](const Eigen::Vector3d& dir) { return canonical_sign(dir.normalized() * dummy_length); };
  if (p.real_count == 2) {
    p.axes[2] = dummy(p.axes[0].cross(p.axes[1]));
  } else if (p.real_count == 1) {
    const Eigen::Vector3d v = p.axes[0].normalized();
    int m = 0;
    for (int a = 1; a < 3; ++a)
      if (std::abs(v[a]) > std::abs(v[m])) m = a;
    const int a = m == 0 ? 1 : 0;
    const Eigen::Vector3d ea = Eigen::Vector3d::Unit(a);
    const Eigen::Vector3d d1 = (ea - ea.dot(v) * v).normalized();
    p.axes[1] = dummy(d1);
    p.axes[2] = dummy(v.cross(d1));
  } else if (p.real_count == 0) {
    for (int a = 0; a < 3; ++a) p.axes[std::size_t(a)] = Eigen::Vector3d::Unit(a) * dummy_length;
  }
}

}  // namespace restitch
