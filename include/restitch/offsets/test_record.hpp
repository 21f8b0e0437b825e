// restitch/offsets/test_record.hpp - one significance test as run, for reports.
//
// The significance tests of offsets/detector.hpp and offsets/part.hpp record
// what they measured, so a report (the analysis JSON's `tests`, `restitch
// analyze --verbose`, the web page's peak tooltip) can say why an offset was
// accepted or rejected: docs/method.md 1.10.
#pragma once

#include <string>
#include <vector>

namespace restitch {

/// One significance test as run on a dominant offset, for reports (the JSON's
/// `tests`, `restitch analyze --verbose`): passed when value >= threshold, or
/// value <= threshold for the tests marked `at_most` (the drift).
struct OffsetTest {
  std::string name;  ///< votes, overlap, contrast, double_drift, repeat, contrast_double, axis_contrast_double
  double value = 0;
  double threshold = 0;
  bool at_most = false;
  bool passed = false;
};

/// The tests that tell a pattern from a pair (the header comment's last group): an offset that passes
/// votes, overlap and contrast and fails only one of these is a pair, reported as a candidate.
inline bool is_pattern_test(const std::string& name) {
  return name == "double_drift" || name == "repeat" || name == "contrast_double" || name == "axis_contrast_double";
}

/// Appends a test to `tests` and returns whether it passed.
template <class = void>
bool record_test(std::vector<OffsetTest>& tests, const char* name, double value, double threshold,
                        bool at_most = false) {
  const bool passed = at_most ? value <= threshold : value >= threshold;
  tests.push_back({name, value, threshold, at_most, passed});
  return passed;
}

}  // namespace restitch
