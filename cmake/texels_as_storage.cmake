# cmake -DIN=shader -DOUT=copy -P texels_as_storage.cmake: the copy of a shader source (or include)
# whose rgba32f texel buffers are storage buffers of vec4, for devices whose texel buffers are too
# small for vknerf's tables (maxTexelBufferElements: gpu::Device::texelsAsStorage). Every texel
# buffer is declared `layout(binding = B, rgba32f) uniform readonly imageBuffer NAME;` and read by
# imageLoad/imageSize: the declaration becomes an SSBO member NAME_texels[], and a .comp's
# imageLoad/imageSize become macros over it, so the kernels' own sources stay one text.
file(READ ${IN} text)
string(REGEX REPLACE
  "layout\\(binding = ([^,()]+), rgba32f\\) uniform readonly imageBuffer ([A-Za-z0-9_]+);"
  "layout(binding = \\1, std430) readonly buffer \\2_Storage { vec4 \\2_texels[]; };"
  text "${text}")
string(REGEX MATCH "rgba32f\\) uniform[^;]*imageBuffer" left "${text}")
if(left)
  message(FATAL_ERROR "${IN}: a texel buffer not declared as `layout(binding = B, rgba32f) uniform readonly imageBuffer NAME;`")
endif()
if(IN MATCHES "\\.comp$")
  string(REGEX REPLACE "(#version [0-9]+[^\n]*\n)"
    "\\1#define VKNERF_TEXELS_AS_STORAGE 1\n#define imageLoad(t, i) t##_texels[i]\n#define imageSize(t) int(t##_texels.length())\n"
    text "${text}")
endif()
file(WRITE ${OUT} "${text}")
