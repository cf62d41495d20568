// Checkpoints: the container (Checkpoint::parse) from the input's bytes, then the input with its
// checksum made right (so that mutations reach past it) read as the command line reads a checkpoint
// it resumes: Trainer::configOf, which parses the container, its JSON and the training configuration.
#include <cstring>
#include <vector>

#include "io/checkpoint/checkpoint.h"
#include "scratch_folder.h"
#include "vknerf/error.h"
#include "vknerf/trainer.h"

using namespace vknerf::fuzz;

namespace {

void readSections(const vknerf::io::Checkpoint& ck) {
  for (const auto& [name, bytes] : ck.sections) {
    try {
      ck.get<float>(name);
      ck.get<float>(name, bytes.size() / sizeof(float));
    } catch (const vknerf::Error&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    readSections(vknerf::io::Checkpoint::parse(data, size, "input"));
  } catch (const vknerf::Error&) {
  }
  if (size < 8) return 0;
  std::vector<uint8_t> fixed(data, data + size);
  const uint64_t sum = vknerf::io::fnv1a(fixed.data(), size - 8);
  std::memcpy(fixed.data() + size - 8, &sum, 8);
  static const fs::path file = scratchFolder() / "input.vknerf";
  writeBytes(file, fixed.data(), fixed.size());
  try {
    vknerf::Trainer::configOf(file.string()).describe();
  } catch (const vknerf::Error&) {
    // A rejected checkpoint is the expected outcome of most inputs; anything else escapes and is reported.
  }
  return 0;
}
