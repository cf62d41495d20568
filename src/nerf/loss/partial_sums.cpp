#include "nerf/loss/partial_sums.h"

#include <string>

#include "vknerf/error.h"
#include "loss/sum_partials_shared.h"

namespace vknerf::nerf {

PartialSums::PartialSums(Context& ctx)
    : kernel_(ctx, {gpu::shaders::sum_partials, {gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(glsl::SumPartialsPush), {}}) {}

void PartialSums::record(gpu::Recorder& rec, const SummedValues& in, const gpu::BufferRange& partials) {
  if (in.count == 0) return;
  if (in.stride == 0 || in.component >= in.stride) throw Error("PartialSums: component must lie within a nonzero stride");
  gpu::requireBytes("PartialSums", "values", in.values, (uint64_t(in.count - 1) * in.stride + in.component + 1) * 4);
  gpu::requireBytes("PartialSums", "partials", partials, uint64_t(partialCount(in.count)) * 4);
  const glsl::SumPartialsPush p{in.count, in.stride, in.component};
  rec.dispatch(kernel_, {in.values, partials}, p, partialCount(in.count), 1, 1, "sum_partials");
}

}  // namespace vknerf::nerf
