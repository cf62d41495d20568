#include "gpu/compile/kernel_compiler.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <utility>

#include "gpu/compile/mesa_disk_cache.h"

namespace vknerf::gpu {

bool kernelsCompileAhead(VkPhysicalDevice physical, bool ownDevice) {
  if (!ownDevice || mesaShaderCacheDisabled()) return false;
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props.pNext = &driver;
  vkGetPhysicalDeviceProperties2(physical, &props);
  return driver.driverID == VK_DRIVER_ID_MESA_LLVMPIPE;
}

KernelCompiler::KernelCompiler(VkPhysicalDevice physical, uint32_t queueFamily, const KernelFeatures& features,
                               bool ahead, uint32_t threads)
    : physical_(physical), queueFamily_(queueFamily), features_(features), ahead_(ahead),
      threads_(std::max(1u, threads)) {}

KernelCompiler::~KernelCompiler() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  queued_.notify_all();
  for (std::thread& t : pool_) t.join();
}

std::string KernelCompiler::key(const Kernel& k, std::span<const BufferRange> bindings, uint32_t* texelPow2) const {
  const KernelDesc& d = k.desc();
  uint32_t pow2 = 0;
  for (size_t i = 0; i < d.bindings.size(); ++i) {
    if (d.bindings[i] == Binding::StorageImage) return "";
    if (d.bindings[i] != Binding::TexelRgba32f) continue;
    if (i >= bindings.size() || !bindings[i].buffer || i >= 32) return "";
    const VkDeviceSize size = bindings[i].buffer->handleSize();
    if ((size & (size - 1)) == 0) pow2 |= 1u << i;
  }
  *texelPow2 = pow2;
  // The SPIR-V (named by its shader id), the layout, the specialization constants and the variant.
  std::string key = d.shader.name;
  key += '/' + std::to_string(pow2) + '/' + std::to_string(d.pushConstantBytes) + '/';
  for (Binding b : d.bindings) key += char('0' + int(b));
  for (const SpecConstant& s : d.specialization) key += ',' + std::to_string(s.id) + '=' + std::to_string(s.value);
  return key;
}

bool KernelCompiler::cold(const Kernel& k, std::span<const BufferRange> bindings) const {
  uint32_t pow2 = 0;
  if (!ahead_) return false;
  const std::string id = key(k, bindings, &pow2);
  return !id.empty() && !started_.count(id);
}

void KernelCompiler::dispatching(const Kernel& k, std::span<const BufferRange> bindings) {
  if (!ahead_) return;
  uint32_t pow2 = 0;
  std::string id = key(k, bindings, &pow2);
  if (id.empty() || !started_.insert(std::move(id)).second) return;
  ++startedSinceFinish_;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back({k.desc(), pow2});
  }
  queued_.notify_one();
  if (pool_.size() < threads_ && pool_.size() < started_.size()) {
    // Devices are made and destroyed on this thread, the thread that owns vknerf's device.
    devices_.push_back(std::make_unique<CompileDevice>(physical_, queueFamily_, features_));
    pool_.emplace_back([this, &device = *devices_.back()] { work(device); });
  }
}

void KernelCompiler::work(CompileDevice& device) {
  for (;;) {
    KernelVariant variant;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      queued_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      variant = std::move(queue_.front());
      queue_.pop_front();
      ++busy_;
    }
    std::exception_ptr failed;
    try {
      device.compile(variant);
    } catch (...) {
      failed = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --busy_;
      if (!failed) ++stats_.compiledAhead;
      else if (!error_) error_ = failed;
    }
    compiled_.notify_all();
  }
}

void KernelCompiler::finish() {
  if (!ahead_ || pool_.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  const uint64_t started = startedSinceFinish_;
  startedSinceFinish_ = 0;
  auto outstanding = [&] { return uint64_t(queue_.size()) + busy_; };
  if (started == 0 && outstanding() == 0 && !error_) return;
  // Reports (compiled, compiled + outstanding) without the lock, so that the pool goes on.
  auto report = [&] {
    if (!progress_) return;
    const uint64_t done = stats_.compiledAhead, total = done + outstanding();
    lock.unlock();
    try {
      progress_(done, total);
    } catch (...) {
      lock.lock();
      throw;
    }
    lock.lock();
  };
  report();
  while (outstanding() > 0) {
    const uint64_t before = outstanding();
    compiled_.wait(lock, [&] { return outstanding() < before; });
    report();
  }
  // The last variants' entries may still be queued for Mesa's writer, starved while the pool ran.
  lock.unlock();
  waitForMesaCacheWriters(std::chrono::seconds(10));
  lock.lock();
  stats_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (std::exception_ptr e = std::exchange(error_, nullptr)) std::rethrow_exception(e);
}

void KernelCompiler::countPipeline(double seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++stats_.pipelines;
  stats_.seconds += seconds;
}

void KernelCompiler::setProgress(std::function<void(uint64_t, uint64_t)> progress) { progress_ = std::move(progress); }

CompileStats KernelCompiler::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

}  // namespace vknerf::gpu
