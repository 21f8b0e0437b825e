// restitch/runtime.hpp - choosing among the shipped policies at run time.
//
// The library's policies are template parameters; a program that lets its
// user pick one (the CLI's --descriptor, the web page's dropdowns) needs a
// closed set of instantiations to choose from. This header is that set:
// names in, the matching instantiation called. It is a std::variant / a
// switch over names, not a virtual base class: the policies stay templates, and only this file knows the closed set.
//
//   descriptors  "shot" (default), "fpfh"
//   matchers     "brute_force" (default, the exact reference), "reduced" (PCA candidates with exact
//                re-ranking: the same result, faster on varied descriptors, slower when many tie)
//   detectors    "histogram" (default, the paper's offset histogram), "autocorrelation" (peaks of the
//                translational symmetry transform S_T by FFT, offsets/autocorrelation.hpp)
//   label spaces "lattice" (default), "regular" (the paper's baseline)
//
// An unknown name is an invalid_argument Status listing the known ones.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "restitch/analyze.hpp"
#include "restitch/detail/instantiation.hpp"
#include "restitch/offsets/autocorrelation.hpp"
#include "restitch/retarget.hpp"

namespace restitch {

template <class = void>
const std::vector<std::string>& descriptor_names() {
  static const std::vector<std::string> n{"shot", "fpfh"};
  return n;
}
template <class = void>
const std::vector<std::string>& matcher_names() {
  static const std::vector<std::string> n{"brute_force", "reduced"};
  return n;
}
template <class = void>
const std::vector<std::string>& detector_names() {
  static const std::vector<std::string> n{"histogram", "autocorrelation"};
  return n;
}
template <class = void>
const std::vector<std::string>& label_space_names() {
  static const std::vector<std::string> n{"lattice", "regular"};
  return n;
}

/// The seam energies by name (RetargetOptions::seam_energy; the default first).
template <class = void>
const std::vector<std::string>& seam_energy_names() {
  static const std::vector<std::string> n{"descriptor", "geometry"};
  return n;
}

namespace detail {
template <class = void>
Status unknown_name(const char* what, const std::string& name, const std::vector<std::string>& known) {
  std::string list;
  for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
  return error(StatusCode::invalid_argument, "unknown " + std::string(what) + " '" + name + "' (known: " + list + ")");
}
template <class D, class M, class Det>
Result<Analysis> analyze_with(const Mesh& mesh, const Progress& progress, int threads) {
  AnalysisOptions<D, M, Det> options;
  options.threads = threads;
  return analyze(mesh, options, progress);
}
template <class D, class M>
Result<Analysis> analyze_detector(const Mesh& mesh, const std::string& detector, const Progress& progress,
                                  int threads) {
  if (detector == "histogram") return analyze_with<D, M, HistogramOffsetDetector>(mesh, progress, threads);
  if (detector == "autocorrelation")
    return analyze_with<D, M, AutocorrelationOffsetDetector>(mesh, progress, threads);
  return unknown_name("detector", detector, detector_names());
}
template <class D>
Result<Analysis> analyze_matcher(const Mesh& mesh, const std::string& matcher, const std::string& detector,
                                 const Progress& progress, int threads) {
  if (matcher == "brute_force") return analyze_detector<D, BruteForceMatcher>(mesh, detector, progress, threads);
  if (matcher == "reduced") return analyze_detector<D, ReducedMatcher>(mesh, detector, progress, threads);
  return unknown_name("matcher", matcher, matcher_names());
}
}  // namespace detail

/// analyze() with the descriptor, matcher and offset detector named at run time, default options
/// otherwise; `threads` is AnalysisOptions::threads (1: the calling thread alone; 0: every core).
template <class = void>
Result<Analysis> analyze_named(const Mesh& mesh, const std::string& descriptor, const std::string& matcher,
                                      const std::string& detector, const Progress& progress = {},
                                      int threads = 1) {
  if (descriptor == "shot")
    return detail::analyze_matcher<ShotDescriptor>(mesh, matcher, detector, progress, threads);
  if (descriptor == "fpfh")
    return detail::analyze_matcher<FpfhDescriptor>(mesh, matcher, detector, progress, threads);
  return detail::unknown_name("descriptor", descriptor, descriptor_names());
}

/// analyze() with the descriptor and matcher named at run time and the default ("histogram") detector.
template <class = void>
Result<Analysis> analyze_named(const Mesh& mesh, const std::string& descriptor = "shot",
                                      const std::string& matcher = "brute_force", const Progress& progress = {}) {
  return analyze_named(mesh, descriptor, matcher, "histogram", progress);
}

/// promote_offsets (analyze.hpp) for an analysis made by analyze_named, whose options are the defaults.
inline Status promote_offsets_named(const Mesh& mesh, const std::vector<Eigen::Vector3d>& offsets, Analysis& a) {
  return promote_offsets(mesh, AnalysisOptions<>{}, offsets, a);
}

/// The seam energy named `name` ("geometry" or "descriptor"), or invalid_argument listing them.
template <class = void>
Result<SeamEnergy> seam_energy_named(const std::string& name) {
  SeamEnergy e = SeamEnergy::geometry;
  if (!parse_seam_energy(name, e)) return detail::unknown_name("seam energy", name, seam_energy_names());
  return e;
}

/// A Retargeter whose label space is chosen at run time.
class AnyRetargeter {
 public:
  /// Builds the retargeter; check status() before use.
  template <class = void>
  AnyRetargeter(const Mesh& mesh, const Analysis& analysis, const std::string& label_space = "lattice",
                const RetargetOptions& options = {}) {
    if (label_space == "lattice")
      r_.emplace<Retargeter<LatticeLabels>>(mesh, analysis, options);
    else if (label_space == "regular")
      r_.emplace<Retargeter<RegularLabels>>(mesh, analysis, options);
    else
      status_ = detail::unknown_name("label space", label_space, label_space_names());
  }
  template <class = void>
  Status status() const {
    if (!status_) return status_;
    return std::visit(
        [](const auto& r) -> Status {
          if constexpr (std::is_same_v<std::decay_t<decltype(r)>, std::monostate>)
            return {};
          else
            return r.status();
        },
        r_);
  }
  Result<RetargetResult> retarget(const Eigen::Array3i& steps, const Progress& progress = {}) {
    return on_retargeter<RetargetResult>(*this, [&](auto& r) { return r.retarget(steps, progress); });
  }
  Result<SeamMrf> labelling_problem(const Eigen::Array3i& steps) {
    return on_retargeter<SeamMrf>(*this, [&](auto& r) { return r.labelling_problem(steps); });
  }
  /// Retargeter::retarget_to_size of the chosen label space.
  Result<RetargetResult> retarget_to_size(const Eigen::Vector3d& size, bool exact, const Progress& progress = {}) {
    return on_retargeter<RetargetResult>(*this, [&](auto& r) { return r.retarget_to_size(size, exact, progress); });
  }
  /// Retargeter::set_pivot of the chosen label space.
  template <class = void>
  void set_pivot(const Pivots& pivot) {
    std::visit(
        [&](auto& r) {
          if constexpr (!std::is_same_v<std::decay_t<decltype(r)>, std::monostate>) r.set_pivot(pivot);
        },
        r_);
  }
  Result<Eigen::Array3i> steps_for_size(const Eigen::Vector3d& size) const {
    return on_retargeter<Eigen::Array3i>(*this, [&](const auto& r) { return r.steps_for_size(size); });
  }

 private:
  /// `call(retargeter)` on the chosen label space's Retargeter (of `self`, const or not), or the
  /// status when it failed.
  template <class T, class Self, class Call>
  static Result<T> on_retargeter(Self& self, Call&& call) {
    RESTITCH_TRY(self.status());
    return std::visit(
        [&](auto& r) -> Result<T> {
          if constexpr (std::is_same_v<std::decay_t<decltype(r)>, std::monostate>)
            return error(StatusCode::internal, "no retargeter");
          else
            return call(r);
        },
        self.r_);
  }

  Status status_;
  std::variant<std::monostate, Retargeter<LatticeLabels>, Retargeter<RegularLabels>> r_;
};

// The compiled mode (restitch/detail/instantiation.hpp): every analysis this header can name but the
// default one (analyze.hpp instantiates that).
RESTITCH_INSTANTIATE(Result<Analysis> analyze(const Mesh&, const AnalysisOptions<ShotDescriptor, BruteForceMatcher,
                                              AutocorrelationOffsetDetector>&, const Progress&))
RESTITCH_INSTANTIATE(Result<Analysis> analyze(const Mesh&, const AnalysisOptions<ShotDescriptor, ReducedMatcher,
                                              HistogramOffsetDetector>&, const Progress&))
RESTITCH_INSTANTIATE(Result<Analysis> analyze(const Mesh&, const AnalysisOptions<ShotDescriptor, ReducedMatcher,
                                              AutocorrelationOffsetDetector>&, const Progress&))
RESTITCH_INSTANTIATE(Result<Analysis> analyze(const Mesh&, const AnalysisOptions<FpfhDescriptor, BruteForceMatcher,
                                              HistogramOffsetDetector>&, const Progress&))
RESTITCH_INSTANTIATE(Result<Analysis> analyze(const Mesh&, const AnalysisOptions<FpfhDescriptor, BruteForceMatcher,
                                              AutocorrelationOffsetDetector>&, const Progress&))
RESTITCH_INSTANTIATE(Result<Analysis> analyze(const Mesh&, const AnalysisOptions<FpfhDescriptor, ReducedMatcher,
                                              HistogramOffsetDetector>&, const Progress&))
RESTITCH_INSTANTIATE(Result<Analysis> analyze(const Mesh&, const AnalysisOptions<FpfhDescriptor, ReducedMatcher,
                                              AutocorrelationOffsetDetector>&, const Progress&))

}  // namespace restitch
