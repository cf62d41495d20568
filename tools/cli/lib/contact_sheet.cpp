#include "lib/contact_sheet.h"

#include <algorithm>
#include <cmath>

#include "vknerf/image_io.h"
#include "lib/pixel_text.h"
#include "lib/render_output.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"

namespace vknerf::nerf {
namespace {

constexpr std::array<uint8_t, 3> kInk{30, 30, 30};

void blit(ImageRGBA8& dst, const ImageRGBA8& src, uint32_t x, uint32_t y) {
  for (uint32_t r = 0; r < src.height && y + r < dst.height; ++r) {
    const uint32_t n = std::min(src.width, dst.width - std::min(dst.width, x));
    std::copy_n(&src.rgba[size_t(r) * src.width * 4], size_t(n) * 4, &dst.rgba[(size_t(y + r) * dst.width + x) * 4]);
  }
}

}  // namespace

ImageRGBA8 errorRgba(const std::vector<float>& render, const std::vector<float>& truth, uint32_t width,
                     uint32_t height, float fullScale) {
  const size_t pixels = size_t(width) * height;
  if (render.size() != pixels * 3 || truth.size() != pixels * 3) throw Error("error image: the images differ in size");
  ImageRGBA8 out{width, height, std::vector<uint8_t>(pixels * 4, 255)};
  for (size_t p = 0; p < pixels; ++p) {
    float e = 0;
    for (int k = 0; k < 3; ++k) e += std::fabs(render[p * 3 + k] - truth[p * 3 + k]);
    const auto rgb = mapColour(e / 3.0f / fullScale);
    std::copy(rgb.begin(), rgb.end(), &out.rgba[p * 4]);
  }
  return out;
}

ImageRGBA8 fitInside(const ImageRGBA8& image, uint32_t maxSide) {
  const uint32_t longest = std::max(image.width, image.height);
  if (longest <= maxSide || longest == 0) return image;
  const double s = double(maxSide) / double(longest);
  const uint32_t w = std::max(1u, uint32_t(std::lround(image.width * s))), h = std::max(1u, uint32_t(std::lround(image.height * s)));
  ImageRGBA8 out{w, h, std::vector<uint8_t>(size_t(w) * h * 4)};
  // Each output pixel averages the input pixels whose index maps into it: a box filter, which keeps
  // a thin floater visible as a faint smudge instead of dropping it as point sampling would.
  for (uint32_t y = 0; y < h; ++y) {
    const uint32_t y0 = uint32_t(uint64_t(y) * image.height / h), y1 = std::max(y0 + 1, uint32_t(uint64_t(y + 1) * image.height / h));
    for (uint32_t x = 0; x < w; ++x) {
      const uint32_t x0 = uint32_t(uint64_t(x) * image.width / w), x1 = std::max(x0 + 1, uint32_t(uint64_t(x + 1) * image.width / w));
      uint32_t sum[4] = {0, 0, 0, 0};
      for (uint32_t sy = y0; sy < y1; ++sy)
        for (uint32_t sx = x0; sx < x1; ++sx)
          for (int k = 0; k < 4; ++k) sum[k] += image.rgba[(size_t(sy) * image.width + sx) * 4 + k];
      const uint32_t n = (y1 - y0) * (x1 - x0);
      for (int k = 0; k < 4; ++k) out.rgba[(size_t(y) * w + x) * 4 + k] = uint8_t((sum[k] + n / 2) / n);
    }
  }
  return out;
}

ContactSheet::ContactSheet(std::array<std::string, 4> titles, uint32_t tileSize)
    : titles_(std::move(titles)), tileSize_(tileSize) {
  if (tileSize_ == 0) throw Error("contact sheet: the tile size must be positive");
}

void ContactSheet::addRow(const std::string& label, const std::array<ImageRGBA8, 4>& tiles) {
  Row row{label, {}};
  for (size_t c = 0; c < 4; ++c) row.tiles[c] = fitInside(tiles[c], tileSize_);
  rows_.push_back(std::move(row));
}

ImageRGBA8 ContactSheet::compose() const {
  // Columns as wide as their widest tile or title (and a space); the sheet as wide as the columns or
  // the widest label.
  std::array<uint32_t, 4> columnWidth{};
  for (size_t c = 0; c < 4; ++c) {
    columnWidth[c] = textWidth(titles_[c]) + 2 * kGap;
    for (const Row& r : rows_) columnWidth[c] = std::max(columnWidth[c], r.tiles[c].width);
  }
  uint32_t width = kGap;
  for (uint32_t w : columnWidth) width += w + kGap;
  uint32_t height = kGap + kTextHeight;
  for (const Row& r : rows_) {
    width = std::max(width, 2 * kGap + textWidth(r.label));
    uint32_t tall = 0;
    for (const ImageRGBA8& t : r.tiles) tall = std::max(tall, t.height);
    height += kTextHeight + tall + kGap;
  }
  ImageRGBA8 sheet{width, height, std::vector<uint8_t>(size_t(width) * height * 4, 255)};
  uint32_t x = kGap;
  for (size_t c = 0; c < 4; ++c) {
    drawText(sheet, int(x), int(kGap), titles_[c], kInk);
    x += columnWidth[c] + kGap;
  }
  uint32_t y = kGap + kTextHeight;
  for (const Row& r : rows_) {
    drawText(sheet, int(kGap), int(y), r.label, kInk);
    y += kTextHeight;
    x = kGap;
    uint32_t tall = 0;
    for (size_t c = 0; c < 4; ++c) {
      blit(sheet, r.tiles[c], x, y);
      x += columnWidth[c] + kGap;
      tall = std::max(tall, r.tiles[c].height);
    }
    y += tall + kGap;
  }
  return sheet;
}

void ContactSheet::save(const std::string& path) const {
  const ImageRGBA8 sheet = compose();
  // RGB: the sheet is opaque, and a quarter fewer bytes keeps a committed sheet small.
  std::vector<uint8_t> rgb(size_t(sheet.width) * sheet.height * 3);
  for (size_t p = 0; p < size_t(sheet.width) * sheet.height; ++p)
    std::copy_n(&sheet.rgba[p * 4], 3, &rgb[p * 3]);
  const auto png = encodePng(sheet.width, sheet.height, 3, rgb.data());
  writeFileAtomically(path, png.data(), png.size());
}

}  // namespace vknerf::nerf
