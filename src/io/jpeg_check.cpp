#include "io/jpeg_check.h"

namespace vknerf::nerf {

namespace {

bool standalone(uint8_t marker) {  // markers without a length: TEM, RSTn, SOI, EOI
  return marker == 0x01 || (marker >= 0xD0 && marker <= 0xD9);
}

// The tables of the DHT segment whose body (after the length) starts at `pos`, read as stb reads
// them: while the segment's length is not used up, a class/id byte, 16 code counts and the values,
// reading on past the segment's end when a table runs over it and zeros past the end of the file.
bool dhtFits(const uint8_t* data, size_t size, size_t pos, long length) {
  while (length > 0) {
    int codes = 0;
    for (size_t i = 1; i <= 16; ++i) codes += pos + i < size ? data[pos + i] : 0;
    if (codes > 256) return false;
    pos += 17 + size_t(codes);
    length -= 17 + codes;
  }
  return true;
}

}  // namespace

bool jpegHuffmanTablesFit(const uint8_t* data, size_t size) {
  if (size < 2 || data[0] != 0xFF || data[1] != 0xD8) return true;
  size_t pos = 2;
  bool inScan = false;  // after SOS: entropy-coded bytes, where FF 00 and FF D0..D7 are not segments
  while (pos + 1 < size) {
    if (data[pos] != 0xFF) {
      ++pos;
      continue;
    }
    const uint8_t marker = data[pos + 1];
    if (marker == 0xFF) {  // fill byte
      ++pos;
      continue;
    }
    if (inScan && (marker == 0x00 || (marker >= 0xD0 && marker <= 0xD7))) {
      pos += 2;
      continue;
    }
    if (marker == 0xD9) return true;  // EOI
    pos += 2;
    if (standalone(marker)) continue;
    if (pos + 2 > size) return true;
    const size_t length = size_t(data[pos]) << 8 | data[pos + 1];  // includes its own two bytes
    if (length < 2) return true;                                    // stb rejects it
    if (marker == 0xC4 && !dhtFits(data, size, pos + 2, long(length) - 2)) return false;
    inScan = marker == 0xDA;
    pos += length;
  }
  return true;
}

}  // namespace vknerf::nerf
