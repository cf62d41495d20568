#pragma once
// `bench scenes`' table: one row per scene and build, as Markdown (scenes.md) and CSV (scenes.csv).
// A number that was not measured (the run failed, or an older build does not print it) is empty
// in the CSV and "-" in the Markdown; the status says why.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace vknerf::bench {

struct SceneRow {
  std::string scene, build;
  bool failed = false;
  std::string status = "ok";  // "ok", or what failed, one line
  std::optional<double> psnr, ssim;
  std::optional<uint32_t> steps;
  std::optional<double> samplesPerRay, secondsPerView, hostMiB, deviceMiB;
  std::optional<double> renderSamplesPerPixel;  // what a held-out render shaded, per pixel
  std::string sheet;  // the contact sheet's file name in the output folder, "" when none was written
};

// The CSV's header line, without the line break.
extern const char* const kSceneTableCsvHeader;

std::string sceneTableCsv(const std::vector<SceneRow>& rows);
// `preamble` (Markdown lines: device, budget, flags) comes before the table.
std::string sceneTableMarkdown(const std::vector<SceneRow>& rows, const std::string& preamble);

}  // namespace vknerf::bench
