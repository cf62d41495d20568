#include "models/common/parameter_groups.h"

namespace vknerf::models {

void ParameterGroups::add(ParameterGroup& group, ParameterRole role) { entries_.push_back({&group, &group, role}); }

void ParameterGroups::addState(StatePart& part) { entries_.push_back({&part, nullptr, ParameterRole::Other}); }

void ParameterGroups::recordOptimizerSteps(gpu::Recorder& rec, nerf::OptimizerStep at) {
  for (const Entry& e : entries_)
    if (e.group) e.group->recordOptimizerStep(rec, at);
}

std::vector<StateArray> ParameterGroups::state() {
  std::vector<StateArray> out;
  for (const Entry& e : entries_) e.part->appendState(out);
  return out;
}

size_t ParameterGroups::parameterCount() const {
  size_t n = 0;
  for (const Entry& e : entries_)
    if (e.group) n += e.group->parameterCount();
  return n;
}

size_t ParameterGroups::parameterCount(ParameterRole role) const {
  size_t n = 0;
  for (const Entry& e : entries_)
    if (e.group && e.role == role) n += e.group->parameterCount();
  return n;
}

}  // namespace vknerf::models
