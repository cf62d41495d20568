// Image files (src/io/image/image_io.*): PNG/JPEG in, PNG out, premultiplied box-filter downscale.
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "support/dataset_files.h"
#include "support/error_message.h"
#include "support/temp_dir.h"

using namespace vknerf;
using namespace vknerf::test;

namespace {
class DatasetImage : public TempDirTest {};
}  // namespace

TEST_F(DatasetImage, PngRoundTripKeepsRgbaExactly) {
  ImageRGBA8 img = patternImage(7, 5, 3, true);
  img.rgba[3] = 17;  // partial alpha survives too
  writePng(dir() / "a.png", img);
  ImageRGBA8 back = vknerf::loadImage((dir() / "a.png").string());
  EXPECT_EQ(back.width, 7u);
  EXPECT_EQ(back.height, 5u);
  EXPECT_EQ(back.rgba, img.rgba);
  uint32_t w = 0, h = 0;
  ASSERT_TRUE(vknerf::readImageSize((dir() / "a.png").string(), w, h));
  EXPECT_EQ(w, 7u);
  EXPECT_EQ(h, 5u);
}

TEST_F(DatasetImage, RgbAndGreyFilesGetOpaqueAlpha) {
  const uint8_t rgb[2 * 2 * 3] = {10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120};
  const uint8_t grey[2 * 2] = {0, 85, 170, 255};
  ASSERT_TRUE(stbi_write_png((dir() / "rgb.png").c_str(), 2, 2, 3, rgb, 6));
  ASSERT_TRUE(stbi_write_png((dir() / "grey.png").c_str(), 2, 2, 1, grey, 2));
  ImageRGBA8 a = vknerf::loadImage((dir() / "rgb.png").string());
  ImageRGBA8 b = vknerf::loadImage((dir() / "grey.png").string());
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(a.rgba[4 * i + c], rgb[3 * i + c]);
      EXPECT_EQ(b.rgba[4 * i + c], grey[i]);
    }
    EXPECT_EQ(a.rgba[4 * i + 3], 255);
    EXPECT_EQ(b.rgba[4 * i + 3], 255);
  }
}

TEST_F(DatasetImage, JpegLoads) {
  // A flat colour survives JPEG's 8x8 DCT almost exactly; 4 levels allow for chroma rounding.
  std::vector<uint8_t> rgb(16 * 16 * 3);
  for (size_t i = 0; i < rgb.size(); i += 3) rgb[i] = 200, rgb[i + 1] = 120, rgb[i + 2] = 40;
  ASSERT_TRUE(stbi_write_jpg((dir() / "a.jpg").c_str(), 16, 16, 3, rgb.data(), 100));
  ImageRGBA8 img = vknerf::loadImage((dir() / "a.jpg").string());
  ASSERT_EQ(img.width, 16u);
  ASSERT_EQ(img.height, 16u);
  for (size_t p = 0; p < 256; ++p) {
    EXPECT_NEAR(img.rgba[4 * p], 200, 4);
    EXPECT_NEAR(img.rgba[4 * p + 1], 120, 4);
    EXPECT_NEAR(img.rgba[4 * p + 2], 40, 4);
    EXPECT_EQ(img.rgba[4 * p + 3], 255);
  }
  uint32_t w = 0, h = 0;
  EXPECT_TRUE(vknerf::readImageSize((dir() / "a.jpg").string(), w, h));
  EXPECT_EQ(w, 16u);
  EXPECT_EQ(h, 16u);
}

TEST_F(DatasetImage, DownscaleWeightsColourByAlpha) {
  // One 2x2 block: opaque red, transparent blue, one-third green, transparent black. Alpha is the
  // mean 340 / 4 = 85; colour is sum(c * a) / sum(a): red 200 * 255 / 340 = 150, green
  // 200 * 85 / 340 = 50, and the transparent blue contributes nothing.
  ImageRGBA8 img{2, 2, {200, 0, 0, 255, 0, 0, 200, 0, 0, 200, 0, 85, 0, 0, 0, 0}};
  ImageRGBA8 out = vknerf::downscaleImage(img, 2);
  ASSERT_EQ(out.width, 1u);
  ASSERT_EQ(out.height, 1u);
  EXPECT_EQ(out.rgba, (std::vector<uint8_t>{150, 50, 0, 85}));
  // A fully transparent block keeps the plain mean of its colours.
  ImageRGBA8 clear{2, 2, {10, 20, 30, 0, 30, 40, 50, 0, 50, 60, 70, 0, 70, 80, 90, 0}};
  EXPECT_EQ(vknerf::downscaleImage(clear, 2).rgba, (std::vector<uint8_t>{40, 50, 60, 0}));
}

TEST_F(DatasetImage, DownscaleMatchesDoubleReference) {
  ImageRGBA8 img{13, 11, std::vector<uint8_t>(13 * 11 * 4)};
  std::srand(7);
  for (auto& v : img.rgba) v = uint8_t(std::rand() % 256);
  for (size_t p = 0; p < 13 * 11; p += 5) img.rgba[4 * p + 3] = 0;  // some fully transparent pixels
  for (uint32_t n : {1u, 2u, 3u, 4u}) {
    ImageRGBA8 out = vknerf::downscaleImage(img, n);
    ASSERT_EQ(out.width, 13u / n);
    ASSERT_EQ(out.height, 11u / n);
    for (uint32_t y = 0; y < out.height; ++y)
      for (uint32_t x = 0; x < out.width; ++x) {
        double wsum[3] = {0, 0, 0}, sum[3] = {0, 0, 0}, a = 0;
        for (uint32_t dy = 0; dy < n; ++dy)
          for (uint32_t dx = 0; dx < n; ++dx) {
            const uint8_t* p = &img.rgba[((y * n + dy) * 13 + x * n + dx) * 4];
            for (int c = 0; c < 3; ++c) wsum[c] += double(p[c]) * p[3], sum[c] += p[c];
            a += p[3];
          }
        const uint8_t* o = &out.rgba[(y * out.width + x) * 4];
        // The output rounds the exact rational mean to the nearest level: within half a level.
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(o[c], a > 0 ? wsum[c] / a : sum[c] / (n * n), 0.5 + 1e-9);
        EXPECT_NEAR(o[3], a / (n * n), 0.5 + 1e-9);
      }
  }
}

TEST_F(DatasetImage, DownscaleRejectsZeroAndTooSmall) {
  ImageRGBA8 img = patternImage(3, 2, 0);
  EXPECT_MESSAGE_HAS(errorOf([&] { vknerf::downscaleImage(img, 0); }), "at least 1");
  EXPECT_MESSAGE_HAS(errorOf([&] { vknerf::downscaleImage(img, 3); }), "3x2");
}

TEST_F(DatasetImage, UnreadableFilesNameThePath) {
  std::string missing = (dir() / "nope.png").string();
  EXPECT_MESSAGE_HAS(errorOf([&] { vknerf::loadImage(missing); }), missing);
  writeText(dir() / "junk.png", "this is not a PNG file at all");
  std::string junk = (dir() / "junk.png").string();
  EXPECT_MESSAGE_HAS(errorOf([&] { vknerf::loadImage(junk); }), junk);
  uint32_t w, h;
  EXPECT_FALSE(vknerf::readImageSize(junk, w, h));
  EXPECT_MESSAGE_HAS(errorOf([&] { vknerf::savePng((dir() / "no" / "such" / "dir.png").string(), patternImage(2, 2, 0)); }),
                     "dir.png");
}

TEST_F(DatasetImage, DecodeFromMemoryMatchesTheFile) {
  ImageRGBA8 img = patternImage(6, 4, 2, true);
  const auto png = vknerf::encodePng(img.width, img.height, 4, img.rgba.data());
  ImageRGBA8 back = vknerf::decodeImage(png.data(), png.size(), "in memory");
  EXPECT_EQ(back.width, 6u);
  EXPECT_EQ(back.height, 4u);
  EXPECT_EQ(back.rgba, img.rgba);
  const std::string junk = "this is not a PNG file at all";
  EXPECT_MESSAGE_HAS(errorOf([&] { vknerf::decodeImage(reinterpret_cast<const uint8_t*>(junk.data()), junk.size(), "junk"); }),
                     "'junk'");
}

namespace {

std::vector<uint8_t> flatJpeg() {
  std::vector<uint8_t> rgb(16 * 16 * 3, 128);
  std::vector<uint8_t> jpeg;
  stbi_write_jpg_to_func(
      [](void* out, void* data, int size) {
        auto* v = static_cast<std::vector<uint8_t>*>(out);
        v->insert(v->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
      },
      &jpeg, 16, 16, 3, rgb.data(), 90);
  return jpeg;
}

// Offset of the first marker 0xFF `code` after the SOI, 0 when there is none.
size_t markerAt(const std::vector<uint8_t>& jpeg, uint8_t code) {
  for (size_t i = 2; i + 1 < jpeg.size(); ++i)
    if (jpeg[i] == 0xFF && jpeg[i + 1] == code) return i;
  return 0;
}

// A corrupt JPEG is one clear error naming the file, from the decoder and the loader alike.
void expectRefused(const std::vector<uint8_t>& jpeg, const std::filesystem::path& path) {
  EXPECT_MESSAGE_HAS(errorOf([&] { vknerf::decodeImage(jpeg.data(), jpeg.size(), "bad.jpg"); }),
                     "cannot read image 'bad.jpg': ");
  writeText(path, std::string(jpeg.begin(), jpeg.end()));
  EXPECT_MESSAGE_HAS(errorOf([&] { vknerf::loadImage(path.string()); }), path.string());
}

}  // namespace

// stb_image 2.27 writes past its Huffman arrays for a table of more than 256 codes, and reads past
// them when a scan names a table no DHT defined (both found by fuzz/image_fuzzer.cpp); JPEG now
// decodes through libjpeg-turbo, which refuses both.
TEST_F(DatasetImage, JpegHuffmanTableOfTooManyCodesIsRefused) {
  auto jpeg = flatJpeg();
  size_t dht = markerAt(jpeg, 0xC4);
  ASSERT_NE(dht, 0u);
  for (size_t i = 0; i < 16; ++i) jpeg[dht + 5 + i] = 17;  // 16 * 17 = 272 codes
  expectRefused(jpeg, dir() / "bad.jpg");
  uint32_t w, h;
  EXPECT_FALSE(vknerf::readImageSize((dir() / "bad.jpg").string(), w, h));
}

TEST_F(DatasetImage, JpegScanNamingAnUndefinedHuffmanTableIsRefused) {
  auto jpeg = flatJpeg();
  size_t sos = markerAt(jpeg, 0xDA);
  ASSERT_NE(sos, 0u);
  ASSERT_EQ(jpeg[sos + 4], 3);  // components in the scan; each is (id, DC table << 4 | AC table)
  jpeg[sos + 6] = 0x33;         // tables 3: stb_image's encoder defines only 0 and 1
  expectRefused(jpeg, dir() / "bad.jpg");
}

TEST_F(DatasetImage, TruncatedJpegIsRefusedNotDecodedAsGrey) {
  const auto whole = flatJpeg();
  const size_t sos = markerAt(whole, 0xDA);
  ASSERT_NE(sos, 0u);
  // Every cut from inside the headers to just before the end-of-image marker.
  for (size_t cut = 3; cut + 2 < whole.size(); ++cut) {
    std::vector<uint8_t> jpeg(whole.begin(), whole.begin() + cut);
    EXPECT_MESSAGE_HAS(errorOf([&] { vknerf::decodeImage(jpeg.data(), jpeg.size(), "cut.jpg"); }),
                       "cannot read image 'cut.jpg': ")
        << "cut at " << cut << " of " << whole.size();
  }
}

// An empty IDAT chunk ahead of the image data is valid PNG; stb_image 2.27 copies it with
// memcpy(NULL, p, 0) (found by fuzz/image_fuzzer.cpp, see src/io/image/stb_implementation.cpp).
TEST_F(DatasetImage, PngWithAnEmptyDataChunkLoads) {
  ImageRGBA8 img = patternImage(5, 3, 1);
  auto png = vknerf::encodePng(img.width, img.height, 4, img.rgba.data());
  const uint8_t idat[4] = {'I', 'D', 'A', 'T'};
  auto at = std::search(png.begin(), png.end(), idat, idat + 4);
  ASSERT_NE(at, png.end());
  const uint8_t empty[12] = {0, 0, 0, 0, 'I', 'D', 'A', 'T', 0x35, 0xAF, 0x06, 0x1E};  // length 0, type, CRC
  png.insert(at - 4, empty, empty + 12);
  ImageRGBA8 back = vknerf::decodeImage(png.data(), png.size(), "empty chunk");
  EXPECT_EQ(back.rgba, img.rgba);
}

// A chunk claiming more bytes than the file holds: stb_image 2.27 allocates for the claim before
// reading (a 10 KB file claimed 1 GiB and stb asked for 2 GiB; found by fuzz/image_fuzzer.cpp).
TEST_F(DatasetImage, PngChunkLongerThanTheFileIsRefusedBeforeDecoding) {
  ImageRGBA8 img = patternImage(5, 3, 1);
  auto png = vknerf::encodePng(img.width, img.height, 4, img.rgba.data());
  const uint8_t idat[4] = {'I', 'D', 'A', 'T'};
  auto at = std::search(png.begin(), png.end(), idat, idat + 4);
  ASSERT_NE(at, png.end());
  const uint8_t huge[4] = {0x40, 0x00, 0x06, 0x5a};  // 1073743450 bytes, as the fuzzer's file claimed
  std::copy(huge, huge + 4, at - 4);
  EXPECT_MESSAGE_HAS(errorOf([&] { vknerf::decodeImage(png.data(), png.size(), "huge chunk"); }),
                     "cannot read image 'huge chunk': corrupt PNG (a chunk claims more bytes than the file holds)");
}

// Bytes with no PNG or JPEG signature that stb_image 2.27 takes for a TGA whose header claims a huge
// image, then decodes for seconds (a fuzzer timeout): only PNG and JPEG reach stb.
TEST_F(DatasetImage, BytesThatAreNeitherPngNorJpegAreRefused) {
  const uint8_t tgaLike[] = {0xff, 0x00, 0x0b, 0x8b, 0xf8, 0xe5, 0x9c, 0x62, 0x57, 0xff, 0xff, 0xff, 0x00, 0x08,
                             0xff, 0xff, 0x0f, 0x08, 0x00, 0x00, 0x00, 0x2d, 0x00, 0x00, 0x00, 0xff, 0xff};
  EXPECT_MESSAGE_HAS(errorOf([&] { vknerf::decodeImage(tgaLike, sizeof tgaLike, "tga-like"); }), "not a PNG or JPEG");
}
