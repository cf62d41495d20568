#pragma once
// One recording, submitted once and waited for: what most GPU tests do with a Recorder.
#include <utility>

#include "gpu/dispatch/recorder.h"
#include "vknerf/context.h"

namespace vknerf::test {

// Records `record(rec)` into a fresh Recorder of `ctx` between begin() and end(), submits it and
// waits. Tests that submit a recording again, or read its timings, keep their own Recorder.
template <class Record>
void submitOnce(Context& ctx, Record&& record) {
  gpu::Recorder rec(ctx);
  rec.begin();
  std::forward<Record>(record)(rec);
  rec.end();
  rec.submitAndWait();
}

}  // namespace vknerf::test
