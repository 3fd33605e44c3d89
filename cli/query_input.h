#pragma once
// Query input of `brdf eval`: --at TI,TS,PHIS options and CSV lines "theta_i,theta_s,phi_s"
// (degrees) from a file or stdin; output CSV "theta_i,theta_s,phi_s,value", each number in the
// fewest digits that read back as the same double.
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace brdf_cli {

struct Query {
  double theta_i_deg, theta_s_deg, phi_s_deg;
  int number;    // --at option (1-based) or CSV line number
  bool from_at;
  std::string origin() const;  // "--at #2" or "line 5", for error messages
};

// Longest CSV query line accepted (characters, without the newline).
inline constexpr std::size_t kMaxQueryLineLength = 4096;

// Reads queries from --at values and from the CSV source ("" none, "-" stdin, else a file path).
// Blank lines and lines starting with # are skipped; a header "theta_i,theta_s,phi_s[,...]" is
// recognised by its names before the first data line. Throws InvalidArgument naming the
// parameter and the line number on malformed input, on a line longer than kMaxQueryLineLength,
// or on a directory.
std::vector<Query> read_queries(const std::vector<std::string>& at_values, const std::string& queries_source);

// Writes the CSV of the queries and their values (values[k] at queries[k], from the batch API;
// std::to_chars, shortest round trip). A non-finite value is an error naming its query's line,
// raised before anything is written.
void write_evaluations(std::ostream& out, const std::vector<Query>& queries, const std::vector<double>& values);

}  // namespace brdf_cli
