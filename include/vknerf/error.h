#pragma once
// Every failure vknerf reports is a vknerf::Error carrying one line that names what failed
// (the file and field for bad input, the Vulkan call and its result for device failures).
#include <stdexcept>
#include <string>

namespace vknerf {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The device or the host ran out of memory for something the caller asked to allocate (the message
// says what and how large): what an oversized batch, image or model gives, which the caller may
// answer by asking for less.
struct OutOfMemoryError : Error {
  using Error::Error;
};

}  // namespace vknerf
