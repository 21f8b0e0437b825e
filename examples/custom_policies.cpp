// Plugging your own descriptor and matcher into restitch::analyze.
//
// Both policies below are written here, not in the library: a crude 3-D
// "shape context" descriptor (neighbour counts per octant and shell, in the
// world frame) and a plain double-loop matcher. analyze() checks their
// contracts at compile time (see restitch/descriptor/descriptor.hpp and
// restitch/matcher/matcher.hpp). The program analyzes the bundled pin header
// (8 pins at 2.54 mm) and prints what it found:
//   principal_offsets 1
//   pitch 2.5400
#include <cmath>
#include <cstdio>
#include <limits>

#include "restitch/families/families.hpp"
#include "restitch/restitch.hpp"

// 16 values: for each neighbour within `radius`, its octant (sign of dx, dy,
// dz) and shell (inner or outer half), counted and L2-normalized.
struct OctantDescriptor {
  static constexpr const char* name = "octants";
  float radius = 0.2f;
  int dimension() const { return 16; }
  restitch::Status compute(const restitch::PointSet& support, const restitch::PointSet& queries,
                           restitch::DescriptorMatrix& out, const restitch::Progress& progress) const {
    out.setZero(queries.size(), dimension());
    for (Eigen::Index q = 0; q < queries.size(); ++q) {
      if (q % 1024 == 0 && !progress.report("descriptors", double(q) / double(queries.size())))
        return restitch::error(restitch::StatusCode::cancelled, "cancelled");
      for (Eigen::Index s = 0; s < support.size(); ++s) {
        const Eigen::Vector3f d = support.points.row(s) - queries.points.row(q);
        const float r = d.norm();
        if (r >= radius || r == 0) continue;
        const int octant = (d.x() > 0) + 2 * (d.y() > 0) + 4 * (d.z() > 0);
        out(q, octant * 2 + (r > radius / 2)) += 1;
      }
      const float n = out.row(q).norm();
      if (n > 0)
        out.row(q) /= n;
      else
        out.row(q).setConstant(std::numeric_limits<float>::quiet_NaN());
    }
    return {};
  }
};

// Every feature's most similar feature farther than tau; ties (within 1e-6)
// go to the shorter offset, as the matcher contract asks.
struct LoopMatcher {
  static constexpr const char* name = "loops";
  restitch::Status match(const restitch::PointSet& features, const restitch::DescriptorMatrix& descriptors, float tau,
                         std::vector<restitch::Match>& out, const restitch::Progress&) const {
    const Eigen::Index n = features.size();
    out.assign(std::size_t(n), restitch::Match{});
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!descriptors.row(i).allFinite()) continue;
      double best = INFINITY, best_len = INFINITY;
      for (Eigen::Index j = 0; j < n; ++j) {
        if (j == i || !descriptors.row(j).allFinite()) continue;
        const double len = (features.points.row(j) - features.points.row(i)).cast<double>().norm();
        if (!(len > tau)) continue;
        const double d = (descriptors.row(j) - descriptors.row(i)).cast<double>().norm();
        const bool tie = std::abs(d - best) <= std::max(1e-6 * std::max(d, best), 1e-6);
        if ((tie && len < best_len) || (!tie && d < best)) {
          best = d, best_len = len;
          out[std::size_t(i)].target = std::int32_t(j);
          out[std::size_t(i)].distance = float(d);
        }
      }
    }
    return {};
  }
};

int main() {
  restitch::Result<restitch::families::SampleModel> sample = restitch::families::generate("pin_header");
  if (!sample) return std::fprintf(stderr, "%s\n", sample.status().message().c_str()), 1;
  restitch::AnalysisOptions<OctantDescriptor, LoopMatcher> options;
  restitch::Result<restitch::Analysis> analysis = restitch::analyze(sample->mesh, options);
  if (!analysis) return std::fprintf(stderr, "%s\n", analysis.status().message().c_str()), 1;
  std::printf("descriptor %s, matcher %s\n", analysis->descriptor_name.c_str(), analysis->matcher_name.c_str());
  const auto principal = analysis->principal_model_units();
  std::printf("principal_offsets %zu\n", principal.size());
  for (const Eigen::Vector3d& v : principal) std::printf("pitch %.4f\n", v.norm());
  return 0;
}
