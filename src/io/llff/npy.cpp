// The .npy format (numpy/lib/format.py): the magic "\x93NUMPY", a major and a minor version byte, the
// header's length (2 bytes little-endian in 1.0, 4 in 2.0), the header, then the raw values. The
// header is a Python dict literal such as
//   {'descr': '<f8', 'fortran_order': False, 'shape': (20, 17), }
// padded with spaces and ended by a newline. It is parsed by hand, as strictly as numpy writes it:
// the three keys once each, nothing else.
#include "io/llff/npy.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>

#include "vknerf/error.h"

namespace vknerf::io::detail {
namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr size_t kMagicSize = 6;
// numpy itself refuses headers over 10000 bytes unless told otherwise; one of a 2-D float array
// is under 128.
constexpr size_t kMaxHeader = 1 << 16;

struct Header {
  std::vector<uint64_t> shape;
  std::string descr;
  bool fortran = false;
  size_t dataOffset = 0;  // bytes before the first value
  size_t itemSize = 0;
  uint64_t count = 1;  // values, the product of the shape
};

[[noreturn]] void fail(const std::string& name, const std::string& what) { throw Error(name + ": " + what); }

// A cursor over the header text.
class HeaderText {
 public:
  HeaderText(std::string_view text, const std::string& name) : s_(text), name_(name) {}

  void skipSpace() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
  }
  bool take(char c) {
    skipSpace();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void expect(char c, const std::string& context) {
    if (!take(c)) bad(std::string("expected '") + c + "' " + context);
  }
  // A quoted string without escapes ('...' or "...").
  std::string string(const std::string& context) {
    skipSpace();
    if (i_ >= s_.size() || (s_[i_] != '\'' && s_[i_] != '"')) bad("expected a quoted string " + context);
    const char quote = s_[i_++];
    const size_t end = s_.find(quote, i_);
    if (end == std::string_view::npos) bad("unterminated string " + context);
    std::string out(s_.substr(i_, end - i_));
    if (out.find('\\') != std::string::npos) bad("escaped characters in a string " + context);
    i_ = end + 1;
    return out;
  }
  bool boolean(const std::string& field) {
    skipSpace();
    for (const auto& [word, value] : {std::pair{std::string_view("True"), true}, {std::string_view("False"), false}})
      if (s_.substr(i_, word.size()) == word) {
        i_ += word.size();
        return value;
      }
    fieldError(field, "must be True or False");
  }
  // A tuple of non-negative integers: (), (3,), (20, 17) with an optional trailing comma.
  std::vector<uint64_t> tuple(const std::string& field) {
    if (!take('(')) fieldError(field, "must be a tuple of whole numbers such as (20, 17)");
    std::vector<uint64_t> out;
    while (!take(')')) {
      skipSpace();
      uint64_t v = 0;
      size_t digits = 0;
      for (; i_ < s_.size() && s_[i_] >= '0' && s_[i_] <= '9'; ++i_, ++digits) {
        // 2^40 values are more than any file here holds; the bound keeps the product in 64 bits.
        v = v * 10 + uint64_t(s_[i_] - '0');
        if (v > (uint64_t(1) << 40)) fieldError(field, "has a dimension beyond 2^40");
      }
      if (digits == 0) fieldError(field, "must be a tuple of whole numbers such as (20, 17)");
      if (out.size() == 32) fieldError(field, "has more than 32 dimensions");
      out.push_back(v);
      if (!take(',')) {
        if (!take(')')) fieldError(field, "must be a tuple of whole numbers such as (20, 17)");
        break;
      }
    }
    return out;
  }
  bool atEnd() {
    skipSpace();
    return i_ == s_.size();
  }
  [[noreturn]] void fieldError(const std::string& field, const std::string& what) {
    fail(name_, ".npy header field '" + field + "' " + what);
  }
  [[noreturn]] void bad(const std::string& what) { fail(name_, ".npy header is not the dict numpy writes: " + what); }

 private:
  std::string_view s_;
  const std::string& name_;
  size_t i_ = 0;
};

// Parses the magic, version and header dict from the start of a file; `bytes` must reach at least
// to the end of the header (the whole file, or its first kMaxHeader + 12 bytes).
Header parseHeader(std::span<const uint8_t> bytes, const std::string& name) {
  if (bytes.size() < kMagicSize + 2 || std::memcmp(bytes.data(), kMagic, kMagicSize) != 0)
    fail(name, "not a .npy file (it does not begin with \\x93NUMPY)");
  const uint8_t major = bytes[kMagicSize], minor = bytes[kMagicSize + 1];
  if ((major != 1 && major != 2) || minor != 0)
    fail(name, ".npy format version " + std::to_string(major) + "." + std::to_string(minor) + " is not read (1.0 or 2.0)");
  const size_t lengthBytes = major == 1 ? 2 : 4, start = kMagicSize + 2 + lengthBytes;
  if (bytes.size() < start) fail(name, ".npy header is truncated");
  size_t length = 0;
  for (size_t k = 0; k < lengthBytes; ++k) length |= size_t(bytes[kMagicSize + 2 + k]) << (8 * k);
  if (length > kMaxHeader) fail(name, ".npy header length " + std::to_string(length) + " is beyond 65536 bytes");
  if (bytes.size() < start + length) fail(name, ".npy header is truncated (it states " + std::to_string(length) + " bytes)");
  std::string_view text(reinterpret_cast<const char*>(bytes.data()) + start, length);
  for (char c : text)
    if (c < 0x20 && c != '\n' && c != '\t' && c != '\r') fail(name, ".npy header holds a control character");

  HeaderText h(text, name);
  Header out;
  out.dataOffset = start + length;
  std::optional<std::string> descr;
  std::optional<bool> fortran;
  std::optional<std::vector<uint64_t>> shape;
  h.expect('{', "at the start");
  while (!h.take('}')) {
    const std::string key = h.string("as a key");
    h.expect(':', "after '" + key + "'");
    if (key == "descr" && !descr)
      descr = h.string("for 'descr'");
    else if (key == "fortran_order" && !fortran)
      fortran = h.boolean(key);
    else if (key == "shape" && !shape)
      shape = h.tuple(key);
    else if (key == "descr" || key == "fortran_order" || key == "shape")
      h.fieldError(key, "is given twice");
    else
      h.bad("unexpected key '" + key + "' (descr, fortran_order, shape)");
    if (!h.take(',')) {
      h.expect('}', "after the value of '" + key + "'");
      break;
    }
  }
  if (!h.atEnd()) h.bad("text after the closing '}'");
  if (!descr) h.fieldError("descr", "is missing");
  if (!fortran) h.fieldError("fortran_order", "is missing");
  if (!shape) h.fieldError("shape", "is missing");

  if (*descr == "<f8")
    out.itemSize = 8;
  else if (*descr == "<f4")
    out.itemSize = 4;
  else if (*descr == ">f8" || *descr == ">f4")
    h.fieldError("descr", "is '" + *descr + "': big-endian values are not read (save as '<f8' or '<f4')");
  else
    h.fieldError("descr", "is '" + *descr + "': the values must be float64 ('<f8') or float32 ('<f4')");
  out.descr = *descr;
  out.fortran = *fortran;
  out.shape = *shape;
  if (out.fortran && out.shape.size() > 2)
    h.fieldError("fortran_order", "is True for " + std::to_string(out.shape.size()) + " dimensions (read for at most 2)");
  for (uint64_t d : out.shape) {
    // Each dimension is below 2^40; the product is checked against 2^40 before it can overflow.
    if (d != 0 && out.count > (uint64_t(1) << 40) / d) h.fieldError("shape", "holds more than 2^40 values");
    out.count *= d;
  }
  return out;
}

std::string shapeText(const std::vector<uint64_t>& shape) {
  std::string s = "(";
  for (size_t k = 0; k < shape.size(); ++k) s += (k ? ", " : "") + std::to_string(shape[k]);
  return s + (shape.size() == 1 ? ",)" : ")");
}

void checkDataSize(const Header& h, uint64_t fileSize, const std::string& name) {
  const uint64_t want = h.dataOffset + h.count * h.itemSize;
  if (fileSize != want)
    fail(name, "the data holds " + std::to_string(fileSize - h.dataOffset) + " bytes where shape " + shapeText(h.shape) +
                   " of '" + h.descr + "' takes " + std::to_string(h.count * h.itemSize) +
                   (fileSize < want ? " (the file is truncated)" : " (the file has bytes after its data)"));
}

}  // namespace

NpyArray parseNpy(std::span<const uint8_t> bytes, const std::string& name) {
  const Header h = parseHeader(bytes, name);
  checkDataSize(h, bytes.size(), name);
  NpyArray out;
  out.shape = h.shape;
  out.descr = h.descr;
  out.values.resize(h.count);
  const uint8_t* data = bytes.data() + h.dataOffset;
  // Fortran order of an r x c array is the C order of its c x r transpose.
  const uint64_t rows = h.shape.size() == 2 ? h.shape[0] : 1, cols = h.shape.size() == 2 ? h.shape[1] : h.count;
  for (uint64_t k = 0; k < h.count; ++k) {
    uint64_t bits = 0;
    for (size_t b = 0; b < h.itemSize; ++b) bits |= uint64_t(data[k * h.itemSize + b]) << (8 * b);
    const double v = h.itemSize == 8 ? std::bit_cast<double>(bits) : double(std::bit_cast<float>(uint32_t(bits)));
    const uint64_t at = h.fortran && h.shape.size() == 2 ? (k % rows) * cols + k / rows : k;
    out.values[at] = v;
  }
  return out;
}

NpyArray readNpy(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(name, "cannot be opened");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) fail(name, "cannot be read");
  in.seekg(0);
  // The header first, so that a shape the file cannot hold is refused before anything is allocated.
  std::vector<uint8_t> bytes(std::min<uint64_t>(uint64_t(size), kMaxHeader + 12));
  if (!in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()))) fail(name, "cannot be read");
  checkDataSize(parseHeader(bytes, name), uint64_t(size), name);
  bytes.resize(size_t(size));
  const size_t done = std::min<size_t>(size_t(size), kMaxHeader + 12);
  if (!in.read(reinterpret_cast<char*>(bytes.data()) + done, std::streamsize(bytes.size() - done))) fail(name, "cannot be read");
  return parseNpy(bytes, name);
}

}  // namespace vknerf::io::detail
