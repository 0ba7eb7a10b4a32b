#include "cli/progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace trailscope::cli {

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), tty_(::isatty(STDERR_FILENO) != 0) {}

ProgressBar::~ProgressBar() {
  if (enabled_ && drawn_ && tty_) std::fputc('\n', stderr);
}

void ProgressBar::update(double fraction, std::string_view stage) {
  if (!enabled_) return;
  fraction = std::clamp(fraction, 0.0, 1.0);
  const int permille = static_cast<int>(fraction * 1000);
  if (tty_) {
    if (permille == last_permille_) return;
    last_permille_ = permille;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::string bar(filled, '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%s [%s] %5.1f%% %-10.*s", label_.c_str(), bar.c_str(), fraction * 100.0,
                 static_cast<int>(stage.size()), stage.data());
    std::fflush(stderr);
  } else {
    const int decile = permille / 100;
    if (decile == last_decile_) return;
    last_decile_ = decile;
    std::fprintf(stderr, "%s %3d%% %.*s\n", label_.c_str(), decile * 10, static_cast<int>(stage.size()),
                 stage.data());
  }
  drawn_ = true;
}

}  // namespace trailscope::cli
