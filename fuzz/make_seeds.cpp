// Writes the fuzzers' seed corpus from the sample scene: make_seeds <assets/tabletop> <corpus folder>
// gives <corpus>/{transforms,colmap,colmap_binary,llff,checkpoint,image}/, one folder per fuzzer.
#include <stb/stb_image_write.h>  // declarations only: libvknerf holds the implementation

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/checkpoint/checkpoint.h"
#include "io/checkpoint/config_json.h"
#include "vknerf/image_io.h"
#include "scratch_folder.h"
#include "support/colmap_model_files.h"
#include "support/llff_files.h"
#include "vknerf/error.h"

namespace fs = std::filesystem;
using nlohmann::json;
using vknerf::fuzz::writeBytes;

namespace {

std::string readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw vknerf::Error("cannot open '" + p.string() + "'");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeText(const fs::path& p, const std::string& text) {
  writeBytes(p, reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

// The scene's transforms files cut to their first three frames (the images the fuzzer provides),
// as they are, without the box (so that the cameras and alpha masks place it) and with explicit
// intrinsics.
void transformsSeeds(const fs::path& scene, const fs::path& out) {
  for (const char* split : {"train", "test"}) {
    json j = json::parse(readText(scene / (std::string("transforms_") + split + ".json")));
    j["frames"].erase(j["frames"].begin() + 3, j["frames"].end());
    writeText(out / (std::string(split) + ".json"), j.dump(2));
    json noBox = j;
    noBox.erase("aabb");
    writeText(out / (std::string(split) + "_no_box.json"), noBox.dump(2));
    json intrinsics = j;
    intrinsics.erase("camera_angle_x");
    intrinsics.update({{"fl_x", 9.5}, {"fl_y", 9.5}, {"cx", 4.0}, {"cy", 3.0}, {"w", 8}, {"h", 6},
                       {"camera_model", "OPENCV"}, {"k1", 0}, {"aabb_scale", 4}, {"offset", {0.5, 0.5, 0.5}}});
    intrinsics.erase("aabb");
    writeText(out / (std::string(split) + "_intrinsics.json"), intrinsics.dump(2));
  }
}

// COLMAP text models of three cameras around the origin, the files separated by NUL bytes as the
// fuzzer splits them.
void colmapSeeds(const fs::path& out) {
  const std::string cameras =
      "# Camera list with one line of data per camera:\n"
      "1 PINHOLE 8 6 9.5 9.5 4 3\n"
      "2 SIMPLE_RADIAL 8 6 9.5 4 3 0\n";
  const std::string images =
      "# Image list with two lines of data per image:\n"
      "1 1 0 0 0 0 0 4 1 a.png\n"
      "10 12 1 20 30 -1\n"
      "2 0.70710678 0 0.70710678 0 0 0 4 2 b.png\n"
      "\n"
      "3 0 1 0 0 0 0 4 1 c.png\n"
      "\n";
  const std::string points =
      "# 3D point list with one line of data per point:\n"
      "1 0.5 0.2 0.1 255 0 0 0.5 1 0\n"
      "2 -0.5 -0.2 0.3 0 255 0 0.5\n"
      "3 0.1 0.4 -0.6 0 0 255 0.5 2 1 3 0\n";
  const std::string nul(1, '\0');
  writeText(out / "model.txt", cameras + nul + images + nul + points);
  writeText(out / "no_points.txt", cameras + nul + images);
}

// The model of colmapSeeds in COLMAP's binary form, the files joined by the fuzzer's marker; and
// one whose cameras are of the other models vknerf reads.
void colmapBinarySeeds(const fs::path& out) {
  using namespace vknerf::test;
  ColmapModelRecords m;
  m.cameras = {{1, "PINHOLE", 8, 6, {9.5, 9.5, 4, 3}}, {2, "SIMPLE_RADIAL", 8, 6, {9.5, 4, 3, 0}}};
  const double h = 0.70710678118654752;
  m.images = {{1, {1, 0, 0, 0}, {0, 0, 4}, 1, "a.png", {{10, 12, 1}, {20, 30, -1}}},
              {2, {h, 0, h, 0}, {0, 0, 4}, 2, "b.png", {}},
              {3, {0, 1, 0, 0}, {0, 0, 4}, 1, "c.png", {}}};
  m.points = {{1, {0.5, 0.2, 0.1}, {255, 0, 0}, 0.5, {{1, 0}}},
              {2, {-0.5, -0.2, 0.3}, {0, 255, 0}, 0.5, {}},
              {3, {0.1, 0.4, -0.6}, {0, 0, 255}, 0.5, {{2, 1}, {3, 0}}}};
  ColmapModelRecords others = m;
  others.cameras = {{1, "SIMPLE_PINHOLE", 8, 6, {9.5, 4, 3}}, {2, "OPENCV", 8, 6, {9.5, 9.5, 4, 3, 0, 0, 0, 0}},
                    {3, "RADIAL", 8, 6, {9.5, 4, 3, 0, 0}}, {4, "FULL_OPENCV", 8, 6, {9.5, 9.5, 4, 3, 0, 0, 0, 0, 0, 0, 0, 0}}};
  others.images[2].camera = 4;
  const fs::path tmp = out / "tmp";
  auto joined = [&](const ColmapModelRecords& model, bool withPoints) {
    fs::remove_all(tmp);
    writeColmapBinary(tmp, model);
    std::string all = readText(tmp / "cameras.bin") + "%%%%" + readText(tmp / "images.bin");
    if (withPoints) all += "%%%%" + readText(tmp / "points3D.bin");
    return all;
  };
  writeText(out / "model.bin", joined(m, true));
  writeText(out / "no_points.bin", joined(m, false));
  writeText(out / "other_models.bin", joined(others, true));
  fs::remove_all(tmp);
}

// poses_bounds.npy files of three cameras around the origin (the fuzzer's three images at 8x6): as
// np.save writes float64, and as float32 in format 2.0, and in Fortran order.
void llffSeeds(const fs::path& out) {
  using namespace vknerf::test;
  const std::array<double, 16> poses[] = {{0, 0, 1, 4, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1},
                                          {-1, 0, 0, 0, 0, 0, 1, 4, 0, 1, 0, 0, 0, 0, 0, 1},
                                          {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 4, 0, 0, 0, 1}};
  std::vector<std::array<double, 17>> rows;
  for (const auto& c2w : poses) rows.push_back(llffRow(c2w, 6, 8, 9.5, 1, 6));
  writeText(out / "f8.npy", poseBoundsBytes(rows));
  writeText(out / "f4_v2.npy", poseBoundsBytes(rows, {true, 2, false}));
  writeText(out / "fortran.npy", poseBoundsBytes(rows, {false, 1, true}));
}

// Hand-built checkpoints of both models, laid out as Trainer::save writes them, with small sections.
void checkpointSeeds(const fs::path& out) {
  vknerf::TrainConfig vanilla, fast;
  fast.model = vknerf::FastModel{};
  fs::create_directories(out);
  for (const auto& [name, config] : {std::pair{"vanilla", vanilla}, std::pair{"fast", fast}}) {
    vknerf::io::Checkpoint ck;
    json j = {{"format", "vknerf"}, {"config", vknerf::io::toJson(config)}, {"step", 3},
              {"bounds", {{"min", {-1, -1, -1}}, {"max", {1, 1, 1}}}},
              {"scene", {{"cameras", 3}, {"width", 8}, {"height", 6}}}};
    ck.config = j.dump(2);
    ck.put("params", std::vector<float>{0.5f, -1.0f, 2.0f, 0.0f});
    ck.put("adam_m", std::vector<float>{0.0f, 0.0f});
    ck.save((out / (std::string(name) + ".vknerf")).string());
  }
}

void appendBytes(void* context, void* data, int size) {
  auto* v = static_cast<std::vector<uint8_t>*>(context);
  v->insert(v->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
}

// A scene image as it is, and small PNGs (grey, grey+alpha, RGB, RGBA) and a JPEG cut from it.
void imageSeeds(const fs::path& scene, const fs::path& out) {
  const std::string png = readText(scene / "train" / "r_0.png");
  writeText(out / "scene.png", png);
  const vknerf::ImageRGBA8 full = vknerf::decodeImage(reinterpret_cast<const uint8_t*>(png.data()), png.size(), "r_0.png");
  const vknerf::ImageRGBA8 small = vknerf::downscaleImage(full, 12);
  for (int channels = 1; channels <= 4; ++channels) {
    std::vector<uint8_t> pixels;
    for (size_t p = 0; p < size_t(small.width) * small.height; ++p)
      for (int c = 0; c < channels; ++c) pixels.push_back(small.rgba[p * 4 + (channels == 2 && c == 1 ? 3 : c)]);
    auto bytes = vknerf::encodePng(small.width, small.height, channels, pixels.data());
    writeBytes(out / ("small_" + std::to_string(channels) + ".png"), bytes.data(), bytes.size());
  }
  std::vector<uint8_t> jpeg;
  if (!stbi_write_jpg_to_func(appendBytes, &jpeg, int(small.width), int(small.height), 4, small.rgba.data(), 90))
    throw vknerf::Error("cannot encode the JPEG seed");
  writeBytes(out / "small.jpg", jpeg.data(), jpeg.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s <assets/tabletop> <corpus folder>\n", argv[0]);
    return 2;
  }
  try {
    const fs::path scene = argv[1], out = argv[2];
    transformsSeeds(scene, out / "transforms");
    colmapSeeds(out / "colmap");
    colmapBinarySeeds(out / "colmap_binary");
    llffSeeds(out / "llff");
    checkpointSeeds(out / "checkpoint");
    imageSeeds(scene, out / "image");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
