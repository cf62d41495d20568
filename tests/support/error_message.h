#pragma once
// The message of a vknerf::Error, for tests that check what an error says.
#include <gtest/gtest.h>

#include <exception>
#include <string>

#include "vknerf/error.h"

namespace vknerf::test {

// The message of the vknerf::Error that `f` throws; a test failure when it throws nothing or
// something else.
template <class F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw a non-vknerf exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "did not throw";
  return {};
}

#define EXPECT_MESSAGE_HAS(message, part) \
  EXPECT_NE(std::string(message).find(part), std::string::npos) << "message: " << (message) << "\nexpected: " << (part)

}  // namespace vknerf::test
