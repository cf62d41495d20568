#include "progress.h"

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>

namespace vknerf::cli {

std::function<void(uint64_t, uint64_t)> progressPrinter(std::string what, bool clearWhenDone) {
  using Clock = std::chrono::steady_clock;
  constexpr double kLogEverySeconds = 5;
  struct State {
    bool tty = ::isatty(fileno(stdout));
    Clock::time_point start = Clock::now(), lastLine = Clock::now();
  };
  auto st = std::make_shared<State>();
  return [st, what = std::move(what), clearWhenDone](uint64_t done, uint64_t total) {
    const bool finished = done >= total;
    const double pct = total ? 100.0 * double(done) / double(total) : 100.0;
    if (st->tty) {
      if (finished && clearWhenDone) {
        std::printf("\r\033[K");
      } else {
        std::printf("\r%s %llu/%llu (%.0f%%)%s", what.c_str(), (unsigned long long)done, (unsigned long long)total, pct,
                    finished ? "\n" : "");
      }
      std::fflush(stdout);
      return;
    }
    // Without a terminal only long jobs report, every few seconds and once at the end.
    const auto now = Clock::now();
    const bool due = std::chrono::duration<double>(now - st->lastLine).count() >= kLogEverySeconds;
    const bool wasLong = std::chrono::duration<double>(now - st->start).count() >= kLogEverySeconds;
    if (due || (finished && wasLong && !clearWhenDone)) {
      std::printf("%s %llu/%llu (%.0f%%)\n", what.c_str(), (unsigned long long)done, (unsigned long long)total, pct);
      std::fflush(stdout);
      st->lastLine = now;
    }
  };
}

std::function<void(uint64_t, uint64_t)> compileProgressPrinter() {
  using Clock = std::chrono::steady_clock;
  constexpr double kLogEverySeconds = 5, kQuickSeconds = 1;
  struct State {
    bool tty = ::isatty(fileno(stdout));
    bool between = true;  // no batch in progress: the next call starts one
    Clock::time_point start, lastLine;
  };
  auto st = std::make_shared<State>();
  return [st](uint64_t done, uint64_t total) {
    const auto now = Clock::now();
    if (st->between) st->start = st->lastLine = now, st->between = false;
    const bool finished = done >= total;
    const double seconds = std::chrono::duration<double>(now - st->start).count();
    const double pct = total ? 100.0 * double(done) / double(total) : 100.0;
    char line[96];
    std::snprintf(line, sizeof line, "compiling kernels %llu/%llu (%.0f%%)", (unsigned long long)done,
                  (unsigned long long)total, pct);
    if (st->tty) {
      if (finished && seconds < kQuickSeconds) std::printf("\r\033[K");
      else std::printf("\r%s%s", line, finished ? "\n" : "");
      std::fflush(stdout);
    } else if (std::chrono::duration<double>(now - st->lastLine).count() >= kLogEverySeconds ||
               (finished && seconds >= kLogEverySeconds)) {
      std::printf("%s\n", line);
      std::fflush(stdout);
      st->lastLine = now;
    }
    if (finished) st->between = true;
  };
}

double hostPeakMiB() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return double(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace vknerf::cli
