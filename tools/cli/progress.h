#pragma once
// Progress of a long load or render on the terminal: on a TTY one line rewritten in place, else a
// line every few seconds, so logs stay short.
#include <cstdint>
#include <functional>
#include <string>

namespace vknerf::cli {

// A (done, total) callback printing "<what> done/total (P%)". `clearWhenDone` erases the line on a
// TTY once done == total (for a render whose result the caller reports on its own line).
std::function<void(uint64_t done, uint64_t total)> progressPrinter(std::string what, bool clearWhenDone = false);

// Kernel compilation, for Context::setCompileProgress: "compiling kernels 14/38 (37%)". Each batch
// of kernels restarts the clock; one that took under a second (a warm shader cache) leaves nothing
// behind on a terminal, and only one of five seconds or more prints its last count in a log.
std::function<void(uint64_t done, uint64_t total)> compileProgressPrinter();

// "host peak 1234.5 MiB" from getrusage's maximum resident set size.
double hostPeakMiB();

}  // namespace vknerf::cli
