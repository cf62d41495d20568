#pragma once
// A loader that stands in for what a shared capture lacks (LLFF's images_N/ for a missing images/,
// the files beside a transforms.json for absolute paths from its author's machine) says what it
// used, so that a result is never trained on other photos than the user thinks without a word.
#include <string>

namespace vknerf::io::detail {

// Writes "vknerf: <line>" to stderr, once per process for each distinct line: a scene loaded again
// (train's split, then eval's) does not repeat it. Safe to call from several threads.
void noteOnce(const std::string& line);

}  // namespace vknerf::io::detail
