// Row limits on the backward kernels (shaders/gpu/row_limit.glsl): the MLP backward and the
// hash-grid backward recorded for a capacity but cut to a row count the device holds (a training
// step's marched sample total) must equal the same backward recorded for exactly that many rows.
// Per-row outputs (dL/dgamma(x)) bit for bit, and nothing written at or past the limit; the
// reductions over rows (dW, the table gradient) within the float-atomic tolerance of tests/test_mlp.cpp
// (atomics add in any order), and bit for bit for the deterministic SortReduce table gradient.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/recorder.h"
#include "nerf/encoding/hash_encoding.h"
#include "nerf/network/mlp.h"
#include "support/gpu_test.h"
#include "support/random_values.h"
#include "support/submit_once.h"

using namespace vknerf;

namespace {

constexpr float kSentinel = -777.0f;
constexpr uint32_t kRows = 1000;
// tests/test_mlp.cpp's gradient tolerance (float atomics in any order).
constexpr double kGradRel = 1e-3, kGradAbsScale = 1e-4;

using RowLimitBackward = vknerf::test::GpuTest;

using test::uniformFloats;

void expectNearSums(const std::vector<float>& got, const std::vector<float>& want, const char* what) {
  ASSERT_EQ(got.size(), want.size());
  float scale = 0;
  for (float w : want) scale = std::max(scale, std::fabs(w));
  for (size_t i = 0; i < want.size(); ++i)
    ASSERT_NEAR(got[i], want[i], kGradRel * std::fabs(want[i]) + kGradAbsScale * scale) << what << " entry " << i;
}

}  // namespace

// The NeRF MLP in chunks of 256 rows, for the fast model's shape and a deeper one with a skip layer.
TEST_F(RowLimitBackward, NerfMlpEqualsTheBackwardOverTheTotal) {
  std::vector<nerf::MlpConfig> configs(2);
  configs[0].depth = 1, configs[0].width = 64, configs[0].skipLayer = 0, configs[0].posDims = 16, configs[0].dirDims = 16;
  configs[0].density = DensityActivation::TruncExp;
  configs[1].depth = 3, configs[1].width = 32, configs[1].skipLayer = 2, configs[1].posDims = 21, configs[1].dirDims = 9;
  for (const auto& cfg : configs) {
    nerf::NerfMlp mlp(ctx(), cfg);
    mlp.setChunkRows(256);
    nerf::NerfMlp::Workspace ws(ctx(), mlp, kRows);
    auto params = gpu::Buffer::of(ctx(), mlp.initialParameters());
    auto pos = gpu::Buffer::of(ctx(), uniformFloats(size_t(kRows) * mlp.posStride(), 4));
    auto dir = gpu::Buffer::of(ctx(), uniformFloats(size_t(kRows) * mlp.dirStride(), 5));
    auto dOut = gpu::Buffer::of(ctx(), uniformFloats(size_t(kRows) * 4, 6));
    gpu::Buffer out(ctx(), VkDeviceSize(kRows) * 16);
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      mlp.recordForward(rec, kRows, params, pos, dir, out, &ws);
    });
    // Backward over `rows` rows, cut to `limit` on the device when given: (grads, dPos).
    auto backward = [&](uint32_t rows, const uint32_t* limit) {
      auto grads = gpu::Buffer::zeros(ctx(), VkDeviceSize(mlp.parameterCount()) * 4);
      auto dPos = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kRows) * mlp.posStride(), kSentinel));
      auto word = gpu::Buffer::of(ctx(), std::vector<uint32_t>{limit ? *limit : 0u, 0, 0, 0});
      gpu::BufferRange limitWord(word, 0, 4), dPosRange(dPos);
      test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
        mlp.recordBackward(rec, rows, params, pos, dir, out, dOut, grads, ws, &dPosRange, limit ? &limitWord : nullptr);
      });
      return std::make_pair(grads.download<float>(), dPos.download<float>());
    };
    for (uint32_t total : {1u, 100u, 256u, 257u, 700u}) {
      SCOPED_TRACE(testing::Message() << "depth " << cfg.depth << ", total " << total);
      const auto [wantGrads, wantDPos] = backward(total, nullptr);
      const auto [grads, dPos] = backward(kRows, &total);
      const size_t rowFloats = mlp.posStride();
      ASSERT_EQ(std::memcmp(dPos.data(), wantDPos.data(), size_t(total) * rowFloats * 4), 0)
          << "dL/dgamma(x) below the limit differs from the backward over the total";
      for (size_t i = size_t(total) * rowFloats; i < dPos.size(); ++i)
        ASSERT_EQ(dPos[i], kSentinel) << "row " << i / rowFloats << " past the limit was written";
      expectNearSums(grads, wantGrads, "dW");
    }
    // A limit of 0 adds nothing; one past the batch is the whole batch.
    uint32_t zero = 0, past = kRows + 1;
    const auto [none, untouched] = backward(kRows, &zero);
    for (float g : none) ASSERT_EQ(g, 0.0f);
    for (float d : untouched) ASSERT_EQ(d, kSentinel);
    expectNearSums(backward(kRows, &past).first, backward(kRows, nullptr).first, "dW (limit past the batch)");
  }
}

// Every backward mode; SortReduce also in passes smaller than the batch (a pass boundary inside
// and past the limit).
TEST_F(RowLimitBackward, HashGridEqualsTheBackwardOverTheTotal) {
  const ref::HashGridConfig config{8, 2, 12, 4, 1.6};
  auto pos = gpu::Buffer::of(ctx(), uniformFloats(4 * size_t(kRows), 1));
  const uint32_t stride = 20;
  auto dF = gpu::Buffer::of(ctx(), uniformFloats(size_t(kRows) * stride, 2));
  for (auto mode : {nerf::HashBackwardMode::Atomic, nerf::HashBackwardMode::SubgroupMerged,
                    nerf::HashBackwardMode::SortReduce}) {
    for (uint32_t budget : {0u, 8u * 300u}) {
      if (budget && mode != nerf::HashBackwardMode::SortReduce) continue;
      nerf::HashEncoding enc(ctx(), config, mode);
      if (budget) enc.setSortSlotBudget(budget);
      auto backward = [&](uint32_t rows, const uint32_t* limit) {
        auto grads = gpu::Buffer::zeros(ctx(), VkDeviceSize(enc.parameterCount()) * 4);
        auto word = gpu::Buffer::of(ctx(), std::vector<uint32_t>{limit ? *limit : 0u, 0, 0, 0});
        gpu::BufferRange limitWord(word, 0, 4);
        test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
          enc.recordBackward(rec, rows, pos, dF, stride, 0, grads, limit ? &limitWord : nullptr);
        });
        return grads.download<float>();
      };
      for (uint32_t total : {0u, 1u, 63u, 299u, 301u, 777u, kRows}) {
        SCOPED_TRACE(testing::Message() << "mode " << uint32_t(mode) << ", budget " << budget << ", total " << total);
        const auto got = backward(kRows, &total);
        const auto want = total ? backward(total, nullptr) : std::vector<float>(enc.parameterCount(), 0.0f);
        if (mode == nerf::HashBackwardMode::SortReduce)
          ASSERT_EQ(std::memcmp(got.data(), want.data(), got.size() * 4), 0) << "SortReduce is deterministic";
        else
          expectNearSums(got, want, "table gradient");
      }
    }
  }
}
