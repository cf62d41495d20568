#pragma once
// CSV as RFC 4180 has it: a field holding a comma, a double quote or a line break is enclosed in
// double quotes, with each double quote inside doubled. Image names come from the scene's files.
#include <string>

namespace vknerf::nerf {

std::string csvField(const std::string& text);

}  // namespace vknerf::nerf
