#pragma once
// libbrdf error type. Bad input is an error, never a silent clamp (conventions.md, "Domain").
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace libbrdf {

// Thrown for any out-of-domain or malformed input. what() is one line that names the parameter
// and the allowed range, e.g. "sigma_s: must be a finite number >= 0 um (got -1)".
class InvalidArgument : public std::invalid_argument {
 public:
  InvalidArgument(std::string parameter, const std::string& message);
  const std::string& parameter() const noexcept { return parameter_; }

 private:
  std::string parameter_;
};

// Throws InvalidArgument unless `value` is finite and lo <= value (< or <=) hi.
void require_finite(const char* parameter, double value);
void require_at_least(const char* parameter, double value, double lo, const char* unit = "");
void require_positive(const char* parameter, double value, const char* unit = "");
// Polar angle in radians, allowed [0, pi/2): a direction on or below the horizon is an error.
void require_polar_angle(const char* parameter, double theta_rad);
// What require_polar_angle accepts, as a test (inline for the batch loops).
inline bool polar_angle_valid(double theta_rad) {
  return theta_rad >= 0.0 && theta_rad < 0.5 * 3.14159265358979323846;  // false for NaN; +Inf fails < pi/2
}
// Throws unless lo <= value <= hi (finite); the message names the parameter and the range.
void require_in_range(const char* parameter, double value, double lo, double hi, const char* unit = "");

// Untrusted text (a CSV line, a file name, a header attribute) for an error message: at most
// `max_chars` characters, bytes outside printable ASCII written as \xHH, "..." where cut, so a
// message stays one short line whatever the input (a 50 MB line, raw control characters).
std::string message_excerpt(std::string_view text, std::size_t max_chars = 60);

}  // namespace libbrdf
