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
// Re-ranking. Pass 2's candidates first get their float distance in the
// full space, as BruteForceMatcher computes it (with its rigorous error
// bound, whatever the summation order); only those that can still tie with
// the best go to the exact double distance. Where descriptors nearly tie
// (flat faces of man-made models) the lower bounds admit thousands of
// candidates per feature: on a real 10k-feature fence the exact distances
// took 6.3 of the matcher's 7.4 s, 1.0 s with this filter.
//
// When brute force is faster (speed only; the answer is the same):
//  * fewer than `min_rows` (4096) rows: the basis (covariance of up to
//    `pca_rows` rows, a 352 x 352 eigensolver, the embedding) costs 30-60 ms,
//    about what brute force's whole scan costs there (measured on the real
//    models: 1.5k-2k features 35-50 ms brute force, 70-110 ms reduced;
//    4.4k: 220 against 194 ms).
//  * the probe: on `probe_rows` (64) rows at an even stride, the share of
//    targets whose lower bound is under the row's best float distance
//    estimates pass 2's candidates. Each costs a full-space dot product,
//    about four times a pair of brute force's blocked product (which
//    shares each loaded row across a block and computes half the pairs),
//    so above 1/8 of the targets brute force's scan is the cheaper one:
//    `max_candidate_share` = 0.125. Measured shares: bookshelves 0.0002,
//    real models 0.002-0.07, the real fence 0.215 (reduced 2.1 s, brute
//    force 1.0 s).
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
  /// Rows used to estimate the covariance (>= 1). 1024 at an even stride give as good a basis as
  /// 4096 on the measured models (pass 2 as fast or faster) for a quarter of the product: matching
  /// radiator3 1.59 -> 1.20 s, the 184k-triangle bookshelf 1.67 -> 1.63 s.
  Eigen::Index pca_rows = 1024;
  /// Workers for the pair scans (detail/parallel.hpp; 0: every hardware thread). The matches are
  /// the same whatever the number.
  int threads = 1;
  /// Brute force instead where the probe estimates that more than this share of the targets would be
  /// pass-2 candidates (1: never; see the header comment). Speed only: both give the same matches.
  double max_candidate_share = 0.125;
  Eigen::Index probe_rows = 64;  ///< rows the probe looks at
  /// Brute force instead below this many rows (0: never): the basis costs about as much as the
  /// whole brute-force scan there (see the header comment).
  Eigen::Index min_rows = 4096;

  template <class = void>
  Status match(const PointSet& features, const DescriptorMatrix& descriptors, float tau, std::vector<Match>& out,
               const Progress& progress = {}) const {
    return detail::guarded("ReducedMatcher::match", [&]() -> Status {
      RESTITCH_ASSERT(dimensions >= 1 && seeds >= 1 && pca_rows >= 1, "ReducedMatcher parameters must be >= 1");
      const Eigen::Index dim = descriptors.cols();
      detail::MatchProblem p;
      RESTITCH_TRY(detail::prepare_matching(features, descriptors, tau, out, p));
      if (!progress.report("matching", 0.0)) return error(StatusCode::cancelled, "cancelled while matching features");
      const std::size_t n = p.size();
      if (n < 2) return progress.report("matching", 1.0) ? Status() : error(StatusCode::cancelled, "cancelled");
      const Eigen::Index rows = static_cast<Eigen::Index>(n);
      // Brute force on the problem already prepared, where it is faster (see the header comment).
      const auto brute_force = [&]() -> Status {
        RESTITCH_TRY(detail::match_all_pairs(p, ties, threads, out, progress));
        return progress.report("matching", 1.0) ? Status() : error(StatusCode::cancelled, "cancelled");
      };
      if (dim <= dimensions + 1 || rows < min_rows) return brute_force();

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

      const Eigen::VectorXf norms = p.descriptor.rowwise().squaredNorm();  // the probe's and pass 2's
      // Probe (docs/method.md 1.3): on `probe_rows` rows at an even stride, the share of targets whose
      // lower bound falls under the row's best float distance, an estimate of the candidates pass 2
      // would keep. Where descriptors nearly tie everywhere (flat faces), the lower bounds do not
      // separate them and brute force's scan is cheaper than pass 2's candidates.
      if (max_candidate_share < 1 && probe_rows > 0) {
        const Eigen::Index probes = std::min<Eigen::Index>(probe_rows, rows);
        detail::RowMatrixXf q(probes, dim), qe(probes, dimensions + 1);
        for (Eigen::Index k = 0; k < probes; ++k)
          q.row(k) = p.descriptor.row((k * rows) / probes), qe.row(k) = emb.row((k * rows) / probes);
        const detail::RowMatrixXf full = q * p.descriptor.transpose(), low = qe * emb.transpose();
        const Eigen::VectorXf enorms = emb.rowwise().squaredNorm();
        double share = 0;
        for (Eigen::Index k = 0; k < probes; ++k) {
          const std::size_t i = static_cast<std::size_t>((k * rows) / probes);
          float best = std::numeric_limits<float>::infinity();
          for (Eigen::Index j = 0; j < rows; ++j)
            if (std::size_t(j) != i && p.admissible(i, std::size_t(j)))
              best = std::min(best, norms[Eigen::Index(i)] + norms[j] - 2.0f * full(k, j));
          std::size_t under = 0;
          for (Eigen::Index j = 0; j < rows; ++j)
            under += std::size_t(j) != i && enorms[Eigen::Index(i)] + enorms[j] - 2.0f * low(k, j) <= best;
          share += double(under) / double(rows - 1);
        }
        share /= double(probes);
        if (share > max_candidate_share) return brute_force();
      }

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
      const std::size_t workers = std::size_t(resolve_threads(threads));
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
      // The candidates' float distances in the full space first, as BruteForceMatcher computes them
      // (any summation order is within its error bound): only those that can still tie with the
      // best go to the exact (double, in k order) re-ranking. Where descriptors nearly tie (flat
      // faces of man-made models) the lower bounds admit thousands of candidates per feature, and
      // the exact distances, not the scans, were the cost (a fence: 6.3 of 7.4 s).
      const detail::FloatTieBound full{detail::float_distance_error(dim, detail::max_squared_norm(p.descriptor)),
                                       ties};
      std::vector<double> scratch;
      std::vector<std::int32_t> ids, kept;
      std::vector<float> d2;
      for (std::size_t i = 0; i < n; ++i) {
        ids.clear();
        for (const CandidateState& st : states) ids.insert(ids.end(), st.cand[i].begin(), st.cand[i].end());
        d2.resize(ids.size());
        float best = std::numeric_limits<float>::infinity();
        const auto row = p.descriptor.row(static_cast<Eigen::Index>(i));
        for (std::size_t k = 0; k < ids.size(); ++k) {
          d2[k] = norms[static_cast<Eigen::Index>(i)] + norms[ids[k]] - 2.0f * row.dot(p.descriptor.row(ids[k]));
          best = std::min(best, d2[k]);
        }
        const float limit = full(best);
        kept.clear();
        for (std::size_t k = 0; k < ids.size(); ++k)
          if (d2[k] <= limit) kept.push_back(ids[k]);
        detail::choose_match(p, i, kept, ties, scratch, out);
      }
      if (!progress.report("matching", 1.0)) return error(StatusCode::cancelled, "cancelled while matching features");
      return {};
    });
  }
};

}  // namespace restitch
