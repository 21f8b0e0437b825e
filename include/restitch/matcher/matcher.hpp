// restitch/matcher/matcher.hpp - the matcher policy contract (docs/method.md 1.3).
//
// For every feature x a matcher finds the feature y minimising the descriptor
// distance |S(y) - S(x)|_2 subject to |y - x| > tau; the offset y - x is one
// vote of the offset statistics. restitch ships BruteForceMatcher (the exact
// reference, matcher/brute_force.hpp) and ReducedMatcher (PCA lower bounds
// with exact re-ranking, matcher/reduced.hpp). A user may plug in any type
// that satisfies this contract:
//
//   struct MyMatcher {
//     // out is resized to #features. out[i] is the match of feature i.
//     restitch::Status match(const restitch::PointSet& features,
//                            const restitch::DescriptorMatrix& descriptors,
//                            float tau,
//                            std::vector<restitch::Match>& out,
//                            const restitch::Progress& progress) const;
//   };
//
// The answer is fully specified, so every exact matcher returns the same
// vector bit for bit:
//   * features.points row i is x_i (normalized units); descriptors row i is
//     S(x_i) (#features by D, D >= 1).
//   * Admissible targets of i: every j != i with |x_j - x_i| > tau, strictly,
//     evaluated as sum_k (double(x_j,k) - double(x_i,k))^2 > double(tau)^2, and
//     with a finite descriptor row and finite position.
//   * Descriptor distance d(i, j) = sqrt(sum_k (double(S_jk) - double(S_ik))^2),
//     summed in k order, in double.
//   * d* = min over admissible j of d(i, j). The tie set is every admissible j
//     with d(i, j) - d* <= max(ties.relative * d(i, j), ties.absolute), i.e.
//     |d1 - d2| <= 1e-6 max(d1, d2) by default, with an absolute floor of 1e-6
//     descriptor units so that exact duplicates (d = 0) and float noise around
//     0 count as ties. SHOT is L2-normalised, so descriptor units are those of
//     a unit vector.
//   * The match is the member of the tie set with the shortest offset
//     |x_j - x_i| (squared, in double as above), then the lowest index j: on
//     repeated geometry the votes gather on the fundamental period.
//   * out[i] = {j, float(d(i, j))}. Rows with any non-finite value (NaN or
//     infinity) in the descriptor or the position never match and are never
//     matched: {-1, +infinity}. So is a feature with no admissible target.
//   * Errors: invalid_argument (descriptors.rows() != #features, D == 0 with
//     features present, tau negative or not finite), too_large (more than
//     2^31 - 1 features), cancelled. On error `out` is unspecified.
//   * Deterministic; no threads; Progress stage "matching".
//
// `is_matcher_policy_v<T>` checks the signature; the analysis entry point
// static_asserts it.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/progress.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// The match of one feature: the target feature's index (-1: none) and the
/// descriptor distance to it.
struct Match {
  std::int32_t target = -1;
  float distance = std::numeric_limits<float>::infinity();
  bool operator==(const Match& o) const { return target == o.target && distance == o.distance; }
  bool operator!=(const Match& o) const { return !(*this == o); }
};

/// When two descriptor distances count as equal (see the contract above).
/// relative must be in [0, 1), absolute >= 0.
struct TieRule {
  double relative = 1e-6;
  double absolute = 1e-6;
  /// d (>= dstar) ties with the best distance dstar.
  bool ties(double d, double dstar) const { return d - dstar <= std::max(relative * d, absolute); }
  /// An upper bound on every distance that can tie with a best distance <= u.
  double upper(double u) const { return std::max(u / (1.0 - relative), u + absolute) * (1.0 + 1e-12); }
};

namespace detail {
template <class T, class = void>
struct is_matcher_policy : std::false_type {};
template <class T>
struct is_matcher_policy<
    T, std::void_t<decltype(std::declval<const T&>().match(
           std::declval<const PointSet&>(), std::declval<const DescriptorMatrix&>(), std::declval<float>(),
           std::declval<std::vector<Match>&>(), std::declval<const Progress&>()))>>
    : std::bool_constant<std::is_same_v<decltype(std::declval<const T&>().match(
                                            std::declval<const PointSet&>(), std::declval<const DescriptorMatrix&>(),
                                            std::declval<float>(), std::declval<std::vector<Match>&>(),
                                            std::declval<const Progress&>())),
                                        Status>> {};
}  // namespace detail

template <class T>
inline constexpr bool is_matcher_policy_v = detail::is_matcher_policy<T>::value;

}  // namespace restitch
