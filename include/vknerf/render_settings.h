#pragma once
// Sampling when rendering a loaded model (Model::load); 0 keeps what the model was trained with.
#include <cstdint>
#include <optional>

namespace vknerf {

struct RenderSettings {
  uint32_t coarseSamples = 0, fineSamples = 0;  // vanilla: stratified + importance samples per ray
  uint32_t marchSteps = 0;                      // fast: march steps per scene-box diagonal
  // fast, sampled by a proposal: the samples a ray the proposal places for the field (its weights
  // spread over them by inverse CDF); fewer render faster, each standing for more of the ray's weight.
  uint32_t proposalSamples = 0;
  // fast: a ray stops once its transmittance is below this (what lies behind adds less than that
  // times its colour); 0 shades every sample the march finds. In [0, 1).
  float minTransmittance = 1e-4f;
  // fast, trained with an appearance embedding: the training photo (its index in the training
  // split) whose appearance vector renders use; none: the mean of the photos' vectors.
  std::optional<uint32_t> appearancePhoto;
  // The pixels a batch of Model::render renders (one submission each) and the pipeline's buffers
  // are sized for; 0: the model's own (16384 for the fast model, 4096 for the vanilla one). Fewer
  // need less device memory, more fewer submissions; the pixels are the same either way (up to a
  // marched ray's light behind minTransmittance, which segments of other lengths may stop apart).
  uint32_t raysPerBatch = 0;
  // Time each kernel of Model::render on the device (timestamp queries): RenderedImage::kernelMs
  // then says where a view's time went. Off by default: the queries cost a little.
  bool profile = false;
};

}  // namespace vknerf
