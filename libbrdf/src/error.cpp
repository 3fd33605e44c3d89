#include "libbrdf/error.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "libbrdf/geometry.h"
#include "number_text.h"

namespace libbrdf {

InvalidArgument::InvalidArgument(std::string parameter, const std::string& message)
    : std::invalid_argument(parameter + ": " + message), parameter_(std::move(parameter)) {}

namespace detail {
std::string number_text(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.15g", value);
  if (std::strtod(buffer, nullptr) != value) std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}
}  // namespace detail

namespace {
using detail::number_text;
std::string with_unit(const char* unit) { return (unit && *unit) ? std::string(" ") + unit : std::string(); }
}  // namespace

void require_finite(const char* parameter, double value) {
  if (!std::isfinite(value)) throw InvalidArgument(parameter, "must be a finite number (got " + number_text(value) + ")");
}

void require_at_least(const char* parameter, double value, double lo, const char* unit) {
  if (!std::isfinite(value) || value < lo)
    throw InvalidArgument(parameter, "must be a finite number >= " + number_text(lo) + with_unit(unit) +
                                         " (got " + number_text(value) + ")");
}

void require_positive(const char* parameter, double value, const char* unit) {
  if (!std::isfinite(value) || value <= 0.0)
    throw InvalidArgument(parameter, "must be a finite number > 0" + with_unit(unit) + " (got " + number_text(value) + ")");
}

void require_polar_angle(const char* parameter, double theta_rad) {
  if (!polar_angle_valid(theta_rad))
    throw InvalidArgument(parameter, "must be in [0, 90) degrees (got " + number_text(radians_to_degrees(theta_rad)) + ")");
}

void require_in_range(const char* parameter, double value, double lo, double hi, const char* unit) {
  if (!(std::isfinite(value) && value >= lo && value <= hi))
    throw InvalidArgument(parameter, "must be in [" + number_text(lo) + ", " + number_text(hi) + "]" + with_unit(unit) +
                                         " (got " + number_text(value) + ")");
}

std::string message_excerpt(std::string_view text, std::size_t max_chars) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (out.size() >= max_chars) {
      out += "... (" + std::to_string(text.size()) + " bytes)";
      break;
    }
    const unsigned char byte = static_cast<unsigned char>(text[i]);
    if (byte >= 0x20 && byte < 0x7f) {
      out += static_cast<char>(byte);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", byte);
      out += hex;
    }
  }
  return out;
}

}  // namespace libbrdf
