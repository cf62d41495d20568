#include "lib/bench/scene_table.h"

#include <cstdio>
#include <sstream>

#include "lib/csv.h"

namespace vknerf::bench {
namespace {

template <class T>
std::string formatted(const std::optional<T>& v, const char* format) {
  if (!v) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, *v);
  return buf;
}

// A status or file name inside a Markdown table cell: one line, no column separators.
std::string cell(std::string text) {
  std::string out;
  for (char c : text) {
    if (c == '\n' || c == '\r') c = ' ';
    if (c == '|') out += '\\';
    out += c;
  }
  return out.empty() ? "-" : out;
}

// A link to the sheet beside the table; <...> keeps a name with spaces or parentheses one link.
std::string sheetLink(const std::string& sheet) {
  if (sheet.empty()) return "-";
  std::string link = "[";
  link.append(cell(sheet)).append("](<").append(cell(sheet)).append(">)");
  return link;
}

}  // namespace

const char* const kSceneTableCsvHeader =
    "scene,build,psnr,ssim,steps,samples_per_ray,seconds_per_view,render_samples_per_pixel,host_peak_mib,device_mib,sheet,"
    "status";

std::string sceneTableCsv(const std::vector<SceneRow>& rows) {
  std::ostringstream f;
  f << kSceneTableCsvHeader << "\n";
  for (const SceneRow& r : rows)
    f << nerf::csvField(r.scene) << "," << nerf::csvField(r.build) << "," << formatted(r.psnr, "%.4f") << ","
      << formatted(r.ssim, "%.5f") << "," << formatted(r.steps, "%u") << "," << formatted(r.samplesPerRay, "%.3f") << ","
      << formatted(r.secondsPerView, "%.4f") << "," << formatted(r.renderSamplesPerPixel, "%.2f") << ","
      << formatted(r.hostMiB, "%.1f") << "," << formatted(r.deviceMiB, "%.1f")
      << "," << nerf::csvField(r.sheet) << "," << nerf::csvField(r.status) << "\n";
  return f.str();
}

std::string sceneTableMarkdown(const std::vector<SceneRow>& rows, const std::string& preamble) {
  std::ostringstream md;
  md << preamble << "\n"
     << "| scene | build | held-out PSNR dB | SSIM | steps | samples/ray | s/view | render samples/pixel | peak host MiB | "
        "device MiB | sheet | status |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|\n";
  for (const SceneRow& r : rows)
    md << "| " << cell(r.scene) << " | " << cell(r.build) << " | " << cell(formatted(r.psnr, "%.2f")) << " | "
       << cell(formatted(r.ssim, "%.3f")) << " | " << cell(formatted(r.steps, "%u")) << " | "
       << cell(formatted(r.samplesPerRay, "%.1f")) << " | " << cell(formatted(r.secondsPerView, "%.2f")) << " | "
       << cell(formatted(r.renderSamplesPerPixel, "%.1f")) << " | "
       << cell(formatted(r.hostMiB, "%.0f")) << " | " << cell(formatted(r.deviceMiB, "%.0f")) << " | "
       << sheetLink(r.sheet) << " | " << cell(r.status) << " |\n";
  return md.str();
}

}  // namespace vknerf::bench
