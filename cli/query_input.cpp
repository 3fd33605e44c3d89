#include "query_input.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "libbrdf/error.h"
#include "model_options.h"

namespace brdf_cli {

using libbrdf::InvalidArgument;

namespace {
bool looks_like_header(const std::string& line) {
  return line.find_first_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_") != std::string::npos &&
         line.find_first_of("eE") != line.find_first_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_");
}

Query parse_triple(const std::string& text, const char* parameter, std::string origin) {
  try {
    const std::vector<double> v = parse_number_list(text, 3, parameter);
    return {v[0], v[1], v[2], std::move(origin)};
  } catch (const InvalidArgument&) {
    throw InvalidArgument(parameter, origin + ": expected theta_i,theta_s,phi_s in degrees (got '" + text + "')");
  }
}
}  // namespace

std::vector<Query> read_queries(const std::vector<std::string>& at_values, const std::string& source) {
  std::vector<Query> queries;
  for (std::size_t i = 0; i < at_values.size(); ++i)
    queries.push_back(parse_triple(at_values[i], "at", "--at #" + std::to_string(i + 1)));
  if (source.empty()) return queries;
  std::ifstream file;
  std::istream* in = &std::cin;
  if (source != "-") {
    file.open(source);
    if (!file) throw InvalidArgument("queries", "cannot open file '" + source + "'");
    in = &file;
  }
  std::string line;
  int number = 0;
  bool seen_data = false;
  while (std::getline(*in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    if (!seen_data && number == 1 && looks_like_header(line)) continue;  // header line allowed
    seen_data = true;
    queries.push_back(parse_triple(line, "queries", "line " + std::to_string(number)));
  }
  return queries;
}

void write_evaluations(std::ostream& out, const std::vector<Query>& queries,
                       const std::function<double(const libbrdf::ScatterAngles&)>& evaluate) {
  // Evaluate everything first so that an error leaves no partial table on stdout.
  std::vector<double> values(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const Query& q = queries[i];
    try {
      values[i] = evaluate(libbrdf::scatter_angles_from_degrees(q.theta_i_deg, q.theta_s_deg, q.phi_s_deg));
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(e.parameter(), q.origin + ": " + std::string(e.what()).substr(e.parameter().size() + 2));
    }
  }
  out << "theta_i,theta_s,phi_s,value\n";
  char buffer[128];
  for (std::size_t i = 0; i < queries.size(); ++i) {
    std::snprintf(buffer, sizeof buffer, "%.17g,%.17g,%.17g,%.17g\n", queries[i].theta_i_deg, queries[i].theta_s_deg,
                  queries[i].phi_s_deg, values[i]);
    out << buffer;
  }
}

}  // namespace brdf_cli
