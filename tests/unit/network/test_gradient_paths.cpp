// The gradient kernels' paths (nerf/network/gradient_paths.h): chosen from the device's features,
// and each path's SPIR-V free of the capabilities its features may lack. A pipeline declaring a
// capability the device does not support is invalid even where the code using it never runs, and
// lavapipe supports them all, so the modules are checked here word by word: the paths' results are
// checked against the CPU reference in tests/unit/network/test_mlp.cpp (MlpNerfPaths, MlpDensePaths)
// and tests/unit/encoding/test_hash_encoding.cpp (every HashBackwardMode).
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "gpu/device/device.h"
#include "gpu/kernels/shader_ids.h"
#include "nerf/encoding/hash_encoding.h"
#include "nerf/network/dense_layer.h"
#include "nerf/network/gradient_paths.h"

using namespace vknerf;

namespace {

// SPIR-V's OpCapability operands that matter here (the SPIR-V specification, "Capability").
constexpr uint32_t kOpCapability = 17;
constexpr uint32_t kSubgroupVote = 62, kSubgroupArithmetic = 63, kSubgroupQuad = 68;  // 62..68: past basic
constexpr uint32_t kAtomicFloat32AddEXT = 6033;

std::set<uint32_t> capabilities(const gpu::ShaderCode& code) {
  std::set<uint32_t> caps;
  for (size_t at = 5; at < code.wordCount;) {  // after the 5-word header: (words << 16 | opcode), operands
    const uint32_t words = code.words[at] >> 16, opcode = code.words[at] & 0xffffu;
    if (opcode == kOpCapability) caps.insert(code.words[at + 1]);
    at += words ? words : 1;
  }
  return caps;
}

bool hasFloatAtomics(const gpu::ShaderCode& code) { return capabilities(code).count(kAtomicFloat32AddEXT) != 0; }
// Any subgroup operation beyond the basic ones (which Vulkan 1.1 requires in compute).
bool hasSubgroupOperations(const gpu::ShaderCode& code) {
  for (uint32_t c : capabilities(code))
    if (c >= kSubgroupVote && c <= kSubgroupQuad) return true;
  return false;
}

gpu::KernelFeatures features(bool floatAtomics, bool arithmetic, bool vote) {
  gpu::KernelFeatures f;
  f.bufferFloatAtomicAdd = floatAtomics, f.subgroupArithmetic = arithmetic, f.subgroupVote = vote;
  return f;
}

}  // namespace

TEST(GradientPaths, ChosenFromTheFeatures) {
  // Everything (lavapipe, RDNA3, Arc): the atomic paths, the faster where they exist.
  auto all = nerf::gradientPathsFor(features(true, true, true));
  EXPECT_TRUE(all.dwFloatAtomics && all.dwSubgroupReduce && all.hashSubgroupMerge);
  EXPECT_EQ(all.hash, nerf::HashBackwardMode::Atomic);
  // No float atomics on buffers (RDNA2, Tiger Lake, many mobile GPUs): compare-and-swap adds.
  auto noAtomics = nerf::gradientPathsFor(features(false, true, true));
  EXPECT_FALSE(noAtomics.dwFloatAtomics);
  EXPECT_TRUE(noAtomics.dwSubgroupReduce);
  EXPECT_EQ(noAtomics.hash, nerf::HashBackwardMode::CompareSwap);
  EXPECT_FALSE(noAtomics.hashSubgroupMerge);
  // Float atomics without subgroup arithmetic or vote: the workgroup reduction, no merged scatter.
  for (auto f : {features(true, false, true), features(true, true, false)}) {
    auto p = nerf::gradientPathsFor(f);
    EXPECT_TRUE(p.dwFloatAtomics);
    EXPECT_EQ(p.dwSubgroupReduce, f.subgroupArithmetic);
    EXPECT_EQ(p.hash, nerf::HashBackwardMode::Atomic);
    EXPECT_FALSE(p.hashSubgroupMerge);
  }
  // What Vulkan 1.2 requires and no more.
  auto none = nerf::gradientPathsFor(gpu::KernelFeatures{});
  EXPECT_FALSE(none.dwFloatAtomics || none.dwSubgroupReduce || none.hashSubgroupMerge);
  EXPECT_EQ(none.hash, nerf::HashBackwardMode::CompareSwap);
}

// The weight gradient's module for each path declares float atomics only where it adds with them,
// and subgroup operations only where it reduces with them.
TEST(GradientPaths, WeightGradientModulesDeclareOnlyTheirPathsCapabilities) {
  for (uint32_t floatAtomics : {0u, 1u})
    for (uint32_t subgroup : {0u, 1u}) {
      nerf::MlpTuning t;
      t.dwFloatAtomics = floatAtomics, t.dwSubgroup = subgroup;
      const gpu::ShaderCode& code = nerf::weightGradientShader(t);
      SCOPED_TRACE(code.name);
      EXPECT_EQ(hasFloatAtomics(code), floatAtomics != 0);
      EXPECT_EQ(hasSubgroupOperations(code), subgroup != 0);
      EXPECT_EQ(capabilities(code).count(kSubgroupArithmetic), subgroup);
    }
}

// The hash table's scatter without merging declares no subgroup operations (merged, it declares
// vote and arithmetic); SortReduce's kernels and the prefix sum they use need neither float atomics
// nor subgroup operations, nor does the separate position gradient SortReduce runs, nor
// CompareSwap's scatter.
TEST(GradientPaths, HashBackwardModulesDeclareOnlyTheirPathsCapabilities) {
  for (const gpu::ShaderCode* code : {&gpu::shaders::encode_hash_backward, &gpu::shaders::encode_hash_backward_position}) {
    SCOPED_TRACE(code->name);
    EXPECT_TRUE(hasFloatAtomics(*code));
    EXPECT_FALSE(hasSubgroupOperations(*code));
  }
  for (const gpu::ShaderCode* code :
       {&gpu::shaders::encode_hash_backward_merged, &gpu::shaders::encode_hash_backward_position_merged}) {
    SCOPED_TRACE(code->name);
    EXPECT_EQ(capabilities(*code).count(kSubgroupVote), 1u);
    EXPECT_EQ(capabilities(*code).count(kSubgroupArithmetic), 1u);
  }
  for (const gpu::ShaderCode* code :
       {&gpu::shaders::encode_hash_backward_count, &gpu::shaders::encode_hash_backward_scatter,
        &gpu::shaders::encode_hash_backward_reduce, &gpu::shaders::scan_blocks, &gpu::shaders::scan_add,
        &gpu::shaders::encode_hash_position_gradient, &gpu::shaders::encode_hash_backward_cas,
        &gpu::shaders::encode_hash_backward_position_cas}) {
    SCOPED_TRACE(code->name);
    EXPECT_FALSE(hasFloatAtomics(*code));
    EXPECT_FALSE(hasSubgroupOperations(*code));
  }
}
