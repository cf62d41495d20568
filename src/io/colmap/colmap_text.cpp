// COLMAP text model: cameras.txt, images.txt and (optionally) points3D.txt, parsed into a
// ColmapModel (colmap_scene.cpp gives it its meaning).
#include <charconv>
#include <fstream>
#include <sstream>

#include "io/colmap/colmap_model.h"
#include "vknerf/error.h"

namespace vknerf::io::detail {
namespace {

struct Line {
  size_t number = 0;
  std::string text;
};

std::vector<Line> readLines(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open '" + path.string() + "'");
  std::vector<Line> lines;
  std::string s;
  for (size_t n = 1; std::getline(in, s); ++n) {
    if (!s.empty() && s.back() == '\r') s.pop_back();
    lines.push_back({n, s});
  }
  return lines;
}

bool skippable(const std::string& s) {
  size_t i = s.find_first_not_of(" \t");
  return i == std::string::npos || s[i] == '#';
}

std::vector<std::string> tokens(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

// The rest of `s` after its first `count` whitespace-separated tokens, trailing blanks removed.
std::string afterTokens(const std::string& s, int count) {
  size_t i = 0;
  for (int k = 0; k < count; ++k) {
    i = s.find_first_not_of(" \t", i);
    i = s.find_first_of(" \t", i);
  }
  i = s.find_first_not_of(" \t", i);
  std::string rest = i == std::string::npos ? "" : s.substr(i);
  while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\t')) rest.pop_back();
  return rest;
}

struct LineError {
  std::string at;  // "path:line"
  [[noreturn]] void operator()(const std::string& what) const { throw Error(at + ": " + what); }
};

LineError at(const fs::path& path, const Line& line) { return {path.string() + ":" + std::to_string(line.number)}; }

double toDouble(const std::string& s, const LineError& fail, const char* what) {
  double v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v))
    fail(std::string(what) + " is not a finite number: '" + s + "'");
  return v;
}

uint64_t toUint(const std::string& s, const LineError& fail, const char* what) {
  uint64_t v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) fail(std::string(what) + " is not a whole number: '" + s + "'");
  return v;
}

void readCameras(const fs::path& path, ColmapModel& model) {
  for (const Line& line : readLines(path)) {
    if (skippable(line.text)) continue;
    LineError fail = at(path, line);
    auto t = tokens(line.text);
    if (t.size() < 4) fail("expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
    ColmapCamera c;
    c.where = fail.at;
    uint64_t id = toUint(t[0], fail, "CAMERA_ID");
    c.model = colmapModelByName(t[1]);
    if (!c.model) fail("camera model " + t[1] + " is not a COLMAP camera model");
    c.width = toUint(t[2], fail, "WIDTH");
    c.height = toUint(t[3], fail, "HEIGHT");
    for (size_t i = 4; i < t.size(); ++i) c.params.push_back(toDouble(t[i], fail, "camera parameter"));
    model.addCamera(id, std::move(c));
  }
}

void readImages(const fs::path& path, ColmapModel& model) {
  auto lines = readLines(path);
  for (size_t i = 0; i < lines.size(); ++i) {
    if (skippable(lines[i].text)) continue;
    LineError fail = at(path, lines[i]);
    auto t = tokens(lines[i].text);
    if (t.size() < 10) fail("expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    toUint(t[0], fail, "IMAGE_ID");
    ColmapImage img;
    img.where = fail.at;
    for (int k = 0; k < 4; ++k) img.q[k] = toDouble(t[1 + k], fail, "quaternion component");
    for (int k = 0; k < 3; ++k) img.t[k] = toDouble(t[5 + k], fail, "translation component");
    img.cameraId = toUint(t[8], fail, "CAMERA_ID");
    // The name is the rest of the line: file names may hold spaces.
    img.name = afterTokens(lines[i].text, 9);
    model.images.push_back(std::move(img));
    // The POINTS2D line follows (possibly empty); it must hold (X, Y, POINT3D_ID) triples.
    if (++i < lines.size() && tokens(lines[i].text).size() % 3 != 0)
      at(path, lines[i])("expected the POINTS2D line (X Y POINT3D_ID triples) after the image line");
  }
}

void readPoints(const fs::path& path, ColmapModel& model) {
  for (const Line& line : readLines(path)) {
    if (skippable(line.text)) continue;
    LineError fail = at(path, line);
    auto t = tokens(line.text);
    if (t.size() < 8 || (t.size() - 8) % 2 != 0) fail("expected POINT3D_ID X Y Z R G B ERROR TRACK[] (IMAGE_ID POINT2D_IDX pairs)");
    toUint(t[0], fail, "POINT3D_ID");
    std::array<double, 3> p;
    for (int k = 0; k < 3; ++k) p[k] = toDouble(t[1 + k], fail, "point coordinate");
    model.points.push_back(p);
  }
}

}  // namespace

ColmapModel readColmapText(const fs::path& modelDir) {
  ColmapModel model;
  model.camerasFile = modelDir / "cameras.txt";
  model.imagesFile = modelDir / "images.txt";
  readCameras(model.camerasFile, model);
  readImages(model.imagesFile, model);
  std::error_code ec;
  if (fs::is_regular_file(modelDir / "points3D.txt", ec)) readPoints(modelDir / "points3D.txt", model);
  return model;
}

}  // namespace vknerf::io::detail
