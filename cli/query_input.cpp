#include "query_input.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "libbrdf/error.h"
#include "model_options.h"

namespace brdf_cli {

using libbrdf::InvalidArgument;

namespace {
// The CSV header is recognised by its names: theta_i,theta_s,phi_s (optionally followed by more
// columns, e.g. the ",value" of eval's own output), blanks around names allowed. Any other first
// line is data, so "30,40,nan" or "inf,40,180" is an error, not a dropped header.
bool is_header(const std::string& line) {
  std::string compact;
  for (char c : line)
    if (c != ' ' && c != '\t') compact += c;
  const std::string names = "theta_i,theta_s,phi_s";
  return compact == names || compact.compare(0, names.size() + 1, names + ",") == 0;
}

Query parse_triple(const std::string& text, const char* parameter, std::string origin) {
  try {
    const std::vector<double> v = parse_number_list(text, 3, parameter);
    return {v[0], v[1], v[2], std::move(origin)};
  } catch (const InvalidArgument&) {
    throw InvalidArgument(parameter, origin + ": expected theta_i,theta_s,phi_s in degrees (got '" +
                                         libbrdf::message_excerpt(text) + "')");
  }
}

// One line of at most kMaxQueryLineLength characters (a query needs three 17-digit numbers,
// ~75): a longer line -- a binary file, /dev/zero -- is an error after that many bytes, instead
// of growing a string without bound. False at the end of the input.
bool read_line(std::istream& in, std::string& line, int number) {
  line.clear();
  std::streambuf* buffer = in.rdbuf();
  for (;;) {
    const int c = buffer->sbumpc();
    if (c == std::char_traits<char>::eof()) return !line.empty();
    if (c == '\n') return true;
    if (line.size() >= kMaxQueryLineLength)
      throw InvalidArgument("queries", "line " + std::to_string(number) + " is longer than " +
                                           std::to_string(kMaxQueryLineLength) + " characters (starts '" +
                                           libbrdf::message_excerpt(line, 40) + "')");
    line += static_cast<char>(c);
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
    std::error_code ec;
    if (std::filesystem::is_directory(source, ec))
      throw InvalidArgument("queries", "'" + libbrdf::message_excerpt(source) + "' is a directory, not a CSV file");
    file.open(source, std::ios::binary);
    if (!file) throw InvalidArgument("queries", "cannot open file '" + libbrdf::message_excerpt(source) + "'");
    in = &file;
  }
  std::string line;
  int number = 0;
  bool seen_data = false;
  while (read_line(*in, line, number + 1)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    if (!seen_data && is_header(line)) {
      seen_data = true;  // the header is allowed once, before any data
      continue;
    }
    seen_data = true;
    queries.push_back(parse_triple(line, "queries", "line " + std::to_string(number)));
  }
  if (in->bad()) throw InvalidArgument("queries", "read error in '" + libbrdf::message_excerpt(source) + "'");
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
      // No NaN or Inf ever reaches the output: a model that overflows at a query is an error there.
      if (!std::isfinite(values[i]))
        throw InvalidArgument("value", "not a finite number at this query (the model overflows here; e.g. mbk-rough, "
                                       "eq. 15, grows like 1/g as g -> 0)");
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
