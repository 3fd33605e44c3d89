// A double as text for messages and metadata: the shorter of %.15g and %.17g that reads back as
// the same double (1e-07, not 9.9999999999999995e-08). Defined in error.cpp.
#pragma once

#include <string>

namespace libbrdf::detail {
std::string number_text(double value);
}  // namespace libbrdf::detail
