// Compiling kernels before they first run (src/gpu/compile/kernel_compiler.h): on lavapipe every kernel
// variant a recording dispatches starts compiling once, and its submission waits for it, with
// progress on the submitting thread; results are unchanged; a training step or render after the first compiles
// nothing and creates no pipeline.
#include <pthread.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/device/device.h"
#include "gpu/kernels/kernel.h"
#include "gpu/compile/kernel_compiler.h"
#include "gpu/compile/mesa_disk_cache.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/sample_scene.h"
#include "support/tiny_config.h"
#include "vknerf/trainer.h"
#include "encoding/encode_sh_shared.h"

using namespace vknerf;

namespace {

class KernelCompilerTest : public test::GpuTest {
 protected:
  void TearDown() override {
    ctx().setCompileProgress({});  // the context outlives the test
    GpuTest::TearDown();
  }
};

// shaders/encoding/encode_sh.comp's push constants; limitBase ROW_LIMIT_NONE: every row.
using glsl::ShPush;

bool sameStats(const CompileStats& a, const CompileStats& b) {
  return a.pipelines == b.pipelines && a.compiledAhead == b.compiledAhead;
}

const Dataset& scene() { return test::quarterSizeSampleScene(); }

// Sets (or, with nullptr, unsets) an environment variable for a scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    value ? setenv(name, value, 1) : unsetenv(name);
  }
  ~ScopedEnv() { old_ ? setenv(name_, old_->c_str(), 1) : unsetenv(name_); }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

}  // namespace

TEST_F(KernelCompilerTest, EachVariantCompilesOnceBeforeItsSubmission) {
  gpu::KernelCompiler& compiler = gpu::device(ctx()).compiler();
  if (!compiler.ahead())
    GTEST_SKIP() << "this device compiles kernels when they are created (not lavapipe with its shader cache)";
  std::vector<std::pair<uint64_t, uint64_t>> calls;
  bool otherThread = false;
  const auto caller = std::this_thread::get_id();
  ctx().setCompileProgress([&](uint64_t done, uint64_t total) {
    calls.emplace_back(done, total);
    otherThread |= std::this_thread::get_id() != caller;
  });

  // Degree 3, which no model uses: compiled by this test alone. Directions in a buffer of a
  // power-of-two size (16 texels) and in one of another size (17 texels): two variants.
  gpu::Kernel sh(ctx(), {gpu::shaders::encode_sh,
                         {gpu::Binding::TexelRgba32f, gpu::Binding::Storage, gpu::Binding::Storage,
                          gpu::Binding::Storage},
                         sizeof(ShPush),
                         {{glsl::ShSpec::DEGREE, 3}}});
  if (sh.desc().bindings[0] != gpu::Binding::TexelRgba32f)
    GTEST_SKIP() << "texel tables are storage buffers under this device's maxTexelBufferElements: one variant";
  const std::vector<float> dirs = {0.6f, 0.0f, 0.8f, 0.0f, 0.0f, -1.0f, 0.0f, 0.0f};  // two unit directions
  std::vector<float> pow2(16 * 4, 0.0f), other(17 * 4, 0.0f);
  std::copy(dirs.begin(), dirs.end(), pow2.begin());
  std::copy(dirs.begin(), dirs.end(), other.begin());
  auto dirsPow2 = gpu::Buffer::of(ctx(), pow2), dirsOther = gpu::Buffer::of(ctx(), other);
  auto limit = gpu::Buffer::zeros(ctx(), 16), noGather = gpu::Buffer::zeros(ctx(), 16);
  gpu::Buffer outPow2(ctx(), 2 * 3 * 16), outOther(ctx(), 2 * 3 * 16);  // 9 coefficients: 3 vec4 per row
  const ShPush push{2, 3, 0, 0xffffffffu, 0};

  const CompileStats before = ctx().compileStats();
  gpu::Recorder rec(ctx());
  auto record = [&] {
    rec.begin();
    rec.dispatch(sh, {dirsPow2, outPow2, noGather, limit}, push, 1);
    rec.dispatch(sh, {dirsOther, outOther, noGather, limit}, push, 1);
    rec.end();
  };
  const std::vector<gpu::BufferRange> withPow2{dirsPow2, outPow2, noGather, limit},
      withOther{dirsOther, outOther, noGather, limit};
  EXPECT_TRUE(compiler.cold(sh, withPow2));
  EXPECT_TRUE(compiler.cold(sh, withOther));
  record();  // starts both compiles
  EXPECT_FALSE(compiler.cold(sh, withPow2));
  EXPECT_FALSE(compiler.cold(sh, withOther));
  rec.submitAndWait();  // waits for them
  const CompileStats after = ctx().compileStats();
  EXPECT_EQ(after.compiledAhead, before.compiledAhead + 2);
  EXPECT_GE(after.seconds, before.seconds);
  // (compiled, known): from the count when the submission began waiting to both compiled.
  const uint64_t b = before.compiledAhead;
  ASSERT_FALSE(calls.empty());
  EXPECT_GE(calls.front().first, b);
  EXPECT_EQ(calls.back(), std::make_pair(b + 2, b + 2));
  for (size_t i = 0; i < calls.size(); ++i) {
    EXPECT_EQ(calls[i].second, b + 2);
    if (i) EXPECT_GT(calls[i].first, calls[i - 1].first);
  }
  EXPECT_FALSE(otherThread) << "progress is reported on the submitting thread";

  // The same kernels again: nothing to compile, nothing reported.
  calls.clear();
  record();
  rec.submitAndWait();
  EXPECT_TRUE(calls.empty());
  EXPECT_TRUE(sameStats(ctx().compileStats(), after));

  // Results as the shader defines them: SH bands 0-2 of each direction (tests/reference/encoding/sh_encoding.h).
  for (const gpu::Buffer* out : {&outPow2, &outOther}) {
    auto f = out->download<float>();
    for (int row = 0; row < 2; ++row) {
      const float x = dirs[4 * row], y = dirs[4 * row + 1], z = dirs[4 * row + 2];
      const float* o = &f[12 * row];
      EXPECT_TRUE(test::near(o[0], 0.28209479177387814, 1e-6, 1e-6));
      EXPECT_TRUE(test::near(o[1], -0.48860251190291987 * y, 1e-6, 1e-6));
      EXPECT_TRUE(test::near(o[2], 0.48860251190291987 * z, 1e-6, 1e-6));
      EXPECT_TRUE(test::near(o[3], -0.48860251190291987 * x, 1e-6, 1e-6));
      EXPECT_TRUE(test::near(o[6], 0.94617469575755997 * z * z - 0.31539156525251999, 1e-6, 1e-6));
    }
  }
}

TEST_F(KernelCompilerTest, TrainingAndRenderingCompileNothingAfterTheirFirstUse) {
  for (TrainConfig cfg : {test::tinyVanillaConfig(), TrainConfig::fast(ctx())}) {
    SCOPED_TRACE(cfg.describe());
    uint32_t first = 2, then = 3;  // steps that may compile, then steps that must not
    if (cfg.isFast()) {  // small, with occupancy-grid updates (every cell, then a quarter) in both parts
      FastModel& m = cfg.fastModel();
      m.hashLevels = 6, m.hashLog2Size = 14, m.width = 32, m.gridResolution = 32;
      m.marchSteps = m.maxSamplesPerRay = 128;
      m.samplesPerBatch = 1u << 14;
      m.gridUpdateInterval = 4, m.gridWarmupSteps = 8;
      cfg.raysPerBatch = 1u << 12;
      first = m.gridWarmupSteps + m.gridUpdateInterval + 1, then = 2 * m.gridUpdateInterval + 1;
    }
    Trainer trainer(test::sharedContext(), scene(), cfg);
    for (uint32_t i = 0; i < first; ++i) trainer.step();
    const CompileStats warm = ctx().compileStats();
    for (uint32_t i = 0; i < then; ++i) trainer.step(i == 0);
    EXPECT_TRUE(sameStats(ctx().compileStats(), warm)) << "a later step compiled a kernel or created a pipeline";

    const Camera& cam = scene().cameras[0];
    trainer.model().render(cam);
    const CompileStats rendered = ctx().compileStats();
    trainer.model().render(cam);
    EXPECT_TRUE(sameStats(ctx().compileStats(), rendered)) << "a second render compiled a kernel or created a pipeline";
  }
}

TEST(KernelCompiler, ReadsMesasShaderCacheSwitchAsMesaDoes) {
  ScopedEnv old("MESA_GLSL_CACHE_DISABLE", nullptr);
  {
    ScopedEnv v("MESA_SHADER_CACHE_DISABLE", nullptr);
    EXPECT_FALSE(gpu::mesaShaderCacheDisabled());
  }
  for (const char* on : {"1", "true", "TRUE", "yes"}) {
    ScopedEnv v("MESA_SHADER_CACHE_DISABLE", on);
    EXPECT_TRUE(gpu::mesaShaderCacheDisabled()) << on;
  }
  for (const char* off : {"0", "false", "no", ""}) {
    ScopedEnv v("MESA_SHADER_CACHE_DISABLE", off);
    EXPECT_FALSE(gpu::mesaShaderCacheDisabled()) << off;
  }
  // The older name counts only when the current one is not set.
  ScopedEnv glsl("MESA_GLSL_CACHE_DISABLE", "true");
  {
    ScopedEnv v("MESA_SHADER_CACHE_DISABLE", nullptr);
    EXPECT_TRUE(gpu::mesaShaderCacheDisabled());
  }
  ScopedEnv v("MESA_SHADER_CACHE_DISABLE", "false");
  EXPECT_FALSE(gpu::mesaShaderCacheDisabled());
}

TEST(MesaDiskCache, KnowsItsWriterThreadsByName) {
  EXPECT_TRUE(gpu::isMesaCacheWriter("vknerf:disk$0"));
  EXPECT_TRUE(gpu::isMesaCacheWriter("vknerf_:disk$12"));  // long process names are cut to fit
  EXPECT_FALSE(gpu::isMesaCacheWriter("vknerf"));
  EXPECT_FALSE(gpu::isMesaCacheWriter("llvmpipe-0"));
  EXPECT_FALSE(gpu::isMesaCacheWriter("vknerf:disk$"));
  EXPECT_FALSE(gpu::isMesaCacheWriter("vknerf:disk$0a"));
}

// A thread named as Mesa's writer works a while, then waits on a condition variable as Mesa's
// queue does when empty: the wait returns after it has gone back to waiting, well before the timeout.
TEST(MesaDiskCache, WaitsUntilTheWriterWaitsForWork) {
  std::mutex m;
  std::condition_variable wake;
  bool named = false, quit = false;
  std::atomic<bool> working{true};
  std::thread writer([&] {
    pthread_setname_np(pthread_self(), "test:disk$7");
    {
      std::lock_guard<std::mutex> lock(m);
      named = true;
    }
    wake.notify_all();
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(300);
    while (std::chrono::steady_clock::now() < until) {
    }
    working = false;
    std::unique_lock<std::mutex> lock(m);
    wake.wait(lock, [&] { return quit; });
  });
  {
    std::unique_lock<std::mutex> lock(m);
    wake.wait(lock, [&] { return named; });
  }
  const auto timeout = std::chrono::seconds(60);
  const auto start = std::chrono::steady_clock::now();
  gpu::waitForMesaCacheWriters(timeout);
  EXPECT_FALSE(working) << "returned while the writer was busy";
  EXPECT_LT(std::chrono::steady_clock::now() - start, timeout) << "did not see the writer go back to waiting";
  {
    std::lock_guard<std::mutex> lock(m);
    quit = true;
  }
  wake.notify_all();
  writer.join();
}
