#include "store/failpoint.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <string>

namespace trailscope::server::failpoint_detail {

namespace {
struct Armed {
  std::string name;  ///< the failpoint's name ("" when none is armed)
  long at = 1;       ///< the hit that kills
  std::atomic<long> hits{0};
  Armed() {
    const char* env = std::getenv("TRAILSCOPE_FAILPOINT");
    if (!env) return;
    name = env;
    if (const auto hash = name.find('#'); hash != std::string::npos) {
      at = std::max(1L, std::atol(name.c_str() + hash + 1));
      name.resize(hash);
    }
  }
};

Armed& state() noexcept {
  static Armed a;  // thread-safe initialisation (C++11 magic statics)
  return a;
}
}  // namespace

std::string_view armed() noexcept {
  return state().name;
}

void hit(std::string_view name) noexcept {
  Armed& a = state();
  if (a.hits.fetch_add(1) + 1 != a.at) return;
  // write(2), not iostreams: nothing buffered is lost, and the test reads this line to know the kill came
  // from this failpoint and not from something else.
  const std::string line = "failpoint " + std::string(name) + ": SIGKILL\n";
  [[maybe_unused]] const auto n = ::write(STDERR_FILENO, line.data(), line.size());
  ::kill(::getpid(), SIGKILL);
}

}  // namespace trailscope::server::failpoint_detail
