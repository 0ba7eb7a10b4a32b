#pragma once
// A progress bar on stderr for long CLI verbs: redrawn in place on a terminal, a line per 10% otherwise
// (so logs of CI runs stay readable).
#include <string>
#include <string_view>

#include "trailscope/core/progress.hpp"

namespace trailscope::cli {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label, bool enabled = true);
  ~ProgressBar();  ///< finishes the line
  void update(double fraction, std::string_view stage);
  ProgressFn fn() {
    return [this](double f, std::string_view s) { update(f, s); };
  }

 private:
  std::string label_;
  bool enabled_, tty_;
  int last_permille_ = -1;
  int last_decile_ = -1;
  bool drawn_ = false;
};

}  // namespace trailscope::cli
