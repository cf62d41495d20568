#pragma once
// What a call writes to stderr, for tests of the notes the loaders print there.
#include <gtest/gtest.h>

#include <string>

namespace vknerf::test {

template <class F>
std::string stderrOf(F&& f) {
  testing::internal::CaptureStderr();
  try {
    f();
  } catch (...) {
    testing::internal::GetCapturedStderr();
    throw;
  }
  return testing::internal::GetCapturedStderr();
}

// How many times `part` occurs in `text`.
inline size_t occurrences(const std::string& text, const std::string& part) {
  size_t n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++n;
  return n;
}

}  // namespace vknerf::test
