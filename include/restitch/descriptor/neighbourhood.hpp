// restitch/descriptor/neighbourhood.hpp - fixed-radius neighbour search with
// PCL's membership rule, shared by the SHOT and FPFH descriptor policies.
//
// `detail::RadiusSearch` builds one nanoflann k-d tree over a set of support
// points and answers "which support points lie within R of q?" exactly as PCL
// 1.13's KdTreeFLANN does (docs/descriptors.md, N1-N2):
//
//   * the squared distance is computed in float32 as ((dx*dx + dy*dy) + dz*dz)
//     (FLANN's L2_Simple<float>), and a point j is a neighbour iff
//     d2(q, j) < float(double(R) * double(R)), a strict test: a point at exactly
//     R is excluded, the query itself (d2 = 0) is included;
//   * the distances handed back are those squared float distances;
//   * support points with a non-finite coordinate are never neighbours (PCL
//     drops them from its tree).
//
// nanoflann only proposes candidates (its search radius is slightly inflated);
// membership is then decided by the float test above, so it does not depend
// on nanoflann's own arithmetic. Results come in the tree's traversal order,
// which is deterministic for a given support set (and, as the tree splits at
// bounding-box midpoints, unchanged by an exactly representable translation).
// PCL's order is its own tree's; order only changes float summation, about
// 1e-7. (Sorting by index cost about 20% of SHOT's time, so it is not done.)
//
// Contract: the support points are copied once (finite ones only, 12 bytes
// each) at construction; `find` clears and fills a caller-owned vector, so a
// loop over queries allocates nothing once the vector has grown. A query with
// a non-finite coordinate has no neighbours.
//
// Cost: construction O(P log P); a query O(log P + k) for k candidates.
//
// nanoflann 1.4.3 contains `throw` statements (unreachable in the way
// restitch uses the tree: it is built before any search, an empty tree is
// never searched), so a build with -fno-exceptions fails inside nanoflann.
// restitch's builds keep exceptions enabled natively and use Emscripten's
// default mode, which accepts `throw`; restitch itself never throws.
//
// Floating-point contraction: the distance test reproduces PCL only when the
// compiler does not fuse a*b+c into an FMA. Baseline x86-64 and wasm32 have no
// FMA instructions; on targets that do, build with -ffp-contract=off.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <nanoflann.hpp>
#include <string>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/mesh.hpp"
#include "restitch/status.hpp"

namespace restitch {
namespace detail {

/// Shared argument checks of the descriptor policies.
template <class = void>
Status check_descriptor_input(const char* policy, float radius, const PointSet& support,
                                     const PointSet& queries) {
  if (!(radius > 0.0f) || !std::isfinite(radius)) {
    return error(StatusCode::invalid_argument,
                 std::string(policy) + ": radius must be positive and finite, got " + std::to_string(radius));
  }
  if (support.points.rows() != support.normals.rows()) {
    return error(StatusCode::invalid_argument, std::string(policy) + ": support set has " +
                                                   std::to_string(support.points.rows()) + " points but " +
                                                   std::to_string(support.normals.rows()) + " normals");
  }
  if (queries.points.rows() != queries.normals.rows()) {
    return error(StatusCode::invalid_argument, std::string(policy) + ": query set has " +
                                                   std::to_string(queries.points.rows()) + " points but " +
                                                   std::to_string(queries.normals.rows()) + " normals");
  }
  if (support.points.rows() > static_cast<Eigen::Index>(std::numeric_limits<std::uint32_t>::max() / 2)) {
    return error(StatusCode::too_large, std::string(policy) + ": support set has more than 2^31 points");
  }
  return Status();
}

/// How many queries between two progress reports.
constexpr Eigen::Index descriptor_progress_stride = 2048;

/// One neighbour: its row in the support set and its squared float distance.
struct Neighbour {
  std::uint32_t index;
  float sqr_distance;
};

/// PCL's squared distance: FLANN's L2_Simple<float>, ((dx*dx + dy*dy) + dz*dz).
template <class = void>
float pcl_sqr_distance(const float* a, const float* b) {
  const float dx = a[0] - b[0];
  const float dy = a[1] - b[1];
  const float dz = a[2] - b[2];
  float r = dx * dx;
  r += dy * dy;
  r += dz * dz;
  return r;
}

/// Fixed-radius search over support points; see the file comment.
class RadiusSearch {
 public:
  /// points: #P by 3 (rows may be non-finite: they are left out).
  /// radius > 0 and finite (the caller validates it).
  template <class = void>
  RadiusSearch(const MatrixX3f& points, double radius)
      : sqr_radius_(static_cast<float>(radius * radius)), adaptor_{&packed_}, tree_(3, adaptor_, params()) {
    RESTITCH_ASSERT(radius > 0 && std::isfinite(radius), "RadiusSearch needs a positive finite radius");
    packed_.reserve(static_cast<std::size_t>(points.rows()) * 3);
    ids_.reserve(static_cast<std::size_t>(points.rows()));
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      const float x = points(i, 0), y = points(i, 1), z = points(i, 2);
      if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(z))) continue;
      packed_.push_back(x);
      packed_.push_back(y);
      packed_.push_back(z);
      ids_.push_back(static_cast<std::uint32_t>(i));
    }
    // Candidates are proposed with a slightly larger radius, then filtered
    // exactly; the margin covers any rounding difference in nanoflann.
    search_radius_ = sqr_radius_ * 1.0001f + std::numeric_limits<float>::min();
    if (!ids_.empty()) tree_.buildIndex();
  }

  RadiusSearch(const RadiusSearch&) = delete;
  RadiusSearch& operator=(const RadiusSearch&) = delete;

  /// The squared radius used by the membership test: float(R*R).
  float sqr_radius() const { return sqr_radius_; }

  /// Clears `out` and fills it with the support points within R of q
  /// (strict, float32), in tree order.
  template <class = void>
  void find(const float* q, std::vector<Neighbour>& out) const {
    out.clear();
    if (ids_.empty() || !(std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]))) return;
    Collector collector{this, q, &out};
    tree_.findNeighbors(collector, q, nanoflann::SearchParams(32, 0.0f, false));
  }

 private:
  // nanoflann's dataset adaptor contract: point count, coordinate access and
  // an optional bounding box (false: let the tree compute it).
  struct Adaptor {
    const std::vector<float>* xyz;
    std::size_t kdtree_get_point_count() const { return xyz->size() / 3; }
    float kdtree_get_pt(std::size_t i, std::size_t d) const { return (*xyz)[3 * i + d]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const {
      return false;
    }
  };
  using Tree =
      nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Adaptor>, Adaptor, 3, std::uint32_t>;

  // nanoflann's result-set contract for findNeighbors: worstDist() bounds the
  // search, addPoint() receives each candidate (returning true continues).
  struct Collector {
    const RadiusSearch* self;
    const float* q;
    std::vector<Neighbour>* out;
    float worstDist() const { return self->search_radius_; }
    std::size_t size() const { return out->size(); }
    bool full() const { return true; }
    template <class = void>
    bool addPoint(float, std::uint32_t i) {
      const float d2 = pcl_sqr_distance(q, &self->packed_[3 * static_cast<std::size_t>(i)]);
      if (d2 < self->sqr_radius_) out->push_back(Neighbour{self->ids_[i], d2});
      return true;
    }
  };

  template <class = void>
  static nanoflann::KDTreeSingleIndexAdaptorParams params() {
    return nanoflann::KDTreeSingleIndexAdaptorParams(16,
                                                     nanoflann::KDTreeSingleIndexAdaptorFlags::SkipInitialBuildIndex);
  }

  float sqr_radius_;
  float search_radius_ = 0.0f;
  std::vector<float> packed_;       // finite support points, xyz interleaved
  std::vector<std::uint32_t> ids_;  // their rows in the support set
  Adaptor adaptor_;
  Tree tree_;
};

}  // namespace detail
}  // namespace restitch
