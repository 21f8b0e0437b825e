// restitch/matcher/reduced.hpp - PCA lower bounds, exact re-ranking (docs/method.md 1.3).
//
// ReducedMatcher implements the matcher contract of matcher/matcher.hpp and
// returns exactly what BruteForceMatcher returns (same targets, same
// distances, bit for bit) on every input: it is exact by construction, only
// faster when the descriptors' variance lives in few directions (SHOT on
// man-made models).
//
// Method. P holds the `dimensions` leading principal directions of the
// descriptors (covariance of at most `pca_rows` rows taken at an even
// stride; any orthonormal P keeps the bound valid, so this estimate only
// affects speed). Each descriptor a becomes e(a) = [P^T (a - m), |r(a)|] with
// r(a) the residual of a - m outside span(P). Then
//     |e(a) - e(b)|^2 = |P^T (a - b)|^2 + (|r(a)| - |r(b)|)^2 <= |a - b|^2,
// a lower bound (the triangle inequality on the residuals). Two passes of
// the symmetric blocked scan run in this (dimensions + 1)-dimensional space:
//   1. the `seeds` smallest lower bounds per feature; their exact distances
//      give an upper bound U >= d* of the best distance;
//   2. every admissible target whose lower bound is <= upper(U)^2 + E (E: a
//      rigorous bound on the float and residual rounding) is a candidate;
//      nothing that can tie is missed. Exact re-ranking and the tie rule as
//      in BruteForceMatcher.
// When D <= dimensions + 1 the reduction is pointless and BruteForceMatcher
// runs instead.
//
// Cost: O(#F D^2 + min(#F, pca_rows) D^2 + D^3) for the basis and embedding,
// then 2 x #F^2 (dimensions + 1) flops in float matrix products (half
// products, as brute force) plus O(D) per candidate. Dense ties (many
// identical descriptors) make the candidate lists long; that cost is the same
// in brute force. Measured (g++ -O2, SSE2, one core, CPU time, the synthetic
// data of the brute-force measurement): 10k x 352 in 0.5 s, 25k x 352 in
// 2.3-2.9 s; the pair scan and the small products dominate, so `dimensions`
// matters little (8: 0.46 s, 32: 0.64 s at 10k).
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/matcher/brute_force.hpp"
#include "restitch/matcher/matcher.hpp"
#include "restitch/progress.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// Exact matcher on PCA lower bounds (see the top of this header).
struct ReducedMatcher {
  TieRule ties;
  int dimensions = 32;           ///< principal directions kept (>= 1)
  int seeds = 4;                 ///< pass-1 nearest lower bounds per feature (>= 1)
  Eigen::Index pca_rows = 4096;  ///< rows used to estimate the covariance (>= 1)
  /// Workers for the pair scans (detail/parallel.hpp; 0: every hardware thread). The matches are
  /// the same whatever the number.
  int threads = 1;

  Status match(const PointSet& features, const DescriptorMatrix& descriptors, float tau, std::vector<Match>& out,
               const Progress& progress = {}) const {
    return detail::guarded("ReducedMatcher::match", [&]() -> Status {
      RESTITCH_ASSERT(dimensions >= 1 && seeds >= 1 && pca_rows >= 1, "ReducedMatcher parameters must be >= 1");
      const Eigen::Index dim = descriptors.cols();
      if (dim <= dimensions + 1) return BruteForceMatcher{ties, threads}.match(features, descriptors, tau, out, progress);
      detail::MatchProblem p;
      RESTITCH_TRY(detail::prepare_matching(features, descriptors, tau, out, p));
      if (!progress.report("matching", 0.0)) return error(StatusCode::cancelled, "cancelled while matching features");
      const std::size_t n = p.size();
      if (n < 2) return progress.report("matching", 1.0) ? Status() : error(StatusCode::cancelled, "cancelled");
      const Eigen::Index rows = static_cast<Eigen::Index>(n);

      // Basis: mean and covariance (float product, sampled rows), leading eigenvectors.
      const Eigen::RowVectorXd mean = p.descriptor.cast<double>().colwise().sum() / double(rows);
      const Eigen::Index m = std::min(rows, pca_rows);
      detail::RowMatrixXf sample(m, dim);
      const Eigen::RowVectorXf meanf = mean.cast<float>();
      for (Eigen::Index k = 0; k < m; ++k) sample.row(k) = p.descriptor.row((k * rows) / m) - meanf;
      const Eigen::MatrixXd cov = (sample.transpose() * sample).cast<double>();
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
      const Eigen::MatrixXd basis = eig.eigenvectors().rightCols(dimensions);  // dim x dimensions, orthonormal

      // Embedding [P^T (a - m), |r(a)|], r^2 = |a - m|^2 - |P^T (a - m)|^2 (double).
      detail::RowMatrixXf emb(rows, dimensions + 1);
      double max_sq = 0, max_norm_sq = 0;
      const Eigen::Index chunk = 1024;
      for (Eigen::Index r0 = 0; r0 < rows; r0 += chunk) {
        const Eigen::Index c = std::min(chunk, rows - r0);
        const Eigen::MatrixXd x = p.descriptor.middleRows(r0, c).cast<double>().rowwise() - mean;
        const Eigen::MatrixXd proj = x * basis;
        for (Eigen::Index k = 0; k < c; ++k) {
          const double all = x.row(k).squaredNorm(), in = proj.row(k).squaredNorm();
          const double res = std::sqrt(std::max(0.0, all - in));
          emb.row(r0 + k).head(dimensions) = proj.row(k).cast<float>();
          emb(r0 + k, dimensions) = static_cast<float>(res);
          max_sq = std::max(max_sq, in + res * res);
          max_norm_sq = std::max(max_norm_sq, all);
        }
      }
      // Error of the float lower bound: float products and rounding of e to
      // float (8 u max|e|^2), plus the residual's cancellation: |r' - r| <=
      // delta = sqrt(8 (D + k) sqrt(k + 1) 2^-53 max|a - m|^2) (rounding of the
      // double projections and norms, 4x to spare), costing 8 delta max|e| +
      // 4 delta^2; and 1e-10 max|a - m|^2 for the projection's own rounding and
      // the basis' departure from orthonormality (both ~1e-13 relative).
      const double delta =
          std::sqrt(8.0 * double(dim + dimensions) * std::sqrt(double(dimensions + 1)) * 0x1.0p-53 * max_norm_sq);
      const double err = detail::float_distance_error(dimensions + 1, max_sq) + 16.0 * 0x1.0p-24 * max_sq +
                         8.0 * delta * std::sqrt(max_sq) + 4.0 * delta * delta + 1e-10 * max_norm_sq;

      // Pass 1: the `seeds` smallest lower bounds per feature (max-heaps), one set per worker.
      const std::size_t k_seeds = static_cast<std::size_t>(seeds);
      struct SeedState {
        std::size_t k;
        std::vector<float> threshold;
        std::vector<std::pair<float, std::int32_t>> heap;
        std::vector<std::uint32_t> heap_size;
        SeedState(std::size_t rows, std::size_t k_)
            : k(k_), threshold(rows, std::numeric_limits<float>::infinity()), heap(rows * k_), heap_size(rows, 0) {}
        void offer(std::size_t i, std::size_t j, float d2) {
          auto* h = heap.data() + i * k;
          std::uint32_t& s = heap_size[i];
          if (s < k) {
            h[s++] = {d2, static_cast<std::int32_t>(j)};
            std::push_heap(h, h + s);
          } else {
            std::pop_heap(h, h + s);
            h[s - 1] = {d2, static_cast<std::int32_t>(j)};
            std::push_heap(h, h + s);
          }
          if (s == k) threshold[i] = h[0].first;
        }
      };
      const std::size_t workers = std::size_t(std::max(1, resolve_threads(threads)));
      std::vector<float> threshold(n);
      {
        std::vector<SeedState> states(workers, SeedState(n, k_seeds));
        RESTITCH_TRY(detail::scan_pairs(p, emb, states, progress, 0.05, 0.45));
        // Upper bound of d* from every worker's seeds' exact distances, then the pass-2 threshold.
        for (std::size_t i = 0; i < n; ++i) {
          double u = std::numeric_limits<double>::infinity();
          bool any = false;
          for (const SeedState& st : states)
            for (std::uint32_t k = 0; k < st.heap_size[i]; ++k, any = true)
              u = std::min(u, detail::exact_squared_distance(p.descriptor.row(static_cast<Eigen::Index>(i)).data(),
                                                             p.descriptor.row(st.heap[i * k_seeds + k].second).data(),
                                                             dim));
          if (!any) {
            threshold[i] = -std::numeric_limits<float>::infinity();  // no admissible target at all
            continue;
          }
          const double t = ties.upper(std::sqrt(u));
          threshold[i] = detail::float_at_least(t * t + err);
        }
      }

      // Pass 2: all candidates under the threshold (fixed), one list per worker; exact re-ranking.
      struct CandidateState {
        std::vector<float> threshold;
        std::vector<std::vector<std::int32_t>> cand;
        void offer(std::size_t i, std::size_t j, float) { cand[i].push_back(static_cast<std::int32_t>(j)); }
      };
      std::vector<CandidateState> states(workers, CandidateState{threshold, std::vector<std::vector<std::int32_t>>(n)});
      RESTITCH_TRY(detail::scan_pairs(p, emb, states, progress, 0.45, 0.95));
      std::vector<double> scratch;
      std::vector<std::int32_t> ids;
      for (std::size_t i = 0; i < n; ++i) {
        ids.clear();
        for (const CandidateState& st : states) ids.insert(ids.end(), st.cand[i].begin(), st.cand[i].end());
        detail::choose_match(p, i, ids, ties, scratch, out);
      }
      if (!progress.report("matching", 1.0)) return error(StatusCode::cancelled, "cancelled while matching features");
      return {};
    });
  }
};

}  // namespace restitch
