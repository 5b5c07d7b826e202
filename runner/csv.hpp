// CSV with a header line (RFC 4180: comma-separated, fields with commas, quotes or line breaks
// in double quotes, "" for a quote inside them; LF or CRLF line ends). Every command that reads
// or writes tables uses these two functions, so quoting and error messages are the same
// everywhere.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <span>
#include <string>
#include <vector>

#include "input_error.hpp"

namespace sglab::runner {

struct CsvRecord {
  std::vector<std::string> fields;  // the field texts, unquoted
  std::size_t line = 0;             // 1-based line of the input on which the record starts
};

struct CsvTable {
  std::vector<std::string> header;  // column names, unique
  std::vector<CsvRecord> rows;      // each with exactly header.size() fields

  // Index of the column called `name` in the header, or npos.
  std::size_t column(const std::string& name) const;
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);
};

// Reads a whole table. `source` names the input in messages (a path, or "<stdin>"). Throws
// InputError naming the line for malformed input: no header, an unterminated quote, a row
// whose field count differs from the header's, or a duplicate column name (columns are found
// by name, so a duplicate would be ambiguous). A UTF-8 byte-order mark before the header is
// skipped (spreadsheet programs write one), and so are blank lines at the end. An input beyond
// kMaxCsvBytes (text_limits.hpp) is refused as it is read; messages clip the values they quote.
CsvTable read_csv(std::istream& in, const std::string& source);

// Appends one record to `out`: fields joined by commas, quoted only where needed, then "\n".
void append_csv_record(std::string& out, std::span<const std::string> fields);

}  // namespace sglab::runner
