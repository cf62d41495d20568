#include "lib/process/sparse_model.h"

#include <algorithm>
#include <fstream>

#include "vknerf/error.h"

namespace fs = std::filesystem;

namespace vknerf::process {
namespace {

// COLMAP's binary files are little-endian, as is every machine vknerf runs on.
template <typename T>
T read(std::ifstream& in, const fs::path& file) {
  T v{};
  if (!in.read(reinterpret_cast<char*>(&v), sizeof v)) throw Error("'" + file.string() + "' is truncated");
  return v;
}

}  // namespace

ModelSummary summarizeModel(const fs::path& folder) {
  ModelSummary s;
  s.folder = folder;
  const fs::path imagesFile = folder / "images.bin", pointsFile = folder / "points3D.bin";
  std::ifstream images(imagesFile, std::ios::binary);
  if (!images) throw Error("'" + imagesFile.string() + "' cannot be read");
  s.registeredImages = read<uint64_t>(images, imagesFile);

  // points3D.bin: count, then per point id (u64), xyz (3 f64), rgb (3 u8), error (f64), track
  // length (u64) and the track (u32 image id, u32 point index each).
  std::ifstream points(pointsFile, std::ios::binary);
  if (!points) throw Error("'" + pointsFile.string() + "' cannot be read");
  s.points = read<uint64_t>(points, pointsFile);
  double sum = 0;
  for (uint64_t i = 0; i < s.points; ++i) {
    points.seekg(8 + 24 + 3, std::ios::cur);
    sum += read<double>(points, pointsFile);
    const uint64_t track = read<uint64_t>(points, pointsFile);
    points.seekg(std::streamoff(track * 8), std::ios::cur);
  }
  if (!points) throw Error("'" + pointsFile.string() + "' is truncated");
  s.meanReprojectionError = s.points ? sum / double(s.points) : 0;
  return s;
}

std::optional<ModelSummary> largestModel(const fs::path& sparse) {
  std::optional<ModelSummary> best;
  std::error_code ec;
  std::vector<fs::path> folders;
  for (fs::directory_iterator it(sparse, ec), end; !ec && it != end; it.increment(ec))
    if (fs::is_regular_file(it->path() / "images.bin")) folders.push_back(it->path());
  std::sort(folders.begin(), folders.end());
  for (const fs::path& folder : folders) {
    ModelSummary s = summarizeModel(folder);
    if (!best || s.registeredImages > best->registeredImages ||
        (s.registeredImages == best->registeredImages && s.points > best->points))
      best = s;
  }
  return best;
}

}  // namespace vknerf::process
