#include "checks.h"

#include <cmath>
#include <functional>

namespace vknerf::cli {
namespace {

// A number (the whole argument) that `accepts`; else "must be WANTED, got S".
CLI::Validator numberCheck(const char* name, const char* wanted, std::function<bool(double)> accepts) {
  return CLI::Validator(
      [wanted, accepts](std::string& s) -> std::string {
        double v = 0;
        size_t used = 0;
        try {
          v = std::stod(s, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != s.size() || !accepts(v)) return std::string("must be ") + wanted + ", got " + s;
        return "";
      },
      name);
}

}  // namespace

const CLI::Validator PositiveFinite =
    numberCheck("POSITIVE", "a positive finite number", [](double v) { return std::isfinite(v) && v > 0; });
const CLI::Validator FiniteNumber = numberCheck("FINITE", "a finite number", [](double v) { return std::isfinite(v); });
const CLI::Validator UnitFraction =
    numberCheck("[0, 1)", "a number in [0, 1)", [](double v) { return v >= 0 && v < 1; });

}  // namespace vknerf::cli
