#pragma once
#include <vulkan/vulkan.h>

#include <string>

#include "vknerf/error.h"

namespace vknerf::gpu {

const char* resultName(VkResult r);

// Throws vknerf::Error naming the call and its result (vknerf::OutOfMemoryError for out of device
// or host memory); device loss and out-of-memory are not recoverable.
inline void check(VkResult r, const char* what) {
  if (r == VK_SUCCESS) return;
  const std::string msg = std::string(what) + " failed: " + resultName(r);
  if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY) throw OutOfMemoryError(msg);
  throw Error(msg);
}

}  // namespace vknerf::gpu

#define VKN_CHECK(call) ::vknerf::gpu::check((call), #call)
