// `vknerf bench mlp`: throughput of the MLP kernels on the current device next to OpenBLAS sgemm
// doing the same matrix products on the same CPU cores.
//
// Network: a plain MLP of 3 dense W x W layers (ReLU, ReLU, sigmoid) over --batch samples.
// FLOPs counted: 2*B*K*N per product; forward = the 3 layer products; backward = dW of all 3
// layers + dX of the last 2 (the first layer's input gradient is not requested).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "command.h"
#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/network/mlp.h"
#include "core/math/rng.h"
#include "vknerf/error.h"

#ifdef VKNERF_HAVE_BLAS
#include <cblas.h>
#endif

namespace vknerf::cli {
namespace {

constexpr uint32_t kLayers = 3;

struct Result {
  uint32_t width = 0;
  double fwdMs = 0, bwdMs = 0, inferMs = 0, fwdFlops = 0, bwdFlops = 0;
  // Process CPU time (lavapipe's worker threads are ours): insensitive to other processes on the
  // cores, so on a shared machine these ratios are the steadier ones.
  double fwdCpuMs = 1e30, stepCpuMs = 1e30, blasFwdCpuMs = 1e30, blasStepCpuMs = 1e30;
  std::map<std::string, double> kernelMs, kernelFlops;
  double blasFwdMs = 0, blasBwdMs = 0;
};

double sumLabel(const std::vector<std::pair<std::string, double>>& t, const std::string& prefix) {
  double s = 0;
  for (auto& [label, ms] : t)
    if (label.rfind(prefix, 0) == 0) s += ms;
  return s;
}

Result benchWidth(Context& ctx, uint32_t W, uint32_t batch, int reps) {
  Result r;
  r.width = W;
  nerf::DenseMlp mlp(ctx, {W, W, kLayers - 1, W, 1});
  std::vector<float> in(size_t(batch) * W), dOut(size_t(batch) * W);
  for (size_t i = 0; i < in.size(); ++i) {
    in[i] = 2.0f * core::rng01(1, uint32_t(i), 0) - 1.0f;
    dOut[i] = 2.0f * core::rng01(2, uint32_t(i), 0) - 1.0f;
  }
  auto params = gpu::Buffer::of(ctx, mlp.initialParameters());
  auto inBuf = gpu::Buffer::of(ctx, in), dOutBuf = gpu::Buffer::of(ctx, dOut);
  gpu::Buffer out(ctx, in.size() * 4), grads(ctx, mlp.parameterCount() * 4);
  nerf::DenseMlp::Workspace ws(ctx, mlp, batch);

  const double layerFlops = 2.0 * batch * W * W;
  r.fwdFlops = kLayers * layerFlops;
  r.bwdFlops = kLayers * layerFlops + (kLayers - 1) * layerFlops;
  r.kernelFlops = {{"mlp forward", kLayers * layerFlops}, {"mlp dX", (kLayers - 1) * layerFlops},
                   {"mlp dW", kLayers * layerFlops}};

  gpu::Recorder fwd(ctx, true), step(ctx, true), infer(ctx, true);
  infer.begin();
  mlp.recordForward(infer, {batch, inBuf, out}, params, nullptr);  // keeps nothing: 16k-row scratch
  infer.end();
  infer.submitAndWait();
  fwd.begin();
  mlp.recordForward(fwd, {batch, inBuf, out}, params, &ws);
  fwd.end();
  step.begin();
  step.fill(grads, 0);
  mlp.recordForward(step, {batch, inBuf, out}, params, &ws);
  mlp.recordBackward(step, {batch, inBuf, out}, params, {dOutBuf, grads}, ws);
  step.end();
  fwd.submitAndWait();  // first submissions compile the pipelines
  step.submitAndWait();

#ifdef VKNERF_HAVE_BLAS
  // The same products: forward Y = X W; backward dW = X^T dZ, dX = dZ W^T (row-major).
  std::vector<float> X(in), Wm(size_t(W) * W, 0.01f), Y(in.size()), dW(size_t(W) * W);
  auto gemmFwd = [&] {
    for (uint32_t l = 0; l < kLayers; ++l)
      cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, int(batch), int(W), int(W), 1.0f, X.data(), int(W),
                  Wm.data(), int(W), 0.0f, Y.data(), int(W));
  };
  auto gemmBwd = [&] {
    for (uint32_t l = 0; l < kLayers; ++l) {
      cblas_sgemm(CblasRowMajor, CblasTrans, CblasNoTrans, int(W), int(W), int(batch), 1.0f, X.data(), int(W), Y.data(),
                  int(W), 1.0f, dW.data(), int(W));
      if (l > 0)
        cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasTrans, int(batch), int(W), int(W), 1.0f, Y.data(), int(W),
                    Wm.data(), int(W), 0.0f, X.data(), int(W));
    }
  };
  gemmFwd();
#endif
  auto cpu = [](auto&& fn) {
    timespec a{}, b{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &a);
    fn();
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &b);
    return (b.tv_sec - a.tv_sec) * 1e3 + (b.tv_nsec - a.tv_nsec) * 1e-6;
  };
  auto wall = [](auto&& fn) {
    auto t0 = std::chrono::steady_clock::now();
    fn();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  // Other processes share the cores: the GPU and BLAS runs are interleaved and each keeps its best,
  // so a ratio compares like with like.
  r.fwdMs = r.bwdMs = r.inferMs = r.blasFwdMs = r.blasBwdMs = 1e30;
  for (int rep = 0; rep < reps; ++rep) {
    infer.submitAndWait();
    r.inferMs = std::min(r.inferMs, sumLabel(infer.timings(), "mlp"));
    r.fwdCpuMs = std::min(r.fwdCpuMs, cpu([&] { fwd.submitAndWait(); }));
    r.fwdMs = std::min(r.fwdMs, sumLabel(fwd.timings(), "mlp"));
    r.stepCpuMs = std::min(r.stepCpuMs, cpu([&] { step.submitAndWait(); }));
    auto t = step.timings();
    r.bwdMs = std::min(r.bwdMs, sumLabel(t, "mlp") - sumLabel(t, "mlp forward"));
    for (const char* k : {"mlp forward", "mlp dX", "mlp dW", "mlp output backward"}) {
      double v = sumLabel(t, k);
      if (!r.kernelMs.count(k) || v < r.kernelMs[k]) r.kernelMs[k] = v;
    }
#ifdef VKNERF_HAVE_BLAS
    r.blasFwdMs = std::min(r.blasFwdMs, wall(gemmFwd));
    r.blasBwdMs = std::min(r.blasBwdMs, wall(gemmBwd));
    r.blasFwdCpuMs = std::min(r.blasFwdCpuMs, cpu(gemmFwd));
    r.blasStepCpuMs = std::min(r.blasStepCpuMs, cpu([&] {
      gemmFwd();
      gemmBwd();
    }));
#else
    r.blasFwdMs = r.blasBwdMs = 0;
#endif
  }
  return r;
}

// The NeRF network itself (seed §4.8: 8 x 256, skip, colour branch): device time per batch.
nlohmann::json benchNerf(Context& ctx, uint32_t batch, int reps) {
  nerf::MlpConfig cfg;  // the paper's shape
  nerf::NerfMlp mlp(ctx, cfg);
  auto feat = [&](uint32_t stride, uint32_t dims, uint32_t seed) {
    std::vector<float> v(size_t(batch) * stride, 0.0f);
    for (uint32_t r = 0; r < batch; ++r)
      for (uint32_t k = 0; k < dims; ++k) v[size_t(r) * stride + k] = 2.0f * core::rng01(seed, r, k) - 1.0f;
    return v;
  };
  auto params = gpu::Buffer::of(ctx, mlp.initialParameters());
  auto pos = gpu::Buffer::of(ctx, feat(mlp.posStride(), cfg.posDims, 1));
  auto dir = gpu::Buffer::of(ctx, feat(mlp.dirStride(), cfg.dirDims, 2));
  auto dOut = gpu::Buffer::of(ctx, feat(4, 4, 3));
  gpu::Buffer out(ctx, uint64_t(batch) * 16), grads(ctx, mlp.parameterCount() * 4);
  nerf::NerfMlp::Workspace ws(ctx, mlp, batch);
  gpu::Recorder step(ctx, true);
  step.begin();
  step.fill(grads, 0);
  mlp.recordForward(step, {batch, pos, dir, out}, params, &ws);
  mlp.recordBackward(step, {batch, pos, dir, out}, params, {dOut, grads}, ws);
  step.end();
  step.submitAndWait();
  double flops = 0;  // multiply-adds of the padded layers actually computed
  for (const auto& l : mlp.shape().layers) flops += 2.0 * batch * l.k4() * l.n4();
  double fwdMs = 1e30, allMs = 1e30;
  for (int rep = 0; rep < reps; ++rep) {
    step.submitAndWait();
    auto t = step.timings();
    double f = 0, a = 0;
    for (auto& [label, ms] : t) {
      a += ms;
      if (label.find("backward") == std::string::npos && label.find("dW") == std::string::npos &&
          label.find("dX") == std::string::npos)
        f += ms;
    }
    fwdMs = std::min(fwdMs, f);
    allMs = std::min(allMs, a);
  }
  // backward: dW of every layer, dX of every layer but the first (no input gradient requested)
  double bwdFlops = 2 * flops - 2.0 * batch * mlp.shape().layers[0].k4() * mlp.shape().layers[0].n4();
  return {{"network", "nerf 8x256 skip 5"}, {"batch", batch}, {"parameters", mlp.parameterCount()},
          {"fwd_ms", fwdMs}, {"fwd_samples_per_s", batch / (fwdMs * 1e-3)}, {"fwd_gflops", flops / (fwdMs * 1e6)},
          {"ms", allMs}, {"samples_per_s", batch / (allMs * 1e-3)}, {"gflops", (flops + bwdFlops) / (allMs * 1e6)}};
}

// The fast model's network (hash features -> 1 x 64 trunk -> 16 features + sigma -> colour 32 ->
// rgb), the one training and rendering run: its forward with the activations kept for backward
// (training) and without (rendering), run layer by layer and fused into one kernel, next to OpenBLAS
// doing the same products (each layer's padded K x N) in the same run.
nlohmann::json benchFastNerf(Context& ctx, uint32_t batch, int reps) {
  nerf::MlpConfig cfg;
  cfg.depth = 1, cfg.width = 64, cfg.skipLayer = 0, cfg.posDims = 16, cfg.dirDims = 16, cfg.featureWidth = 16;
  cfg.density = DensityActivation::TruncExp;
  auto feat = [&](uint32_t stride, uint32_t dims, uint32_t seed) {
    std::vector<float> v(size_t(batch) * stride, 0.0f);
    for (uint32_t r = 0; r < batch; ++r)
      for (uint32_t k = 0; k < dims; ++k) v[size_t(r) * stride + k] = 2.0f * core::rng01(seed, r, k) - 1.0f;
    return v;
  };
  auto tuning = nerf::MlpTuning::forDevice(ctx);
  struct Path {
    const char* name;
    std::unique_ptr<nerf::NerfMlp> mlp;
    std::unique_ptr<nerf::NerfMlp::Workspace> ws;
    std::unique_ptr<gpu::Recorder> keep, infer;
    double keepMs = 1e30, inferMs = 1e30;
  };
  std::vector<Path> paths(2);
  paths[0].name = "layered", paths[1].name = "fused";
  for (uint32_t i = 0; i < 2; ++i) {
    tuning.fused = i ? 3 : 0;  // both variants fused, or neither
    paths[i].mlp = std::make_unique<nerf::NerfMlp>(ctx, cfg, tuning);
  }
  const auto& shape = paths[0].mlp->shape();
  auto params = gpu::Buffer::of(ctx, paths[0].mlp->initialParameters());
  auto pos = gpu::Buffer::of(ctx, feat(paths[0].mlp->posStride(), cfg.posDims, 1));
  auto dir = gpu::Buffer::of(ctx, feat(paths[0].mlp->dirStride(), cfg.dirDims, 2));
  gpu::Buffer out(ctx, uint64_t(batch) * 16);
  for (auto& p : paths) {
    p.ws = std::make_unique<nerf::NerfMlp::Workspace>(ctx, *p.mlp, batch);
    p.keep = std::make_unique<gpu::Recorder>(ctx, true);
    p.infer = std::make_unique<gpu::Recorder>(ctx, true);
    for (auto* rec : {p.keep.get(), p.infer.get()}) {
      rec->begin();
      p.mlp->recordForward(*rec, {batch, pos, dir, out}, params, rec == p.keep.get() ? p.ws.get() : nullptr);
      rec->end();
      rec->submitAndWait();  // the first submission compiles the pipelines
    }
  }
  double flops = 0;  // multiply-adds of the padded layers
  for (const auto& l : shape.layers) flops += 2.0 * batch * l.k4() * l.n4();
  double blasMs = 1e30;
#ifdef VKNERF_HAVE_BLAS
  std::vector<std::vector<float>> acts;  // each layer's input, then the last output
  for (const auto& l : shape.layers) acts.emplace_back(size_t(batch) * l.k4(), 0.5f);
  acts.emplace_back(size_t(batch) * shape.layers.back().n4());
  std::vector<float> weights(shape.total, 0.01f);
  auto gemm = [&] {
    for (size_t i = 0; i < shape.layers.size(); ++i) {
      const auto& l = shape.layers[i];
      std::vector<float>& y = i + 1 < shape.layers.size() ? acts[i + 1] : acts.back();
      cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, int(batch), int(l.n4()), int(l.k4()), 1.0f, acts[i].data(),
                  int(l.k4()), weights.data() + l.offset, int(l.n4()), 0.0f, y.data(), int(l.n4()));
    }
  };
  gemm();
#endif
  auto wall = [](auto&& fn) {
    auto t0 = std::chrono::steady_clock::now();
    fn();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  // Interleaved, each keeping its best: a ratio compares like with like on a shared machine.
  for (int rep = 0; rep < reps; ++rep) {
    for (auto& p : paths) {
      p.keep->submitAndWait();
      p.keepMs = std::min(p.keepMs, sumLabel(p.keep->timings(), "nerf"));
      p.infer->submitAndWait();
      p.inferMs = std::min(p.inferMs, sumLabel(p.infer->timings(), "nerf"));
    }
#ifdef VKNERF_HAVE_BLAS
    blasMs = std::min(blasMs, wall(gemm));
#endif
  }
  auto json = nlohmann::json{{"network", "fast: 16 -> 64 -> 16 + sigma, + 16 SH -> 32 -> 3"},
                             {"batch", batch},
                             {"gflop", flops * 1e-9},
                             {"blas_gflops", flops / (blasMs * 1e6)}};
  for (auto& p : paths)
    json[p.name] = {{"keep_ms", p.keepMs},
                    {"keep_gflops", flops / (p.keepMs * 1e6)},
                    {"inference_ms", p.inferMs},
                    {"inference_gflops", flops / (p.inferMs * 1e6)},
                    {"inference_ratio", blasMs / p.inferMs}};
  return json;
}

Registration benchMlp("bench mlp", "Throughput of the MLP kernels against OpenBLAS sgemm", [](CLI::App& app, const Globals& g) {
  struct Opts {
    bool json = false;
    uint32_t batch = 1u << 16;
    int reps = 7;
    std::vector<uint32_t> widths{64, 128, 256};
    bool nerf = false, fast = false;
  };
  auto o = std::make_shared<Opts>();
  app.add_flag("--json", o->json, "Print a JSON list, one object per width");
  app.add_option("--batch", o->batch, "Samples per batch")->check(CLI::Range(1u, 1u << 22));
  app.add_option("--reps", o->reps, "Repetitions (the best is reported)")->check(CLI::Range(1, 100));
  app.add_option("--widths", o->widths, "MLP widths (multiples of 4)");
  app.add_flag("--nerf", o->nerf, "Also time the NeRF network (8 x 256, skip, colour branch) forward + backward");
  app.add_flag("--fast-nerf", o->fast, "Also time the fast model's network forward, layer by layer and fused");
  return [o, &g] {
    auto ctx = g.context();
    auto json = nlohmann::json::array();
    if (!o->json)
      std::printf("%d dense WxW layers, batch %u, device %s\n%6s %12s %10s %12s %10s %10s %10s %8s %8s %8s %8s | %9s %9s %9s\n",
                  int(kLayers), o->batch, ctx->describe().c_str(), "width", "fwd samp/s", "fwd GF/s", "f+b samp/s",
                  "f+b GF/s", "blas fwd", "blas f+b", "fwd rat", "f+b rat", "cpu fwd", "cpu f+b", "fwd GF/s", "dX GF/s",
                  "dW GF/s");
    for (uint32_t W : o->widths) {
      if (W == 0 || W % 4) throw vknerf::Error("bench mlp: width " + std::to_string(W) + " is not a positive multiple of 4");
      Result r = benchWidth(*ctx, W, o->batch, o->reps);
      auto gf = [](double flops, double ms) { return ms > 0 ? flops / (ms * 1e6) : 0.0; };
      double fwdG = gf(r.fwdFlops, r.fwdMs), allG = gf(r.fwdFlops + r.bwdFlops, r.fwdMs + r.bwdMs);
      double blasFwd = gf(r.fwdFlops, r.blasFwdMs), blasAll = gf(r.fwdFlops + r.bwdFlops, r.blasFwdMs + r.blasBwdMs);
      double kf = gf(r.kernelFlops["mlp forward"], r.kernelMs["mlp forward"]);
      double kx = gf(r.kernelFlops["mlp dX"], r.kernelMs["mlp dX"]);
      double kw = gf(r.kernelFlops["mlp dW"], r.kernelMs["mlp dW"]);
      double fwdRatio = blasFwd > 0 ? fwdG / blasFwd : 0, ratio = blasAll > 0 ? allG / blasAll : 0;
      json.push_back({{"width", W},
                      {"layers", kLayers},
                      {"batch", o->batch},
                      {"fwd_samples_per_s", o->batch / (r.fwdMs * 1e-3)},
                      {"fwd_gflops", fwdG},
                      {"inference_gflops", gf(r.fwdFlops, r.inferMs)},
                      {"samples_per_s", o->batch / ((r.fwdMs + r.bwdMs) * 1e-3)},
                      {"gflops", allG},
                      {"blas_fwd_gflops", blasFwd},
                      {"blas_gflops", blasAll},
                      {"fwd_ratio", fwdRatio},
                      {"ratio", ratio},
                      {"kernel_gflops", {{"forward", kf}, {"dX", kx}, {"dW", kw}}},
                      {"cpu_time_fwd_ratio", r.blasFwdCpuMs / r.fwdCpuMs},
                      {"cpu_time_ratio", r.blasStepCpuMs / r.stepCpuMs},
                      {"kernel_ms", r.kernelMs}});
      if (!o->json)
        std::printf("%6u %12.0f %10.1f %12.0f %10.1f %10.1f %10.1f %8.2f %8.2f %8.2f %8.2f | %9.1f %9.1f %9.1f\n", W,
                    o->batch / (r.fwdMs * 1e-3), fwdG, o->batch / ((r.fwdMs + r.bwdMs) * 1e-3), allG, blasFwd, blasAll,
                    fwdRatio, ratio, r.blasFwdCpuMs / r.fwdCpuMs, r.blasStepCpuMs / r.stepCpuMs, kf, kx, kw);
    }
    if (o->nerf) {
      auto n = benchNerf(*ctx, o->batch, o->reps);
      if (!o->json)
        std::printf("NeRF MLP 8x256, batch %u: forward %.1f ms (%.0f samples/s, %.1f GFLOP/s), forward+backward %.1f ms "
                    "(%.0f samples/s, %.1f GFLOP/s)\n",
                    o->batch, n["fwd_ms"].get<double>(), n["fwd_samples_per_s"].get<double>(), n["fwd_gflops"].get<double>(),
                    n["ms"].get<double>(), n["samples_per_s"].get<double>(), n["gflops"].get<double>());
      json.push_back(n);
    }
    if (o->fast) {
      auto n = benchFastNerf(*ctx, o->batch, o->reps);
      if (!o->json) {
        std::printf("fast model's MLP (%s), batch %u, %.3f GFLOP; OpenBLAS %.1f GFLOP/s\n",
                    n["network"].get<std::string>().c_str(), o->batch, n["gflop"].get<double>(),
                    n["blas_gflops"].get<double>());
        for (const char* path : {"layered", "fused"})
          std::printf("  %-8s forward keeping activations %7.2f ms (%5.1f GFLOP/s), inference %7.2f ms (%5.1f GFLOP/s, "
                      "%.2f of OpenBLAS)\n",
                      path, n[path]["keep_ms"].get<double>(), n[path]["keep_gflops"].get<double>(),
                      n[path]["inference_ms"].get<double>(), n[path]["inference_gflops"].get<double>(),
                      n[path]["inference_ratio"].get<double>());
      }
      json.push_back(n);
    }
    if (o->json) std::printf("%s\n", json.dump(2).c_str());
#ifndef VKNERF_HAVE_BLAS
    std::fprintf(stderr, "vknerf: built without OpenBLAS; blas columns are 0\n");
#endif
    return 0;
  };
});

}  // namespace
}  // namespace vknerf::cli
