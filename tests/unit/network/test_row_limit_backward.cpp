// Row limits on the backward kernels (shaders/gpu/row_limit.glsl): the MLP backward and the
// hash-grid backward recorded for a capacity but cut to a row count the device holds (a training
// step's marched sample total) must equal the same backward recorded for exactly that many rows.
// Per-row outputs (dL/dgamma(x)) bit for bit, and nothing written at or past the limit; the
// reductions over rows (dW, the table gradient) within the float-atomic tolerance of tests/unit/network/test_mlp.cpp
// (atomics add in any order), and bit for bit for the deterministic SortReduce table gradient.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <tuple>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/encoding/hash_encoding.h"
#include "nerf/network/mlp.h"
#include "reference/encoding/hash_encoding.h"
#include "support/gpu_test.h"
#include "support/random_values.h"
#include "support/row_batches.h"
#include "support/submit_once.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

constexpr float kSentinel = -777.0f;
constexpr uint32_t kRows = 1000;
// tests/unit/network/test_mlp.cpp's gradient tolerance (float atomics in any order).
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

// The fast model's network (one 64-wide layer, a 16-wide feature) and a deeper one with a skip layer.
using test::fastAndDeepNetworks;

// The NeRF MLP in chunks of 256 rows, with the tuning's weight-gradient path.
void expectNerfMlpCutEqualsTheTotal(Context& ctx, const nerf::MlpTuning& tuning) {
  for (const auto& cfg : fastAndDeepNetworks()) {
    nerf::NerfMlp mlp(ctx, cfg, tuning);
    mlp.setChunkRows(256);
    nerf::NerfMlp::Workspace ws(ctx, mlp, kRows);
    auto params = gpu::Buffer::of(ctx, mlp.initialParameters());
    auto pos = gpu::Buffer::of(ctx, uniformFloats(size_t(kRows) * mlp.posStride(), 4));
    auto dir = gpu::Buffer::of(ctx, uniformFloats(size_t(kRows) * mlp.dirStride(), 5));
    auto dOut = gpu::Buffer::of(ctx, uniformFloats(size_t(kRows) * 4, 6));
    gpu::Buffer out(ctx, VkDeviceSize(kRows) * 16);
    test::submitOnce(ctx, [&](gpu::Recorder& rec) {
      mlp.recordForward(rec, {kRows, pos, dir, out}, params, &ws);
    });
    // Backward over `rows` rows, cut to `limit` on the device when given: (grads, dPos).
    auto backward = [&](uint32_t rows, const uint32_t* limit) {
      auto grads = gpu::Buffer::zeros(ctx, VkDeviceSize(mlp.parameterCount()) * 4);
      auto dPos = gpu::Buffer::of(ctx, std::vector<float>(size_t(kRows) * mlp.posStride(), kSentinel));
      auto word = gpu::Buffer::of(ctx, std::vector<uint32_t>{limit ? *limit : 0u, 0, 0, 0});
      nerf::NerfRows batch{rows, pos, dir, out};
      if (limit) batch.rowLimit = gpu::BufferRange(word, 0, 4);
      test::submitOnce(ctx, [&](gpu::Recorder& rec) {
        mlp.recordBackward(rec, batch, params, {dOut, grads, gpu::BufferRange(dPos)}, ws);
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

}  // namespace

TEST_F(RowLimitBackward, NerfMlpEqualsTheBackwardOverTheTotal) {
  expectNerfMlpCutEqualsTheTotal(ctx(), nerf::MlpTuning::forDevice(ctx()));
}

// The weight gradient's other paths (nerf/network/gradient_paths.h) under the cut: the workgroup
// reduction keeps the lanes past the limit at its barriers, and only a whole workgroup past it
// leaves (a limit of 0).
TEST_F(RowLimitBackward, NerfMlpEqualsTheBackwardOverTheTotalOnEveryWeightGradientPath) {
  for (uint32_t floatAtomics : {0u, 1u})
    for (uint32_t subgroup : {0u, 1u}) {
      if (floatAtomics && subgroup) continue;  // lavapipe's default: the test above
      if (!test::deviceRuns(floatAtomics, subgroup)) continue;
      SCOPED_TRACE(testing::Message() << "float atomics " << floatAtomics << ", subgroup " << subgroup);
      nerf::MlpTuning t = nerf::MlpTuning::forDevice(ctx());
      t.dwFloatAtomics = floatAtomics, t.dwSubgroup = subgroup;
      expectNerfMlpCutEqualsTheTotal(ctx(), t);
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
                    nerf::HashBackwardMode::SortReduce, nerf::HashBackwardMode::CompareSwap}) {
    for (uint32_t budget : {0u, 8u * 300u}) {
      if ((budget && mode != nerf::HashBackwardMode::SortReduce) || !test::deviceRuns(mode)) continue;
      nerf::HashEncoding enc(ctx(), config, mode);
      if (budget) enc.setSortSlotBudget(budget);
      auto backward = [&](uint32_t rows, const uint32_t* limit) {
        auto grads = gpu::Buffer::zeros(ctx(), VkDeviceSize(enc.parameterCount()) * 4);
        auto word = gpu::Buffer::of(ctx(), std::vector<uint32_t>{limit ? *limit : 0u, 0, 0, 0});
        gpu::BufferRange limitWord(word, 0, 4);
        test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
          enc.recordBackward(rec, {rows, pos, dF, stride, 0, limit ? std::optional(limitWord) : std::nullopt}, grads);
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

// A gathered backward (rowGather, shaders/gpu/row_gather.glsl): recorded for the capacity, cut to the
// packed rows' count and reading the forward's rows through the index, it must equal the backward
// of a batch holding exactly those rows, packed in that order: dL/dgamma(x) bit for bit (the same
// sums in the same order), nothing written past the packed count, dW within the atomic tolerance.
// The index is a scrambled subset, so neither order nor contiguity is assumed.
TEST_F(RowLimitBackward, NerfMlpGatheredEqualsTheBackwardOfThePackedRows) {
  for (const auto& cfg : fastAndDeepNetworks()) {
    SCOPED_TRACE(testing::Message() << "depth " << cfg.depth);
    nerf::NerfMlp mlp(ctx(), cfg);
    const uint32_t P = mlp.posStride(), Dd = mlp.dirStride();
    const auto posV = uniformFloats(size_t(kRows) * P, 4), dirV = uniformFloats(size_t(kRows) * Dd, 5);
    const auto dOutV = uniformFloats(size_t(kRows) * 4, 6);
    auto params = gpu::Buffer::of(ctx(), mlp.initialParameters());
    std::mt19937 gen(11);
    std::vector<uint32_t> index;
    for (uint32_t r = 0; r < kRows; ++r)
      if (gen() % 3) index.push_back(r);
    std::shuffle(index.begin(), index.end(), gen);
    const uint32_t K = uint32_t(index.size());
    // The rows of `v` (stride floats each) at index, in its order.
    auto packed = [&](const std::vector<float>& v, uint32_t stride) {
      std::vector<float> p;
      for (uint32_t i : index) p.insert(p.end(), v.begin() + size_t(i) * stride, v.begin() + size_t(i + 1) * stride);
      return p;
    };
    // Forward over `rows` rows of (pos, dir), then the backward over `count` rows cut to `limit`,
    // gathered through `gather` when given: (grads, dPos, dDir).
    auto run = [&](const std::vector<float>& pv, const std::vector<float>& dv, const std::vector<float>& gv,
                   uint32_t rows, uint32_t count, const uint32_t* limit, const std::vector<uint32_t>* gather) {
      nerf::NerfMlp::Workspace ws(ctx(), mlp, rows);
      auto pos = gpu::Buffer::of(ctx(), pv), dir = gpu::Buffer::of(ctx(), dv), dOut = gpu::Buffer::of(ctx(), gv);
      gpu::Buffer out(ctx(), VkDeviceSize(rows) * 16);
      auto grads = gpu::Buffer::zeros(ctx(), VkDeviceSize(mlp.parameterCount()) * 4);
      auto dPos = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kRows) * P, kSentinel));
      auto dDir = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kRows) * Dd, kSentinel));
      auto word = gpu::Buffer::of(ctx(), std::vector<uint32_t>{limit ? *limit : 0u, 0, 0, 0});
      auto rowsBuf = gpu::Buffer::of(ctx(), gather ? *gather : std::vector<uint32_t>(4));
      nerf::NerfRows batch{count, pos, dir, out};
      if (limit) batch.rowLimit = gpu::BufferRange(word, 0, 4);
      nerf::NerfGradients gradients{dOut, grads, gpu::BufferRange(dPos)};
      if (gather) gradients.rowGather = gpu::BufferRange(rowsBuf);
      gradients.dDir = gpu::BufferRange(dDir);
      test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
        mlp.recordForward(rec, {rows, pos, dir, out}, params, &ws);
        mlp.recordBackward(rec, batch, params, gradients, ws);
      });
      return std::make_tuple(grads.download<float>(), dPos.download<float>(), dDir.download<float>());
    };
    const auto [wantGrads, wantDPos, wantDDir] = run(packed(posV, P), packed(dirV, Dd), packed(dOutV, 4), K, K, nullptr, nullptr);
    std::vector<uint32_t> gather = index;
    gather.resize(kRows, 0);  // the index covers the capacity; entries past the count are never read
    const auto [grads, dPos, dDir] = run(posV, dirV, dOutV, kRows, kRows, &K, &gather);
    ASSERT_EQ(std::memcmp(dPos.data(), wantDPos.data(), size_t(K) * P * 4), 0)
        << "dL/dgamma(x) of the packed rows differs from the backward of a batch of only them";
    for (size_t i = size_t(K) * P; i < dPos.size(); ++i)
      ASSERT_EQ(dPos[i], kSentinel) << "packed row " << i / P << " past the count was written";
    // dL/d(direction input) (what an appearance vector trains from) likewise, packed.
    ASSERT_EQ(std::memcmp(dDir.data(), wantDDir.data(), size_t(K) * Dd * 4), 0)
        << "dL/d(direction input) of the packed rows differs from the backward of a batch of only them";
    for (size_t i = size_t(K) * Dd; i < dDir.size(); ++i)
      ASSERT_EQ(dDir[i], kSentinel) << "packed row " << i / Dd << " past the count was written (dDir)";
    expectNearSums(grads, wantGrads, "dW");
  }
}

// A gathered backward reads the forward's rows anywhere in the batch, so it must fit one chunk.
TEST_F(RowLimitBackward, NerfMlpGatheredBackwardOverOneChunkIsAnError) {
  nerf::NerfMlp mlp(ctx(), fastAndDeepNetworks()[0]);
  mlp.setChunkRows(256);
  nerf::NerfMlp::Workspace ws(ctx(), mlp, 300);
  auto params = gpu::Buffer::of(ctx(), mlp.initialParameters());
  auto rows = gpu::Buffer::zeros(ctx(), 300 * 64), grads = gpu::Buffer::zeros(ctx(), mlp.parameterCount() * 4);
  nerf::NerfGradients gradients{rows, grads};
  gradients.rowGather = gpu::BufferRange(rows);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    EXPECT_THROW(mlp.recordBackward(rec, {300, rows, rows, rows}, params, gradients, ws), Error);
  });
}
