// restitch/offsets/symmetry_transform.hpp - the translational symmetry transform S_T of a sampled surface, by FFT.
//
// The voxel field of the dense samples, its normalised autocorrelation S_T
// (Kim, Lipman, Funkhouser 2012, eq. 2), S_T at an offset, its radial
// contrast and its peaks. The definitions, every parameter and its reason are
// in restitch/offsets/autocorrelation.hpp (the detector and the structure
// score built on it) and docs/method.md 1.9.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unsupported/Eigen/FFT>
#include <utility>
#include <vector>

#include "restitch/descriptor/descriptor.hpp"
#include "restitch/mesh.hpp"
#include "restitch/normalization.hpp"
#include "restitch/offsets/detector.hpp"
#include "restitch/progress.hpp"
#include "restitch/sampling/poisson_disk.hpp"
#include "restitch/status.hpp"
namespace restitch {

/// A dense 3-D grid of doubles, x fastest: (x, y, z) is values[x + dims.x * (y + dims.y * z)].
struct VoxelGrid {
  Eigen::Array3i dims = Eigen::Array3i::Zero();
  std::vector<double> values;

  std::size_t cells() const { return std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]); }
  template <class = void>
  std::size_t index(int x, int y, int z) const {
    return std::size_t(x) + std::size_t(dims[0]) * (std::size_t(y) + std::size_t(dims[1]) * std::size_t(z));
  }
  template <class = void>
  bool contains(int x, int y, int z) const {
    return x >= 0 && y >= 0 && z >= 0 && x < dims[0] && y < dims[1] && z < dims[2];
  }
  /// The value at (x, y, z); 0 outside the grid.
  double at(int x, int y, int z) const { return contains(x, y, z) ? values[index(x, y, z)] : 0.0; }
  /// Resizes to `d` cells, all zero.
  template <class = void>
  void reset(const Eigen::Array3i& d) {
    dims = d;
    values.assign(cells(), 0.0);
  }
};

/// Parameters of the voxel field (see the header comment).
struct SymmetryFieldOptions {
  double voxel_factor = 2.0;                     ///< voxel edge = voxel_factor x sample spacing
  std::size_t max_cells = std::size_t(1) << 22;  ///< padded FFT grid cells at most; the voxel grows to fit
};

/// S_T of a point set: the field, the grid it lives on and its normalised autocorrelation.
struct SymmetryTransform {
  double voxel = 0;                                  ///< voxel edge used (points' units)
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< low corner of voxel (0, 0, 0)
  Eigen::Array3i fft_size = Eigen::Array3i::Zero();  ///< padded FFT length per axis, N_a >= 2 n_a - 1
  VoxelGrid field;                                   ///< f: the splatted samples, n_a voxels per axis
  double norm2 = 0;                                  ///< ||f||^2 = R(0)
  VoxelGrid S;  ///< S_T(t) for |t_a| <= n_a - 1 at index t + n - 1 (dims 2 n - 1); empty for no points

  /// The centre index of S (t = 0).
  Eigen::Array3i centre() const { return field.dims - 1; }
  /// S_T at voxel offset t; 0 beyond the field's support.
  template <class = void>
  double at(const Eigen::Array3i& t) const {
    const Eigen::Array3i c = centre();
    return S.at(t[0] + c[0], t[1] + c[1], t[2] + c[2]);
  }
};

/// A peak of S_T (see the header comment).
struct SymmetryPeak {
  Eigen::Array3i voxel_offset = Eigen::Array3i::Zero();  ///< t in voxels
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();      ///< sub-voxel position, points' units
  double value = 0;                                      ///< S_T(t) at the voxel offset
  double contrast = 0;                                   ///< the radial contrast K(t) there
};

namespace detail {

/// The smallest m >= n with no prime factor above 5 (n >= 1).
template <class = void>
std::size_t fft_friendly_size(std::size_t n) {
  for (std::size_t m = std::max<std::size_t>(n, 1);; ++m) {
    std::size_t r = m;
    for (std::size_t p : {2, 3, 5})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
}

// The grid of a point set: voxel edge, origin, field size and FFT size, within max_cells.
template <class = void>
Status choose_symmetry_grid(const MatrixX3f& points, double spacing, const SymmetryFieldOptions& options,
                                   SymmetryTransform& out) {
  if (!(spacing > 0) || !std::isfinite(spacing) || !(options.voxel_factor > 0) ||
      !std::isfinite(options.voxel_factor) || options.max_cells < 1)
    return error(StatusCode::invalid_argument,
                 "the symmetry field needs a positive spacing, voxel factor and cell limit");
  if (!points.allFinite()) return error(StatusCode::invalid_argument, "the symmetry field's points must be finite");
  const Eigen::Vector3d lo = points.colwise().minCoeff().cast<double>().transpose();
  const Eigen::Vector3d hi = points.colwise().maxCoeff().cast<double>().transpose();
  double h = options.voxel_factor * spacing;
  for (int attempt = 0; attempt < 400; ++attempt) {
    const Eigen::Vector3d origin = (lo.array() / h).floor().matrix() * h;
    const Eigen::Array3d n = ((hi - origin).array() / h).floor() + 2;  // in double: no overflow for a tiny h
    const Eigen::Array3d padded = 2 * n - 1;
    const double estimate = padded.prod();
    if (estimate <= double(options.max_cells)) {
      Eigen::Array3i dims, fft;
      for (int a = 0; a < 3; ++a) {
        dims[a] = int(n[a]);
        fft[a] = int(fft_friendly_size(std::size_t(padded[a])));
      }
      if (double(fft[0]) * double(fft[1]) * double(fft[2]) <= double(options.max_cells)) {
        out.voxel = h;
        out.origin = origin;
        out.fft_size = fft;
        out.field.dims = dims;
        return {};
      }
    }
    h *= std::max(1.05, std::cbrt(estimate / double(options.max_cells)));
    if (!std::isfinite(h)) break;
  }
  return error(StatusCode::too_large,
               "the symmetry field cannot fit in " + std::to_string(options.max_cells) + " cells");
}

// Calls f(cell index, weight) for the 8 trilinear weights of continuous grid coordinate u (voxel units from the
// grid origin), skipping cells outside the grid.
template <class F>
void trilinear(const VoxelGrid& g, const Eigen::Array3d& u, F&& f) {
  const Eigen::Array3d fl = u.floor();
  const Eigen::Array3d w1 = u - fl, w0 = 1 - w1;
  const int x0 = int(fl[0]), y0 = int(fl[1]), z0 = int(fl[2]);
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int x = x0 + dx, y = y0 + dy, z = z0 + dz;
        if (!g.contains(x, y, z)) continue;
        f(g.index(x, y, z), (dx ? w1[0] : w0[0]) * (dy ? w1[1] : w0[1]) * (dz ? w1[2] : w0[2]));
      }
}

inline bool fft_line_needed(int i, int n, int N) { return i < n || i > N - n; }

}  // namespace detail

/// Trilinear splat of `points` (moved by `shift`) into `field` (its dims kept, values reset) on the grid of
/// edge `voxel` from `origin`; weights falling outside the grid are dropped.
template <class = void>
void splat_points(const MatrixX3f& points, const Eigen::Vector3d& shift, double voxel,
                         const Eigen::Vector3d& origin, VoxelGrid& field) {
  field.values.assign(field.cells(), 0.0);
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Eigen::Array3d u = (points.row(i).cast<double>().transpose() + shift - origin).array() / voxel;
    detail::trilinear(field, u, [&](std::size_t k, double w) { field.values[k] += w; });
  }
}

/// The linear autocorrelation R(t) = sum_x f(x) f(x + t) for |t_a| <= n_a - 1 (n = f.dims), by FFT: zero
/// padding to `fft_size` (each N_a >= 2 n_a - 1, else invalid_argument), 1-D transforms along x, y, z (Eigen's
/// FFT module). `R` gets dims 2 n - 1, R(t) at index t + n - 1. Reports fractions of `stage` after each pass;
/// a cancel gives StatusCode::cancelled. An empty f gives an empty R.
template <class = void>
Status autocorrelate(const VoxelGrid& f, const Eigen::Array3i& fft_size, VoxelGrid& R,
                            const Progress& progress = {}, const char* stage = "autocorrelation") {
  const Eigen::Array3i n = f.dims, N = fft_size;
  if ((n < 0).any() || f.values.size() != f.cells())
    return error(StatusCode::invalid_argument, "autocorrelate: the field's values do not match its dims");
  if (f.cells() == 0) {
    R.reset(Eigen::Array3i::Zero());
    return {};
  }
  if ((N < 2 * n - 1).any())
    return error(StatusCode::invalid_argument, "autocorrelate: the FFT size must be at least 2 n - 1 per axis");
  using Complex = std::complex<double>;
  const std::size_t Nx = std::size_t(N[0]), Ny = std::size_t(N[1]), Nz = std::size_t(N[2]);
  std::vector<Complex> g(Nx * Ny * Nz, Complex(0, 0));
  for (int z = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x) g[std::size_t(x) + Nx * (std::size_t(y) + Ny * std::size_t(z))] = f.at(x, y, z);

  Eigen::FFT<double> fft;
  std::vector<Complex> in, out;
  const std::size_t stride[3] = {1, Nx, Nx * Ny};
  // One pass of 1-D transforms along `axis` over the lines for which keep(i_b, i_c) holds, (b, c) being the
  // other two axes in increasing order.
  const auto pass = [&](int axis, bool inverse, auto keep) {
    const int b = axis == 0 ? 1 : 0, c = axis == 2 ? 1 : 2;
    const std::size_t len = std::size_t(N[axis]);
    in.resize(len);
    out.resize(len);
    for (int ic = 0; ic < N[c]; ++ic)
      for (int ib = 0; ib < N[b]; ++ib) {
        if (!keep(ib, ic)) continue;
        const std::size_t base = std::size_t(ib) * stride[b] + std::size_t(ic) * stride[c];
        for (std::size_t k = 0; k < len; ++k) in[k] = g[base + k * stride[axis]];
        if (inverse)
          fft.inv(out.data(), in.data(), Eigen::Index(len));
        else
          fft.fwd(out.data(), in.data(), Eigen::Index(len));
        for (std::size_t k = 0; k < len; ++k) g[base + k * stride[axis]] = out[k];
      }
  };
  const auto cancelled = [] { return error(StatusCode::cancelled, "cancelled during the autocorrelation"); };
  // Forward: along x only lines through the field (y < n_y, z < n_z) are non-zero, along y those with z < n_z.
  pass(0, false, [&](int y, int z) { return y < n[1] && z < n[2]; });
  if (!progress.report(stage, 1.0 / 6)) return cancelled();
  pass(1, false, [&](int, int z) { return z < n[2]; });
  if (!progress.report(stage, 2.0 / 6)) return cancelled();
  pass(2, false, [](int, int) { return true; });
  if (!progress.report(stage, 3.0 / 6)) return cancelled();
  for (Complex& v : g) v = Complex(std::norm(v), 0);  // |F|^2: the transform of the autocorrelation
  // Back: only offsets |t_a| <= n_a - 1 are wanted, i.e. indices i < n_a or i > N_a - n_a.
  pass(2, true, [](int, int) { return true; });
  if (!progress.report(stage, 4.0 / 6)) return cancelled();
  pass(1, true, [&](int, int z) { return detail::fft_line_needed(z, n[2], N[2]); });
  if (!progress.report(stage, 5.0 / 6)) return cancelled();
  pass(0, true,
       [&](int y, int z) { return detail::fft_line_needed(y, n[1], N[1]) && detail::fft_line_needed(z, n[2], N[2]); });
  R.reset(2 * n - 1);
  const auto wrap = [](int t, int len) { return std::size_t(t < 0 ? t + len : t); };
  for (int tz = -(n[2] - 1); tz <= n[2] - 1; ++tz)
    for (int ty = -(n[1] - 1); ty <= n[1] - 1; ++ty)
      for (int tx = -(n[0] - 1); tx <= n[0] - 1; ++tx)
        R.values[R.index(tx + n[0] - 1, ty + n[1] - 1, tz + n[2] - 1)] =
            g[wrap(tx, N[0]) + Nx * (wrap(ty, N[1]) + Ny * wrap(tz, N[2]))].real();
  return {};
}

/// S_T of a point set (see the header comment): grid from `spacing` and `options`, trilinear splat,
/// FFT autocorrelation, divided by R(0). Reports progress under `stage`. No points: an empty transform.
template <class = void>
Status symmetry_transform(const MatrixX3f& points, double spacing, const SymmetryFieldOptions& options,
                                 SymmetryTransform& out, const Progress& progress = {},
                                 const char* stage = "autocorrelation") {
  out = SymmetryTransform{};
  if (!progress.report(stage, 0)) return error(StatusCode::cancelled, "cancelled during the autocorrelation");
  if (points.rows() == 0) return {};
  RESTITCH_TRY(detail::choose_symmetry_grid(points, spacing, options, out));
  splat_points(points, Eigen::Vector3d::Zero(), out.voxel, out.origin, out.field);
  VoxelGrid R;
  RESTITCH_TRY(autocorrelate(out.field, out.fft_size, R, progress, stage));
  out.norm2 = 0;
  for (double v : out.field.values) out.norm2 += v * v;
  out.S = std::move(R);
  const double r0 = out.S.values[out.S.index(out.centre()[0], out.centre()[1], out.centre()[2])];
  if (!(r0 > 0)) return error(StatusCode::internal, "the autocorrelation at 0 is not positive");
  for (double& v : out.S.values) v /= r0;
  return {};
}

/// S_T at any offset t (points' units): sum_x f(x) g_t(x) / ||f||^2, g_t the splat of `points` moved by t on
/// the transform's grid (see the header comment). `points` must be those the transform was built from.
template <class = void>
double symmetry_at(const MatrixX3f& points, const SymmetryTransform& st, const Eigen::Vector3d& t) {
  if (!(st.norm2 > 0)) return 0;
  double sum = 0;
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Eigen::Array3d u = (points.row(i).cast<double>().transpose() + t - st.origin).array() / st.voxel;
    detail::trilinear(st.field, u, [&](std::size_t k, double w) { sum += w * st.field.values[k]; });
  }
  return sum / st.norm2;
}

/// S_T at a fractional voxel offset, interpolated trilinearly (0 beyond the support).
template <class = void>
double symmetry_interpolated(const SymmetryTransform& st, const Eigen::Array3d& t) {
  const Eigen::Array3d u = t + st.centre().cast<double>();
  double sum = 0;
  detail::trilinear(st.S, u, [&](std::size_t k, double w) { sum += w * st.S.values[k]; });
  return sum;
}

/// What `symmetry_peaks` keeps (lengths in the points' units; see the header comment).
struct SymmetryPeakOptions {
  double tau = 0.15;                        ///< only offsets longer than this
  double min_value = 0.1;                   ///< S_T at the peak at least this
  double min_contrast = 0.002;              ///< the radial contrast at the peak at least this
  double contrast_distance = 2;             ///< d of the radial contrast, in voxels
  double suppression_radius = 0.15;         ///< a peak this close to a stronger one (or its negative) is dropped
  std::size_t max_count = std::size_t(-1);  ///< at most this many peaks
};

/// The radial contrast of S_T at every voxel offset t != 0: K(t) = S_T(t) - (S_T(t - d u) + S_T(t + d u)) / 2,
/// u = t / |t|, d = `distance` voxels (interpolated); 0 at t = 0. Same layout as st.S.
template <class = void>
VoxelGrid symmetry_contrast(const SymmetryTransform& st, double distance) {
  VoxelGrid K;
  K.reset(st.S.dims);
  const Eigen::Array3i c = st.centre();
  for (int z = 0; z < K.dims[2]; ++z)
    for (int y = 0; y < K.dims[1]; ++y)
      for (int x = 0; x < K.dims[0]; ++x) {
        const Eigen::Array3d t = (Eigen::Array3i(x, y, z) - c).cast<double>();
        const double len = t.matrix().norm();
        if (len == 0) continue;
        const Eigen::Array3d step = t * (distance / len);
        K.values[K.index(x, y, z)] = st.S.values[st.S.index(x, y, z)] -
                                     0.5 * (symmetry_interpolated(st, t - step) + symmetry_interpolated(st, t + step));
      }
  return K;
}

/// The peaks of S_T (see the header comment): local maxima of the radial contrast in the half-space, longer
/// than tau, with S_T and contrast above the thresholds, ranked by S_T, non-maximum suppressed.
template <class = void>
std::vector<SymmetryPeak> symmetry_peaks(const SymmetryTransform& st, const SymmetryPeakOptions& o = {}) {
  std::vector<SymmetryPeak> found;
  const VoxelGrid& S = st.S;
  if (S.cells() == 0) return found;
  const VoxelGrid K = symmetry_contrast(st, o.contrast_distance);
  const Eigen::Array3i c = st.centre();
  const std::size_t centre = S.index(c[0], c[1], c[2]);
  for (int z = c[2]; z < S.dims[2]; ++z)
    for (int y = 0; y < S.dims[1]; ++y)
      for (int x = 0; x < S.dims[0]; ++x) {
        const std::size_t i = S.index(x, y, z);
        if (i <= centre) continue;  // the other half-space, and t = 0
        const double v = S.values[i], k = K.values[i];
        if (!(v >= o.min_value) || !(k >= o.min_contrast)) continue;
        const Eigen::Array3i t(x - c[0], y - c[1], z - c[2]);
        if (!(t.cast<double>().matrix().norm() * st.voxel > o.tau)) continue;
        bool peak = true;
        for (int dz = -1; dz <= 1 && peak; ++dz)
          for (int dy = -1; dy <= 1 && peak; ++dy)
            for (int dx = -1; dx <= 1 && peak; ++dx) {
              if (!dx && !dy && !dz) continue;
              const double w = K.at(x + dx, y + dy, z + dz);
              const bool earlier = dz < 0 || (dz == 0 && (dy < 0 || (dy == 0 && dx < 0)));
              peak = earlier ? k > w : k >= w;
            }
        if (!peak) continue;
        SymmetryPeak p;
        p.voxel_offset = t;
        p.value = v;
        p.contrast = k;
        Eigen::Vector3d sub = t.cast<double>().matrix();
        for (int a = 0; a < 3; ++a) {
          const int e[3] = {a == 0, a == 1, a == 2};
          const double lo = K.at(x - e[0], y - e[1], z - e[2]), hi = K.at(x + e[0], y + e[1], z + e[2]);
          const double curvature = lo - 2 * k + hi;
          if (curvature < 0) sub[a] += std::clamp(0.5 * (lo - hi) / curvature, -0.5, 0.5);
        }
        p.offset = sub * st.voxel;
        found.push_back(p);
      }
  std::stable_sort(found.begin(), found.end(),
                   [](const SymmetryPeak& a, const SymmetryPeak& b) { return a.value > b.value; });
  std::vector<SymmetryPeak> kept;
  for (const SymmetryPeak& p : found) {
    if (kept.size() >= o.max_count) break;
    bool suppressed = false;
    for (const SymmetryPeak& q : kept) {
      const Eigen::Vector3d d = ((p.voxel_offset - q.voxel_offset).cast<double>() * st.voxel).matrix();
      const Eigen::Vector3d s = ((p.voxel_offset + q.voxel_offset).cast<double>() * st.voxel).matrix();
      suppressed = suppressed || d.norm() <= o.suppression_radius || s.norm() <= o.suppression_radius;
    }
    if (!suppressed) kept.push_back(p);
  }
  return kept;
}

}  // namespace restitch
