#include "support/gpu_test.h"

#include <cstdio>

namespace vknerf::test {

Context& context() {
  static std::shared_ptr<Context> ctx = [] {
    auto c = Context::create();
    std::fprintf(stderr, "vknerf tests on %s%s\n", c->describe().c_str(),
                 c->validationEnabled() ? " with validation" : "");
    return c;
  }();
  return *ctx;
}

std::shared_ptr<Context> sharedContext() { return std::shared_ptr<Context>(&context(), [](Context*) {}); }

}  // namespace vknerf::test
