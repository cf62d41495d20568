// The per-sample forward kernels over a row index (shaders/gpu/row_gather.glsl): a training forward
// in segments (nerf::SegmentRows) computes only the rows it lists, reading and writing each at its
// own row of the whole batch. Every listed row must hold exactly what the forward over the whole
// batch writes there (same kernel, same per-row arithmetic: bit for bit), every other row must be
// left as it was; the device row limit says how many rows the index lists. The lists are
// scattered, out of order, and cover none, one, some and all of the rows.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <numeric>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "nerf/encoding/hash_encoding.h"
#include "nerf/encoding/sh_encoding.h"
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
constexpr uint32_t kRows = 700;

using RowGatherForward = vknerf::test::GpuTest;
using test::uniformFloats;

struct Gather {
  const gpu::BufferRange* rows;   // null: the whole batch
  const gpu::BufferRange* limit;  // null: no device limit
};
using Record = std::function<void(gpu::Recorder&, const gpu::BufferRange& out, Gather)>;

std::vector<float> run(Context& ctx, uint32_t rowFloats, const Record& record, const std::vector<uint32_t>* list,
                       const uint32_t* limit) {
  auto out = gpu::Buffer::of(ctx, std::vector<float>(size_t(kRows) * rowFloats, kSentinel));
  // The index holds a row for each row of the batch, as a segment's list does; past the limit it is not read.
  std::vector<uint32_t> index(kRows, 0);
  if (list) std::copy(list->begin(), list->end(), index.begin());
  auto rows = gpu::Buffer::of(ctx, index);
  auto limitBuffer = gpu::Buffer::of(ctx, std::vector<uint32_t>{limit ? *limit : 0u, 0, 0, 0});
  const gpu::BufferRange rowRange(rows), limitWord(limitBuffer, 0, 4);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    record(rec, out, {list ? &rowRange : nullptr, limit ? &limitWord : nullptr});
  });
  return out.download<float>();
}

// Lists of rows: none, one, every 7th backwards, a random half, all shuffled.
std::vector<std::vector<uint32_t>> lists() {
  std::vector<std::vector<uint32_t>> l(5);
  l[1] = {kRows - 1};
  for (uint32_t r = kRows; r-- > 0;)
    if (r % 7 == 3) l[2].push_back(r);
  std::vector<uint32_t> all(kRows);
  std::iota(all.begin(), all.end(), 0u);
  std::mt19937 gen(5);
  std::shuffle(all.begin(), all.end(), gen);
  l[3].assign(all.begin(), all.begin() + kRows / 2);
  l[4] = all;
  return l;
}

void expectGathered(Context& ctx, uint32_t rowFloats, const Record& record) {
  const auto whole = run(ctx, rowFloats, record, nullptr, nullptr);
  for (uint32_t r = 0; r < kRows; ++r)
    ASSERT_NE(whole[size_t(r) * rowFloats], kSentinel) << "the whole forward left row " << r << " unwritten";
  for (const auto& list : lists()) {
    const uint32_t n = uint32_t(list.size());
    for (uint32_t limit : {n, n / 3}) {
      SCOPED_TRACE(testing::Message() << n << " rows listed, limit " << limit);
      const auto got = run(ctx, rowFloats, record, &list, &limit);
      std::vector<bool> listed(kRows, false);
      for (uint32_t i = 0; i < std::min(n, limit); ++i) listed[list[i]] = true;
      for (uint32_t r = 0; r < kRows; ++r) {
        const float* g = &got[size_t(r) * rowFloats];
        if (listed[r]) {
          ASSERT_EQ(std::memcmp(g, &whole[size_t(r) * rowFloats], rowFloats * 4), 0)
              << "listed row " << r << " differs from the whole forward";
        } else {
          for (uint32_t j = 0; j < rowFloats; ++j) ASSERT_EQ(g[j], kSentinel) << "row " << r << " is not listed but was written";
        }
      }
    }
  }
}

}  // namespace

TEST_F(RowGatherForward, HashEncoding) {
  nerf::HashEncoding enc(ctx(), ref::HashGridConfig{8, 2, 12, 4, 1.6});
  auto pos = gpu::Buffer::of(ctx(), uniformFloats(4 * size_t(kRows), 1));
  auto table = gpu::Buffer::of(ctx(), uniformFloats(enc.parameterCount(), 2, -1e-1f, 1e-1f));
  const uint32_t stride = enc.paddedDims() + 4;  // a column past the block: untouched either way
  expectGathered(ctx(), stride, [&](gpu::Recorder& rec, const gpu::BufferRange& out, Gather g) {
    nerf::EncodedRows rows{kRows, pos, out, stride, 0};
    if (g.limit) rows.rowLimit = *g.limit;
    if (g.rows) rows.rowGather = *g.rows;
    enc.recordForward(rec, rows, table);
  });
}

TEST_F(RowGatherForward, ShEncoding) {
  nerf::ShEncoding enc(ctx(), 4);
  auto in = gpu::Buffer::of(ctx(), test::unitDirections(kRows, 3));
  expectGathered(ctx(), 16, [&](gpu::Recorder& rec, const gpu::BufferRange& out, Gather g) {
    nerf::EncodedRows rows{kRows, in, out, 16, 0};
    if (g.limit) rows.rowLimit = *g.limit;
    if (g.rows) rows.rowGather = *g.rows;
    enc.recordForward(rec, rows);
  });
}

// The fast model's network and a deeper one with a skip layer, activations kept as in training. The tuning keeps a training
// forward layer by layer (the fused kernel has no row index), so both runs use the same kernels.
TEST_F(RowGatherForward, NerfMlpWithKeptActivations) {
  nerf::MlpTuning tuning = nerf::MlpTuning::forDevice(ctx());
  tuning.fused = 1;  // inference fused, training layered
  for (const auto& cfg : test::fastAndDeepNetworks()) {
    SCOPED_TRACE(testing::Message() << "depth " << cfg.depth);
    nerf::NerfMlp mlp(ctx(), cfg, tuning);
    nerf::NerfMlp::Workspace ws(ctx(), mlp, kRows);
    auto params = gpu::Buffer::of(ctx(), mlp.initialParameters());
    auto pos = gpu::Buffer::of(ctx(), uniformFloats(size_t(kRows) * mlp.posStride(), 4));
    auto dir = gpu::Buffer::of(ctx(), uniformFloats(size_t(kRows) * mlp.dirStride(), 5));
    expectGathered(ctx(), 4, [&](gpu::Recorder& rec, const gpu::BufferRange& out, Gather g) {
      nerf::NerfRows rows{kRows, pos, dir, out};
      if (g.limit) rows.rowLimit = *g.limit;
      if (g.rows) rows.rowGather = *g.rows;
      mlp.recordForward(rec, rows, params, &ws);
    });
  }
}

// The index reaches rows anywhere in the batch: one chunk, and kept activations for the MLP.
TEST_F(RowGatherForward, AGatheredForwardOverChunksOrWithoutAWorkspaceIsAnError) {
  nerf::MlpConfig cfg;
  cfg.depth = 1, cfg.width = 64, cfg.skipLayer = 0, cfg.posDims = 16, cfg.dirDims = 16, cfg.featureWidth = 16;
  nerf::NerfMlp mlp(ctx(), cfg);
  nerf::NerfMlp::Workspace ws(ctx(), mlp, 300);
  auto params = gpu::Buffer::of(ctx(), mlp.initialParameters());
  auto rows = gpu::Buffer::zeros(ctx(), 300 * 64 * 4);
  nerf::NerfRows batch{300, rows, rows, rows};
  batch.rowGather = gpu::BufferRange(rows);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    EXPECT_THROW(mlp.recordForward(rec, batch, params, nullptr), Error);
    mlp.setChunkRows(256);
    EXPECT_THROW(mlp.recordForward(rec, batch, params, &ws), Error);
  });
}
