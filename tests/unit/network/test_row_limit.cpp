// Row limits (shaders/gpu/row_limit.glsl, gpu/dispatch/limited_dispatch.h): the per-sample forward kernels
// recorded for a capacity but cut to a row count that only the device knows (the marcher's sample
// total, in a render recorded into a caller's command buffer), their workgroup counts written on
// the device (indirect dispatch). Below the limit a limited dispatch must write exactly what the unlimited
// one writes (same kernel, same per-row arithmetic: bit for bit); at and past it nothing. Limits
// cover 0, a single row, counts that are not workgroup or rows-per-invocation multiples, chunk
// boundaries, the whole batch and more than the batch.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/limited_dispatch.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/random_values.h"
#include "support/row_batches.h"
#include "support/submit_once.h"
#include "nerf/encoding/hash_encoding.h"
#include "nerf/network/mlp.h"
#include "nerf/encoding/sh_encoding.h"
#include "reference/encoding/hash_encoding.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

constexpr float kSentinel = -777.0f;
constexpr uint32_t kRows = 1000;

using RowLimit = vknerf::test::GpuTest;

using test::uniformFloats;

// Runs `record` into an output of `rowFloats` floats per row prefilled with the sentinel, with no
// limit (nullptr) or with the device uint `limit`; returns the output.
using Record = std::function<void(gpu::Recorder&, const gpu::BufferRange& out, const gpu::BufferRange* limit)>;
std::vector<float> run(Context& ctx, uint32_t rowFloats, const Record& record, const uint32_t* limit) {
  auto out = gpu::Buffer::of(ctx, std::vector<float>(size_t(kRows) * rowFloats, kSentinel));
  auto limitBuffer = gpu::Buffer::of(ctx, std::vector<uint32_t>{limit ? *limit : 0u, 0, 0, 0});
  gpu::BufferRange limitWord(limitBuffer, 0, 4);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    record(rec, out, limit ? &limitWord : nullptr);
  });
  return out.download<float>();
}

void expectLimited(Context& ctx, uint32_t rowFloats, const Record& record, std::initializer_list<uint32_t> limits) {
  const auto whole = run(ctx, rowFloats, record, nullptr);
  for (uint32_t r = 0; r < kRows; ++r)
    ASSERT_NE(whole[size_t(r) * rowFloats], kSentinel) << "the unlimited dispatch left row " << r << " unwritten";
  for (uint32_t limit : limits) {
    const auto cut = run(ctx, rowFloats, record, &limit);
    for (uint32_t r = 0; r < kRows; ++r) {
      const float* got = &cut[size_t(r) * rowFloats];
      if (r < limit) {
        ASSERT_EQ(std::memcmp(got, &whole[size_t(r) * rowFloats], rowFloats * 4), 0)
            << "limit " << limit << ": row " << r << " differs from the unlimited dispatch";
      } else {
        for (uint32_t j = 0; j < rowFloats; ++j)
          ASSERT_EQ(got[j], kSentinel) << "limit " << limit << ": row " << r << " past the limit was written";
      }
    }
  }
}

}  // namespace

TEST_F(RowLimit, HashEncodingForward) {
  nerf::HashEncoding enc(ctx(), ref::HashGridConfig{8, 2, 12, 4, 1.6});
  auto pos = gpu::Buffer::of(ctx(), uniformFloats(4 * size_t(kRows), 1));
  auto table = gpu::Buffer::of(ctx(), uniformFloats(enc.parameterCount(), 2, -1e-1f, 1e-1f));
  const uint32_t stride = enc.paddedDims() + 4;  // a column past the block: untouched either way
  expectLimited(ctx(), stride,
                [&](gpu::Recorder& rec, const gpu::BufferRange& out, const gpu::BufferRange* limit) {
                  nerf::EncodedRows rows{kRows, pos, out, stride, 0};
                  if (limit) rows.rowLimit = *limit;
                  enc.recordForward(rec, rows, table);
                },
                {0, 1, 63, 64, 333, kRows, kRows + 5000});
}

TEST_F(RowLimit, ShEncoding) {
  nerf::ShEncoding enc(ctx(), 4);
  auto in = gpu::Buffer::of(ctx(), test::unitDirections(kRows, 3));
  expectLimited(ctx(), 16,
                [&](gpu::Recorder& rec, const gpu::BufferRange& out, const gpu::BufferRange* limit) {
                  nerf::EncodedRows rows{kRows, in, out, 16, 0};
                  if (limit) rows.rowLimit = *limit;
                  enc.recordForward(rec, rows);
                },
                {0, 1, 65, 999, kRows, UINT32_MAX});
}

// The NeRF MLP in chunks of 256 rows (limits inside the first, on a boundary, inside a later chunk),
// with and without a workspace, for the fast model's shape (one hidden layer, 16 features, trunc-exp
// density: the fused kernel) and a deeper one with a skip layer (two-input dense layers, layer by layer).
TEST_F(RowLimit, NerfMlpForwardInChunks) {
  for (const auto& cfg : test::fastAndDeepNetworks()) {
    for (bool keep : {false, true}) {
      SCOPED_TRACE(testing::Message() << "depth " << cfg.depth << (keep ? ", with a workspace" : ", inference"));
      nerf::NerfMlp mlp(ctx(), cfg);
      mlp.setChunkRows(256);
      nerf::NerfMlp::Workspace ws(ctx(), mlp, kRows);
      auto params = gpu::Buffer::of(ctx(), mlp.initialParameters());
      auto pos = gpu::Buffer::of(ctx(), uniformFloats(size_t(kRows) * mlp.posStride(), 4));
      auto dir = gpu::Buffer::of(ctx(), uniformFloats(size_t(kRows) * mlp.dirStride(), 5));
      expectLimited(ctx(), 4,
                    [&](gpu::Recorder& rec, const gpu::BufferRange& out, const gpu::BufferRange* limit) {
                      nerf::NerfRows rows{kRows, pos, dir, out};
                      if (limit) rows.rowLimit = *limit;
                      mlp.recordForward(rec, rows, params, keep ? &ws : nullptr);
                    },
                    {0, 1, 100, 256, 257, 700, kRows, kRows + 1});
    }
  }
}

TEST_F(RowLimit, LimitBindingMustHoldAUint) {
  nerf::ShEncoding enc(ctx(), 2);
  gpu::Buffer in(ctx(), 64 * 16), out(ctx(), 64 * 16), limit(ctx(), 16);
  gpu::BufferRange tooSmall(limit, 0, 2);
  gpu::Recorder rec(ctx());
  rec.begin();
  EXPECT_THROW(enc.recordForward(rec, {64, in, out, 4, 0, tooSmall}), Error);
  rec.end();
}

// The indirect arguments themselves: chunk c of kind k covers min(chunkRows, limit - c * chunkRows)
// rows (none past the limit or the batch) in workgroups of rowsPerGroup[k] rows.
TEST_F(RowLimit, DispatchArgumentsFollowTheLimit) {
  gpu::LimitedDispatch limited(ctx());
  for (uint32_t limit : {0u, 1u, 300u, 512u, 999u, 5000u}) {
    auto word = gpu::Buffer::of(ctx(), std::vector<uint32_t>{limit, 0, 0, 0});
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      limited.recordArgs(rec, gpu::BufferRange(word, 0, 4), 1000, 256, {64, 256});
    });
    const uint32_t rows = std::min(limit, 1000u);
    for (uint32_t c = 0; c < 4; ++c)
      for (uint32_t k = 0; k < 2; ++k) {
        const gpu::LimitedRows l = limited.rows(c, k);
        EXPECT_EQ(l.base, c * 256);
        auto args = l.args->download<uint32_t>(l.argsOffset / 4 + 3);
        const uint32_t n = rows > c * 256 ? std::min(256u, rows - c * 256) : 0u;
        const uint32_t per = k ? 256 : 64;
        EXPECT_EQ(args[l.argsOffset / 4], (n + per - 1) / per) << "limit " << limit << " chunk " << c << " kind " << k;
        EXPECT_EQ(args[l.argsOffset / 4 + 1], 1u);
        EXPECT_EQ(args[l.argsOffset / 4 + 2], 1u);
      }
  }
  EXPECT_THROW(limited.rows(4, 0), Error);  // only 4 chunks were recorded
}
