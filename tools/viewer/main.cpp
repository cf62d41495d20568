// vknerf-view: an interactive NeRF viewer on vknerf's public API. It owns its window, Vulkan device
// and swapchain; vknerf adopts the device and records each render into the viewer's command buffer,
// writing a storage image that the viewer blits to the screen.
//
//   vknerf-view MODEL.vknerf [--scene DIR] [--camera I] [--train SCENE --time S] [--frames N --screenshot out.png]
//
// Left drag orbits the scene box centre, the wheel zooms, D toggles RGB/depth, R resets the view,
// Esc or Q quits. While the view changes it renders at 1/4 resolution, then once at full resolution.
// Exit codes: 0 success, 1 runtime error (one line), 2 usage error.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "orbit_camera.h"
#include "swapchain.h"
#include "view_renderer.h"
#include "vknerf/context.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"
#include "vknerf/trainer.h"
#include "window_device.h"

namespace viewer {
namespace {

constexpr uint32_t kLowResolutionFactor = 4;
constexpr uint32_t kDefaultSize = 100;  // start camera without a scene
constexpr uint32_t kMinWindowSide = 400;  // small cameras are shown enlarged by an integer factor

struct Options {
  std::string model, scene, split = "test", trainScene, config = "fast", screenshot, device;
  uint32_t camera = 0, downscale = 1, frames = 0, stepsPerFrame = 4;
  double trainSeconds = 0;
};

// Input gathered by GLFW callbacks between frames.
struct Input {
  bool dragging = false;
  double lastX = 0, lastY = 0, dx = 0, dy = 0, scroll = 0;
  bool toggleDepth = false, reset = false, redraw = false;
};

Input& inputOf(GLFWwindow* w) { return *static_cast<Input*>(glfwGetWindowUserPointer(w)); }

void installCallbacks(GLFWwindow* window, Input* input) {
  glfwSetWindowUserPointer(window, input);
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int) {
    if (button != GLFW_MOUSE_BUTTON_LEFT) return;
    Input& in = inputOf(w);
    in.dragging = action == GLFW_PRESS;
    glfwGetCursorPos(w, &in.lastX, &in.lastY);
  });
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
    Input& in = inputOf(w);
    if (in.dragging) in.dx += x - in.lastX, in.dy += y - in.lastY;
    in.lastX = x, in.lastY = y;
  });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double, double y) { inputOf(w).scroll += y; });
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int) {
    if (action != GLFW_PRESS) return;
    if (key == GLFW_KEY_D) inputOf(w).toggleDepth = true;
    if (key == GLFW_KEY_R) inputOf(w).reset = true;
    if (key == GLFW_KEY_ESCAPE || key == GLFW_KEY_Q) glfwSetWindowShouldClose(w, GLFW_TRUE);
  });
  // Exposed or resized: show the last image again (no new render needed).
  glfwSetWindowRefreshCallback(window, [](GLFWwindow* w) { inputOf(w).redraw = true; });
  glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int, int) { inputOf(w).redraw = true; });
}

// The scene's start camera and world up (the mean of its cameras' up vectors: the turntable axis).
struct StartView {
  vknerf::Camera camera;
  glm::vec3 up{0, 0, 1};
  bool fromScene = false;
};

StartView startView(const Options& o) {
  StartView v;
  const std::string scene = !o.scene.empty() ? o.scene : o.trainScene;
  if (scene.empty()) {
    v.camera.width = v.camera.height = kDefaultSize;  // posed once the model's box is known
    return v;
  }
  vknerf::DatasetOptions dopt;
  dopt.split = o.split;
  dopt.downscale = o.downscale;
  vknerf::Dataset data = vknerf::Dataset::load(scene, dopt);
  if (o.camera >= data.cameras.size())
    throw vknerf::Error("--camera " + std::to_string(o.camera) + ": " + scene + " has " + std::to_string(data.cameras.size()) +
                        " " + o.split + " cameras");
  v.camera = data.cameras[o.camera];
  glm::vec3 up(0);
  for (auto& c : data.cameras) up += glm::vec3(c.c2w[1], c.c2w[5], c.c2w[9]);
  if (glm::length(up) > 1e-3f * float(data.cameras.size())) v.up = glm::normalize(up);
  v.fromScene = true;
  return v;
}

// Depth is shown as grey = depth * scale: the far side of the box from the camera maps to white.
float depthScaleFor(const vknerf::Aabb& box, float distance) {
  glm::vec3 extent(box.max[0] - box.min[0], box.max[1] - box.min[1], box.max[2] - box.min[2]);
  return 1.0f / std::max(distance + 0.5f * glm::length(extent), 1e-6f);
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Draws one frame, recreating the swapchain as often as the window asks for it.
void draw(const WindowDevice& wd, Swapchain& swapchain, ViewRenderer& renderer, const RenderRequest* request) {
  for (;;) {
    FrameStatus s = renderer.drawFrame(swapchain, request);
    if (s == FrameStatus::Presented) return;
    vkDeviceWaitIdle(wd.device());
    while (!swapchain.recreate()) {  // minimised: nothing to draw into until it comes back
      glfwWaitEvents();
      if (glfwWindowShouldClose(wd.window())) return;
    }
    if (s == FrameStatus::PresentedStale) return;
  }
}

int runViewer(const Options& o, WindowDevice& wd, const StartView& start) {
  auto ctx = vknerf::Context::adopt(wd.adopted());
  std::fprintf(stderr, "vknerf-view: device %s%s\n", ctx->describe().c_str(), wd.validationEnabled() ? " (validation on)" : "");

  std::optional<vknerf::Model> loaded;
  std::unique_ptr<vknerf::Trainer> trainer;
  if (!o.trainScene.empty()) {
    vknerf::DatasetOptions dopt;
    dopt.downscale = o.downscale;
    vknerf::Dataset train = vknerf::Dataset::load(o.trainScene, dopt);
    vknerf::TrainConfig cfg = vknerf::TrainConfig::named(o.config, *ctx);
    std::printf("training on %zu images of %ux%u from %s: %s\n", train.images.size(), train.images[0].width,
                train.images[0].height, o.trainScene.c_str(), cfg.describe().c_str());
    trainer = std::make_unique<vknerf::Trainer>(ctx, train, cfg);
  } else {
    loaded.emplace(vknerf::Model::load(ctx, o.model));
  }
  const vknerf::Model& model = trainer ? trainer->model() : *loaded;

  vknerf::Camera startCamera = start.fromScene ? start.camera : lookAtBox(model.bounds(), start.camera.width);
  const auto& b = model.bounds();
  const glm::vec3 centre(0.5f * (b.min[0] + b.max[0]), 0.5f * (b.min[1] + b.max[1]), 0.5f * (b.min[2] + b.max[2]));
  OrbitCamera orbit(startCamera, centre, start.up);

  Swapchain swapchain(wd);
  while (!swapchain.recreate()) glfwWaitEvents();
  ViewRenderer renderer(wd, startCamera.width, startCamera.height, kLowResolutionFactor);
  Input input;
  installCallbacks(wd.window(), &input);

  auto trainStart = std::chrono::steady_clock::now();
  double trainingSeconds = 0;
  auto trainSome = [&] {
    if (!trainer || (o.trainSeconds > 0 && secondsSince(trainStart) >= o.trainSeconds)) return false;
    auto t0 = std::chrono::steady_clock::now();
    for (uint32_t i = 0; i < o.stepsPerFrame; ++i) trainer->step();
    trainingSeconds += secondsSince(t0);
    return true;
  };
  RenderRequest request;
  request.model = &model;
  auto fill = [&](bool low) {
    request.low = low;
    request.camera = low ? orbit.cameraAtScale(kLowResolutionFactor) : orbit.camera();
    request.depthScale = depthScaleFor(b, orbit.distance());
  };

  if (o.frames > 0) {
    // Scripted run: N full-resolution frames of the start view, then the screenshot.
    double total = 0, first = 0;
    for (uint32_t i = 0; i < o.frames; ++i) {
      trainSome();
      fill(false);
      auto t0 = std::chrono::steady_clock::now();
      draw(wd, swapchain, renderer, &request);
      double s = secondsSince(t0);
      total += s;
      if (i == 0) first = s;
      glfwPollEvents();
    }
    char training[96] = "";
    if (trainer) std::snprintf(training, sizeof training, "; trained %u steps in %.1f s", trainer->steps(), trainingSeconds);
    std::printf("vknerf-view: %u frames of %ux%u, mean frame time %.1f ms (first %.1f ms)%s\n", o.frames, startCamera.width,
                startCamera.height, 1000.0 * total / o.frames, 1000.0 * first, training);
    if (!o.screenshot.empty()) {
      renderer.saveScreenshot(o.screenshot);
      std::printf("vknerf-view: screenshot %s\n", o.screenshot.c_str());
    }
  } else {
    bool fullPending = true;
    double lastFrame = 0;
    while (!glfwWindowShouldClose(wd.window())) {
      const bool idle = !fullPending && !input.redraw && !(trainer && (o.trainSeconds <= 0 || secondsSince(trainStart) < o.trainSeconds));
      if (idle)
        glfwWaitEventsTimeout(0.5);
      else
        glfwPollEvents();
      bool moved = false;
      if (input.dx != 0 || input.dy != 0) orbit.drag(input.dx, input.dy), moved = true;
      if (input.scroll != 0) orbit.zoom(input.scroll), moved = true;
      if (input.reset) orbit.reset(), moved = true;
      if (input.toggleDepth) {
        request.channel = request.channel == vknerf::RenderChannel::Color ? vknerf::RenderChannel::Depth
                                                                           : vknerf::RenderChannel::Color;
        moved = true;
      }
      input.dx = input.dy = input.scroll = 0;
      input.reset = input.toggleDepth = false;
      const bool trained = trainSome();

      const RenderRequest* r = nullptr;
      if (moved) {
        fill(true);  // quick preview while the view changes
        fullPending = true;
        r = &request;
      } else if (fullPending || trained) {
        fill(false);
        fullPending = false;
        r = &request;
      } else if (!input.redraw) {
        continue;
      }
      input.redraw = false;
      auto t0 = std::chrono::steady_clock::now();
      draw(wd, swapchain, renderer, r);
      if (r) lastFrame = secondsSince(t0);
      char title[160];
      std::snprintf(title, sizeof title, "vknerf-view - %s - %s %.0f ms%s", request.channel == vknerf::RenderChannel::Color ? "RGB" : "depth",
                    renderer.showingLowResolution() ? "1/4 res" : "full res", 1000 * lastFrame,
                    trainer ? (" - step " + std::to_string(trainer->steps())).c_str() : "");
      glfwSetWindowTitle(wd.window(), title);
    }
  }
  if (trainer && !o.model.empty()) {
    trainer->save(o.model);
    std::printf("vknerf-view: model saved to %s after %u steps\n", o.model.c_str(), trainer->steps());
  }
  vkDeviceWaitIdle(wd.device());
  return 0;
}

int run(const Options& o) {
  const StartView start = startView(o);
  // The storage image has the camera's size (screenshots compare pixel for pixel with `vknerf render`);
  // the window shows it enlarged by a whole factor when the camera is small.
  const uint32_t side = std::max(start.camera.width, start.camera.height);
  const uint32_t zoom = std::max(1u, kMinWindowSide / side);
  WindowDevice wd({start.camera.width * zoom, start.camera.height * zoom, "vknerf-view", o.device});
  int rc = 0;
  std::string error;
  try {
    rc = runViewer(o, wd, start);
  } catch (const std::exception& e) {
    error = e.what();
    rc = 1;
  }
  wd.shutdown();  // after every vknerf object is gone; leaks are reported here
  if (!error.empty()) std::fprintf(stderr, "vknerf-view: %s\n", error.c_str());
  if (wd.validationMessages() > 0) {
    std::fprintf(stderr, "vknerf-view: %u validation message(s)\n", wd.validationMessages());
    return 1;
  }
  return rc;
}

}  // namespace
}  // namespace viewer

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  viewer::Options o;
  CLI::App app{"vknerf-view: interactive NeRF viewer (left drag: orbit, wheel: zoom, D: RGB/depth, R: reset, Esc: quit)"};
  app.add_option("model", o.model, "Model checkpoint (from vknerf train); with --train, where to save the trained model on exit");
  app.add_option("--scene", o.scene, "Scene whose camera starts the view (default: the --train scene)");
  app.add_option("--split", o.split, "Split of the scene to take the camera from")->check(CLI::IsMember({"train", "val", "test", "all"}));
  app.add_option("--camera", o.camera, "Index of the start camera in the split");
  app.add_option("--downscale", o.downscale, "Downscale the scene's images (and the view) by this factor")->check(CLI::Range(1u, 64u));
  auto* train = app.add_option("--train", o.trainScene, "Train a model on this scene in the viewer and show it live");
  app.add_option("--time", o.trainSeconds, "Training budget in seconds (default: until the window closes)")->check(CLI::PositiveNumber)->needs(train);
  app.add_option("--config", o.config, "Training configuration: fast (the default, as vknerf train's) or vanilla")->check(CLI::IsMember({"vanilla", "fast"}))->needs(train);
  app.add_option("--steps-per-frame", o.stepsPerFrame, "Training steps between two frames")->check(CLI::Range(1u, 100000u))->needs(train);
  auto* frames = app.add_option("--frames", o.frames, "Render this many full-resolution frames, then exit")->check(CLI::Range(1u, 1000000u));
  app.add_option("--screenshot", o.screenshot, "After --frames, write the last image as PNG")->needs(frames);
  app.add_option("--device", o.device, "Vulkan device: index or name substring (default: $VKNERF_DEVICE, else the best)");
  try {
    app.parse(argc, argv);
    if (o.model.empty() && o.trainScene.empty()) throw CLI::ValidationError("MODEL", "give a model checkpoint, or --train SCENE");
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  // The screenshot never replaces the model or a scene's file, whatever path names it (a link too).
  for (const auto& [path, what] : {std::pair{o.model, "the model"}, {o.scene, "the scene"}, {o.trainScene, "the --train scene"}}) {
    std::error_code ec;
    if (!o.screenshot.empty() && !path.empty() && std::filesystem::equivalent(o.screenshot, path, ec)) {
      std::fprintf(stderr, "vknerf-view: --screenshot %s is %s %s; choose another output\n", o.screenshot.c_str(), what, path.c_str());
      return 2;
    }
  }
  try {
    if (!o.screenshot.empty()) vknerf::checkOutputPath(o.screenshot, "--screenshot");
    return viewer::run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vknerf-view: %s\n", e.what());
    return 1;
  }
}
