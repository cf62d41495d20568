// The images of a dataset, decoded (and box-filtered by the downscale factor) by a pool of threads.
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

#include "io/dataset/dataset_loaders.h"
#include "vknerf/error.h"
#include "vknerf/image_io.h"

namespace vknerf::io::detail {

std::vector<ImageRGBA8> loadImages(const std::vector<FrameSpec>& frames, uint32_t downscale, const DatasetOptions& options) {
  std::vector<ImageRGBA8> images(frames.size());
  std::vector<std::exception_ptr> errors(frames.size());
  std::atomic<size_t> next{0};
  size_t done = 0;
  std::mutex progressLock;
  auto work = [&] {
    for (size_t i; (i = next++) < frames.size();) {
      try {
        const FrameSpec& f = frames[i];
        if (f.image.empty()) throw Error(f.where + ": image not found: " + f.imageTried);
        ImageRGBA8 img = vknerf::loadImage(f.image.string());
        if (img.width < downscale || img.height < downscale)
          throw Error("image '" + f.image.string() + "' (" + std::to_string(img.width) + "x" +
                      std::to_string(img.height) + ") is smaller than the downscale factor " + std::to_string(downscale));
        images[i] = downscale > 1 ? vknerf::downscaleImage(img, downscale) : std::move(img);
      } catch (...) {
        errors[i] = std::current_exception();
      }
      if (options.progress) {
        std::lock_guard<std::mutex> hold(progressLock);
        options.progress(++done, frames.size());
      }
    }
  };
  const size_t cores = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  const size_t threads = std::min<size_t>(frames.size(), cores);
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
  return images;
}

}  // namespace vknerf::io::detail
