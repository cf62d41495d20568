#pragma once
// A storage buffer. On unified-memory devices (lavapipe, integrated GPUs) it lives in host-visible
// memory mapped once for its lifetime; on discrete GPUs it is device-local and transfers go
// through a staging buffer.
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "gpu/memory/memory_account.h"
#include "vknerf/context.h"

namespace vknerf::gpu {

class Buffer {
 public:
  // `what` names the buffer in an out-of-memory error ("the training rays"): name those whose size
  // follows a knob the user can lower.
  static constexpr const char* kUnnamed = "a device buffer";

  Buffer() = default;
  Buffer(Context& ctx, VkDeviceSize bytes, const char* what = kUnnamed);
  template <class T> static Buffer of(Context& ctx, std::span<const T> data, const char* what = kUnnamed) {
    Buffer b(ctx, data.size_bytes(), what);
    b.upload(data);
    return b;
  }
  template <class T> static Buffer of(Context& ctx, const std::vector<T>& data, const char* what = kUnnamed) {
    return of(ctx, std::span<const T>(data), what);
  }
  static Buffer zeros(Context& ctx, VkDeviceSize bytes, const char* what = kUnnamed);
  // A buffer in host-visible memory (cached where the device has such a type), mapped, on every
  // device: the device copies what the host will read into it within a recording, and the host
  // reads it after that recording's fence with no transfer of its own (download() on a discrete
  // device's buffer is a submission and a wait). Small buffers only: the device reads and writes
  // it over the bus on a discrete GPU.
  static Buffer hostReadable(Context& ctx, VkDeviceSize bytes, const char* what = kUnnamed);
  ~Buffer();
  Buffer(Buffer&& o) noexcept { *this = std::move(o); }
  Buffer& operator=(Buffer&& o) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  // The VkBuffer's size: size(), but at least kMinBytes (Vulkan forbids empty buffers).
  static constexpr VkDeviceSize kMinBytes = 16;
  VkDeviceSize handleSize() const { return std::max(size_, kMinBytes); }
  uint64_t id() const { return id_; }  // unique per allocation; keys descriptor caches
  bool valid() const { return buffer_ != VK_NULL_HANDLE; }
  // Host pointer of a mapped (unified-memory) buffer; nullptr on discrete GPUs. Where the memory is
  // not host-coherent, reads and writes through it need invalidate() and flush().
  void* mapped() const { return mapped_; }
  bool hostCoherent() const { return coherent_; }

  void upload(const void* src, VkDeviceSize bytes, VkDeviceSize offset = 0);
  void download(void* dst, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
  template <class T> void upload(std::span<const T> data, VkDeviceSize offset = 0) { upload(data.data(), data.size_bytes(), offset); }
  template <class T> void upload(const std::vector<T>& data, VkDeviceSize offset = 0) { upload(data.data(), data.size() * sizeof(T), offset); }
  template <class T> std::vector<T> download(size_t count, VkDeviceSize offset = 0) const {
    std::vector<T> out(count);
    download(out.data(), count * sizeof(T), offset);
    return out;
  }
  template <class T> std::vector<T> download() const { return download<T>(size_ / sizeof(T)); }
  void zero();

 private:
  Buffer(Context& ctx, VkDeviceSize bytes, const char* what, bool hostReadable);
  Context* ctx_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
  bool coherent_ = true;  // false: mapped memory flushed after host writes, invalidated before host reads
  uint64_t id_ = 0;
  std::shared_ptr<MemoryAccount> account_;  // charged with the allocation while it lives
};

// A bound range of a buffer: large arrays are split into ranges within maxStorageBufferRange.
// It can also name a resource the embedding application owns (Model::recordRender's target): a raw
// VkBuffer range or a storage image view. Those bind only through Kernel::transientSet, never the
// descriptor cache, because a destroyed handle's value may come back for a new object.
struct BufferRange {
  const Buffer* buffer = nullptr;
  VkDeviceSize offset = 0;
  VkDeviceSize range = VK_WHOLE_SIZE;
  VkBuffer external = VK_NULL_HANDLE;  // a caller's buffer (then `buffer` is null; offset/range apply)
  VkImageView image = VK_NULL_HANDLE;  // a caller's storage image view, in VK_IMAGE_LAYOUT_GENERAL
  BufferRange() = default;
  BufferRange(const Buffer& b) : buffer(&b) {}  // NOLINT: a whole buffer binds implicitly
  BufferRange(const Buffer& b, VkDeviceSize off, VkDeviceSize len) : buffer(&b), offset(off), range(len) {}
  static BufferRange externalBuffer(VkBuffer handle, VkDeviceSize off, VkDeviceSize len) {
    BufferRange r;
    r.external = handle;
    r.offset = off;
    r.range = len;
    return r;
  }
  static BufferRange storageImage(VkImageView view) {
    BufferRange r;
    r.image = view;
    return r;
  }
  bool isExternal() const { return external != VK_NULL_HANDLE || image != VK_NULL_HANDLE; }
  VkBuffer handle() const { return buffer ? buffer->handle() : external; }
};

// Bytes a range binds (0 for an empty or invalid one; an external buffer range binds its `range`).
inline VkDeviceSize boundBytes(const BufferRange& r) {
  if (r.external) return r.range == VK_WHOLE_SIZE ? 0 : r.range;
  if (!r.buffer || !r.buffer->valid()) return 0;
  if (r.range != VK_WHOLE_SIZE) return r.range;
  return r.offset < r.buffer->size() ? r.buffer->size() - r.offset : 0;
}

// Rows of `rowBytes` that one binding can hold: within maxStorageBufferRange and, when rows are
// also viewed as rgba32f texels (`texelsPerRow` > 0), within maxTexelBufferElements. Rounded down
// to a multiple of 64 rows, so chunk offsets keep any sane alignment; throws if not even 64 fit.
uint32_t rowsPerBinding(const Context& ctx, VkDeviceSize rowBytes, uint64_t texelsPerRow = 0);

// Calls fn(first, n, chunk) over rows [0, count) in chunks of at most `chunkRows` (chunk: the index).
template <class Fn>
void forRowChunks(uint32_t count, uint32_t chunkRows, Fn&& fn) {
  for (uint32_t first = 0, chunk = 0; first < count; first += chunkRows, ++chunk)
    fn(first, std::min(chunkRows, count - first), chunk);
}

// Rows [first, first + n) of a row-major matrix of `rowBytes` per row, as their own binding.
inline BufferRange rowsOf(const BufferRange& matrix, VkDeviceSize rowBytes, uint32_t first, uint32_t n) {
  return BufferRange(*matrix.buffer, matrix.offset + first * rowBytes, n * rowBytes);
}

// Throws vknerf::Error "<stage>: <what> buffer holds N bytes, needs M" when the range is too small.
void requireBytes(const char* stage, const char* what, const BufferRange& r, uint64_t needed);

// A batch read through a row index (shaders/gpu/row_gather.glsl) indexes the whole batch, so it is
// dispatched as one chunk: throws when `count` rows exceed `chunkRows` or the index holds fewer than
// `count` uints.
void requireGatherInOneChunk(const char* stage, const BufferRange& gather, uint32_t count, uint32_t chunkRows);

}  // namespace vknerf::gpu
