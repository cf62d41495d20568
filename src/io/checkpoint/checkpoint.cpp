#include "io/checkpoint/checkpoint.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "vknerf/error.h"
#include "vknerf/file_output.h"

namespace vknerf::io {
namespace {

constexpr char kMagic[8] = {'V', 'K', 'N', 'E', 'R', 'F', 'C', 'K'};

template <class T> void append(std::vector<uint8_t>& out, T v) {
  auto* p = reinterpret_cast<const uint8_t*>(&v);
  out.insert(out.end(), p, p + sizeof(T));
}

// Reads the bytes [0, size) of `data` in order; never past `size`.
struct Reader {
  const uint8_t* data;
  size_t size;
  const std::string& path;
  size_t pos = 0;
  void need(size_t n, const char* what) {
    if (size - pos < n) throw Error(path + ": truncated checkpoint (reading " + what + ")");
  }
  template <class T> T read(const char* what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, data + pos, sizeof(T));
    pos += sizeof(T);
    return v;
  }
  std::string readString(size_t n, const char* what) {
    need(n, what);
    std::string s(reinterpret_cast<const char*>(data + pos), n);
    pos += n;
    return s;
  }
};

}  // namespace

bool Checkpoint::startsWithMagic(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in.gcount() == 8 && std::memcmp(magic, kMagic, 8) == 0;
}

uint64_t fnv1a(const uint8_t* data, size_t n, uint64_t h) {
  for (size_t i = 0; i < n; ++i) h = (h ^ data[i]) * 1099511628211ull;
  return h;
}

void Checkpoint::save(const std::string& target) const {
  std::vector<uint8_t> out(kMagic, kMagic + 8);
  append(out, kVersion);
  append(out, uint32_t(config.size()));
  out.insert(out.end(), config.begin(), config.end());
  append(out, uint32_t(sections.size()));
  for (const auto& [name, data] : sections) {
    append(out, uint32_t(name.size()));
    out.insert(out.end(), name.begin(), name.end());
    append(out, uint64_t(data.size()));
    out.insert(out.end(), data.begin(), data.end());
  }
  append(out, fnv1a(out.data(), out.size()));

  writeFileAtomically(target, out.data(), out.size());
}

Checkpoint Checkpoint::load(const std::string& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw Error(file + ": is a folder, not a checkpoint");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(file + ": cannot open checkpoint: " + std::strerror(errno));
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return parse(bytes.data(), bytes.size(), file);
}

Checkpoint Checkpoint::parse(const uint8_t* data, size_t size, const std::string& file) {
  if (size < 8 || std::memcmp(data, kMagic, 8) != 0) throw Error(file + ": not a vknerf checkpoint (bad magic)");
  if (size < 8 + 4 + 8) throw Error(file + ": truncated checkpoint");
  Reader r{data, size, file, 8};
  uint32_t version = r.read<uint32_t>("version");
  if (version != kVersion)
    throw Error(file + ": checkpoint version " + std::to_string(version) + " is not supported (expected " +
                std::to_string(kVersion) + ")");
  uint64_t stored;
  std::memcpy(&stored, data + size - 8, 8);
  if (fnv1a(data, size - 8) != stored) throw Error(file + ": checkpoint is corrupt (checksum mismatch)");
  const size_t end = size - 8;
  Reader b{data, end, file, r.pos};  // the body: everything before the checksum
  Checkpoint ck;
  ck.path = file;
  ck.config = b.readString(b.read<uint32_t>("config size"), "config");
  uint32_t count = b.read<uint32_t>("section count");
  for (uint32_t i = 0; i < count; ++i) {
    std::string name = b.readString(b.read<uint32_t>("section name size"), "section name");
    uint64_t n = b.read<uint64_t>("section size");
    b.need(n, "section data");
    ck.sections[name].assign(data + b.pos, data + b.pos + n);
    b.pos += n;
  }
  if (b.pos != end) throw Error(file + ": checkpoint has trailing bytes");
  return ck;
}

const std::vector<uint8_t>& Checkpoint::section(const std::string& name, size_t expectedBytes, size_t elementBytes) const {
  auto it = sections.find(name);
  if (it == sections.end()) throw Error(path + ": checkpoint has no section '" + name + "'");
  if ((expectedBytes != SIZE_MAX && it->second.size() != expectedBytes) || it->second.size() % elementBytes)
    throw Error(path + ": checkpoint section '" + name + "' has " + std::to_string(it->second.size()) +
                " bytes, expected " + std::to_string(expectedBytes));
  return it->second;
}

}  // namespace vknerf::io
