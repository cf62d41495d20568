#include "gpu/buffer.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

#include "gpu/device.h"
#include "gpu/vk_check.h"

namespace vknerf::gpu {
namespace {

std::atomic<uint64_t> nextBufferId{1};

constexpr VkBufferUsageFlags kUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                      VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                                      VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;

struct Raw {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
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

Raw allocate(Context& ctx, VkDeviceSize bytes, VkBufferUsageFlags usage, VkMemoryPropertyFlags want,
             const char* what) {
  Raw raw;
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = bytes;
  bi.usage = usage;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  if (VkResult r = vkCreateBuffer(ctx.device(), &bi, nullptr, &raw.buffer); r != VK_SUCCESS) {
    if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY) outOfMemory(what, bytes, r);
    check(r, "vkCreateBuffer");
  }
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), raw.buffer, &req);
  int type = device(ctx).findMemoryType(req.memoryTypeBits, want);
  if (type < 0) {
    vkDestroyBuffer(ctx.device(), raw.buffer, nullptr);
    throw Error("no Vulkan memory type for a buffer of " + std::to_string(bytes) + " bytes");
  }
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = uint32_t(type);
  VkResult r = vkAllocateMemory(ctx.device(), &ai, nullptr, &raw.memory);
  if (r != VK_SUCCESS) {
    vkDestroyBuffer(ctx.device(), raw.buffer, nullptr);
    outOfMemory(what, bytes, r);
  }
  check(vkBindBufferMemory(ctx.device(), raw.buffer, raw.memory, 0), "vkBindBufferMemory");
  return raw;
}

void release(Context& ctx, Raw& raw) {
  if (raw.buffer) vkDestroyBuffer(ctx.device(), raw.buffer, nullptr);
  if (raw.memory) vkFreeMemory(ctx.device(), raw.memory, nullptr);
  raw = {};
}

constexpr VkMemoryPropertyFlags kHostFlags = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;

}  // namespace

Buffer::Buffer(Context& ctx, VkDeviceSize bytes, const char* what) : ctx_(&ctx), size_(bytes), id_(nextBufferId++) {
  // Vulkan forbids empty buffers; an empty array still gets a valid (unused) handle.
  VkDeviceSize alloc = std::max(bytes, kMinBytes);
  const bool unified = device(ctx).unifiedMemory();
  VkMemoryPropertyFlags want = unified ? (kHostFlags | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)
                                       : VkMemoryPropertyFlags(VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  Raw raw = allocate(ctx, alloc, kUsage, want, what);
  buffer_ = raw.buffer;
  memory_ = raw.memory;
  if (unified) check(vkMapMemory(ctx.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
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
    return;
  }
  Raw staging = allocate(*ctx_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, kHostFlags, "an upload staging buffer");
  void* p;
  check(vkMapMemory(ctx_->device(), staging.memory, 0, VK_WHOLE_SIZE, 0, &p), "vkMapMemory");
  std::memcpy(p, src, bytes);
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
    std::memcpy(dst, static_cast<const char*>(mapped_) + offset, bytes);
    return;
  }
  Raw staging = allocate(*ctx_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, kHostFlags | VK_MEMORY_PROPERTY_HOST_CACHED_BIT,
                         "a download staging buffer");
  device(*ctx_).runOnce([&](VkCommandBuffer cmd) {
    VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(cmd, buffer_, staging.buffer, 1, &region);
  });
  void* p;
  check(vkMapMemory(ctx_->device(), staging.memory, 0, VK_WHOLE_SIZE, 0, &p), "vkMapMemory");
  std::memcpy(dst, p, bytes);
  release(*ctx_, staging);
}

void Buffer::zero() {
  if (mapped_) {
    std::memset(mapped_, 0, size_);
    return;
  }
  device(*ctx_).runOnce([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, buffer_, 0, VK_WHOLE_SIZE, 0); });
}

uint32_t rowsPerBinding(const Context& ctx, VkDeviceSize rowBytes, uint64_t texelsPerRow) {
  const auto& lim = ctx.properties().limits;
  uint64_t rows = lim.maxStorageBufferRange / std::max<VkDeviceSize>(rowBytes, 1);
  if (texelsPerRow) rows = std::min<uint64_t>(rows, lim.maxTexelBufferElements / texelsPerRow);
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
