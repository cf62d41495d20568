#pragma once
// Argument checks shared by the commands: numbers that must be finite, and the usage error that
// main() turns into exit code 2. The files a command reads and writes are checked in command_files.h.
#include <CLI/CLI.hpp>

#include <string>

#include "vknerf/error.h"

namespace vknerf::cli {

// A bad argument found after parsing (a flag combination, a value out of the model's range):
// main() prints it and exits 2, like a parse error.
struct UsageError : Error {
  using Error::Error;
};

// CLI11's PositiveNumber lets NaN through (NaN <= 0 is false) and Range prints double's largest
// value as a 309-digit bound: these say what is wanted in words.
extern const CLI::Validator PositiveFinite;
extern const CLI::Validator FiniteNumber;
// A share in [0, 1) (NaN is none).
extern const CLI::Validator UnitFraction;

}  // namespace vknerf::cli
