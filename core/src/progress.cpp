#include "holo/core/progress.hpp"

#include <unistd.h>
#include <cstdio>

namespace holo {

ProgressReporter::ProgressReporter(std::int64_t total_work, std::string title, bool quiet)
    : total_(std::max<std::int64_t>(total_work, 1)),
      title_(std::move(title)),
      quiet_(quiet),
      tty_(::isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {
  if (!quiet_ && !tty_)
    std::fprintf(stderr, "%s: started (%lld steps)\n", title_.c_str(), static_cast<long long>(total_));
}

ProgressReporter::~ProgressReporter() {
  done();
}

double ProgressReporter::elapsedSeconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressReporter::update(std::int64_t work) {
  done_work_.fetch_add(work, std::memory_order_relaxed);
  if (quiet_ || !tty_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  std::unique_lock lock(draw_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  last_draw_ = now;
  draw(false);
}

void ProgressReporter::done() {
  if (finished_.exchange(true)) return;
  if (quiet_) return;
  std::lock_guard lock(draw_mutex_);
  if (tty_) {
    draw(true);
    std::fputc('\n', stderr);
  } else {
    std::fprintf(stderr, "%s: done in %.1f s\n", title_.c_str(), elapsedSeconds());
  }
}

void ProgressReporter::draw(bool final) {
  const std::int64_t work = final ? total_ : std::min(done_work_.load(), total_);
  const double fraction = static_cast<double>(work) / static_cast<double>(total_);
  const double elapsed = elapsedSeconds();
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string bar(static_cast<std::size_t>(filled), '=');
  bar.resize(kWidth, ' ');
  if (final)
    std::fprintf(stderr, "\r%s [%s] 100%% %.1fs        ", title_.c_str(), bar.c_str(), elapsed);
  else {
    const double left = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    std::fprintf(stderr, "\r%s [%s] %3d%% %.1fs (%.1fs left)", title_.c_str(), bar.c_str(),
                 static_cast<int>(fraction * 100.0), elapsed, left);
  }
  std::fflush(stderr);
}

}  // namespace holo
