#pragma once
// Whether a dataset's pixels fit in memory, checked before anything is decoded or allocated, and
// the --downscale that would make them fit.
#include <cstdint>
#include <span>
#include <string>
#include <utility>

namespace vknerf::io {

using ImageSize = std::pair<uint32_t, uint32_t>;  // width, height

// Bytes of RGBA8 pixels of images of these sizes box-filtered by `downscale` (remainders dropped).
uint64_t rgba8Bytes(std::span<const ImageSize> sizes, uint32_t downscale = 1);

// Host memory free for use now: MemAvailable from /proc/meminfo, else free physical pages.
uint64_t availableHostBytes();

// Throws vknerf::Error when fixedBytes + the images' RGBA8 bytes exceed `available`:
// "<what> needs X MiB (n images: P MiB, <fixedWhat>: F MiB) but <where> has Y MiB; --downscale N
// would fit", or that no downscale would. `downscaleNow` is the factor the images already carry
// (the advice is N = downscaleNow * the extra factor); 0 when unknown, and the advice is relative.
void requireFit(const std::string& what, std::span<const ImageSize> sizes, uint64_t fixedBytes,
                const std::string& fixedWhat, uint64_t available, const std::string& where, uint32_t downscaleNow = 0);

std::string mebibytes(uint64_t bytes);  // "12.3 MiB"

}  // namespace vknerf::io
