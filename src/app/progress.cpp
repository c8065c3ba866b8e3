// The progress bar on stderr (progress.hpp).
#include "progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <mutex>

namespace skin::cli {

using skin::util::ProgressCallback;

namespace {

using Clock = std::chrono::steady_clock;

class Bar {
 public:
  explicit Bar(std::string unit) : unit_(std::move(unit)), start_(Clock::now()) {}

  void update(std::size_t done, std::size_t total) {
    const std::lock_guard lock(mutex_);
    const auto now = Clock::now();
    if (finished_) {  // a new bar after a finished one
      finished_ = false;
      start_ = now;
      last_percent_ = -1;
    }
    const double f =
        total ? std::min(1.0, static_cast<double>(done) / static_cast<double>(total)) : 1.0;
    const int percent = static_cast<int>(100.0 * f);
    const bool last = done >= total;
    if (!last && percent == last_percent_ && now - last_draw_ < std::chrono::milliseconds(100))
      return;
    last_percent_ = percent;
    last_draw_ = now;
    constexpr int kWidth = 40;
    const int fill = static_cast<int>(f * kWidth);
    std::fprintf(stderr, "\r[%s%*s] %3d%%",
                 std::string(static_cast<std::size_t>(fill), '#').c_str(), kWidth - fill, "",
                 percent);
    if (!unit_.empty()) std::fprintf(stderr, "  %zu/%zu %s", done, total, unit_.c_str());
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    std::fprintf(stderr, "  %.1f s", elapsed);
    // The time left, from the pace so far (once there is a pace: 2 % done and a second gone).
    if (!last && f >= 0.02 && elapsed >= 1.0) std::fprintf(stderr, ", ~%.0f s left  ", elapsed * (1 - f) / f);
    std::fprintf(stderr, "%s", last ? "\n" : "");
    std::fflush(stderr);
    finished_ = last;
  }

 private:
  std::mutex mutex_;
  std::string unit_;
  Clock::time_point start_, last_draw_{};
  int last_percent_ = -1;
  bool finished_ = false;
};

}  // namespace

ProgressCallback progress_bar(const std::string& unit) {
  if (::isatty(STDERR_FILENO) == 0) return {};
  auto bar = std::make_shared<Bar>(unit);
  return [bar](std::size_t done, std::size_t total) { bar->update(done, total); };
}

std::function<void(double fraction)> progress_fraction_bar() {
  if (::isatty(STDERR_FILENO) == 0) return {};
  auto bar = std::make_shared<Bar>("");
  return [bar](double f) {
    constexpr std::size_t kSteps = 1000;
    bar->update(static_cast<std::size_t>(std::clamp(f, 0.0, 1.0) * kSteps), kSteps);
  };
}

}  // namespace skin::cli
