// restitch/offsets/refine.hpp - translation-only ICP of a point cloud onto itself.
//
// docs/method.md 1.5. A histogram peak knows its offset only to a bin (0.05). The
// offset t is refined by aligning P + t onto P, the dense point cloud onto
// itself, counting only the overlap (pairs closer than a trimming distance).
//
// The variant used here, and why:
//  * Point-to-plane with a small point-to-point term. The dense samples lie
//    exactly on planar faces, so the distance of p + t to the tangent plane of
//    its partner is (almost) free of sampling noise, where point-to-point
//    distances carry the sample spacing as noise. Each step solves the 3x3
//    system sum(n n^T + lambda I) dt = sum(n n^T e + lambda e), e = q - (p + t),
//    for the partners q (normals n) of the points p; lambda = 0.01 only
//    decides directions no normal constrains, where point-to-point is all
//    there is.
//  * Anchors (restitch's addition): the mesh vertices (the analysis passes its
//    vertex features). Faces only pin their normal direction; a thin part (a
//    picket one sample wide, seen from the side) leaves a direction pinned by
//    nothing but its edges, where point-to-plane is blind and point-to-point
//    on samples converges in hundreds of steps. Repeated modules are exact
//    translates, so their vertices are too: each anchor a whose nearest
//    anchor b to a + t is within the trim adds I dt = (b - a - t) with weight
//    1, i.e. a full point-to-point pull that is exact at the true offset.
//    Without anchors the method is the plain dense-cloud ICP.
//  * A pair counts only when the normals agree (cosine >= 0.866, i.e. within
//    30 degrees): a translation maps a face onto a parallel face, so a partner
//    with another normal is a wrong one (the neighbouring face at an edge).
//  * Two stages. Stage 1 brings the offset near: trimming distance
//    `start_trim` (0.1 = two bins: the bin centre is at most half a bin
//    diagonal, 0.043, from the true offset, plus a sample spacing of slack),
//    until a step is below 0.05 spacings. Stage 2 makes it exact: trimming at
//    the overlap radius (1.5 dense spacings) for samples and at half a spacing
//    for anchors (exact translates coincide once stage 1 is done, and a vertex
//    without a counterpart is rarely that close to another), until a step is
//    below `tolerance` (1e-5: a five-thousandth of a bin, far below the 0.5%
//    of a period the analysis promises). Each stage stops at the iteration cap.
//  * At most `max_sources` points of P (and of the anchors) are moved, an
//    even, deterministic stride; the k-d trees hold all points. 2048 sources
//    estimate a mean residual to well under a sample spacing and keep
//    refinement of ~20 peaks cheap.
//
// Overlap of an offset t: the share of the source points p whose nearest point
// of P to p + t lies within the overlap radius with an agreeing normal.
// `overlap_radius` = 1.5 dense spacings because a (near-)maximal Poisson-disk
// sample leaves no surface point farther than one spacing from a sample.
//
// Units: those of the points (the analysis: normalized). Deterministic: the
// trees are built once, from the points in order, and queried in a fixed
// order. No threads, no randomness.
// Cost: tree builds O(P log P + A log A); each ICP iteration does up to
// 2 * max_sources nearest-neighbour queries and each overlap evaluation up
// to max_sources, O(log P) each. Each query is bounded by the distance its
// caller accepts (the trim or the overlap radius), so a point that lands in
// empty space costs a few nodes, not a descent to the nearest far-away
// surface (the same answers; on the bookshelf sample, 27% fewer
// instructions in these queries and 11% fewer in the whole analysis,
// counted by valgrind --tool=callgrind).
#pragma once

#include <Eigen/Core>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <nanoflann.hpp>
#include <vector>

#include "restitch/detail/point_tree.hpp"
#include "restitch/descriptor/descriptor.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// Parameters of translation-only ICP (lengths in the points' units).
struct IcpOptions {
  double spacing = 0.02;           ///< the dense sample spacing
  double start_trim = 0.1;         ///< first-stage trimming distance (two 0.05 bins)
  double overlap_factor = 1.5;     ///< overlap radius = overlap_factor * spacing; also the second-stage trim
  double normal_cosine = 0.866;    ///< minimum cosine between the normals of a pair
  double point_weight = 0.01;      ///< lambda: weight of the point-to-point term
  double anchor_weight = 1.0;      ///< weight of an anchor's point-to-point pull (a face pair weighs 1)
  int max_iterations = 20;         ///< per stage
  double tolerance = 1e-5;         ///< stop when a step is shorter than this
  std::size_t max_sources = 2048;  ///< points of P (and anchors) moved per iteration (strided subset)

  double overlap_radius() const { return overlap_factor * spacing; }
};

/// What refinement found for one start offset.
struct RefinedOffset {
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  double overlap = 0;  ///< share of source points that land on P (see header)
  double rms = 0;      ///< RMS point-to-plane residual over the final pairs
  int iterations = 0;  ///< total over both stages
  bool converged = false;
};


/// A dense point cloud (and optional anchors) with k-d trees, built once and
/// reused for every offset. Keeps pointers to `cloud` and `anchors`: they
/// must outlive this object and not change. Not copyable (the trees refer to
/// their adaptors). `anchors` may be null or empty.
class SelfAligner {
 public:
  template <class = void>
  explicit SelfAligner(const PointSet& cloud, IcpOptions options = {}, const PointSet* anchors = nullptr)
      : options_(options) {
    init(cloud_, &cloud);
    if (anchors && anchors->size() > 0) init(anchors_, anchors);
  }
  SelfAligner(const SelfAligner&) = delete;
  SelfAligner& operator=(const SelfAligner&) = delete;

  const IcpOptions& options() const { return options_; }
  std::size_t source_count() const { return cloud_.sources.size(); }

  /// Share of the dense source points p with a partner for p + t within the
  /// overlap radius (see header). 0 for an empty cloud.
  template <class = void>
  double overlap(const Eigen::Vector3d& t) const { return overlap(t, cloud_.sources); }

  /// The same share over the given source points only (indices into the
  /// cloud; a part of the surface, offsets/part.hpp). 0 when `sources` is empty.
  template <class = void>
  double overlap(const Eigen::Vector3d& t, const std::vector<std::uint32_t>& sources) const {
    if (sources.empty()) return 0;
    const double r2 = options_.overlap_radius() * options_.overlap_radius();
    std::size_t hits = 0;
    for (std::uint32_t i : sources) {
      std::uint32_t j;
      double d2;
      if (partner(cloud_, i, t, r2, j, d2)) ++hits;
    }
    return double(hits) / double(sources.size());
  }

  /// Source subsets for refine(start, part): indices into the cloud and into
  /// the anchors (offsets/part.hpp). Targets are always the whole cloud.
  struct Sources {
    std::vector<std::uint32_t> cloud, anchors;
  };

  /// The cloud and the anchors (null when there are none) this aligner was built on.
  const PointSet& cloud() const { return *cloud_.set; }
  const PointSet* anchors() const { return anchors_.set; }

  /// Nearest cloud points to `q` within `radius` (appended to `out`, unsorted).
  template <class = void>
  void cloud_within(const Eigen::Vector3d& q, double radius, std::vector<std::uint32_t>& out) const {
    within(cloud_, q, radius, out);
  }
  /// Anchors within `radius` of `q` (appended to `out`); none without anchors.
  template <class = void>
  void anchors_within(const Eigen::Vector3d& q, double radius, std::vector<std::uint32_t>& out) const {
    if (anchors_.set) within(anchors_, q, radius, out);
  }

  /// Refines `start` by translation-only ICP (see header). Never fails; an
  /// offset with no pairs at all stays where it started, with overlap 0.
  template <class = void>
  RefinedOffset refine(const Eigen::Vector3d& start) const { return refine(start, cloud_.sources, anchors_.sources); }

  /// The same ICP moving only `part`'s sources (onto the whole cloud); the
  /// overlap returned is over `part.cloud`.
  template <class = void>
  RefinedOffset refine(const Eigen::Vector3d& start, const Sources& part) const {
    RefinedOffset r = refine(start, part.cloud, part.anchors);
    r.overlap = overlap(r.offset, part.cloud);
    return r;
  }

 private:
  template <class = void>
  RefinedOffset refine(const Eigen::Vector3d& start, const std::vector<std::uint32_t>& sources,
                       const std::vector<std::uint32_t>& anchor_sources) const {
    RefinedOffset r;
    r.offset = start;
    const double trims[2] = {std::max(options_.start_trim, options_.overlap_radius()), options_.overlap_radius()};
    const double anchor_trims[2] = {trims[0], 0.5 * options_.spacing};
    const double tolerances[2] = {std::max(options_.tolerance, 0.05 * options_.spacing), options_.tolerance};
    for (int stage = 0; stage < 2; ++stage) {
      r.converged = false;
      for (int it = 0; it < options_.max_iterations; ++it) {
        ++r.iterations;
        Eigen::Vector3d step;
        if (!solve_step(r.offset, trims[stage], anchor_trims[stage], sources, anchor_sources, step, r.rms)) break;
        r.offset += step;
        r.converged = step.norm() < tolerances[stage];
        if (r.converged) break;
      }
    }
    r.overlap = overlap(r.offset);
    return r;
  }

  struct Cloud {
    const PointSet* set = nullptr;
    detail::PointSetAdaptor adaptor{};
    std::unique_ptr<detail::PointSetTree> tree;
    std::vector<std::uint32_t> sources;
  };

  template <class = void>
  void init(Cloud& c, const PointSet* set) {
    RESTITCH_ASSERT(set->normals.rows() == set->points.rows(), "a point set needs one normal per point");
    c.set = set;
    c.adaptor.points = &set->points;
    c.tree = std::make_unique<detail::PointSetTree>(3, c.adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    const std::size_t n = std::size_t(set->points.rows());
    const std::size_t m = std::min(n, std::max<std::size_t>(options_.max_sources, 1));
    c.sources.reserve(m);
    for (std::size_t k = 0; k < m; ++k) c.sources.push_back(std::uint32_t(k * n / m));  // even stride
  }

  // Nearest point of c to point i + t, if it lies within sqrt(max_d2) and its normal agrees with
  // point i's. The bound only prunes the search (every caller rejects a farther partner).
  template <class = void>
  static bool partner(const Cloud& c, std::uint32_t i, const Eigen::Vector3d& t, std::uint32_t& j, double& d2,
                      double normal_cosine, double max_d2) {
    const PointSet& s = *c.set;
    const Eigen::Vector3d q = s.points.row(i).cast<double>().transpose() + t;
    const float qf[3] = {float(q.x()), float(q.y()), float(q.z())};
    detail::NearestWithin rs = detail::NearestWithin::keeping(max_d2);
    c.tree->findNeighbors(rs, qf, nanoflann::SearchParams());
    if (!rs.found) return false;
    const std::uint32_t idx = rs.index;
    const double cosine = double(s.normals.row(i).dot(s.normals.row(idx)));
    if (!(cosine >= normal_cosine)) return false;
    j = idx;
    d2 = (s.points.row(idx).cast<double>().transpose() - q).squaredNorm();
    return d2 <= max_d2;
  }
  template <class = void>
  bool partner(const Cloud& c, std::uint32_t i, const Eigen::Vector3d& t, double max_d2, std::uint32_t& j,
               double& d2) const {
    return partner(c, i, t, j, d2, options_.normal_cosine, max_d2);
  }

  template <class = void>
  static void within(const Cloud& c, const Eigen::Vector3d& q, double radius, std::vector<std::uint32_t>& out) {
    const float qf[3] = {float(q.x()), float(q.y()), float(q.z())};
    std::vector<std::pair<std::uint32_t, float>> found;
    c.tree->radiusSearch(qf, float(radius * radius), found, nanoflann::SearchParams(32, 0, false));  // unsorted
    for (const auto& f : found) out.push_back(f.first);
  }

  template <class = void>
  bool solve_step(const Eigen::Vector3d& t, double trim, double anchor_trim, const std::vector<std::uint32_t>& sources,
                  const std::vector<std::uint32_t>& anchor_sources, Eigen::Vector3d& step, double& rms) const {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    double sq = 0, weight = 0;
    std::size_t pairs = 0;
    const double lambda = options_.point_weight, trim2 = trim * trim;
    for (std::uint32_t i : sources) {
      std::uint32_t j;
      double d2;
      if (!partner(cloud_, i, t, trim2, j, d2)) continue;
      const PointSet& s = *cloud_.set;
      const Eigen::Vector3d n = s.normals.row(j).cast<double>().transpose();
      const Eigen::Vector3d e =
          s.points.row(j).cast<double>().transpose() - (s.points.row(i).cast<double>().transpose() + t);
      const double en = e.dot(n);
      H += n * n.transpose();
      g += n * en + lambda * e;
      weight += lambda;
      sq += en * en;
      ++pairs;
    }
    if (anchors_.set) {
      const double w = options_.anchor_weight, atrim2 = anchor_trim * anchor_trim;
      for (std::uint32_t i : anchor_sources) {
        std::uint32_t j;
        double d2;
        if (!partner(anchors_, i, t, atrim2, j, d2)) continue;
        const PointSet& s = *anchors_.set;
        g += w * (s.points.row(j).cast<double>().transpose() - (s.points.row(i).cast<double>().transpose() + t));
        weight += w;
      }
    }
    if (pairs == 0 && weight == 0) return false;
    H += weight * Eigen::Matrix3d::Identity();
    step = H.ldlt().solve(g);
    rms = pairs ? std::sqrt(sq / double(pairs)) : 0.0;
    return step.allFinite();
  }

  IcpOptions options_;
  Cloud cloud_, anchors_;
};

}  // namespace restitch
