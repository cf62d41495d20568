#include "checks.h"

#include <cmath>

namespace vknerf::cli {
namespace {

CLI::Validator numberCheck(const char* name, bool positive) {
  return CLI::Validator(
      [positive](std::string& s) -> std::string {
        double v = 0;
        size_t used = 0;
        try {
          v = std::stod(s, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != s.size() || !std::isfinite(v) || (positive && !(v > 0)))
          return std::string("must be a ") + (positive ? "positive " : "") + "finite number, got " + s;
        return "";
      },
      name);
}

}  // namespace

const CLI::Validator PositiveFinite = numberCheck("POSITIVE", true);
const CLI::Validator FiniteNumber = numberCheck("FINITE", false);

}  // namespace vknerf::cli
