#include "lib/process/input_images.h"

#include <algorithm>

#include "vknerf/image_io.h"
#include "vknerf/error.h"

namespace fs = std::filesystem;

namespace vknerf::process {

std::vector<fs::path> listImages(const fs::path& folder) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    std::string ext = it->path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".jpg" || ext == ".jpeg" || ext == ".png") out.push_back(it->path());
  }
  if (ec) throw Error("cannot list '" + folder.string() + "': " + ec.message());
  std::sort(out.begin(), out.end());
  return out;
}

void checkImagesDecode(const std::vector<fs::path>& images, const std::string& folder) {
  constexpr size_t kNamed = 5;  // one line: the first few, then how many more
  std::string named;
  size_t refused = 0;
  for (const fs::path& image : images) {
    try {
      (void)vknerf::loadImage(image.string());
    } catch (const Error& e) {
      // "cannot read image 'PATH': why": the file name is enough here, the folder is named once.
      std::string why = e.what();
      if (const size_t at = why.find("': "); at != std::string::npos) why = why.substr(at + 3);
      if (refused++ < kNamed) named += (named.empty() ? "" : "; ") + image.filename().string() + " (" + why + ")";
    }
  }
  if (refused == 0) return;
  if (refused > kNamed) named += "; and " + std::to_string(refused - kNamed) + " more";
  throw Error("'" + folder + "': " + std::to_string(refused) + " of " + std::to_string(images.size()) +
              " photos cannot be decoded: " + named + "; remove or replace them");
}

void placeImages(const std::vector<fs::path>& images, const fs::path& into) {
  std::error_code ec;
  fs::create_directories(into, ec);
  if (ec) throw Error("cannot create '" + into.string() + "': " + ec.message());
  for (const fs::path& image : images) {
    const fs::path target = into / image.filename();
    fs::create_hard_link(image, target, ec);
    if (ec) fs::copy_file(image, target, fs::copy_options::overwrite_existing, ec);
    if (ec) throw Error("cannot copy '" + image.string() + "' to '" + target.string() + "': " + ec.message());
  }
}

}  // namespace vknerf::process
