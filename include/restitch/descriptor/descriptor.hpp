// restitch/descriptor/descriptor.hpp - the descriptor policy contract.
//
// A descriptor policy turns a point with its neighbourhood into a vector of
// numbers that is equal for equal geometry. restitch ships SHOT (default) and
// FPFH; a user may plug in any type that satisfies this contract:
//
//   struct MyDescriptor {
//     // Values per descriptor.
//     int dimension() const;
//     // One row per query point, in query order, computed with the points of
//     // `support` as the neighbourhood. `out` is resized to
//     // #queries by dimension(). A row that cannot be computed (too few
//     // neighbours, NaN input) is all NaN; matchers skip such rows.
//     // Lengths inside the policy (its radius) are in the units of the points
//     // it is given: the analysis passes normalized coordinates.
//     restitch::Status compute(const restitch::PointSet& support,
//                              const restitch::PointSet& queries,
//                              restitch::DescriptorMatrix& out,
//                              const restitch::Progress& progress) const;
//   };
//
// The run-time parameters (radius, ...) are members of the policy object.
// `is_descriptor_policy_v<T>` checks the contract at compile time; the
// pipeline's entry point static_asserts it with a readable message.
#pragma once

#include <Eigen/Core>
#include <type_traits>
#include <utility>

#include "restitch/mesh.hpp"
#include "restitch/progress.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// Points with unit normals. points, normals: #P by 3.
struct PointSet {
  MatrixX3f points;
  MatrixX3f normals;
  Eigen::Index size() const { return points.rows(); }
};

/// #Q by D descriptor values, one row per point.
using DescriptorMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

namespace detail {
template <class T, class = void>
struct is_descriptor_policy : std::false_type {};
template <class T>
struct is_descriptor_policy<T, std::void_t<decltype(std::declval<const T&>().dimension()),
                                           decltype(std::declval<const T&>().compute(
                                               std::declval<const PointSet&>(), std::declval<const PointSet&>(),
                                               std::declval<DescriptorMatrix&>(), std::declval<const Progress&>()))>>
    : std::bool_constant<std::is_convertible_v<decltype(std::declval<const T&>().dimension()), int> &&
                         std::is_same_v<decltype(std::declval<const T&>().compute(
                                            std::declval<const PointSet&>(), std::declval<const PointSet&>(),
                                            std::declval<DescriptorMatrix&>(), std::declval<const Progress&>())),
                                        Status>> {};
}  // namespace detail

template <class T>
inline constexpr bool is_descriptor_policy_v = detail::is_descriptor_policy<T>::value;

}  // namespace restitch
