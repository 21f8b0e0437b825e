// restitch/descriptor/fpfh.hpp - the FPFH descriptor policy (Rusu et al. 2009).
//
// `FpfhDescriptor` satisfies the descriptor policy contract of
// restitch/descriptor/descriptor.hpp. Its values equal PCL 1.13's
// `FPFHEstimation` with the queries as input cloud and the support set as
// search surface (`setSearchSurface(support)`, normals of the support), to
// about 1e-3 on a scale of 100. PCL's conventions are kept
// (docs/descriptors.md, N and F):
//
//   * Neighbours: support points j with float32 d2(q, j) < float(R*R)
//     (strict), as SHOT.
//   * Pair features (PCL's computePairFeatures, float32, Eigen::Vector4f):
//     the source of a pair is the point whose normal is more parallel to the
//     connecting line (the SPFH centre on a tie); u = n_s, v = dp x u / |dp x u|,
//     w = u x v; f1 = atan2(w.n_t, u.n_t), f2 = v.n_t, f3 = u.dp/|dp|.
//     A degenerate pair (|dp| = 0 or |dp x u| = 0) has f1 = f2 = f3 = 0 and is
//     still binned, at (5, 5, 5). A non-finite feature (NaN normal) goes to
//     bin 0, which is where PCL's (int)floor(NaN) = INT_MIN is clamped on
//     x86-64; restitch gets there without the undefined cast.
//   * Layout: 33 = [f1: 11 bins | f2: 11 | f3: 11]; f1 bin
//     floor(11 (f1 + pi) / (2 pi)), f2 and f3 bins floor(11 (f + 1) / 2),
//     clamped to 0..10.
//   * SPFH(s), for a support point s: over s's neighbours *in the support
//     set*, all except s itself (by index, so exact duplicates of s are
//     degenerate pairs), each pair adds 100 / (k - 1) with k the neighbour
//     count including s.
//   * FPFH(q) = sum over q's support neighbours j with d2(q, j) != 0 of
//     SPFH(j) / d2(q, j) (1/d^2, squared float distance: PCL's weight, not the
//     paper's 1/d). q's own SPFH is *not* added, and neither are exact
//     duplicates of q. Each 11-bin block is then rescaled to sum to 100
//     (a block summing to 0 stays 0).
//   * Queries and support may differ, as in PCL with a search surface: the
//     SPFH of every support point that is a neighbour of some query is
//     computed over that point's own neighbourhood within the support set.
//     So a query's own normal is never used (it enters only when the query
//     also is a support point, through its neighbours' SPFHs).
//   * A query whose only neighbours are at distance 0 (a support point with
//     nothing else within R) -> all-zero row, as PCL. A query with no support
//     point within R at all, or with a non-finite coordinate -> NaN row
//     (PCL's search finds nothing).
//
// Units: radius as for SHOT (units of the points; double(radius) plays PCL's
// double search radius). Values lie in [0, 100].
//
// Contract: `compute` resizes `out` to #queries by 33 (row-major). Empty
// support or queries are fine. Row counts of points and normals must match.
// On a non-ok Status the content of `out` is unspecified.
//
// Cost: one k-d tree over the support; one radius search per query and per
// support point that neighbours a query; O(k) pair features (one sqrt, two
// acos, one atan2 each) per such support point. Memory: the queries'
// neighbour lists (8 bytes per neighbour) and 33 floats per needed support
// point. Single-threaded; deterministic.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/descriptor/neighbourhood.hpp"

namespace restitch {

namespace detail {

/// M_PI as a double (M_PI itself is POSIX, not C++).
constexpr double fpfh_pi = 3.14159265358979323846;

/// PCL's pair features (f1, f2, f3) of the SPFH centre p (normal n_p) and its
/// neighbour q (normal n_q); all in float32 as PCL computes them. Points have
/// w = 1, normals w = 0; returns f = 0 for a degenerate pair.
template <class = void>
void fpfh_pair_features(const Eigen::Vector4f& p, const Eigen::Vector4f& n_p, const Eigen::Vector4f& q,
                               const Eigen::Vector4f& n_q, float& f1, float& f2, float& f3) {
  Eigen::Vector4f dp = q - p;
  dp[3] = 0.0f;
  const float len = dp.norm();
  if (len == 0.0f) {
    f1 = f2 = f3 = 0.0f;
    return;
  }
  Eigen::Vector4f u = n_p, nt = n_q;
  u[3] = nt[3] = 0.0f;
  const float a1 = u.dot(dp) / len;
  const float a2 = nt.dot(dp) / len;
  if (std::acos(std::fabs(a1)) > std::acos(std::fabs(a2))) {  // q is the source
    u = n_q;
    nt = n_p;
    u[3] = nt[3] = 0.0f;
    dp *= -1;
    f3 = -a2;
  } else {
    f3 = a1;
  }
  Eigen::Vector4f v = dp.cross3(u);
  v[3] = 0.0f;
  const float v_norm = v.norm();
  if (v_norm == 0.0f) {
    f1 = f2 = f3 = 0.0f;
    return;
  }
  v /= v_norm;
  Eigen::Vector4f w = u.cross3(v);
  v[3] = 0.0f;
  f2 = v.dot(nt);
  w[3] = 0.0f;
  f1 = std::atan2(w.dot(nt), u.dot(nt));
}

/// Bin of a value b = 11 * (normalised feature) in double: floor, clamped to
/// 0..10; NaN -> 0 (PCL's INT_MIN clamp, without the undefined cast).
template <class = void>
int fpfh_bin(double b) {
  const double f = std::floor(b);
  if (f >= 11) return 10;
  if (f >= 0) return static_cast<int>(f);
  return 0;  // negative or NaN
}

}  // namespace detail

/// FPFH; see the file comment.
struct FpfhDescriptor {
  /// Support radius, in the units of the points. Positive and finite.
  float radius = 0.2f;

  /// 3 features x 11 bins.
  int dimension() const { return 33; }

  template <class = void>
  Status compute(const PointSet& support, const PointSet& queries, DescriptorMatrix& out,
                 const Progress& progress = Progress()) const {
    return detail::guarded("FpfhDescriptor::compute", [&]() -> Status {
      RESTITCH_TRY(detail::check_descriptor_input("FPFH", radius, support, queries));
      const Eigen::Index nq = queries.size();
      const Eigen::Index ns = support.size();
      out.resize(nq, 33);
      if (nq == 0) return Status();

      const detail::RadiusSearch search(support.points, static_cast<double>(radius));
      constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
      // The three passes (query neighbourhoods, SPFHs, weighting) report
      // fractions in [0, 0.25), [0.25, 0.75), [0.75, 1].
      auto cancelled = [&](Eigen::Index done, Eigen::Index total, double from, double span) {
        return done % detail::descriptor_progress_stride == 0 && done > 0 &&
               !progress.report("descriptors", from + span * static_cast<double>(done) / static_cast<double>(total));
      };

      // Pass 1: each query's neighbours (CSR), and which support points need an SPFH.
      std::vector<detail::Neighbour> nn, all;
      nn.reserve(256);
      std::vector<std::size_t> begin(static_cast<std::size_t>(nq) + 1, 0);
      std::vector<std::uint32_t> spfh_row(static_cast<std::size_t>(ns), none);
      for (Eigen::Index i = 0; i < nq; ++i) {
        if (cancelled(i, nq, 0.0, 0.25)) return error(StatusCode::cancelled, "FPFH: cancelled");
        search.find(queries.points.row(i).data(), nn);
        all.insert(all.end(), nn.begin(), nn.end());
        begin[i + 1] = all.size();
        for (const detail::Neighbour& n : nn) spfh_row[n.index] = 0;
      }
      std::uint32_t needed = 0;
      for (std::uint32_t& row : spfh_row) {
        if (row != none) row = needed++;
      }

      // Pass 2: SPFH of every needed support point, over its support neighbourhood.
      std::vector<float> spfh(static_cast<std::size_t>(needed) * 33, 0.0f);
      const float d_pi = 1.0f / (2.0f * static_cast<float>(detail::fpfh_pi));
      for (Eigen::Index s = 0, done = 0; s < ns; ++s) {
        const std::uint32_t row = spfh_row[s];
        if (row == none) continue;
        if (cancelled(++done, needed, 0.25, 0.5)) return error(StatusCode::cancelled, "FPFH: cancelled");
        search.find(support.points.row(s).data(), nn);
        float* h = &spfh[static_cast<std::size_t>(row) * 33];
        if (nn.size() < 2) continue;  // no pair: SPFH stays zero
        const float incr = 100.0f / static_cast<float>(nn.size() - 1);
        const Eigen::Vector4f p(support.points(s, 0), support.points(s, 1), support.points(s, 2), 1.0f);
        const Eigen::Vector4f n_p(support.normals(s, 0), support.normals(s, 1), support.normals(s, 2), 0.0f);
        for (const detail::Neighbour& n : nn) {
          if (n.index == static_cast<std::uint32_t>(s)) continue;
          const Eigen::Index j = n.index;
          const Eigen::Vector4f q(support.points(j, 0), support.points(j, 1), support.points(j, 2), 1.0f);
          const Eigen::Vector4f n_q(support.normals(j, 0), support.normals(j, 1), support.normals(j, 2), 0.0f);
          float f1, f2, f3;
          detail::fpfh_pair_features(p, n_p, q, n_q, f1, f2, f3);
          h[detail::fpfh_bin(11 * ((static_cast<double>(f1) + detail::fpfh_pi) * static_cast<double>(d_pi)))] += incr;
          h[11 + detail::fpfh_bin(11 * ((static_cast<double>(f2) + 1.0) * 0.5))] += incr;
          h[22 + detail::fpfh_bin(11 * ((static_cast<double>(f3) + 1.0) * 0.5))] += incr;
        }
      }

      // Pass 3: FPFH(q) = sum of SPFH(j) / d2(q, j), each block rescaled to 100.
      for (Eigen::Index i = 0; i < nq; ++i) {
        if (cancelled(i, nq, 0.75, 0.25)) return error(StatusCode::cancelled, "FPFH: cancelled");
        float* h = out.row(i).data();
        if (begin[i + 1] == begin[i]) {  // non-finite query: PCL's search finds nothing
          std::fill(h, h + 33, std::numeric_limits<float>::quiet_NaN());
          continue;
        }
        std::fill(h, h + 33, 0.0f);
        double sum[3] = {0, 0, 0};
        for (std::size_t t = begin[i]; t < begin[i + 1]; ++t) {
          const detail::Neighbour& n = all[t];
          if (n.sqr_distance == 0) continue;  // the query itself, or a duplicate of it
          const float weight = 1.0f / n.sqr_distance;
          const float* sp = &spfh[static_cast<std::size_t>(spfh_row[n.index]) * 33];
          for (int b = 0; b < 33; ++b) {
            const float val = sp[b] * weight;
            sum[b / 11] += val;
            h[b] += val;
          }
        }
        for (int block = 0; block < 3; ++block) {
          const double scale = sum[block] != 0 ? 100.0 / sum[block] : 0.0;
          for (int b = 11 * block; b < 11 * block + 11; ++b) h[b] = static_cast<float>(h[b] * scale);
        }
      }
      if (!progress.report("descriptors", 1.0)) return error(StatusCode::cancelled, "FPFH: cancelled");
      return Status();
    });
  }
};

static_assert(is_descriptor_policy_v<FpfhDescriptor>, "FpfhDescriptor must satisfy the descriptor policy contract");

}  // namespace restitch
