// FLOAT_BITS_ADD(array, i, s): array[i] += s, atomically, on a uint array that holds float bits:
// a compare-and-swap loop with the uint atomics core Vulkan has on storage buffers, for devices
// without shaderBufferFloat32AtomicAdd (RDNA2, Xe-LP, most mobile GPUs). A retry happens only when
// another invocation changed the entry between the read and the swap. A macro: GLSL cannot pass a
// buffer's array to a function.
#ifndef VKNERF_GPU_FLOAT_BITS_ADD_GLSL
#define VKNERF_GPU_FLOAT_BITS_ADD_GLSL
#define FLOAT_BITS_ADD(array, i, s)                                                    \
  {                                                                                    \
    uint fbaSeen_, fbaOld_ = array[i];                                                 \
    do {                                                                               \
      fbaSeen_ = fbaOld_;                                                              \
      fbaOld_ = atomicCompSwap(array[i], fbaSeen_, floatBitsToUint(uintBitsToFloat(fbaSeen_) + (s))); \
    } while (fbaOld_ != fbaSeen_);                                                     \
  }
#endif
