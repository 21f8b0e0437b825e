// restitch/offsets/histogram.hpp - the 3-D offset histogram, its peaks and its sparsity.
//
// docs/method.md 1.4. Every matched feature casts one vote for its offset
// v = y - x. Votes are binned in cubes of side `bin_size` (0.05 normalized):
// bin index floor(v / bin_size) per axis, stored in a hash map (detail/cell_hash.hpp) because the
// space is sparse (a few thousand votes over a cube of side 4).
//
// Peaks (the candidates for dominant offsets) come from non-maximum
// suppression: bins are ranked by votes, descending, ties by lexicographic
// bin index (x, then y, then z), ascending; a bin is a peak when no bin
// ranked before it lies within `suppression_radius` (0.15) of it, centre to
// centre (distance <= radius; the radius is turned into a whole number of
// bins squared, so 0.15 / 0.05 is exactly 3 bins, with no rounding surprise).
// Among tied bins this keeps exactly one: the first in index order.
//
// A peak's `mass` is the sum of votes in its bin and its 26 neighbours. A
// true offset that falls on a bin border splits its votes over up to 8 bins;
// the mass counts them all, so ranking peaks by mass (what `find_peaks`
// returns) does not depend on where the bin grid happens to fall. (A bin
// lying next to two peaks counts for both; peaks are > 3 bins apart, so that
// is rare.) `votes` keeps the peak bin's own count, the number NMS used.
//
// Sparsity (the paper's Fig. 5): with the non-empty bins ranked by votes,
// the share of all offsets held by the top 7% and the top 20% of them. The
// number of bins in the top p% is ceil(p * bins / 100), computed in integers
// (so 7% of 100 bins is exactly 7 bins).
//
// Units: whatever the offsets are in (the analysis uses normalized units).
// Cost: binning O(#offsets) expected; sparsity O(B log B) for B non-empty
// bins; peaks O(B * S) hash look-ups, S = the number of bins within the
// radius (122 for 3 bins), plus a sort.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "restitch/detail/cell_hash.hpp"
#include "restitch/status.hpp"

namespace restitch {

/// One non-empty histogram bin: the cube [index, index + 1) * bin_size.
struct OffsetBin {
  Eigen::Vector3i index = Eigen::Vector3i::Zero();
  std::size_t votes = 0;
};

/// The non-empty bins of an offset histogram, ranked (votes descending, then
/// bin index lexicographically ascending).
struct OffsetHistogram {
  double bin_size = 0.05;
  std::vector<OffsetBin> bins;
  std::size_t offsets = 0;  ///< votes cast in total (= sum of bin votes)

  /// Centre of a bin, in the offsets' units.
  template <class = void>
  Eigen::Vector3d center(const Eigen::Vector3i& index) const {
    return (index.cast<double>().array() + 0.5).matrix() * bin_size;
  }
};

/// Offset sparsity, the paper's Fig. 5: share of offsets in the top 7% / 20% of non-empty bins.
struct Sparsity {
  double top7 = 0;
  double top20 = 0;
  std::size_t bins = 0;     ///< non-empty bins
  std::size_t offsets = 0;  ///< offsets binned
};

/// A histogram peak: a candidate dominant offset.
struct HistogramPeak {
  Eigen::Vector3i index = Eigen::Vector3i::Zero();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< the bin centre
  std::size_t votes = 0;                             ///< votes in the peak bin
  std::size_t mass = 0;                              ///< votes in the bin and its 26 neighbours
};

namespace detail {

/// Bin indices are kept within 2^20 of the origin: offsets farther out are not normalized.
inline constexpr std::int64_t histogram_index_limit = (std::int64_t(1) << 20) - 1;

inline Cell bin_cell(const Eigen::Vector3i& i) { return Cell{i.x(), i.y(), i.z()}; }

template <class = void>
bool bin_index_less(const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
  if (a.x() != b.x()) return a.x() < b.x();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.z() < b.z();
}

/// Integer offsets (dx, dy, dz) != 0 with dx^2 + dy^2 + dz^2 <= r2, in a fixed order.
template <class = void>
std::vector<Eigen::Vector3i> ball_stencil(int r2) {
  std::vector<Eigen::Vector3i> s;
  const int r = int(std::floor(std::sqrt(double(r2))));
  for (int x = -r; x <= r; ++x)
    for (int y = -r; y <= r; ++y)
      for (int z = -r; z <= r; ++z)
        if ((x || y || z) && x * x + y * y + z * z <= r2) s.emplace_back(x, y, z);
  return s;
}

}  // namespace detail

/// Bins `offsets` (any units) into cubes of side `bin_size`; `out` is
/// overwritten. Errors: bin_size not positive and finite, a non-finite
/// offset, or an offset more than 2^20 bins from the origin (invalid_argument).
/// Cost O(#offsets) expected, plus O(B log B) to rank the B non-empty bins.
template <class = void>
Status build_offset_histogram(const std::vector<Eigen::Vector3d>& offsets, double bin_size,
                                     OffsetHistogram& out) {
  out = OffsetHistogram{};
  out.bin_size = bin_size;
  if (!(bin_size > 0) || !std::isfinite(bin_size))
    return error(StatusCode::invalid_argument, "the histogram bin size must be a positive finite number");
  detail::CellHashMap<std::size_t> slot(offsets.size());  // bin -> position in out.bins
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    const Eigen::Vector3d f = offsets[k] / bin_size;
    if (!f.allFinite()) return error(StatusCode::invalid_argument, "offset " + std::to_string(k) + " is not finite");
    if (f.cwiseAbs().maxCoeff() >= double(detail::histogram_index_limit))
      return error(StatusCode::invalid_argument,
                   "offset " + std::to_string(k) + " lies too many bins from the origin (are the offsets normalized?)");
    const Eigen::Vector3i idx(int(std::floor(f.x())), int(std::floor(f.y())), int(std::floor(f.z())));
    const auto ins = slot.get(detail::bin_cell(idx), out.bins.size());
    if (ins.second) out.bins.push_back(OffsetBin{idx, 0});
    ++out.bins[*ins.first].votes;
  }
  out.offsets = offsets.size();
  std::sort(out.bins.begin(), out.bins.end(), [](const OffsetBin& a, const OffsetBin& b) {
    return a.votes != b.votes ? a.votes > b.votes : detail::bin_index_less(a.index, b.index);
  });
  return {};
}

/// Sparsity of a ranked histogram (Fig. 5). All zero for an empty histogram. Cost O(B).
template <class = void>
Sparsity offset_sparsity(const OffsetHistogram& h) {
  Sparsity s;
  s.bins = h.bins.size();
  s.offsets = h.offsets;
  if (h.bins.empty() || h.offsets == 0) return s;
  const auto share = [&](std::size_t percent) {
    const std::size_t k = (percent * h.bins.size() + 99) / 100;  // ceil(percent% of the bins)
    std::size_t votes = 0;
    for (std::size_t i = 0; i < k && i < h.bins.size(); ++i) votes += h.bins[i].votes;
    return double(votes) / double(h.offsets);
  };
  s.top7 = share(7);
  s.top20 = share(20);
  return s;
}

/// Non-maximum suppression (see the header comment). Returns the peaks ranked
/// by mass descending, then votes descending, then bin index ascending.
/// `suppression_radius` is in the offsets' units; 0 makes every bin a peak.
/// Cost O(B * S) hash look-ups, S = bins within the radius.
template <class = void>
std::vector<HistogramPeak> find_peaks(const OffsetHistogram& h, double suppression_radius) {
  RESTITCH_ASSERT(suppression_radius >= 0 && std::isfinite(suppression_radius),
                  "the suppression radius must be a non-negative finite number");
  const double rb = suppression_radius / h.bin_size;
  const int r2 = int(std::floor(rb * rb + 1e-9));  // whole bins squared; 0.15 / 0.05 -> exactly 9
  detail::CellHashMap<std::size_t> rank(h.bins.size());  // bin -> its rank
  for (std::size_t i = 0; i < h.bins.size(); ++i) rank.get(detail::bin_cell(h.bins[i].index), i);
  const std::vector<Eigen::Vector3i> ball = detail::ball_stencil(r2);
  const std::vector<Eigen::Vector3i> cube = detail::ball_stencil(3);  // the 26 neighbours
  std::vector<HistogramPeak> peaks;
  for (std::size_t i = 0; i < h.bins.size(); ++i) {
    const OffsetBin& b = h.bins[i];
    bool is_peak = true;
    for (const Eigen::Vector3i& d : ball) {
      const std::size_t* r = rank.find(detail::bin_cell(b.index + d));
      if (r && *r < i) {
        is_peak = false;
        break;
      }
    }
    if (!is_peak) continue;
    HistogramPeak p;
    p.index = b.index;
    p.center = h.center(b.index);
    p.votes = b.votes;
    p.mass = b.votes;
    for (const Eigen::Vector3i& d : cube) {
      const std::size_t* r = rank.find(detail::bin_cell(b.index + d));
      if (r) p.mass += h.bins[*r].votes;
    }
    peaks.push_back(p);
  }
  std::stable_sort(peaks.begin(), peaks.end(), [](const HistogramPeak& a, const HistogramPeak& b) {
    if (a.mass != b.mass) return a.mass > b.mass;
    if (a.votes != b.votes) return a.votes > b.votes;
    return detail::bin_index_less(a.index, b.index);
  });
  return peaks;
}

}  // namespace restitch
