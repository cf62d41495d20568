#pragma once
// eval's contact sheet: one row per held-out view, ground truth | render | depth | error, each tile
// box-filtered down to fit a square of `tileSize` pixels (never enlarged), a title over each column
// and a label (the view's name and PSNR) over each row. A picture of every view shows what a mean
// PSNR hides: floaters, a wall painted where the object should be, depth in pieces.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "vknerf/dataset.h"

namespace vknerf::nerf {

// |render - truth| per pixel, averaged over R, G and B, through the depth images' colour map from
// 0 (dark blue) to `fullScale` (yellow, and anything above it). Both images are 3 floats a pixel.
ImageRGBA8 errorRgba(const std::vector<float>& render, const std::vector<float>& truth, uint32_t width,
                     uint32_t height, float fullScale);

// `image` box-filtered to fit inside maxSide x maxSide, its aspect ratio kept; unchanged when it fits.
ImageRGBA8 fitInside(const ImageRGBA8& image, uint32_t maxSide);

class ContactSheet {
 public:
  static constexpr uint32_t kGap = 4;          // pixels between tiles and around the sheet
  static constexpr uint32_t kTextHeight = 12;  // a line of text: the font's 7 pixels and spacing

  ContactSheet(std::array<std::string, 4> titles, uint32_t tileSize);
  // Each image is shrunk now, so that a sheet of many views holds only its small tiles.
  void addRow(const std::string& label, const std::array<ImageRGBA8, 4>& tiles);
  size_t rows() const { return rows_.size(); }
  // The sheet on a white background, opaque.
  ImageRGBA8 compose() const;
  // compose() as an RGB PNG through writeFileAtomically (an existing file stays whole on failure).
  void save(const std::string& path) const;

 private:
  struct Row {
    std::string label;
    std::array<ImageRGBA8, 4> tiles;
  };
  std::array<std::string, 4> titles_;
  uint32_t tileSize_;
  std::vector<Row> rows_;
};

}  // namespace vknerf::nerf
