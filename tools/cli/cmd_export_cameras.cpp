// `vknerf export cameras MODEL -o transforms.json`: the cameras a model was trained through, as the
// checkpoint recorded them, as an instant-ngp / nerfstudio transforms.json that `vknerf train` reads
// back (vknerf/transforms_file.h). Each frame names its image from the file's folder and states the
// image's own size (lib/camera_frames.h). No device is needed: only the checkpoint's record is read.
#include <cstdio>
#include <string>

#include "command_files.h"
#include "command.h"
#include "lib/camera_frames.h"
#include "vknerf/trainer.h"
#include "vknerf/transforms_file.h"

namespace vknerf::cli {
namespace {

struct Options {
  std::string model, output;
};

int run(const Options& o) {
  CommandFiles files("export cameras");
  files.input(o.model, "model").output(o.output, "-o");
  files.check();
  const std::vector<TrainedCamera> cameras = Model::trainingCamerasOf(o.model);
  // The images the frames name are inputs too: the file may go beside them, never over one.
  for (const TrainedCamera& c : cameras) files.input(c.name, "training image");
  files.check();
  writeTransformsJson(o.output, nerf::framesForFile(cameras, o.output));
  std::printf("%zu training cameras written to %s\n", cameras.size(), o.output.c_str());
  return 0;
}

Registration exportCameras("export cameras",
                           "Export the training cameras the checkpoint recorded as a transforms.json",
                           [](CLI::App& app, const Globals&) {
  auto o = std::make_shared<Options>();
  app.add_option("model", o->model, "Model checkpoint (from vknerf train)")->required();
  app.add_option("-o,--output", o->output, "Output transforms.json")->required();
  return [o] { return run(*o); };
});

}  // namespace
}  // namespace vknerf::cli
