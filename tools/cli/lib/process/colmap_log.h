#pragma once
// Progress of a COLMAP stage read from the lines of its log (COLMAP 3.8's wording):
//   feature_extractor   "Processed file [12/45]"            images featured
//   exhaustive_matcher  "Matching block [2/3, 1/3]"          blocks of image pairs matched
//   sequential_matcher  "Matching image [12/45]"             images matched with their neighbours
//   mapper              "Registering image #7 (12)"          images registered so far
#include <cstdint>
#include <string>

namespace vknerf::process {

enum class ColmapStage { features, exhaustiveMatching, sequentialMatching, mapping };

struct StageProgress {
  uint64_t done = 0, total = 0;  // total 0: not known yet
};

// Updates `progress` from one log line of `stage`; true when the line moved it. The mapper's total
// is not in its log: set it to the number of images beforehand. A line from another stage, or one
// that carries no count, changes nothing.
bool readProgressLine(ColmapStage stage, const std::string& line, StageProgress& progress);

// What a stage counts, for messages: "images featured", "blocks matched", ...
const char* progressUnit(ColmapStage stage);

// What a stage does, for messages: "feature extraction", "exhaustive matching", ...
const char* stageDescription(ColmapStage stage);

// Why a COLMAP run failed, from its log: the last error it states (a glog fatal or error line
// without its time and source prefix, such as "Check failed: ...", or an "ERROR: ..." line), else the
// last line that is not part of a stack trace; "" when there is none. A crash ends the log with
// the stack trace's frames ("    @     0x7fa6ecd278ec  (unknown)"), which say nothing to a user.
std::string failureReason(const std::string& logPath);

}  // namespace vknerf::process
