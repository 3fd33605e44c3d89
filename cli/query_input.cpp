#include "query_input.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string_view>

#include "libbrdf/error.h"
#include "model_options.h"

namespace brdf_cli {

using libbrdf::InvalidArgument;

std::string Query::origin() const { return (from_at ? "--at #" : "line ") + std::to_string(number); }

namespace {
// The CSV header is recognised by its names: theta_i,theta_s,phi_s (optionally followed by more
// columns, e.g. the ",value" of eval's own output), blanks around names allowed. Any other first
// line is data, so "30,40,nan" or "inf,40,180" is an error, not a dropped header.
bool is_header(std::string_view line) {
  std::string compact;
  for (char c : line)
    if (c != ' ' && c != '\t') compact += c;
  const std::string names = "theta_i,theta_s,phi_s";
  return compact == names || compact.compare(0, names.size() + 1, names + ",") == 0;
}

// parse_number_list's rules (model_options.cpp: strtod, blanks " \t\r" around items, finite), for
// error messages and the syntaxes only strtod takes ("+30", hexadecimal, other white space).
Query parse_triple(std::string_view text, const char* parameter, int number, bool from_at) {
  const std::string origin = Query{0, 0, 0, number, from_at}.origin();
  try {
    const std::vector<double> v = parse_number_list(std::string(text), 3, parameter);
    return {v[0], v[1], v[2], number, from_at};
  } catch (const InvalidArgument&) {
    throw InvalidArgument(parameter, origin + ": expected theta_i,theta_s,phi_s in degrees (got '" +
                                         libbrdf::message_excerpt(text) + "')");
  }
}

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// One plain decimal number between blanks, by std::from_chars (correctly rounded, as strtod).
bool parse_number_fast(const char* first, const char* last, double* out) {
  while (first < last && is_blank(*first)) ++first;
  while (last > first && is_blank(last[-1])) --last;
  const auto [end, error] = std::from_chars(first, last, *out);
  return first < last && error == std::errc() && end == last && std::isfinite(*out);
}

// The common line "TI,TS,PHIS" of plain decimals: the same values as parse_triple. False for
// anything else, which parse_triple then accepts or reports.
bool parse_triple_fast(std::string_view line, double* v) {
  const char* begin = line.data();
  const char* const end = begin + line.size();
  for (int k = 0; k < 3; ++k) {
    const char* comma = static_cast<const char*>(std::memchr(begin, ',', static_cast<std::size_t>(end - begin)));
    if ((k < 2) != (comma != nullptr)) return false;  // exactly two commas
    if (!parse_number_fast(begin, k < 2 ? comma : end, v + k)) return false;
    begin = comma + 1;
  }
  return true;
}

// Lines of at most kMaxQueryLineLength characters (a query needs three 17-digit numbers, ~75),
// read in blocks: a longer line -- a binary file, /dev/zero -- is an error after that many bytes,
// instead of growing a buffer without bound.
class LineReader {
 public:
  explicit LineReader(std::istream& in) : buffer_(in.rdbuf()), data_(kBlock + kMaxQueryLineLength + 1) {}

  // The next line without its '\n'; false at the end of the input.
  bool next(std::string_view* line, int number) {
    for (;;) {
      const char* start = data_.data() + begin_;
      const char* newline = static_cast<const char*>(std::memchr(start, '\n', end_ - begin_));
      const std::size_t length = newline ? static_cast<std::size_t>(newline - start) : end_ - begin_;
      if (length > kMaxQueryLineLength)
        throw InvalidArgument("queries", "line " + std::to_string(number) + " is longer than " +
                                             std::to_string(kMaxQueryLineLength) + " characters (starts '" +
                                             libbrdf::message_excerpt(std::string_view(start, kMaxQueryLineLength), 40) + "')");
      if (newline || (at_end_ && length > 0)) {
        *line = std::string_view(start, length);
        begin_ += length + (newline ? 1 : 0);
        return true;
      }
      if (at_end_) return false;
      // Keep the partial line, append the next block.
      std::memmove(data_.data(), start, length);
      begin_ = 0;
      end_ = length;
      const std::streamsize got = buffer_->sgetn(data_.data() + end_, static_cast<std::streamsize>(data_.size() - end_));
      if (got <= 0) at_end_ = true;
      else end_ += static_cast<std::size_t>(got);
    }
  }

 private:
  static constexpr std::size_t kBlock = 1 << 16;
  std::streambuf* buffer_;
  std::vector<char> data_;
  std::size_t begin_ = 0, end_ = 0;
  bool at_end_ = false;
};
}  // namespace

std::vector<Query> read_queries(const std::vector<std::string>& at_values, const std::string& source) {
  std::vector<Query> queries;
  for (std::size_t i = 0; i < at_values.size(); ++i)
    queries.push_back(parse_triple(at_values[i], "at", static_cast<int>(i + 1), true));
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
    // At most one query per 6 bytes ("0,0,0\n"): reserved, not touched, so the vector is never
    // copied while it grows and only the pages it fills are mapped.
    const std::uintmax_t bytes = std::filesystem::file_size(source, ec);
    if (!ec && bytes / 6 < (std::uintmax_t{1} << 28)) queries.reserve(queries.size() + static_cast<std::size_t>(bytes / 6) + 1);
  }
  LineReader reader(*in);
  std::string_view line;
  int number = 0;
  bool seen_data = false;
  while (reader.next(&line, number + 1)) {
    ++number;
    // Spreadsheets' "CSV UTF-8" starts the file with a UTF-8 byte-order mark and ends lines with
    // CRLF. The mark is dropped on line 1 only; anywhere else it is an error naming its line.
    constexpr std::string_view kUtf8ByteOrderMark = "\xEF\xBB\xBF";
    if (number == 1 && line.substr(0, kUtf8ByteOrderMark.size()) == kUtf8ByteOrderMark)
      line.remove_prefix(kUtf8ByteOrderMark.size());
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string_view::npos || line[first] == '#') continue;
    if (!seen_data && is_header(line)) {
      seen_data = true;  // the header is allowed once, before any data
      continue;
    }
    seen_data = true;
    double v[3];
    if (parse_triple_fast(line, v)) queries.push_back({v[0], v[1], v[2], number, false});
    else queries.push_back(parse_triple(line, "queries", number, false));
  }
  if (in->bad()) throw InvalidArgument("queries", "read error in '" + libbrdf::message_excerpt(source) + "'");
  return queries;
}

void write_evaluations(std::ostream& out, const std::vector<Query>& queries, const std::vector<double>& values) {
  // Every value checked first so that an error leaves no partial table on stdout. No NaN or Inf
  // ever reaches the output: a model that overflows at a query is an error there.
  for (std::size_t i = 0; i < queries.size(); ++i)
    if (!std::isfinite(values[i]))
      throw InvalidArgument("value", queries[i].origin() + ": not a finite number at this query (the model overflows here; "
                                     "e.g. mbk-rough, eq. 15, grows like 1/g as g -> 0)");
  out << "theta_i,theta_s,phi_s,value\n";
  // Rows into a block, written when nearly full. Each number in the fewest digits that read back
  // as the same double (std::to_chars without a precision: exact, as %.17g, in ~55 ns instead of
  // ~95, and at the same cost for 1.58e-37 as for 0.0158, so that `--model g` cancels the I/O of
  // any model in a subtraction).
  constexpr std::size_t kBlock = 1 << 16, kRow = 4 * 32;
  std::vector<char> block(kBlock);
  std::size_t used = 0;
  auto put = [&](double x, char after) {
    char* const at = block.data() + used;
    char* const stop = std::to_chars(at, block.data() + kBlock, x).ptr;
    *stop = after;
    used += static_cast<std::size_t>(stop - at) + 1;
  };
  for (std::size_t i = 0; i < queries.size(); ++i) {
    if (kBlock - used < kRow) {
      out.write(block.data(), static_cast<std::streamsize>(used));
      used = 0;
    }
    put(queries[i].theta_i_deg, ',');
    put(queries[i].theta_s_deg, ',');
    put(queries[i].phi_s_deg, ',');
    put(values[i], '\n');
  }
  out.write(block.data(), static_cast<std::streamsize>(used));
}

}  // namespace brdf_cli
