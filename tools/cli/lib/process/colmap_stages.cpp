#include "lib/process/colmap_stages.h"

#include <chrono>

#include "lib/process/subprocess.h"
#include "vknerf/error.h"

namespace vknerf::process {
namespace {

void runStage(const std::string& command, std::vector<std::string> options, ColmapStage stage, const ColmapPaths& paths,
              size_t total, const StageReport& report) {
  std::vector<std::string> argv = {"colmap", command};
  argv.insert(argv.end(), options.begin(), options.end());
  StageProgress progress;
  progress.total = stage == ColmapStage::mapping ? total : 0;
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  if (report) report(stage, progress, 0, false);
  const int status = runLogged({argv,
                                {"QT_QPA_PLATFORM=offscreen"},
                                "colmap",
                                paths.log.string(),
                                [&](const std::string& line) {
                                  if (readProgressLine(stage, line, progress) && report) report(stage, progress, seconds(), false);
                                }});
  throwIfStopped();  // COLMAP was passed the signal: not its failure
  if (status != 0) {
    const std::string why = failureReason(paths.log.string());
    throw Error(std::string("COLMAP failed at ") + stageDescription(stage) + " (colmap " + command + ", exit status " +
                std::to_string(status) + ")" + (why.empty() ? "" : ": " + why) + "; log: " + paths.log.string());
  }
  if (stage != ColmapStage::mapping && progress.total) progress.done = progress.total;
  if (report) report(stage, progress, seconds(), true);
}

}  // namespace

void runColmap(const ColmapPaths& paths, const ColmapSettings& s, size_t imageCount, const StageReport& report) {
  const std::string db = paths.database.string(), images = paths.images.string();
  std::error_code ec;
  for (const auto& folder : {paths.database.parent_path(), paths.sparse})
    if (std::filesystem::create_directories(folder, ec); ec)
      throw Error("cannot create '" + folder.string() + "': " + ec.message());
  runStage("feature_extractor",
           {"--database_path", db, "--image_path", images, "--ImageReader.single_camera", "1",
            "--ImageReader.camera_model", s.cameraModel, "--SiftExtraction.use_gpu", "0",
            "--SiftExtraction.max_image_size", std::to_string(s.siftMaxImageSize),
            "--SiftExtraction.max_num_features", std::to_string(s.siftMaxFeatures)},
           ColmapStage::features, paths, imageCount, report);
  if (s.matcher == Matcher::exhaustive)
    // Blocks of 10 images: the log then shows progress within a set that one block of 50 would hold.
    runStage("exhaustive_matcher",
             {"--database_path", db, "--SiftMatching.use_gpu", "0", "--ExhaustiveMatching.block_size", "10"},
             ColmapStage::exhaustiveMatching, paths, imageCount, report);
  else
    runStage("sequential_matcher",
             {"--database_path", db, "--SiftMatching.use_gpu", "0", "--SequentialMatching.overlap",
              std::to_string(s.sequentialOverlap), "--SequentialMatching.loop_detection", "0"},
             ColmapStage::sequentialMatching, paths, imageCount, report);
  runStage("mapper", {"--database_path", db, "--image_path", images, "--output_path", paths.sparse.string()},
           ColmapStage::mapping, paths, imageCount, report);
}

}  // namespace vknerf::process
