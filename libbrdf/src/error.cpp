#include "libbrdf/error.h"

#include <cmath>
#include <sstream>

#include "libbrdf/geometry.h"

namespace libbrdf {

InvalidArgument::InvalidArgument(std::string parameter, const std::string& message)
    : std::invalid_argument(parameter + ": " + message), parameter_(std::move(parameter)) {}

namespace {
std::string describe(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}
std::string with_unit(const char* unit) { return (unit && *unit) ? std::string(" ") + unit : std::string(); }
}  // namespace

void require_finite(const char* parameter, double value) {
  if (!std::isfinite(value)) throw InvalidArgument(parameter, "must be a finite number (got " + describe(value) + ")");
}

void require_at_least(const char* parameter, double value, double lo, const char* unit) {
  if (!std::isfinite(value) || value < lo)
    throw InvalidArgument(parameter, "must be a finite number >= " + describe(lo) + with_unit(unit) +
                                         " (got " + describe(value) + ")");
}

void require_positive(const char* parameter, double value, const char* unit) {
  if (!std::isfinite(value) || value <= 0.0)
    throw InvalidArgument(parameter, "must be a finite number > 0" + with_unit(unit) + " (got " + describe(value) + ")");
}

void require_polar_angle(const char* parameter, double theta_rad) {
  if (!std::isfinite(theta_rad) || theta_rad < 0.0 || theta_rad >= 0.5 * kPi)
    throw InvalidArgument(parameter, "must be in [0, 90) degrees (got " + describe(radians_to_degrees(theta_rad)) + ")");
}

}  // namespace libbrdf
