// `vknerf fit-image IMAGE`: the seed's spectral-bias experiment (§2.8, §6.7). Fits (u, v) -> rgb with
// a plain MLP, with positional encoding (default) or on raw coordinates (--no-encoding), and
// reports the PSNR of the fit; -o writes the fitted image.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

#include "checks.h"
#include "command_files.h"
#include "command.h"
#include "vknerf/image_io.h"
#include "kernels/fit_image.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"

namespace vknerf::cli {
namespace {

Registration fitImageCmd("fit-image", "Fit an image as (u, v) -> rgb with an MLP (spectral-bias demo)", [](CLI::App& app, const Globals& g) {
  struct Opts {
    std::string image, output;
    nerf::FitImageConfig cfg;
    bool noEncoding = false;
    uint32_t every = 100;
  };
  auto o = std::make_shared<Opts>();
  app.add_option("IMAGE", o->image, "Image to fit (PNG, JPEG, ...)")->required()->check(CLI::ExistingFile);
  app.add_option("--steps", o->cfg.steps, "Adam steps (full batch)")->check(CLI::Range(1u, 1000000u));
  app.add_flag("--no-encoding", o->noEncoding, "Raw (u, v) inputs instead of the frequency encoding");
  app.add_option("--levels", o->cfg.levels, "Frequency octaves L of the encoding")->check(CLI::Range(1u, 16u));
  app.add_option("--width", o->cfg.width, "Hidden width (multiple of 4)")->check(CLI::Range(4u, 1024u));
  app.add_option("--lr", o->cfg.learningRate, "Adam learning rate")->check(PositiveFinite);
  app.add_option("--seed", o->cfg.seed, "Initialisation seed");
  app.add_option("--every", o->every, "Print the training loss every N steps (0: never)");
  app.add_option("-o,--output", o->output, "Write the fitted image (PNG)");
  return [o, &g] {
    if (o->cfg.width % 4) throw UsageError("fit-image: --width must be a multiple of 4");
    CommandFiles files("fit-image");  // before the fit, which a bad path would lose
    files.input(o->image, "IMAGE").output(o->output, "-o");
    files.check();
    int w = 0, h = 0, channels = 0;
    unsigned char* data = stbi_load(o->image.c_str(), &w, &h, &channels, 4);
    if (!data) throw Error("fit-image: cannot read " + o->image + ": " + stbi_failure_reason());
    std::vector<uint32_t> rgba(size_t(w) * h);
    for (size_t i = 0; i < rgba.size(); ++i)
      rgba[i] = uint32_t(data[4 * i]) | uint32_t(data[4 * i + 1]) << 8 | uint32_t(data[4 * i + 2]) << 16 |
                uint32_t(data[4 * i + 3]) << 24;
    stbi_image_free(data);
    o->cfg.encoding = !o->noEncoding;
    std::printf("fit-image: %s, %dx%d, %s, %u steps\n", o->image.c_str(), w, h,
                o->cfg.encoding ? ("encoding L=" + std::to_string(o->cfg.levels)).c_str() : "raw (u, v)", o->cfg.steps);
    auto r = nerf::fitImage(*g.context(), rgba, uint32_t(w), uint32_t(h), o->cfg, o->every, [](uint32_t step, double mse) {
      std::printf("step %6u  mse %.6f  psnr %.2f dB\n", step, mse, mse > 0 ? -10.0 * std::log10(mse) : 100.0);
      std::fflush(stdout);
    });
    std::printf("psnr %.2f dB\n", r.psnr);
    if (!o->output.empty()) {
      std::vector<unsigned char> px(r.rgb.size());
      for (size_t i = 0; i < px.size(); ++i) px[i] = (unsigned char)(std::clamp(r.rgb[i], 0.0f, 1.0f) * 255.0f + 0.5f);
      const auto png = vknerf::encodePng(uint32_t(w), uint32_t(h), 3, px.data());
      writeFileAtomically(o->output, png.data(), png.size());
      std::printf("wrote %s\n", o->output.c_str());
    }
    return 0;
  };
});

}  // namespace
}  // namespace vknerf::cli
