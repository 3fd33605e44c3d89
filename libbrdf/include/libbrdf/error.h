#pragma once
// libbrdf error type. Bad input is an error, never a silent clamp (conventions.md, "Domain").
#include <stdexcept>
#include <string>

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

}  // namespace libbrdf
