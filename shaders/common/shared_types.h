// What a kernel's shader and its host code share, written once: the push-constant block and the
// specialization constants' ids, in shaders/<stage>/<kernel>_shared.h, which both include (GLSL by
// #include with -I shaders/, C++ with shaders/ on the include path). This header makes the one text
// mean a GLSL declaration or a C++ one.
//
//   PUSH_CONSTANTS_BEGIN(XPush)            GLSL: layout(push_constant) uniform XPush { ... } pc;
//     uint count;                          C++:  struct vknerf::glsl::XPush { ... };
//   PUSH_CONSTANTS_END
//
//   SPEC_CONSTANTS_BEGIN(XSpec)            GLSL: layout(local_size_x_id = 0) in;
//     LOCAL_SIZE_X_ID(0)                         layout(constant_id = 1) const uint K4 = 64;
//     SPEC_CONSTANT(1, uint, K4, 64)       C++:  struct vknerf::glsl::XSpec { static constexpr
//   SPEC_CONSTANTS_END                             uint32_t LOCAL_SIZE_X = 0, K4 = 1; };
//
// The host names a constant by its id (gpu::SpecConstant{Spec::K4, value}, src/gpu/kernels/kernel.h); the
// defaults are the shader's, used where the host gives no value.
//
// Layout: push constants use std430 offsets, where a vec4 or uvec4 starts at a multiple of 16
// bytes. C++ sees vec4 as float[4] (4-byte aligned, so the host keeps its array syntax and sizeof
// has no tail padding): every block puts its vector members where both agree, and a
// PUSH_CONSTANTS_OFFSET check beside a vector that follows scalars keeps it so.
#ifndef VKNERF_SHARED_TYPES_H
#define VKNERF_SHARED_TYPES_H

#ifdef __cplusplus

#include <cstddef>
#include <cstdint>

namespace vknerf::glsl {
using uint = std::uint32_t;
using vec4 = float[4];
using uvec4 = std::uint32_t[4];
}  // namespace vknerf::glsl

#define PUSH_CONSTANTS_BEGIN(Name) namespace vknerf::glsl { struct Name {
#define PUSH_CONSTANTS_END }; }
// GLSL's uvec4 name[n]; flat in C++ (uint32_t name[4 n]), so the host indexes it by component.
#define UVEC4_ARRAY(name, n) uint name[4 * (n)]
#define PUSH_CONSTANTS_OFFSET(Name, member, bytes) \
  static_assert(offsetof(vknerf::glsl::Name, member) == (bytes), #Name "::" #member " is not at its std430 offset");

#define SPEC_CONSTANTS_BEGIN(Name) namespace vknerf::glsl { struct Name {
#define LOCAL_SIZE_X_ID(id) static constexpr uint LOCAL_SIZE_X = id;
#define SPEC_CONSTANT(id, type, name, value) static constexpr uint name = id;
#define SPEC_CONSTANTS_END }; }

#else  // GLSL

#define PUSH_CONSTANTS_BEGIN(Name) layout(push_constant) uniform Name {
#define PUSH_CONSTANTS_END } pc;
#define UVEC4_ARRAY(name, n) uvec4 name[n]
#define PUSH_CONSTANTS_OFFSET(Name, member, bytes)

#define SPEC_CONSTANTS_BEGIN(Name)
#define LOCAL_SIZE_X_ID(id) layout(local_size_x_id = id) in;
#define SPEC_CONSTANT(id, type, name, value) layout(constant_id = id) const type name = value;
#define SPEC_CONSTANTS_END

#endif
#endif
