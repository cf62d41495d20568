#pragma once
// Mesa's shader disk cache as the kernel compiler (kernel_compiler.h) relies on it: whether the
// environment switches it off, and waiting for its writer. Mesa writes an entry on a thread of its
// own ("<process>:disk$0", SCHED_BATCH at nice 19), queued after the compile; while other threads
// of the process are busy that thread barely runs, so entries compiled on the private devices may
// not be on disk yet when vknerf's device looks them up, which would then compile them again.
#include <chrono>

namespace vknerf::gpu {

// As Mesa 22.3 reads it: MESA_SHADER_CACHE_DISABLE, else the older MESA_GLSL_CACHE_DISABLE, set to
// 1, true or yes (any case).
bool mesaShaderCacheDisabled();

// Whether a thread name is one of Mesa's cache writers: "<process>:disk$<n>".
bool isMesaCacheWriter(const char* threadName);

// Returns once every cache writer thread of this process sleeps waiting for work (Linux /proc), or
// after `timeout`; at once when there is none (the cache is off, or not Mesa).
void waitForMesaCacheWriters(std::chrono::milliseconds timeout);

}  // namespace vknerf::gpu
