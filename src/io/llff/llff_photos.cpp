// findLlffPhotos (llff_photos.h).
#include "io/llff/llff_photos.h"

#include <algorithm>
#include <cctype>
#include <string>

#include "io/dataset/load_note.h"
#include "vknerf/error.h"

namespace vknerf::io::detail {
namespace {

namespace fs = std::filesystem;

bool isDir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

// The photos of `dir`: its .png, .jpg and .jpeg files (any case), sorted by name as load_llff does.
std::vector<fs::path> photosIn(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::string ext = it->path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    std::error_code typeError;  // an entry that cannot be examined is not a photo
    if ((ext == ".png" || ext == ".jpg" || ext == ".jpeg") && it->is_regular_file(typeError)) out.push_back(it->path());
  }
  if (ec) throw Error("'" + dir.string() + "' cannot be listed: " + ec.message());
  std::sort(out.begin(), out.end(), [](const fs::path& a, const fs::path& b) { return a.filename().string() < b.filename().string(); });
  return out;
}

std::vector<fs::path> photosFor(const fs::path& dir, size_t rows, const fs::path& file) {
  std::vector<fs::path> photos = photosIn(dir);
  if (photos.size() != rows)
    throw Error("'" + dir.string() + "' holds " + std::to_string(photos.size()) + " photos (.png, .jpg, .jpeg) but '" +
                file.string() + "' has " + std::to_string(rows) + " rows, one per photo");
  return photos;
}

// The N of every images_N/ folder in `folder` (N a whole number >= 1 written without leading
// zeros), ascending.
std::vector<uint32_t> scaledFolders(const fs::path& folder) {
  std::vector<uint32_t> out;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string(), digits = name.substr(std::min<size_t>(7, name.size()));
    if (name.rfind("images_", 0) != 0 || digits.empty() || digits.size() > 6 || digits[0] == '0' ||
        !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
      continue;
    std::error_code typeError;
    if (it->is_directory(typeError)) out.push_back(uint32_t(std::stoul(digits)));
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string folderList(const std::vector<uint32_t>& ns) {
  std::string out;
  for (uint32_t n : ns) out += (out.empty() ? "" : ", ") + ("images_" + std::to_string(n) + "/");
  return out;
}

}  // namespace

LlffPhotos findLlffPhotos(const fs::path& file, size_t rows, uint32_t downscale, uint32_t width, uint32_t height) {
  const fs::path folder = file.parent_path(), imagesDir = folder / "images";
  const fs::path asked = folder / ("images_" + std::to_string(downscale));
  LlffPhotos out;
  if (downscale > 1 && isDir(asked)) {
    // Photos already that much smaller: loaded as they are. images/ beside them must still pair
    // with the rows, as it always has.
    if (isDir(imagesDir)) photosFor(imagesDir, rows, file);
    out.files = photosFor(asked, rows, file);
    out.factor = downscale;
    return out;
  }
  if (isDir(imagesDir)) {
    out.files = photosFor(imagesDir, rows, file);
    out.downscale = downscale;
    return out;
  }

  const std::vector<uint32_t> present = scaledFolders(folder);
  if (present.empty())
    throw Error(file.string() + ": no images/ folder beside it ('" + imagesDir.string() + "' not found), nor any images_N/");
  // The coarsest that divides the request gives exactly the size asked for with the least decoding.
  uint32_t n = 0;
  for (uint32_t p : present)
    if (downscale % p == 0) n = p;
  if (n == 0) {
    const auto coarser = std::find_if(present.begin(), present.end(), [&](uint32_t p) { return p > downscale; });
    if (coarser == present.end())
      throw Error(file.string() + ": no images/ folder beside it, and downscale " + std::to_string(downscale) +
                  " cannot be made from " + folderList(present) + ": it is not a multiple of any of their N");
    n = *coarser;
  }
  out.files = photosFor(folder / ("images_" + std::to_string(n)), rows, file);
  out.factor = n;
  out.downscale = n <= downscale ? downscale / n : 1;  // a coarser folder is used as it is
  const std::string hwf = "hwf's " + std::to_string(width) + "x" + std::to_string(height);
  std::string how = n == 1 ? "photos at " + hwf : "photos " + std::to_string(n) + " times smaller than " + hwf;
  if (out.downscale > 1) how += ", shrunk " + std::to_string(out.downscale) + " times more for downscale " + std::to_string(downscale);
  if (n > downscale && downscale > 1) how += ", coarser than the downscale " + std::to_string(downscale) + " asked for";
  noteOnce(file.string() + ": no images/ folder beside it; using " + (folder / ("images_" + std::to_string(n))).string() +
           "/ (" + how + ")");
  return out;
}

}  // namespace vknerf::io::detail
