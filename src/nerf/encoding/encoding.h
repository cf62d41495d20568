#pragma once
// The one contract every encoding keeps (tiny-cuda-nn's Encoding: forward(input, output, params),
// backward(dL/doutput -> dL/dparams, dL/dinput)), so that a model takes its encoding as a value:
// the fast field's position encoding is a constructor argument (models/fast/fast_field.h), and a
// second one is a class of this folder, not an edit of the model.
//   forward   rows.inputs (vec4 per row) -> rows.features (a block of paddedDims() columns)
//   backward  dL/dfeatures (read from rows.features) -> += dL/dparams, and optionally dL/dinputs
// A fixed encoding (frequency, spherical harmonics) has no parameters and no backward.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "gpu/dispatch/recorder.h"
#include "nerf/encoding/encoded_rows.h"
#include "nerf/optim/adam.h"

namespace vknerf::nerf {

// What a backward writes: the parameters' gradient (accumulated) and, with `dInputs`, the gradient
// of each row's input (vec4 per row, w = 0; overwritten) from `params` as the forward read them.
struct EncodingGradients {
  gpu::BufferRange params, grads;
  std::optional<gpu::BufferRange> dInputs;
};

class Encoding {
 public:
  virtual ~Encoding() = default;

  virtual uint32_t outputDims() const = 0;
  uint32_t paddedDims() const { return (outputDims() + 3) / 4 * 4; }

  // Trainable parameters: how many, their initial values (deterministic in the seed) and the parts
  // a gradient can reach (the optimizer steps those alone; empty: all). None for a fixed encoding.
  virtual size_t parameterCount() const { return 0; }
  virtual std::vector<float> initialParameters(uint32_t seed) const { (void)seed; return {}; }
  virtual std::vector<ParameterRange> trainedParts() const { return {}; }

  // `params`: parameterCount() floats (unbound for a fixed encoding).
  virtual void recordForward(gpu::Recorder& rec, const EncodedRows& rows, const gpu::BufferRange& params) = 0;
  // Throws for an encoding without parameters or input gradient.
  virtual void recordBackward(gpu::Recorder& rec, const EncodedRows& rows, const EncodingGradients& gradients);
};

}  // namespace vknerf::nerf
