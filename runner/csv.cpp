#include "csv.hpp"

#include <algorithm>
#include <istream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include <fmt/core.h>

#include "input_error.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::runner {
namespace {

class Parser {
 public:
  Parser(std::string_view text, const std::string& source) : s_(text), source_(source) {}

  bool at_end() const { return i_ >= s_.size(); }
  // Whether only line ends remain (trailing blank lines, which are not rows).
  bool only_line_ends_left() const { return s_.find_first_not_of("\r\n", i_) == std::string_view::npos; }
  std::size_t line() const { return line_; }

  // One record, consuming its line end (LF, CRLF or a lone CR).
  std::vector<std::string> record() {
    std::vector<std::string> fields;
    for (;;) {
      fields.push_back(at(i_) == '"' ? quoted_field() : plain_field());
      if (at(i_) == ',') {
        ++i_;
        continue;
      }
      if (at(i_) == '\r') ++i_;
      if (at(i_) == '\n') ++i_;
      ++line_;
      return fields;
    }
  }

 private:
  // The character at j, or '\0' past the end (callers only compare it with ',', '"', CR, LF).
  char at(std::size_t j) const { return j < s_.size() ? s_[j] : '\0'; }
  bool ends_field(std::size_t j) const { return j >= s_.size() || s_[j] == ',' || s_[j] == '\n' || s_[j] == '\r'; }

  std::string plain_field() {
    const std::size_t start = i_;
    while (!ends_field(i_)) {
      if (s_[i_] == '"')
        throw InputError(
            fmt::format("{}: line {}: a double quote inside an unquoted field "
                        "(quote the whole field and double the quote)",
                        source_, line_));
      ++i_;
    }
    return std::string(s_.substr(start, i_ - start));
  }

  std::string quoted_field() {
    const std::size_t start_line = line_;
    std::string field;
    ++i_;  // opening quote
    for (;;) {
      if (at_end()) throw InputError(fmt::format("{}: line {}: quoted field is never closed", source_, start_line));
      const char ch = s_[i_++];
      if (ch == '"') {
        if (at(i_) != '"') break;
        ++i_;  // "" is one quote
      } else if (ch == '\n') {
        ++line_;
      }
      field += ch;
    }
    if (!ends_field(i_))
      throw InputError(fmt::format("{}: line {}: text after the closing quote of a field", source_, line_));
    return field;
  }

  std::string_view s_;
  const std::string& source_;
  std::size_t i_ = 0;
  std::size_t line_ = 1;
};

bool needs_quotes(const std::string& field) { return field.find_first_of(",\"\r\n") != std::string::npos; }

}  // namespace

std::size_t CsvTable::column(const std::string& name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  return it == header.end() ? npos : static_cast<std::size_t>(it - header.begin());
}

CsvTable read_csv(std::istream& in, const std::string& source) {
  std::string text;
  // Read in blocks so that an input beyond the limit is refused before it fills the memory.
  for (char block[1 << 16]; in.read(block, sizeof block) || in.gcount() > 0;) {
    text.append(block, std::size_t(in.gcount()));
    if (const auto error = input_size_error(text.size(), kMaxCsvBytes, "the input"))
      throw InputError(source + ": " + *error);
  }
  if (in.bad()) throw std::runtime_error(source + ": read error");
  std::string_view body = text;
  constexpr std::string_view kBom = "\xEF\xBB\xBF";
  if (body.starts_with(kBom)) body.remove_prefix(kBom.size());
  if (body.empty()) throw InputError(source + ": the input is empty; expected a CSV header line");

  Parser parser(body, source);
  CsvTable table;
  table.header = parser.record();
  for (std::size_t i = 0; i < table.header.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (table.header[i] == table.header[j])
        throw InputError(
            fmt::format("{}: line 1: column '{}' appears twice in the header", source, clip_text(table.header[i])));
  while (!parser.at_end()) {
    CsvRecord record;
    record.line = parser.line();
    record.fields = parser.record();
    if (record.fields.size() == 1 && record.fields[0].empty() && table.header.size() > 1 &&
        parser.only_line_ends_left())
      break;  // blank lines at the end of the input
    if (record.fields.size() != table.header.size())
      throw InputError(fmt::format("{}: row {} (line {}) has {} field{}, the header has {}", source,
                                   table.rows.size() + 1, record.line, record.fields.size(),
                                   record.fields.size() == 1 ? "" : "s", table.header.size()));
    table.rows.push_back(std::move(record));
  }
  return table;
}

TableFile read_table_file(const std::string& path) {
  std::string text;
  try {
    text = read_input_file(path, kMaxCsvBytes, "a table");
  } catch (const InputFileError& e) {
    throw InputError(e.what());
  }
  TableFile t;
  std::size_t body = 0;
  while (body < text.size() && text[body] == '#') {
    const std::size_t end = std::min(text.find('\n', body), text.size());
    const std::string_view line(text.data() + body, end - body);
    constexpr std::string_view kGenerated = "# Generated by `";
    if (t.command.empty() && line.substr(0, kGenerated.size()) == kGenerated) {
      const std::size_t close = line.find('`', kGenerated.size());
      if (close != std::string_view::npos)
        t.command = std::string(line.substr(kGenerated.size(), close - kGenerated.size()));
    }
    body = end + 1;
  }
  std::istringstream in(body < text.size() ? text.substr(body) : std::string());
  t.csv = read_csv(in, path);
  return t;
}

void append_csv_record(std::string& out, std::span<const std::string> fields) {
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i > 0) out += ',';
    const std::string& f = fields[i];
    if (!needs_quotes(f)) {
      out += f;
      continue;
    }
    out += '"';
    for (const char ch : f) {
      if (ch == '"') out += '"';
      out += ch;
    }
    out += '"';
  }
  out += '\n';
}

}  // namespace sglab::runner
