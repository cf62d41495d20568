#pragma once
// Shared test harness: one Vulkan context per test process (validation enabled when
// VKNERF_VALIDATION=1, as ctest sets it), and a fixture that fails any test during which the
// validation layer reported a warning or an error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "vknerf/context.h"

namespace vknerf::nerf {
enum class HashBackwardMode : uint32_t;  // nerf/encoding/hash_encoding.h
}

namespace vknerf::test {

Context& context();
// The same context as a shared_ptr, for the APIs that take one (Trainer, Model::load). It does not
// own the context: the harness keeps it for the whole process.
std::shared_ptr<Context> sharedContext();

// Whether this device runs a kernel path needing these optional features. Under a device profile
// (VKNERF_DEVICE_PROFILE) the device may lack what a path forced by a test needs; lavapipe as it
// is runs every path, a profile's run those of its class.
bool deviceRuns(bool floatAtomics, bool subgroupArithmetic, bool subgroupVote = false);
// The same for a hash-grid backward mode.
bool deviceRuns(nerf::HashBackwardMode mode);

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override { before_ = context().validationMessages(); }
  void TearDown() override {
    EXPECT_EQ(context().validationMessages(), before_) << "the validation layer reported messages (see stderr)";
  }
  Context& ctx() { return context(); }

 private:
  uint32_t before_ = 0;
};

// |gpu - ref| <= abs + rel * |ref|, and both finite.
inline ::testing::AssertionResult near(double gpu, double ref, double rel, double abs) {
  if (!std::isfinite(gpu)) return ::testing::AssertionFailure() << "gpu value " << gpu << " is not finite";
  double err = std::fabs(gpu - ref);
  if (err <= abs + rel * std::fabs(ref)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "gpu " << gpu << " vs ref " << ref << " (err " << err << " > "
                                       << abs + rel * std::fabs(ref) << ")";
}

}  // namespace vknerf::test
