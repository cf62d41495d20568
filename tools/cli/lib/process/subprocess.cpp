#include "lib/process/subprocess.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <chrono>
#include <cstring>
#include <fstream>

#include "vknerf/error.h"

extern char** environ;

namespace vknerf::process {
namespace {

// Our environment with `extra` added; an entry of ours with the same name is replaced.
std::vector<std::string> environmentWith(const std::vector<std::string>& extra) {
  std::vector<std::string> out;
  for (char** e = environ; *e; ++e) {
    const std::string entry = *e;
    bool replaced = false;
    for (const std::string& x : extra)
      if (entry.compare(0, x.find('=') + 1, x, 0, x.find('=') + 1) == 0) replaced = true;
    if (!replaced) out.push_back(entry);
  }
  out.insert(out.end(), extra.begin(), extra.end());
  return out;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> out;
  for (auto& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

// forwardStopSignals(): the child being waited for (0: none), the first stop signal, and whether
// children get a process group of their own. Read by the signal handler: lock-free atomics only.
std::atomic<pid_t> runningChild{0};
std::atomic<int> stopSignal{0};
std::atomic<bool> forwarding{false};
Forwarding forwardingWhen = Forwarding::always;

extern "C" void forwardToChild(int sig) {
  int none = 0;
  stopSignal.compare_exchange_strong(none, sig);
  if (const pid_t pid = runningChild.load(); pid > 0) ::kill(pid, sig);
}

}  // namespace

namespace {

// Installs forwardToChild for SIGINT and SIGTERM; `before` (when given) receives the handlers it replaces.
void installForwarding(struct sigaction* before) {
  struct sigaction sa {};
  sa.sa_handler = forwardToChild;
  sa.sa_flags = SA_RESTART;  // the read of the child's output and the wait go on
  sigemptyset(&sa.sa_mask);
  ::sigaction(SIGINT, &sa, before ? &before[0] : nullptr);
  ::sigaction(SIGTERM, &sa, before ? &before[1] : nullptr);
}

}  // namespace

void forwardStopSignals(Forwarding when) {
  forwarding = true;
  forwardingWhen = when;
  if (when == Forwarding::always) installForwarding(nullptr);
}

int stopSignalReceived() { return stopSignal.load(); }

Stopped::Stopped(int sig)
    : std::runtime_error(std::string("stopped by ") + (sig == SIGINT ? "SIGINT" : "SIGTERM")), signal(sig) {}

void throwIfStopped() {
  if (const int sig = stopSignal.load()) throw Stopped(sig);
}

int runLogged(const Subprocess& p, ChildUsage* usage) {
  if (const int sig = stopSignal.load()) return 128 + sig;  // stopped: no new child, and no log for one
  struct stat logBefore;
  const bool hadLog = ::stat(p.logPath.c_str(), &logBefore) == 0;
  std::ofstream log(p.logPath, std::ios::app | std::ios::binary);
  if (!log) throw Error("cannot write the log '" + p.logPath + "': " + std::strerror(errno));
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw Error("cannot start " + p.argv.at(0) + ": " + std::strerror(errno));
  std::vector<std::string> args = p.argv, env = environmentWith(p.env);
  auto argv = pointers(args), envp = pointers(env);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
  // Forwarding while this child runs only: the handlers before it are back once it has ended.
  struct sigaction handlersBefore[2];
  const bool forwardingNow = forwarding && forwardingWhen == Forwarding::whileAChildRuns;
  if (forwardingNow) installForwarding(handlersBefore);
  struct Restore {
    bool active;
    struct sigaction* before;
    ~Restore() {
      if (!active) return;
      ::sigaction(SIGINT, &before[0], nullptr);
      ::sigaction(SIGTERM, &before[1], nullptr);
    }
  } restore{forwardingNow, handlersBefore};
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  if (forwarding) {
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
  }
  pid_t pid = -1;
  const auto start = std::chrono::steady_clock::now();
  const int err = posix_spawnp(&pid, argv[0], &actions, &attributes, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  ::close(fds[1]);
  if (err == 0) {
    runningChild = pid;
    // A signal that came while the child was being started found no child to pass it to.
    if (const int sig = stopSignal.load()) ::kill(pid, sig);
  }
  if (err != 0) {
    ::close(fds[0]);
    // A program that never started wrote nothing: a log made for it would be an empty file left behind.
    log.close();
    if (!hadLog) ::unlink(p.logPath.c_str());
    if (err == ENOENT)
      throw Error(p.debianPackage.empty() ? p.argv[0] + ": not found"
                                          : p.argv[0] + " is not installed (Debian package: " + p.debianPackage + ")");
    throw Error("cannot start " + p.argv[0] + ": " + std::strerror(err));
  }
  // COLMAP ends some progress lines with '\r' rather than '\n': both end a line here.
  std::string pending;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    log.write(buf, n);
    log.flush();
    for (ssize_t i = 0; i < n; ++i) {
      if (buf[i] == '\n' || buf[i] == '\r') {
        if (p.onLine && !pending.empty()) p.onLine(pending);
        pending.clear();
      } else {
        pending += buf[i];
      }
    }
  }
  if (p.onLine && !pending.empty()) p.onLine(pending);
  ::close(fds[0]);
  int status = 0;
  rusage ru{};
  while (::wait4(pid, &status, 0, &ru) < 0 && errno == EINTR) {
  }
  runningChild = 0;
  if (usage) {
    usage->peakHostMiB = double(ru.ru_maxrss) / 1024.0;  // KiB on Linux
    usage->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

std::string lastLogLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line)) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.rfind("Run with --help", 0) == 0) continue;  // CLI11's footer below its error
    if (!line.empty() && line.find_first_not_of("=-") != std::string::npos) last = line;
  }
  return last;
}

}  // namespace vknerf::process
