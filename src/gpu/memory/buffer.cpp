#include "gpu/memory/buffer.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

#include "gpu/device/device.h"
#include "gpu/device/vk_check.h"

namespace vknerf::gpu {
namespace {

std::atomic<uint64_t> nextBufferId{1};

constexpr VkBufferUsageFlags kUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                      VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                                      VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;

struct Raw {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  bool coherent = true;  // host-coherent memory (or not mapped at all)
  void* mapped = nullptr;
};

std::string mebibytes(uint64_t bytes) {
  char s[32];
  std::snprintf(s, sizeof s, "%.1f MiB", double(bytes) / (1 << 20));
  return s;
}

// Out of memory is what an oversized batch or image gives: say which buffer, how big, and how much
// its owner holds already, so the caller can say what to lower.
[[noreturn]] void outOfMemory(const char* what, VkDeviceSize bytes, VkResult r) {
  std::string msg = std::string("cannot allocate ") + what + " of " + mebibytes(bytes) + " (" + std::to_string(bytes) +
                    " bytes)";
  if (auto account = MemoryAccount::current(); account && account->bytes() > 0)
    msg += " with " + mebibytes(account->bytes()) + " allocated for the same model before it";
  throw OutOfMemoryError(msg + ": " + resultName(r));
}

bool outOfMemoryResult(VkResult r) { return r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY; }

void release(Context& ctx, Raw& raw) {
  if (raw.buffer) vkDestroyBuffer(ctx.device(), raw.buffer, nullptr);
  if (raw.memory) {
    vkFreeMemory(ctx.device(), raw.memory, nullptr);
    device(ctx).allocations()--;
  }
  raw = {};
}

// A buffer in the first of `required`'s memory types (best first: Device::memoryTypesFor) that has
// room, mapped when `map`. A heap that is full falls back to the next type, so a small device-local
// carve-out does not stop a buffer that the larger heap would take.
Raw allocate(Context& ctx, VkDeviceSize bytes, VkBufferUsageFlags usage, VkMemoryPropertyFlags required,
             VkMemoryPropertyFlags prefer, bool map, const char* what) {
  Device& dev = device(ctx);
  Raw raw;
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = bytes;
  bi.usage = usage;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  if (VkResult r = vkCreateBuffer(ctx.device(), &bi, nullptr, &raw.buffer); r != VK_SUCCESS) {
    if (outOfMemoryResult(r)) outOfMemory(what, bytes, r);
    check(r, "vkCreateBuffer");
  }
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), raw.buffer, &req);
  const auto types = dev.memoryTypesFor(req.memoryTypeBits, required, prefer);
  if (types.empty()) {
    vkDestroyBuffer(ctx.device(), raw.buffer, nullptr);
    throw Error("no Vulkan memory type for a buffer of " + std::to_string(bytes) + " bytes");
  }
  if (dev.allocations().load() >= ctx.properties().limits.maxMemoryAllocationCount) {
    vkDestroyBuffer(ctx.device(), raw.buffer, nullptr);
    throw OutOfMemoryError(std::string("cannot allocate ") + what + ": the device's " +
                           std::to_string(ctx.properties().limits.maxMemoryAllocationCount) +
                           " memory allocations (maxMemoryAllocationCount) are all in use");
  }
  VkResult r = VK_ERROR_OUT_OF_DEVICE_MEMORY;
  for (uint32_t type : types) {
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = type;
    r = vkAllocateMemory(ctx.device(), &ai, nullptr, &raw.memory);
    if (r == VK_SUCCESS) {
      const auto flags = dev.memoryProperties().memoryTypes[type].propertyFlags;
      raw.coherent = !map || ((flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) && dev.hostCoherent());
      break;
    }
    if (!outOfMemoryResult(r)) break;
  }
  if (r != VK_SUCCESS) {
    vkDestroyBuffer(ctx.device(), raw.buffer, nullptr);
    raw.memory = VK_NULL_HANDLE;
    if (outOfMemoryResult(r)) outOfMemory(what, bytes, r);
    check(r, "vkAllocateMemory");
  }
  dev.allocations()++;
  if (VkResult b = vkBindBufferMemory(ctx.device(), raw.buffer, raw.memory, 0); b != VK_SUCCESS) {
    release(ctx, raw);
    check(b, "vkBindBufferMemory");
  }
  if (map) {
    if (VkResult m = vkMapMemory(ctx.device(), raw.memory, 0, VK_WHOLE_SIZE, 0, &raw.mapped); m != VK_SUCCESS) {
      release(ctx, raw);
      check(m, "vkMapMemory");
    }
  }
  return raw;
}

// Non-coherent mapped memory: host writes are flushed before the device reads them, and the
// device's writes invalidated before the host reads them. Whole allocations, so that the range
// is a multiple of nonCoherentAtomSize by the rule for VK_WHOLE_SIZE.
void flushMapped(Context& ctx, VkDeviceMemory memory) {
  VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory, 0, VK_WHOLE_SIZE};
  check(vkFlushMappedMemoryRanges(ctx.device(), 1, &range), "vkFlushMappedMemoryRanges");
}
void invalidateMapped(Context& ctx, VkDeviceMemory memory) {
  VkMappedMemoryRange range{VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE, nullptr, memory, 0, VK_WHOLE_SIZE};
  check(vkInvalidateMappedMemoryRanges(ctx.device(), 1, &range), "vkInvalidateMappedMemoryRanges");
}

constexpr VkMemoryPropertyFlags kHostVisible = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
// What a fresh buffer holds under a device profile: every byte 0xFF, a NaN as a float and
// 0xFFFFFFFF as a uint, as unpredictable as a GPU's recycled memory but always the same.
constexpr uint32_t kFreshBytes = 0xFFFFFFFFu;

}  // namespace

Buffer::Buffer(Context& ctx, VkDeviceSize bytes, const char* what) : Buffer(ctx, bytes, what, false) {}

Buffer Buffer::hostReadable(Context& ctx, VkDeviceSize bytes, const char* what) { return Buffer(ctx, bytes, what, true); }

Buffer::Buffer(Context& ctx, VkDeviceSize bytes, const char* what, bool hostReadable)
    : ctx_(&ctx), size_(bytes), id_(nextBufferId++) {
  // Vulkan forbids empty buffers; an empty array still gets a valid (unused) handle.
  VkDeviceSize alloc = std::max(bytes, kMinBytes);
  Device& dev = device(ctx);
  const bool unified = dev.unifiedMemory();
  // Unified: any host-visible type, device-local first. Discrete: device-local first, and host
  // memory the device reads over the bus when the device-local heap is full. Host-readable: any
  // host-visible type, cached first (host reads of uncached memory are slow).
  Raw raw = hostReadable ? allocate(ctx, alloc, kUsage, kHostVisible, VK_MEMORY_PROPERTY_HOST_CACHED_BIT, true, what)
            : unified    ? allocate(ctx, alloc, kUsage, kHostVisible, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, true, what)
                         : allocate(ctx, alloc, kUsage, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, false, what);
  buffer_ = raw.buffer;
  memory_ = raw.memory;
  mapped_ = raw.mapped;
  coherent_ = raw.coherent;
  if (dev.fillsNewBuffers()) dev.runOnce([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, buffer_, 0, VK_WHOLE_SIZE, kFreshBytes); });
  account_ = MemoryAccount::current();
  if (account_) account_->charge(size_);
}

Buffer Buffer::zeros(Context& ctx, VkDeviceSize bytes, const char* what) {
  Buffer b(ctx, bytes, what);
  b.zero();
  return b;
}

Buffer::~Buffer() {
  if (!ctx_) return;
  Raw raw{buffer_, memory_};
  release(*ctx_, raw);  // unmapped implicitly by vkFreeMemory
  if (account_) account_->refund(size_);
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    if (ctx_) {
      Raw raw{buffer_, memory_};
      release(*ctx_, raw);
      if (account_) account_->refund(size_);
    }
    ctx_ = std::exchange(o.ctx_, nullptr);
    buffer_ = std::exchange(o.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(o.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(o.size_, 0);
    mapped_ = std::exchange(o.mapped_, nullptr);
    coherent_ = std::exchange(o.coherent_, true);
    id_ = std::exchange(o.id_, 0);
    account_ = std::move(o.account_);
  }
  return *this;
}

void Buffer::upload(const void* src, VkDeviceSize bytes, VkDeviceSize offset) {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw Error("Buffer::upload: " + std::to_string(offset + bytes) + " bytes into a buffer of " + std::to_string(size_));
  if (mapped_) {
    std::memcpy(static_cast<char*>(mapped_) + offset, src, bytes);
    if (!coherent_) flushMapped(*ctx_, memory_);
    return;
  }
  Raw staging = allocate(*ctx_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, kHostVisible,
                         VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, true, "an upload staging buffer");
  std::memcpy(staging.mapped, src, bytes);
  if (!staging.coherent) flushMapped(*ctx_, staging.memory);
  device(*ctx_).runOnce([&](VkCommandBuffer cmd) {
    VkBufferCopy region{0, offset, bytes};
    vkCmdCopyBuffer(cmd, staging.buffer, buffer_, 1, &region);
  });
  release(*ctx_, staging);
}

void Buffer::download(void* dst, VkDeviceSize bytes, VkDeviceSize offset) const {
  if (bytes == 0) return;
  if (offset + bytes > size_) throw Error("Buffer::download: " + std::to_string(offset + bytes) + " bytes from a buffer of " + std::to_string(size_));
  if (mapped_) {
    if (!coherent_) invalidateMapped(*ctx_, memory_);
    std::memcpy(dst, static_cast<const char*>(mapped_) + offset, bytes);
    return;
  }
  // Cached memory reads fast on the host; any host-visible type will do where there is none.
  Raw staging = allocate(*ctx_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, kHostVisible,
                         VK_MEMORY_PROPERTY_HOST_CACHED_BIT, true, "a download staging buffer");
  device(*ctx_).runOnce([&](VkCommandBuffer cmd) {
    VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(cmd, buffer_, staging.buffer, 1, &region);
  });
  if (!staging.coherent) invalidateMapped(*ctx_, staging.memory);
  std::memcpy(dst, staging.mapped, bytes);
  release(*ctx_, staging);
}

void Buffer::zero() {
  if (mapped_) {
    std::memset(mapped_, 0, size_);
    if (!coherent_) flushMapped(*ctx_, memory_);
    return;
  }
  device(*ctx_).runOnce([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, buffer_, 0, VK_WHOLE_SIZE, 0); });
}

uint32_t rowsPerBinding(const Context& ctx, VkDeviceSize rowBytes, uint64_t texelsPerRow) {
  const auto& lim = ctx.properties().limits;
  uint64_t rows = lim.maxStorageBufferRange / std::max<VkDeviceSize>(rowBytes, 1);
  if (texelsPerRow) rows = std::min<uint64_t>(rows, device(ctx).maxTexelElements() / texelsPerRow);
  rows = std::min<uint64_t>(rows, 1u << 30) / 64 * 64;
  if (rows == 0) throw Error("a row of " + std::to_string(rowBytes) + " bytes exceeds the device's buffer range");
  return uint32_t(rows);
}

void requireBytes(const char* stage, const char* what, const BufferRange& r, uint64_t needed) {
  if (needed > 0 && boundBytes(r) < needed)
    throw Error(std::string(stage) + ": " + what + " buffer holds " + std::to_string(boundBytes(r)) + " bytes, needs " +
                std::to_string(needed));
}

void requireGatherInOneChunk(const char* stage, const BufferRange& gather, uint32_t count, uint32_t chunkRows) {
  if (count > chunkRows)
    throw Error(std::string(stage) + ": a batch read through a row index of " + std::to_string(count) +
                " rows does not fit one chunk of " + std::to_string(chunkRows));
  requireBytes(stage, "row index", gather, uint64_t(count) * 4);
}

}  // namespace vknerf::gpu
