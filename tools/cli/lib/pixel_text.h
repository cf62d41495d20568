#pragma once
// Short labels drawn into an image with stb_easy_font's segment font (ASCII, about 6 pixels a
// character, 7 pixels tall): enough to name a view and its PSNR on a contact sheet without a
// font file.
#include <array>
#include <cstdint>
#include <string>

#include "vknerf/dataset.h"

namespace vknerf::nerf {

// Width in pixels of `text` as drawText draws it.
uint32_t textWidth(const std::string& text);
// Draws `text` with its top-left corner at (x, y), clipped to the image.
void drawText(ImageRGBA8& image, int x, int y, const std::string& text, std::array<uint8_t, 3> colour);

}  // namespace vknerf::nerf
