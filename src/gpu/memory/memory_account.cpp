#include "gpu/memory/memory_account.h"

#include <utility>

namespace vknerf::gpu {
namespace {
thread_local std::shared_ptr<MemoryAccount> open;
}  // namespace

std::shared_ptr<MemoryAccount> MemoryAccount::current() { return open; }

MemoryAccount::Scope::Scope(std::shared_ptr<MemoryAccount> account) : previous_(std::exchange(open, std::move(account))) {}

MemoryAccount::Scope::~Scope() { open = std::move(previous_); }

}  // namespace vknerf::gpu
