// Tests for offsets/autocorrelation.hpp: the FFT autocorrelation against a brute-force oracle, S_T's
// normalisation and peaks on fields of known period, the grid limit, the AutocorrelationOffsetDetector on
// point clouds and (through analyze) on every sample family and on models without repetition, and the
// structure score.
#include "restitch/offsets/autocorrelation.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "restitch/analyze.hpp"
#include "restitch/families/families.hpp"
#include "restitch/runtime.hpp"

#include "support/mesh_builders.hpp"
#include "support/sampled_shapes.hpp"

using namespace restitch;
using Eigen::Array3i;
using Eigen::Vector3d;
using namespace restitch::test;

static_assert(is_offset_detector_v<AutocorrelationOffsetDetector>, "the autocorrelation detector is a detector");
static_assert(!detector_uses_matches_v<AutocorrelationOffsetDetector>, "it ignores matches");
static_assert(detector_uses_matches_v<HistogramOffsetDetector>, "the histogram needs them");

namespace {

// R(t) = sum_x f(x) f(x + t), summed directly.
double brute_force_correlation(const VoxelGrid& f, const Array3i& t) {
  double sum = 0;
  for (int z = 0; z < f.dims[2]; ++z)
    for (int y = 0; y < f.dims[1]; ++y)
      for (int x = 0; x < f.dims[0]; ++x) sum += f.at(x, y, z) * f.at(x + t[0], y + t[1], z + t[2]);
  return sum;
}

// Points on the faces of n copies of a small module along x, pitch `pitch`, on exactly representable
// coordinates (multiples of 1/64): every copy is the same points translated.
MatrixX3f periodic_points(int copies, double pitch) {
  std::vector<Vector3d> module;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      module.emplace_back(0.25 + i / 16.0, 0.25 + j / 16.0, 0.25);  // a plate...
      module.emplace_back(0.25, 0.25 + i / 16.0, 0.25 + j / 32.0);  // ...and a wall on it
    }
  MatrixX3f P(Eigen::Index(module.size()) * copies, 3);
  Eigen::Index r = 0;
  for (int c = 0; c < copies; ++c)
    for (const Vector3d& m : module) P.row(r++) = (m + Vector3d(c * pitch, 0, 0)).cast<float>().transpose();
  return P;
}

using AcOptions = AnalysisOptions<ShotDescriptor, BruteForceMatcher, AutocorrelationOffsetDetector>;

}  // namespace

TEST_CASE("autocorrelate equals a brute-force autocorrelation, linear and not circular", "[autocorrelation]") {
  std::mt19937_64 rng(3);
  VoxelGrid f;
  f.reset(Array3i(7, 5, 4));
  for (double& v : f.values) v = unit(rng) < 0.4 ? unit(rng) : 0.0;
  for (const Array3i& N : {Array3i(13, 9, 7), Array3i(15, 10, 8), Array3i(16, 12, 9)}) {  // 2n - 1, friendly, more
    INFO("FFT size " << N.transpose());
    VoxelGrid R;
    REQUIRE(autocorrelate(f, N, R).ok());
    REQUIRE((R.dims == 2 * f.dims - 1).all());
    const double r0 = brute_force_correlation(f, Array3i::Zero());
    REQUIRE(r0 > 0);
    for (int z = 0; z < R.dims[2]; ++z)
      for (int y = 0; y < R.dims[1]; ++y)
        for (int x = 0; x < R.dims[0]; ++x) {
          const Array3i t(x - f.dims[0] + 1, y - f.dims[1] + 1, z - f.dims[2] + 1);
          const double expected = brute_force_correlation(f, t);
          INFO("t = " << t.transpose());
          CHECK(std::abs(R.at(x, y, z) - expected) <= 1e-12 * r0);
        }
  }
  // Too little padding would fold offsets onto each other (circular correlation): refused.
  VoxelGrid R;
  CHECK(autocorrelate(f, Array3i(12, 9, 7), R).code() == StatusCode::invalid_argument);
  // Cancellation.
  const Progress cancel([](std::string_view, double) { return false; });
  CHECK(autocorrelate(f, Array3i(13, 9, 7), R, cancel).code() == StatusCode::cancelled);
  CHECK(detail::fft_friendly_size(13) == 15);
  CHECK(detail::fft_friendly_size(97) == 100);
  CHECK(detail::fft_friendly_size(128) == 128);
}

TEST_CASE("S_T: S_T(0) = 1, symmetric, and it peaks exactly at a field's period", "[autocorrelation]") {
  // Five copies at a pitch of 1.25 = 5 voxels of 0.25 (spacing 0.125, voxel factor 2): the copies' fields are
  // disjoint and identical, so S_T(period) = 4/5 exactly.
  const int copies = 5;
  const MatrixX3f P = periodic_points(copies, 1.25);
  SymmetryTransform st;
  REQUIRE(symmetry_transform(P, 0.125, {}, st).ok());
  REQUIRE(st.voxel == 0.25);
  CHECK(st.at(Array3i::Zero()) == Approx(1.0).epsilon(1e-12));
  CHECK(st.at(Array3i(5, 0, 0)) == Approx(double(copies - 1) / copies).epsilon(1e-12));
  CHECK(st.at(Array3i(10, 0, 0)) == Approx(double(copies - 2) / copies).epsilon(1e-12));
  double max_elsewhere = 0;
  for (int z = 0; z < st.S.dims[2]; ++z)
    for (int y = 0; y < st.S.dims[1]; ++y)
      for (int x = 0; x < st.S.dims[0]; ++x) {
        const Array3i t = Array3i(x, y, z) - st.centre();
        CHECK(st.S.at(x, y, z) == Approx(st.at(-t)).margin(1e-12));  // S_T(t) = S_T(-t)
        CHECK(st.S.at(x, y, z) >= -1e-12);
        CHECK(st.S.at(x, y, z) <= 1 + 1e-12);
        if ((t != 0).any() && (t.abs() != Array3i(5, 0, 0)).any())
          max_elsewhere = std::max(max_elsewhere, st.S.at(x, y, z));
      }
  CHECK(max_elsewhere < 0.8);  // t = +-period is the largest value after t = 0
  // The peaks: the period first, in the kept half-space, then its multiple.
  SymmetryPeakOptions po;
  po.tau = 0.5;
  po.min_value = 0.05;
  po.suppression_radius = 0.5;
  const std::vector<SymmetryPeak> peaks = symmetry_peaks(st, po);
  REQUIRE(peaks.size() >= 2);
  CHECK((peaks[0].voxel_offset == Array3i(5, 0, 0)).all());
  CHECK(peaks[0].value == Approx(0.8).epsilon(1e-12));
  CHECK(std::abs(peaks[0].offset.x() - 1.25) <= 0.5 * st.voxel);
  CHECK((peaks[1].voxel_offset == Array3i(10, 0, 0)).all());
  for (std::size_t i = 0; i < peaks.size(); ++i) {
    const Array3i& t = peaks[i].voxel_offset;
    CHECK((t[2] > 0 || (t[2] == 0 && (t[1] > 0 || (t[1] == 0 && t[0] > 0)))));  // one sign of each offset
    CHECK(t.cast<double>().matrix().norm() * st.voxel > 0.5);
    if (i > 0) CHECK(peaks[i - 1].value >= peaks[i].value);
    CHECK(peaks[i].contrast >= po.min_contrast);
  }
  // A long plate slides onto itself: S_T is high along it but falls linearly, with no radial contrast, so
  // no peak, whatever its value.
  MatrixX3f plate(64 * 8, 3);
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 8; ++j) plate.row(i * 8 + j) << float(i / 16.0), float(j / 16.0), 0.f;
  SymmetryTransform sp;
  REQUIRE(symmetry_transform(plate, 0.125, {}, sp).ok());
  CHECK(sp.at(Array3i(3, 0, 0)) > 0.7);
  CHECK(symmetry_peaks(sp, po).empty());
  // symmetry_at reproduces the FFT's values at voxel offsets (and 1 at 0).
  CHECK(symmetry_at(P, st, Vector3d::Zero()) == Approx(1.0).epsilon(1e-12));
  CHECK(symmetry_at(P, st, Vector3d(1.25, 0, 0)) == Approx(0.8).epsilon(1e-12));
  CHECK(symmetry_at(P, st, Vector3d(0.5, 0.25, 0)) == Approx(st.at(Array3i(2, 1, 0))).margin(1e-12));
  // Off the grid (a pitch of 1.3 = 5.2 voxels) the moved samples are splatted again: copy c moved by the
  // period lands exactly on copy c + 1's splat, so S_T(period) = sum_{c >= 1} |f_c|^2 / sum_c |f_c|^2 with f_c
  // copy c's own (phase-dependent) splat.
  const MatrixX3f Q = periodic_points(copies, 1.3);
  SymmetryTransform sq;
  REQUIRE(symmetry_transform(Q, 0.125, {}, sq).ok());
  const Eigen::Index per_copy = Q.rows() / copies;
  double all = 0, moved_onto = 0;
  for (int c = 0; c < copies; ++c) {
    VoxelGrid fc = sq.field;
    splat_points(Q.middleRows(c * per_copy, per_copy), Vector3d::Zero(), sq.voxel, sq.origin, fc);
    double n2 = 0;
    for (double v : fc.values) n2 += v * v;
    all += n2;
    if (c > 0) moved_onto += n2;
  }
  const double at_period = symmetry_at(Q, sq, Vector3d(1.3, 0, 0));
  CHECK(at_period == Approx(moved_onto / all).epsilon(1e-5));
  CHECK(at_period > 0.7);
  CHECK(sq.at(Array3i(5, 0, 0)) < at_period);  // the voxel grid's nearest value (the blur keeps most of it)
}

TEST_CASE("S_T grid: voxel from the spacing, padding, and a cell limit met before allocating", "[autocorrelation]") {
  const MatrixX3f P = periodic_points(5, 1.25);
  SymmetryTransform st;
  REQUIRE(symmetry_transform(P, 0.125, {}, st).ok());
  CHECK((st.fft_size >= 2 * st.field.dims - 1).all());
  CHECK(st.origin == Vector3d(0.25, 0.25, 0.25));  // floor(min / voxel) * voxel
  // A limit smaller than the grid: the voxel grows until the padded grid fits.
  SymmetryFieldOptions small;
  small.max_cells = 300;  // the grid above needs 45 x 5 x 3 = 675
  CHECK(st.fft_size.prod() == 675);
  REQUIRE(symmetry_transform(P, 0.125, small, st).ok());
  CHECK(st.voxel > 0.25);
  CHECK(double(st.fft_size.prod()) <= 300);
  CHECK(st.at(Array3i::Zero()) == Approx(1.0).epsilon(1e-12));
  // An absurd request (spacing 1e-9 on a unit-sized model) is met by growing the voxel, never by allocating.
  REQUIRE(symmetry_transform(P, 1e-9, {}, st).ok());
  CHECK(double(st.fft_size.prod()) <= double(SymmetryFieldOptions{}.max_cells));
  // Bad parameters and points.
  CHECK(symmetry_transform(P, 0, {}, st).code() == StatusCode::invalid_argument);
  SymmetryFieldOptions zero;
  zero.max_cells = 0;
  CHECK(symmetry_transform(P, 0.125, zero, st).code() == StatusCode::invalid_argument);
  MatrixX3f bad = P;
  bad(3, 1) = NAN;
  CHECK(symmetry_transform(bad, 0.125, {}, st).code() == StatusCode::invalid_argument);
  // No points: an empty transform, no peaks.
  REQUIRE(symmetry_transform(MatrixX3f(0, 3), 0.125, {}, st).ok());
  CHECK(symmetry_peaks(st).empty());
}

TEST_CASE("autocorrelation detector: a sheared lattice of boxes is found and significant",
          "[autocorrelation][detector]") {
  const PointSet cloud = lattice_cloud(11);
  const std::vector<Match> no_matches;
  OffsetDetection det;
  const AutocorrelationOffsetDetector detector;
  REQUIRE(detector.detect({cloud, cloud, no_matches, 0.02, 0.15}, det, {}).ok());
  std::vector<Vector3d> significant;
  for (const DominantOffset& d : det.dominant)
    if (d.significant) significant.push_back(d.offset);
  REQUIRE(significant.size() >= 2);
  CHECK(recovered(kT1, significant, 0.003, 0.2));
  CHECK(recovered(kT2, significant, 0.003, 0.2));
  CHECK(det.peaks >= 2);
  CHECK(det.timings_ms.count("autocorrelation") == 1);
  CHECK(det.timings_ms.count("refinement") == 1);
  CHECK(det.timings_ms.count("histogram") == 0);
  for (const DominantOffset& d : det.dominant) {
    CHECK(d.votes > 0);
    CHECK(d.votes <= std::size_t(cloud.size()));
  }
  // Deterministic.
  OffsetDetection again;
  REQUIRE(detector.detect({cloud, cloud, no_matches, 0.02, 0.15}, again, {}).ok());
  REQUIRE(again.dominant.size() == det.dominant.size());
  for (std::size_t i = 0; i < det.dominant.size(); ++i) CHECK(again.dominant[i].offset == det.dominant[i].offset);
  // Cancellation in either stage, bad evidence and parameters.
  for (const char* stop_at : {"autocorrelation", "refinement"}) {
    const Progress cancel([&](std::string_view stage, double) { return stage != stop_at; });
    CHECK(detector.detect({cloud, cloud, no_matches, 0.02, 0.15}, det, cancel).code() == StatusCode::cancelled);
  }
  CHECK(detector.detect({cloud, cloud, no_matches, 0.0, 0.15}, det, {}).code() == StatusCode::invalid_argument);
  AutocorrelationOffsetDetector bad;
  bad.min_strength = 2;
  CHECK(bad.detect({cloud, cloud, no_matches, 0.02, 0.15}, det, {}).code() == StatusCode::invalid_argument);
}

TEST_CASE("autocorrelation detector: a sliding plate has no significant offset", "[autocorrelation][detector]") {
  std::mt19937_64 rng(5);
  std::vector<Vector3d> P, N;
  sample_box(P, N, Vector3d(-0.5, -0.35, -0.02), Vector3d(0.5, 0.35, 0.02), 0.02, rng);
  const PointSet cloud = to_point_set(P, N);
  OffsetDetection det;
  REQUIRE(AutocorrelationOffsetDetector{}.detect({cloud, cloud, {}, 0.02, 0.15}, det, {}).ok());
  for (const DominantOffset& d : det.dominant) CHECK_FALSE(d.significant);
}

TEST_CASE("autocorrelation detector recovers the generators of every sample family", "[autocorrelation][samples]") {
  for (const char* family : {"bookshelf", "facade", "facade_sheared", "fence", "pin_header"}) {
    DYNAMIC_SECTION(family) {
      const Result<families::SampleModel> sample = families::generate(family);
      REQUIRE(sample.ok());
      const Result<Analysis> a = analyze(sample->mesh, AcOptions{});
      REQUIRE(a.ok());
      const std::vector<Vector3d> found = a->principal_model_units();
      for (const Vector3d& g : sample->generators) {
        INFO("generator " << g.transpose());
        for (const Vector3d& f : found) INFO("principal " << f.transpose());
        for (const DominantOffset& d : a->dominant)
          INFO("dominant " << a->normalization.to_model_offset(d.offset).transpose() << " votes " << d.votes
                           << " overlap " << d.overlap << " significant " << d.significant);
        CHECK(recovered(g, found, 0.01, 1.0));
      }
      CHECK(found.size() == sample->generators.size());
      CHECK(a->detector_name == "autocorrelation");
      CHECK(a->timings_ms.count("autocorrelation") == 1);
      CHECK(a->timings_ms.count("matching") == 0);  // the detector ignores matches: the stage is skipped
      CHECK(a->matches.empty());
    }
  }
}

TEST_CASE("autocorrelation detector: a model without repetition yields zero principal offsets", "[autocorrelation]") {
  for (std::uint64_t seed : {1u, 4u, 12u, 20u}) {
    const Mesh mesh = random_boxes(seed);
    REQUIRE(validate(mesh).ok());
    const Result<Analysis> a = analyze(mesh, AcOptions{});
    REQUIRE(a.ok());
    INFO("seed " << seed);
    for (const DominantOffset& d : a->dominant)
      INFO("dominant " << d.offset.transpose() << " votes " << d.votes << " overlap " << d.overlap << " contrast "
                       << d.contrast << " significant " << d.significant);
    CHECK(a->principal.empty());
    CHECK(a->lattice.principal_count() == 0);
  }
}

TEST_CASE("runtime: the detector is chosen by name", "[autocorrelation][runtime]") {
  CHECK(detector_names() == std::vector<std::string>{"histogram", "autocorrelation"});
  const Result<families::SampleModel> sample = families::generate("pin_header", {{"pins", 5}});
  REQUIRE(sample.ok());
  const Result<Analysis> named = analyze_named(sample->mesh, "shot", "brute_force", "autocorrelation");
  const Result<Analysis> templated = analyze(sample->mesh, AcOptions{});
  REQUIRE(named.ok());
  REQUIRE(templated.ok());
  CHECK(named->detector_name == "autocorrelation");
  CHECK(named->principal == templated->principal);
  CHECK(named->lattice.A == templated->lattice.A);
  const Result<Analysis> def = analyze_named(sample->mesh, "shot", "brute_force", "histogram");
  REQUIRE(def.ok());
  CHECK(def->detector_name == "histogram");
  const Result<Analysis> bad = analyze_named(sample->mesh, "shot", "brute_force", "fourier");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.status().code() == StatusCode::invalid_argument);
  CHECK_THAT(bad.status().message(), Catch::Contains("detector") && Catch::Contains("'fourier'") &&
                                         Catch::Contains("histogram") && Catch::Contains("autocorrelation"));
}

TEST_CASE("structure score: a repeated model scores higher than random boxes; resizes keep the structure",
          "[autocorrelation][structure]") {
  double lowest_family = 1;
  for (const char* family : {"bookshelf", "facade", "facade_sheared", "fence", "pin_header"}) {
    const Result<families::SampleModel> sample = families::generate(family);
    REQUIRE(sample.ok());
    const Result<double> s = structure_score(sample->mesh);
    REQUIRE(s.ok());
    INFO(family << ": " << *s);
    CHECK(*s > 0);
    CHECK(*s <= 1);
    lowest_family = std::min(lowest_family, *s);
  }
  double highest_random = 0;
  for (std::uint64_t seed : {1u, 4u, 12u, 20u}) {
    const Result<double> s = structure_score(random_boxes(seed));
    REQUIRE(s.ok());
    INFO("random boxes " << seed << ": " << *s);
    highest_random = std::max(highest_random, *s);
  }
  INFO("lowest family " << lowest_family << ", highest random " << highest_random);
  CHECK(lowest_family > highest_random);

  // structure_at: S_T at the true generator, in the input's normalization. Two more modules (what a perfect
  // resize gives) keep the structure and add to it; the same module count at another pitch loses it.
  const Result<families::SampleModel> fence = families::generate("fence");
  REQUIRE(fence.ok());
  const std::string count = fence->count_parameters[0];
  const int n = fence->counts[0];
  const Result<families::SampleModel> longer = families::generate("fence", {{count, double(n + 2)}});
  REQUIRE(longer.ok());
  const Normalization reference = Normalization::of(bounding_box(fence->mesh));
  const std::vector<Vector3d> g = {fence->generators[0]};
  const Result<StructureValues> in = structure_at(fence->mesh, g, reference);
  const Result<StructureValues> out = structure_at(longer->mesh, g, reference);
  REQUIRE(in.ok());
  REQUIRE(out.ok());
  REQUIRE(in->values.size() == 1);
  CHECK(in->voxel == Approx(0.04));
  CHECK(out->voxel == in->voxel);
  INFO("input " << in->values[0] << ", two more modules " << out->values[0]);
  CHECK(in->values[0] > 0.5);
  CHECK(out->values[0] > in->values[0]);
  const Result<StructureValues> off = structure_at(fence->mesh, {fence->generators[0] * 1.3}, reference);
  REQUIRE(off.ok());
  CHECK(off->values[0] < in->values[0] - 0.1);  // the rails still slide onto themselves: not 0
  // Bad input.
  CHECK(structure_at(fence->mesh, g, Normalization{Vector3d::Zero(), 0.0}).status().code() ==
        StatusCode::invalid_argument);
  CHECK(structure_score(Mesh{}).status().code() == StatusCode::invalid_mesh);
}
