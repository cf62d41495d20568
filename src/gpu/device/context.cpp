#include "vknerf/context.h"

#include <sstream>
#include <utility>

#include "gpu/device/device.h"
#include "gpu/compile/kernel_compiler.h"
#include "gpu/device/physical_devices.h"

namespace vknerf {

std::vector<DeviceInfo> Context::listDevices() {
  VkInstance inst = gpu::createInstance(false);
  auto out = gpu::describeDevices(inst);
  vkDestroyInstance(inst, nullptr);
  return out;
}

std::shared_ptr<Context> Context::create(const ContextOptions& options) {
  return std::shared_ptr<Context>(new Context(gpu::Device::create(options)));
}

std::shared_ptr<Context> Context::adopt(const AdoptedDevice& handles) {
  return std::shared_ptr<Context>(new Context(gpu::Device::adopt(handles)));
}

Context::Context(std::unique_ptr<gpu::Device> device) : device_(std::move(device)) {}
Context::~Context() = default;

VkInstance Context::instance() const { return device_->instance(); }
VkPhysicalDevice Context::physicalDevice() const { return device_->physicalDevice(); }
VkDevice Context::device() const { return device_->handle(); }
VkQueue Context::queue() const { return device_->queue(); }
uint32_t Context::queueFamily() const { return device_->queueFamily(); }
const VkPhysicalDeviceProperties& Context::properties() const { return device_->properties(); }
std::string Context::deviceName() const { return properties().deviceName; }
bool Context::isCpu() const { return properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }
bool Context::floatAtomics() const { return device_->floatAtomics(); }
bool Context::owned() const { return device_->owned(); }
std::string Context::profile() const { return device_->profile() ? device_->profile()->name : ""; }
std::vector<std::string> Context::capabilities() const { return device_->describeCapabilities(); }
std::vector<std::string> Context::profileNames() {
  std::vector<std::string> names;
  for (const auto& p : gpu::deviceProfiles()) names.push_back(p.name);
  return names;
}
void Context::setCompileProgress(std::function<void(uint64_t, uint64_t)> progress) {
  device_->compiler().setProgress(std::move(progress));
}
CompileStats Context::compileStats() const { return device_->compiler().stats(); }
uint32_t Context::validationMessages() const { return device_->validationMessages(); }
bool Context::validationEnabled() const { return device_->validationEnabled(); }

std::string Context::describe() const {
  const auto& p = properties();
  std::ostringstream os;
  os << p.deviceName << " [" << gpu::typeName(p.deviceType) << ", Vulkan " << VK_API_VERSION_MAJOR(p.apiVersion) << "."
     << VK_API_VERSION_MINOR(p.apiVersion) << (floatAtomics() ? ", float atomics" : "")
     << (profile().empty() ? "" : ", as " + profile()) << "]";
  return os.str();
}

}  // namespace vknerf
