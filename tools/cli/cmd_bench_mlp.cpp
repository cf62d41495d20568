// `vknerf bench mlp`: throughput of the MLP kernels on the current device next to OpenBLAS sgemm
// doing the same matrix products on the same CPU cores.
//
// Network: a plain MLP of 3 dense W x W layers (ReLU, ReLU, sigmoid) over --batch samples.
// FLOPs counted: 2*B*K*N per product; forward = the 3 layer products; backward = dW of all 3
// layers + dX of the last 2 (the first layer's input gradient is not requested).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "command.h"
#include "gpu/buffer.h"
#include "gpu/recorder.h"
#include "nerf/mlp.h"
#include "reference/rng.h"
#include "vknerf/error.h"

#ifdef VKNERF_HAVE_BLAS
#include <cblas.h>
#endif

namespace vknerf::cli {
namespace {

constexpr uint32_t kLayers = 3;

struct Result {
  uint32_t width = 0;
  double fwdMs = 0, bwdMs = 0, fwdFlops = 0, bwdFlops = 0;
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
    in[i] = 2.0f * ref::rng01(1, uint32_t(i), 0) - 1.0f;
    dOut[i] = 2.0f * ref::rng01(2, uint32_t(i), 0) - 1.0f;
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

  gpu::Recorder fwd(ctx, true), step(ctx, true);
  fwd.begin();
  mlp.recordForward(fwd, batch, params, inBuf, out, &ws);
  fwd.end();
  step.begin();
  step.fill(grads, 0);
  mlp.recordForward(step, batch, params, inBuf, out, &ws);
  mlp.recordBackward(step, batch, params, inBuf, out, dOutBuf, grads, ws);
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
  auto wall = [](auto&& fn) {
    auto t0 = std::chrono::steady_clock::now();
    fn();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  // Other processes share the cores: the GPU and BLAS runs are interleaved and each keeps its best,
  // so a ratio compares like with like.
  r.fwdMs = r.bwdMs = r.blasFwdMs = r.blasBwdMs = 1e30;
  for (int rep = 0; rep < reps; ++rep) {
    fwd.submitAndWait();
    r.fwdMs = std::min(r.fwdMs, sumLabel(fwd.timings(), "mlp"));
    step.submitAndWait();
    auto t = step.timings();
    r.bwdMs = std::min(r.bwdMs, sumLabel(t, "mlp") - sumLabel(t, "mlp forward"));
    for (const char* k : {"mlp forward", "mlp dX", "mlp dW", "mlp output backward"}) {
      double v = sumLabel(t, k);
      if (!r.kernelMs.count(k) || v < r.kernelMs[k]) r.kernelMs[k] = v;
    }
#ifdef VKNERF_HAVE_BLAS
    r.blasFwdMs = std::min(r.blasFwdMs, wall(gemmFwd));
    r.blasBwdMs = std::min(r.blasBwdMs, wall(gemmBwd));
#else
    r.blasFwdMs = r.blasBwdMs = 0;
#endif
  }
  return r;
}

Registration benchMlp("bench mlp", "Throughput of the MLP kernels against OpenBLAS sgemm", [](CLI::App& app, const Globals& g) {
  struct Opts {
    bool json = false;
    uint32_t batch = 1u << 16;
    int reps = 7;
    std::vector<uint32_t> widths{64, 128, 256};
  };
  auto o = std::make_shared<Opts>();
  app.add_flag("--json", o->json, "Print a JSON list, one object per width");
  app.add_option("--batch", o->batch, "Samples per batch")->check(CLI::Range(1u, 1u << 22));
  app.add_option("--reps", o->reps, "Repetitions (the best is reported)")->check(CLI::Range(1, 100));
  app.add_option("--widths", o->widths, "MLP widths (multiples of 4)");
  return [o, &g] {
    auto ctx = g.context();
    auto json = nlohmann::json::array();
    if (!o->json)
      std::printf("%d dense WxW layers, batch %u, device %s\n%6s %12s %10s %12s %10s %10s %10s %8s %8s | %9s %9s %9s\n",
                  int(kLayers), o->batch, ctx->describe().c_str(), "width", "fwd samp/s", "fwd GF/s", "f+b samp/s",
                  "f+b GF/s", "blas fwd", "blas f+b", "fwd rat", "f+b rat", "fwd GF/s", "dX GF/s", "dW GF/s");
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
                      {"samples_per_s", o->batch / ((r.fwdMs + r.bwdMs) * 1e-3)},
                      {"gflops", allG},
                      {"blas_fwd_gflops", blasFwd},
                      {"blas_gflops", blasAll},
                      {"fwd_ratio", fwdRatio},
                      {"ratio", ratio},
                      {"kernel_gflops", {{"forward", kf}, {"dX", kx}, {"dW", kw}}},
                      {"kernel_ms", r.kernelMs}});
      if (!o->json)
        std::printf("%6u %12.0f %10.1f %12.0f %10.1f %10.1f %10.1f %8.2f %8.2f | %9.1f %9.1f %9.1f\n", W,
                    o->batch / (r.fwdMs * 1e-3), fwdG, o->batch / ((r.fwdMs + r.bwdMs) * 1e-3), allG, blasFwd, blasAll,
                    fwdRatio, ratio, kf, kx, kw);
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
