// restitch/progress.hpp - progress reporting and cancellation.
//
// Long calls take a `const Progress&`. They call `report(stage, fraction)` now
// and then (fraction in [0, 1] within the named stage). The callback returns
// false to cancel; the call then returns StatusCode::cancelled promptly.
// The default Progress reports nowhere and never cancels. The CLI draws a bar
// from it; the web demo posts it from its worker.
#pragma once

#include <functional>
#include <string_view>

namespace restitch {

class Progress {
 public:
  using Callback = std::function<bool(std::string_view stage, double fraction)>;

  Progress() = default;
  explicit Progress(Callback cb) : cb_(std::move(cb)) {}

  /// Reports progress; returns false when the caller asked to cancel.
  bool report(std::string_view stage, double fraction) const { return cb_ ? cb_(stage, fraction) : true; }

 private:
  Callback cb_;
};

}  // namespace restitch
