#pragma once
// Device memory charged to one owner (a model's pipeline), counted by allocation rather than by
// hand-written lists of buffers: while a MemoryAccount::Scope is open on this thread, every
// gpu::Buffer created charges its bytes to that account until the buffer is destroyed.
#include <atomic>
#include <cstdint>
#include <memory>

namespace vknerf::gpu {

class MemoryAccount {
 public:
  uint64_t bytes() const { return bytes_.load(); }
  void charge(uint64_t n) { bytes_ += n; }
  void refund(uint64_t n) { bytes_ -= n; }

  // The account buffers created on this thread are charged to, or null.
  static std::shared_ptr<MemoryAccount> current();

  // Opens `account` for the buffers created on this thread until destroyed (scopes nest).
  class Scope {
   public:
    explicit Scope(std::shared_ptr<MemoryAccount> account);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    std::shared_ptr<MemoryAccount> previous_;
  };

 private:
  std::atomic<uint64_t> bytes_{0};
};

}  // namespace vknerf::gpu
