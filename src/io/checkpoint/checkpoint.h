#pragma once
// The checkpoint file: a versioned container of named binary sections plus a JSON config, closed by
// a checksum over everything before it. Written with writeFileAtomically (vknerf/file_output.h), so a
// crash never leaves a half-written checkpoint under the real name.
//
//   "VKNERFCK"  u32 version  u32 configBytes  config (JSON text)
//   u32 sectionCount  { u32 nameBytes  name  u64 dataBytes  data }*
//   u64 FNV-1a hash of all preceding bytes
#include <cstdint>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace vknerf::io {

struct Checkpoint {
  static constexpr uint32_t kVersion = 1;
  std::string config;                                     // JSON text
  std::map<std::string, std::vector<uint8_t>> sections;  // parameters, optimizer state, occupancy, ...

  template <class T> void put(const std::string& name, const std::vector<T>& v) {
    auto* p = reinterpret_cast<const uint8_t*>(v.data());
    sections[name].assign(p, p + v.size() * sizeof(T));
  }
  // Throws vknerf::Error naming the file and the section when missing or of the wrong size.
  template <class T> std::vector<T> get(const std::string& name, size_t expectedCount = SIZE_MAX) const {
    const auto& bytes = section(name, expectedCount == SIZE_MAX ? SIZE_MAX : expectedCount * sizeof(T), sizeof(T));
    std::vector<T> v(bytes.size() / sizeof(T));
    if (!v.empty()) __builtin_memcpy(v.data(), bytes.data(), bytes.size());
    return v;
  }

  void save(const std::string& path) const;
  static Checkpoint load(const std::string& path);
  // Whether the file at `path` begins as a checkpoint does (false when it cannot be read).
  static bool startsWithMagic(const std::string& path);
  // The file's bytes already in memory; `path` names it in messages.
  static Checkpoint parse(const uint8_t* data, size_t size, const std::string& path);

  std::string path;  // set by load(), for error messages

 private:
  const std::vector<uint8_t>& section(const std::string& name, size_t expectedBytes, size_t elementBytes) const;
};

uint64_t fnv1a(const uint8_t* data, size_t n, uint64_t h = 1469598103934665603ull);

}  // namespace vknerf::io
