#include "lib/process/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace vknerf::process {

std::string processReport(const ModelSummary& m, size_t images, const SceneBox& b, double seconds) {
  char text[1024];
  std::snprintf(text, sizeof text,
                "registered %llu of %zu images\n"
                "mean reprojection error %.3f px\n"
                "%llu points\n"
                "scene box [%.3f %.3f %.3f] .. [%.3f %.3f %.3f] (from %s, the model centred and scaled to half extent 1)\n"
                "processed in %.1f s\n",
                (unsigned long long)m.registeredImages, images, m.meanReprojectionError, (unsigned long long)m.points,
                b.box.min[0], b.box.min[1], b.box.min[2], b.box.max[0], b.box.max[1], b.box.max[2], b.source.c_str(),
                seconds);
  return text;
}

size_t registeredNeeded(size_t images, double share) {
  return std::max<size_t>(3, size_t(std::ceil(share * double(images) - 1e-9)));
}

}  // namespace vknerf::process
