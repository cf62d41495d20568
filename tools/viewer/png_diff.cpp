// vknerf-png-diff A.png B.png [--max-mean T] [--min-mean T]: mean and largest absolute difference of
// the RGB channels of two PNGs of the same size, in 8-bit levels (0..255). Exit 0 when the mean is
// within the given bounds, 1 when not (or on unreadable/mismatched input), 2 on usage errors.
// The viewer's check compares its screenshot with `vknerf render`'s PNG of the same camera.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <memory>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

namespace {

struct Image {
  int width = 0, height = 0;
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels{nullptr, stbi_image_free};
};

Image load(const std::string& path) {
  Image img;
  int channels = 0;
  img.pixels.reset(stbi_load(path.c_str(), &img.width, &img.height, &channels, 3));
  if (!img.pixels) {
    std::fprintf(stderr, "vknerf-png-diff: %s: cannot read PNG (%s)\n", path.c_str(), stbi_failure_reason());
    std::exit(1);
  }
  return img;
}

}  // namespace

int main(int argc, char** argv) {
  std::string a, b;
  double maxMean = -1, minMean = -1;
  CLI::App app{"Mean absolute RGB difference of two PNGs, in 8-bit levels"};
  app.add_option("a", a, "First PNG")->required();
  app.add_option("b", b, "Second PNG")->required();
  app.add_option("--max-mean", maxMean, "Fail unless the mean difference is below this");
  app.add_option("--min-mean", minMean, "Fail unless the mean difference is above this");
  CLI11_PARSE(app, argc, argv);

  Image x = load(a), y = load(b);
  if (x.width != y.width || x.height != y.height) {
    std::fprintf(stderr, "vknerf-png-diff: %s is %dx%d but %s is %dx%d\n", a.c_str(), x.width, x.height, b.c_str(), y.width,
                 y.height);
    return 1;
  }
  const size_t n = size_t(x.width) * x.height * 3;
  double sum = 0;
  int largest = 0;
  size_t differing = 0;
  for (size_t i = 0; i < n; ++i) {
    int d = std::abs(int(x.pixels.get()[i]) - int(y.pixels.get()[i]));
    sum += d;
    largest = std::max(largest, d);
    differing += d != 0;
  }
  const double mean = sum / double(n);
  std::printf("%s vs %s (%dx%d): mean |difference| %.4f levels, largest %d, %zu of %zu channel values differ\n", a.c_str(),
              b.c_str(), x.width, x.height, mean, largest, differing, n);
  bool ok = true;
  if (maxMean >= 0 && !(mean < maxMean)) std::printf("FAIL: mean %.4f is not below %.4f\n", mean, maxMean), ok = false;
  if (minMean >= 0 && !(mean > minMean)) std::printf("FAIL: mean %.4f is not above %.4f\n", mean, minMean), ok = false;
  return ok ? 0 : 1;
}
