#pragma once
// Running an external program (colmap, ffmpeg) with its output appended to a log file, each line
// also handed to a callback so the caller can show progress parsed from it.
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace vknerf::process {

struct Subprocess {
  std::vector<std::string> argv;     // argv[0] is looked up on PATH
  std::vector<std::string> env;      // "NAME=value" entries added to (or replacing in) ours
  std::string debianPackage;         // named when argv[0] is not installed
  std::string logPath;               // stdout and stderr are appended here
  std::function<void(const std::string& line)> onLine;  // optional, for each line as it arrives
};

// What the finished child used, from wait4(): its peak resident memory (ru_maxrss) is its own,
// measured by the kernel, which no report of the child's can replace.
struct ChildUsage {
  double peakHostMiB = 0;
  double seconds = 0;  // wall time from start to exit
};

// Runs `p` to completion and returns its exit status (128 + N when killed by signal N). Throws
// vknerf::Error "<program> is not installed (Debian package: <package>)" when argv[0] is not on
// PATH (without a package: "<program>: not found"), and naming the log when the log cannot be
// opened. `usage`, when given, receives what the child used.
int runLogged(const Subprocess& p, ChildUsage* usage = nullptr);

// The last non-empty line of a log file ("" when there is none): the reason a program gave.
// CLI11's closing advice ("Run with --help for more information.") is not a reason: the line
// before it is taken.
std::string lastLogLine(const std::string& path);

// From now on SIGINT and SIGTERM are passed on to the child runLogged is waiting for, which is
// waited for as usual (a `train` saves first), and no further child is started: runLogged then
// returns 128 + the signal at once. Children run in a process group of their own, so that a Ctrl-C
// at the terminal reaches them once, through this process, rather than twice. For a command that
// runs children for minutes or hours (`bench scenes`): stopped, it must not leave them running.
//
// whileAChildRuns: only while a child runs; otherwise the handlers before are kept (a command that
// ends at once on a signal between its children, `process`). Its caller calls throwIfStopped()
// after each child.
enum class Forwarding { always, whileAChildRuns };
void forwardStopSignals(Forwarding when = Forwarding::always);
// The first SIGINT or SIGTERM received since forwardStopSignals(), or 0.
int stopSignalReceived();

// What throwIfStopped() throws once a stop signal was passed on and the child has ended: the
// command line exits 128 + signal, after the destructors have removed what the run had made.
struct Stopped : std::runtime_error {
  explicit Stopped(int sig);
  int signal;
};
void throwIfStopped();

}  // namespace vknerf::process
