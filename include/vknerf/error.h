#pragma once
// Every failure vknerf reports is a vknerf::Error carrying one line that names what failed
// (the file and field for bad input, the Vulkan call and its result for device failures).
#include <stdexcept>
#include <string>

namespace vknerf {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace vknerf
