// restitch/descriptor/shot.hpp - the SHOT descriptor policy (Tombari et al.
// 2010) with the local reference frame fixed to the world axes.
//
// `ShotDescriptor` satisfies the descriptor policy contract of
// restitch/descriptor/descriptor.hpp. Its values equal PCL 1.13's
// `SHOTEstimation` given identity reference frames through
// `setInputReferenceFrames` (one per query) and the support set as search
// surface, to about 1e-5 (measured against PCL: see tests/descriptor_test.cpp).
// Every PCL convention is kept (docs/descriptors.md, N and S):
//
//   * Neighbours of a query q: support points j with float32
//     d2(q, j) < float(R*R) (strict; the query itself counts when it is a
//     support point). Fewer than 5 neighbours -> the row is all NaN.
//   * Frame: x = (1,0,0), y = (0,1,0), z = (0,0,1). restitch seeks
//     translations only, so no rotation invariance is wanted; this also avoids
//     the sign ambiguity of PCL's own SHOT frame on planar patches.
//   * 352 = 32 volumes x 11 cosine slots. Volume v = 4*s + 2*r + e: azimuth
//     sector s = 0..7 of atan2(y, x), sector s covering (-pi + s*pi/4,
//     -pi + (s+1)*pi/4] (ties to the lower sector as PCL's bit logic does),
//     r = 1 beyond R/2, e = 1 for z > 0. Slot k = floor(b + 0.5) with
//     b = 5 * (1 + cos), cos = clamp(n_j . z) the *neighbour's* normal; the
//     query's normal is never used.
//   * Additive quadrilinear interpolation (cosine, radial, elevation,
//     azimuth), including PCL's quirks: the cosine neighbour slot is taken
//     modulo 10 (not 11), so cos in (0.8, 0.9) spills into slot 0; mass is lost
//     inside R/4, beyond 3R/4 and near the poles.
//   * Neighbours with d < 1e-15 (the query, exact duplicates) or a non-finite
//     normal add nothing but still count toward the 5.
//   * The row is divided by its L2 norm (double sum of float squares); a row
//     whose neighbours were all skipped is 0/0 = NaN, as in PCL.
//   * A query with a non-finite coordinate -> NaN row.
//
// Units: radius is in the units of the points (the analysis passes normalized
// coordinates, where the default 0.2 is the paper's support radius). The
// float radius is widened to double once, and that double plays the role of
// PCL's `search_radius_` (PCL's radius is a double; pass PCL double(radius)
// to compare).
//
// Contract: `compute` resizes `out` to #queries by 352 (row-major). Empty
// support or queries are fine. support.points/normals and queries.points/
// normals must have equal row counts; query normals are not used. On a
// non-ok Status the content of `out` is unspecified.
//
// Cost: one k-d tree over the support set (O(P log P)), then per query a
// radius search plus O(k) work with one sqrt, acos and atan2 per neighbour.
// No allocation per query. Single-threaded; deterministic.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/descriptor/neighbourhood.hpp"
#include "restitch/detail/parallel.hpp"

namespace restitch {

namespace detail {

// PCL's angle constants (impl/shot.hpp), as doubles.
constexpr double shot_rad_45 = 0.78539816339744830961566084581988;
constexpr double shot_rad_90 = 1.5707963267948966192313216916398;
constexpr double shot_rad_135 = 2.3561944901923449288469825374596;
constexpr double shot_rad_pi_7_8 = 2.7488935718910690836548129603691;

/// Azimuth sector 0..7 of (x, y) with PCL's tie rules: a direction on a
/// sector boundary goes to the sector below it; x = y = 0 gives 0.
template <class = void>
int shot_azimuth_sector(double x, double y) {
  const double ax = std::abs(x), ay = std::abs(y);
  if (y > 0 || (y == 0 && x < 0)) {                           // upper half plane, or phi = pi
    if (x > 0 || (x == 0 && y > 0)) return ax >= ay ? 4 : 5;  // (0, pi/2]
    return ax > ay ? 7 : 6;                                   // (pi/2, pi]
  }
  if (x > 0 || (x == 0 && y > 0)) return ax > ay ? 3 : 2;  // (-pi/2, 0]
  return (ax >= ay) ? 0 : 1;                               // (-pi, -pi/2], with x = 0 -> 1, x = y = 0 -> 0
}

}  // namespace detail

/// SHOT with a world-axis frame; see the file comment.
struct ShotDescriptor {
  /// Support radius, in the units of the points. Positive and finite.
  float radius = 0.2f;
  /// Workers (detail/parallel.hpp; 0: every hardware thread). The descriptors are the same whatever
  /// the number.
  int threads = 1;

  /// 32 volumes x 11 cosine slots.
  int dimension() const { return 352; }

  template <class = void>
  Status compute(const PointSet& support, const PointSet& queries, DescriptorMatrix& out,
                 const Progress& progress = Progress()) const {
    return detail::guarded("ShotDescriptor::compute", [&]() -> Status {
      RESTITCH_TRY(detail::check_descriptor_input("SHOT", radius, support, queries));
      const Eigen::Index nq = queries.size();
      out.resize(nq, 352);
      if (nq == 0) return Status();

      const double r = static_cast<double>(radius);
      const detail::RadiusSearch search(support.points, r);
      // Per support point, the cosine coordinate b = 5 (1 + n.z), split into its
      // slot k and the signed offset delta = b - k; k = -1 marks a non-finite
      // normal (skipped, as PCL does).
      std::vector<std::int8_t> slot(static_cast<std::size_t>(support.size()));
      std::vector<double> delta(static_cast<std::size_t>(support.size()));
      for (Eigen::Index j = 0; j < support.size(); ++j) {
        const float nx = support.normals(j, 0), ny = support.normals(j, 1), nz = support.normals(j, 2);
        if (!(std::isfinite(nx) && std::isfinite(ny) && std::isfinite(nz))) {
          slot[j] = -1;
          continue;
        }
        double c = static_cast<double>(nz);  // n . (0,0,1)
        if (c > 1.0) c = 1.0;
        if (c < -1.0) c = -1.0;
        const double b = ((1.0 + c) * 10) / 2;
        const int k = static_cast<int>(std::floor(b + 0.5));
        slot[j] = static_cast<std::int8_t>(k);
        delta[j] = b - k;
      }

      // Each query writes its own row: chunks of queries are tasks (detail/parallel.hpp).
      const Eigen::Index chunk = detail::descriptor_progress_stride;
      const std::size_t chunks = std::size_t((nq + chunk - 1) / chunk);
      const int workers = int(std::min<std::size_t>(std::size_t(resolve_threads(threads)), chunks));  // chunks >= 1
      std::vector<std::vector<detail::Neighbour>> neighbours(static_cast<std::size_t>(workers));
      const auto describe = [&](std::size_t task, int worker) {
        std::vector<detail::Neighbour>& nn = neighbours[std::size_t(worker)];
        const Eigen::Index end = std::min(nq, Eigen::Index(task + 1) * chunk);
        for (Eigen::Index i = Eigen::Index(task) * chunk; i < end; ++i) {
          float* h = out.row(i).data();
          const float* q = queries.points.row(i).data();
          search.find(q, nn);  // empty for a non-finite query
          if (nn.size() < 5) {
            std::fill(h, h + 352, std::numeric_limits<float>::quiet_NaN());
            continue;
          }
          std::fill(h, h + 352, 0.0f);
          accumulate(support, q, nn, slot.data(), delta.data(), r, h);
          normalise(h);
        }
      };
      const auto tick = [&](std::size_t done) {
        return done >= chunks || progress.report("descriptors", double(done) / double(chunks));
      };
      if (!detail::parallel_tasks(workers, chunks, describe, tick)) return error(StatusCode::cancelled, "SHOT: cancelled");
      if (!progress.report("descriptors", 1.0)) return error(StatusCode::cancelled, "SHOT: cancelled");
      return Status();
    });
  }

 private:
  // Adds every neighbour's interpolated votes to h (352 floats). One loop of
  // about 85 lines on purpose: it is SHOT's inner loop, the quadrilinear
  // interpolation of PCL's SHOTEstimation step by step (docs/descriptors.md, S1-S6),
  // and reads best side by side with PCL's own.
  template <class = void>
  static void accumulate(const PointSet& support, const float* q, const std::vector<detail::Neighbour>& nn,
                         const std::int8_t* slot, const double* delta, double r, float* h) {
    using namespace detail;
    const double r14 = r / 4, r12 = r / 2, r34 = (r * 3) / 4;
    for (const Neighbour& n : nn) {
      const int k = slot[n.index];
      if (k < 0) continue;  // non-finite normal
      const double d = std::sqrt(static_cast<double>(n.sqr_distance));
      if (std::abs(d - 0.0) < 1e-15) continue;  // the query itself or a duplicate
      const float* p = support.points.row(n.index).data();
      // Local coordinates: differences in float, dot with the world axes (exact).
      double x = static_cast<double>(p[0] - q[0]);
      double y = static_cast<double>(p[1] - q[1]);
      double z = static_cast<double>(p[2] - q[2]);
      if (std::abs(x) < 1e-30) x = 0;
      if (std::abs(y) < 1e-30) y = 0;
      if (std::abs(z) < 1e-30) z = 0;

      const int sector = shot_azimuth_sector(x, y);
      const int v = 4 * sector + (d > r12 ? 2 : 0) + (z > 0 ? 1 : 0);
      float* vol = h + 11 * v;

      // Cosine: the other half of the vote goes to the adjacent slot, mod 10.
      const double dc = delta[n.index];
      double own = 1 - std::abs(dc);
      if (dc > 0) {
        vol[(k + 1) % 10] += static_cast<float>(dc);
      } else {
        vol[(k - 1 + 10) % 10] += -static_cast<float>(dc);
      }

      // Radial: shells split at R/2, interpolated between R/4 and 3R/4.
      if (d > r12) {
        const double t = (d - r34) / r12;
        if (d > r34) {
          own += 1 - t;
        } else {
          own += 1 + t;
          h[11 * (v - 2) + k] -= static_cast<float>(t);
        }
      } else {
        const double t = (d - r14) / r12;
        if (d < r14) {
          own += 1 + t;
        } else {
          own += 1 - t;
          h[11 * (v + 2) + k] += static_cast<float>(t);
        }
      }

      // Elevation: hemispheres split at z = 0, interpolated between 45 and 135 degrees.
      double ic = z / d;
      if (ic < -1.0) ic = -1.0;
      if (ic > 1.0) ic = 1.0;
      const double theta = std::acos(ic);
      if (theta > shot_rad_90 || (std::abs(theta - shot_rad_90) < 1e-30 && z <= 0)) {
        const double t = (theta - shot_rad_135) / shot_rad_90;
        if (theta > shot_rad_135) {
          own += 1 - t;
        } else {
          own += 1 + t;
          h[11 * (v + 1) + k] -= static_cast<float>(t);
        }
      } else {
        const double t = (theta - shot_rad_45) / shot_rad_90;
        if (theta < shot_rad_45) {
          own += 1 + t;
        } else {
          own += 1 - t;
          h[11 * (v - 1) + k] += static_cast<float>(t);
        }
      }

      // Azimuth: interpolated towards the adjacent sector, skipped on the z axis.
      if (y != 0.0 || x != 0.0) {
        const double phi = std::atan2(y, x);
        double t = (phi - (-shot_rad_pi_7_8 + shot_rad_45 * sector)) / shot_rad_45;
        t = std::max(-0.5, std::min(t, 0.5));
        if (t > 0) {
          own += 1 - t;
          h[11 * ((v + 4) % 32) + k] += static_cast<float>(t);
        } else {
          own += 1 + t;
          h[11 * ((v - 4 + 32) % 32) + k] -= static_cast<float>(t);
        }
      }

      vol[k] += static_cast<float>(own);
    }
  }

  // Divides h by its L2 norm (double sum of float squares); 0/0 = NaN as PCL.
  template <class = void>
  static void normalise(float* h) {
    double acc = 0;
    for (int j = 0; j < 352; ++j) acc += h[j] * h[j];
    const float norm = static_cast<float>(std::sqrt(acc));
    for (int j = 0; j < 352; ++j) h[j] /= norm;
  }
};

static_assert(is_descriptor_policy_v<ShotDescriptor>, "ShotDescriptor must satisfy the descriptor policy contract");

}  // namespace restitch
