// One dense layer over a block of its output columns (DenseLayer's firstColumn: a proposal's feature
// layer, whose sigma column alone is read and trained). From firstColumn on, the forward, the input
// gradient and the weight gradient must be the layer's, against a double-precision CPU reference;
// before it the forward leaves y as it was, the backwards read no dz there (NaN in those columns
// changes nothing, as if they were 0) and the weight gradient adds nothing to those columns'
// weights and biases. Shapes: a 64-wide trunk into the fast model's feature layer (17 columns, the
// block of 4 from 16) and a wider one of several 8-column blocks from column 8, with a ReLU, over a
// row count that is no multiple of a workgroup's rows; under the device's tuning and a GPU's shape
// (MlpTuning::forDevice off the CPU: one row an invocation, 4 x 4 weight-gradient tiles, so that the
// blocks after firstColumn split otherwise).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/layouts/mlp_layout.h"
#include "gpu/dispatch/limited_dispatch.h"
#include "gpu/memory/buffer.h"
#include "nerf/network/dense_layer.h"
#include "support/gpu_test.h"
#include "support/random_values.h"
#include "support/submit_once.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

using DenseColumns = vknerf::test::GpuTest;
using test::uniformFloats;

constexpr uint32_t kRows = 301;
constexpr float kSentinel = -777.0f;
// Float rounding of a sum of K products against the double reference: at most (K + 1) 2^-24 times
// the sum of the terms' magnitudes in any order of summation (Higham's bound for recursive sums;
// the weight gradient's atomics add in any order too). Twice that bound, per entry.
constexpr double kUnit = 1.0 / (1u << 24);
double tolerance(double absSum, uint32_t terms) { return 2.0 * (terms + 1) * kUnit * absSum + 1e-30; }

struct Case {
  uint32_t ka, n, firstColumn;
  core::Activation act;
};

TEST_F(DenseColumns, FromAColumnOnTheLayerIsComputedAndNothingBeforeIt) {
  const Case cases[] = {{64, 17, 16, core::Activation::None}, {24, 30, 8, core::Activation::Relu}};
  nerf::MlpTuning gpuShape = nerf::MlpTuning::forDevice(ctx());
  gpuShape.local = gpuShape.dwLocal = 128, gpuShape.rows = gpuShape.dxRows = 1;
  gpuShape.dwKT = gpuShape.dwNT = 4, gpuShape.dwU = 4, gpuShape.dwRows = 64;
  for (const nerf::MlpTuning& tuning : {nerf::MlpTuning::forDevice(ctx()), gpuShape})
    for (const Case& k : cases) {
      SCOPED_TRACE(testing::Message() << k.ka << " inputs, " << k.n << " outputs from column " << k.firstColumn << ", "
                                      << tuning.rows << " rows an invocation");
      core::DenseShape shape{k.ka, 0, k.n, k.act};
      std::vector<core::DenseShape> layers{shape};
      const uint64_t total = core::layOut(layers);
      shape = layers[0];
      const std::vector<float> params = core::initialParameters(layers, total, 7);
      const uint32_t ka4 = shape.ka4(), n4 = shape.n4(), first = k.firstColumn;
      const std::vector<float> a = uniformFloats(size_t(kRows) * ka4, 11, -1.0f, 1.0f);
      std::vector<float> dz = uniformFloats(size_t(kRows) * n4, 13, -1.0f, 1.0f);
      for (uint32_t r = 0; r < kRows; ++r)
        for (uint32_t c = 0; c < first; ++c) dz[size_t(r) * n4 + c] = std::numeric_limits<float>::quiet_NaN();
      // The weight gradient adds into what the buffer holds: a sentinel everywhere, so that an entry it
      // must not touch shows.
      std::vector<float> gradsIn(total, kSentinel);

      nerf::DenseLayer layer(ctx(), shape, tuning);
      auto P = gpu::Buffer::of(ctx(), params), A = gpu::Buffer::of(ctx(), a), DZ = gpu::Buffer::of(ctx(), dz);
      auto Y = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kRows) * n4, kSentinel));
      auto DA = gpu::Buffer::of(ctx(), std::vector<float>(size_t(kRows) * ka4, kSentinel));
      auto G = gpu::Buffer::of(ctx(), gradsIn);
      const nerf::Mat a4{A, ka4}, y4{Y, n4}, dz4{DZ, n4}, da4{DA, ka4};
      const gpu::LimitedDispatch uncut(ctx());
      test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
        const nerf::LayerRows rows{kRows, uncut.uncut()};
        layer.recordForward(rec, rows, P, a4, a4, y4, nullptr, first);
        layer.recordBackwardInput(rec, rows, P, dz4, a4, {nerf::GradMode::Store, da4}, first);
        layer.recordBackwardWeights(rec, rows, a4, a4, dz4, G, first);
      });
      const std::vector<float> y = Y.download<float>(), da = DA.download<float>(), grads = G.download<float>();

      auto w = [&](uint32_t kk, uint32_t c) { return double(params[shape.offset + uint64_t(kk) * n4 + c]); };
      auto bias = [&](uint32_t c) { return double(params[shape.biasOffset() + c]); };
      for (uint32_t r = 0; r < kRows; ++r) {
        for (uint32_t c = 0; c < n4; ++c) {
          const float got = y[size_t(r) * n4 + c];
          if (c < first) {
            ASSERT_EQ(got, kSentinel) << "row " << r << ", column " << c << " before the block";
            continue;
          }
          double z = bias(c), absSum = std::abs(bias(c));
          for (uint32_t kk = 0; kk < k.ka; ++kk) {
            z += double(a[size_t(r) * ka4 + kk]) * w(kk, c);
            absSum += std::abs(double(a[size_t(r) * ka4 + kk]) * w(kk, c));
          }
          const double want = c >= k.n ? 0.0 : (k.act == core::Activation::Relu ? std::max(z, 0.0) : z);
          ASSERT_NEAR(got, want, tolerance(absSum, k.ka)) << "y, row " << r << ", column " << c;
        }
        for (uint32_t kk = 0; kk < ka4; ++kk) {
          double want = 0, absSum = 0;
          for (uint32_t c = first; c < n4; ++c) {
            want += double(dz[size_t(r) * n4 + c]) * w(kk, c);
            absSum += std::abs(double(dz[size_t(r) * n4 + c]) * w(kk, c));
          }
          ASSERT_NEAR(da[size_t(r) * ka4 + kk], want, tolerance(absSum, n4 - first))
              << "da, row " << r << ", input " << kk;
        }
      }
      // dW[k][c] and dBias[c] from the block on, the sentinel added to; the columns before untouched.
      auto expectGradient = [&](uint64_t at, uint32_t c, const std::vector<double>& x) {
        if (c < first) {
          ASSERT_EQ(grads[at], kSentinel) << "gradient entry " << at << ", column " << c << " before the block";
          return;
        }
        double want = kSentinel, absSum = std::abs(double(kSentinel));
        for (uint32_t r = 0; r < kRows; ++r) {
          want += x[r] * double(dz[size_t(r) * n4 + c]);
          absSum += std::abs(x[r] * double(dz[size_t(r) * n4 + c]));
        }
        ASSERT_NEAR(grads[at], want, tolerance(absSum, kRows)) << "gradient entry " << at << ", column " << c;
      };
      std::vector<double> x(kRows);
      for (uint32_t kk = 0; kk < ka4; ++kk) {
        for (uint32_t r = 0; r < kRows; ++r) x[r] = a[size_t(r) * ka4 + kk];
        for (uint32_t c = 0; c < n4; ++c) expectGradient(shape.offset + uint64_t(kk) * n4 + c, c, x);
      }
      std::fill(x.begin(), x.end(), 1.0);
      for (uint32_t c = 0; c < n4; ++c) expectGradient(shape.biasOffset() + c, c, x);
    }
}

// A block must start on a vec4 and hold a column.
TEST_F(DenseColumns, AFirstColumnOffAVec4OrPastTheLayerIsRefused) {
  core::DenseShape shape{16, 0, 17, core::Activation::None};
  nerf::DenseLayer layer(ctx(), shape, nerf::MlpTuning::forDevice(ctx()));
  auto buffer = gpu::Buffer::of(ctx(), std::vector<float>(size_t(64) * 20, 0.0f));
  const nerf::Mat m{buffer, 16}, y{buffer, 20};
  const gpu::LimitedDispatch uncut(ctx());
  const nerf::LayerRows rows{4, uncut.uncut()};
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    for (uint32_t bad : {2u, 20u, 24u}) {
      EXPECT_THROW(layer.recordForward(rec, rows, buffer, m, m, y, nullptr, bad), Error) << bad;
      EXPECT_THROW(layer.recordBackwardWeights(rec, rows, m, m, y, buffer, bad), Error) << bad;
    }
  });
}

}  // namespace
