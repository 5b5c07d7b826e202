// Bounds on untrusted text (scene files, --set values, CSV inputs, sweep manifests), shared by
// every parser so that a hostile or careless input gets a short clear error instead of a stack
// overflow, an allocation failure or a message as long as the input.
//  • clip_text: what a message shows of a bad value — at most kMaxQuotedChars characters, control
//    bytes (NUL included, which would cut a C-string message short) written as \xNN, and the
//    length of the whole when it was cut.
//  • json_nesting_error: JSON nested deeper than kMaxJsonDepth (a recursive consumer of the
//    document, or its destructor, would otherwise exhaust the stack).
//  • input_size_error: a text larger than a per-kind limit.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace sglab {

inline constexpr std::size_t kMaxQuotedChars = 80;
// Far deeper than any scene or manifest (4 levels) needs; far shallower than the stack allows.
inline constexpr std::size_t kMaxJsonDepth = 64;
inline constexpr std::size_t kMaxJsonBytes = std::size_t(64) << 20;  // 64 MiB: scenes, --set values, manifests
inline constexpr std::size_t kMaxCsvBytes = std::size_t(4) << 30;    // 4 GiB: tables read whole into memory

// The text as a message shows it: control bytes and DEL escaped as \xNN; cut where what is shown
// would pass max_chars (kMaxQuotedChars) characters, with "… (N bytes)" appended.
inline std::string clip_text(std::string_view s, std::size_t max_chars = kMaxQuotedChars) {
  // max_chars bounds what is shown, escapes included (a control byte shows as 4 characters), so
  // a value of control bytes cannot make the message 4× longer than the bound.
  std::string out;
  for (const char ch : s) {
    const auto u = static_cast<unsigned char>(ch);
    const bool escaped = u < 0x20 || u == 0x7f;
    if (out.size() + (escaped ? 4 : 1) > max_chars) {
      out.append("… (").append(std::to_string(s.size())).append(" bytes)");
      break;
    }
    if (escaped) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += ch;
    }
  }
  return out;
}

// A value as an error message names it: clip_text(s) between single quotes. Every option or field
// that takes a name (a method, a quantity, an environment, a geometry) quotes a bad one through
// this, so that a 100 KB value gives an 80-character quote.
// (Built by appending: GCC 12's -Wrestrict misfires on `"'" + std::string&&`, GCC PR 105651.)
inline std::string quote(std::string_view s) {
  std::string out = "'";
  out += clip_text(s);
  out += '\'';
  return out;
}

// The longest message the command prints (and the Python module raises) for one error: a safety
// net behind quote() for any message that still holds a long text (several long paths, say).
inline constexpr std::size_t kMaxMessageBytes = 2000;

// `message` cut to at most max_bytes bytes (at a UTF-8 character boundary) with "… (N bytes)"
// appended when it was cut; control bytes other than newline and tab kept as they are.
inline std::string bounded_message(std::string_view message, std::size_t max_bytes = kMaxMessageBytes) {
  if (message.size() <= max_bytes) return std::string(message);
  std::size_t cut = max_bytes;
  while (cut > 0 && (static_cast<unsigned char>(message[cut]) & 0xc0) == 0x80) --cut;  // not inside a character
  return std::string(message.substr(0, cut)) + "… (" + std::to_string(message.size()) + " bytes)";
}

// Whether `s` is well-formed UTF-8 (RFC 3629: no overlong forms, no surrogates, at most
// U+10FFFF). JSON holds only UTF-8, so text a command records in JSON (paths in stats and
// manifests) must be.
inline bool valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto b = static_cast<unsigned char>(s[i]);
    std::size_t n = 0;
    unsigned long cp = 0, min = 0;
    if (b < 0x80) {
      ++i;
      continue;
    }
    if ((b & 0xe0) == 0xc0) n = 1, cp = b & 0x1f, min = 0x80;
    else if ((b & 0xf0) == 0xe0) n = 2, cp = b & 0x0f, min = 0x800;
    else if ((b & 0xf8) == 0xf0) n = 3, cp = b & 0x07, min = 0x10000;
    else return false;
    for (std::size_t k = 1; k <= n; ++k) {
      if (i + k >= s.size()) return false;
      const auto c = static_cast<unsigned char>(s[i + k]);
      if ((c & 0xc0) != 0x80) return false;
      cp = (cp << 6) | (c & 0x3f);
    }
    if (cp < min || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return false;
    i += n + 1;
  }
  return true;
}

// Why `text` (JSON) nests too deep for the parser, or nullopt. Counts [ and { outside strings.
inline std::optional<std::string> json_nesting_error(std::string_view text, std::size_t max_depth = kMaxJsonDepth) {
  std::size_t depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (ch == '\\') escaped = true;
      else if (ch == '"') in_string = false;
      continue;
    }
    if (ch == '"') {
      in_string = true;
    } else if (ch == '[' || ch == '{') {
      if (++depth > max_depth)
        return "JSON nested deeper than " + std::to_string(max_depth) + " levels (at byte " + std::to_string(i + 1) +
               ")";
    } else if ((ch == ']' || ch == '}') && depth > 0) {
      --depth;
    }
  }
  return std::nullopt;
}

// Why a text of `bytes` bytes is too large for a `what` ("a scene file") limited to `max`, or nullopt.
inline std::optional<std::string> input_size_error(std::size_t bytes, std::size_t max, const char* what) {
  if (bytes <= max) return std::nullopt;
  return std::string(what) + " of " + std::to_string(bytes) + " bytes exceeds the limit of " + std::to_string(max) +
         " bytes";
}

// A file given as input that cannot be read as one (read_input_file); callers rethrow it as their
// own input error (exit status 2).
struct InputFileError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// The whole of the regular file `path` (a `what`: "a fit record"), read only after its size is
// known to be at most `max_bytes`. Opened without blocking and checked through the open
// descriptor, so a FIFO (which would block forever), a device (/dev/zero, which never ends), a
// directory or an oversize file is refused before a byte is read. Throws InputFileError naming
// the (clipped) path and the reason.
inline std::string read_input_file(const std::string& path, std::size_t max_bytes, const char* what) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw InputFileError(quote(path) + ": cannot open " + what + " (" + std::strerror(errno) + ")");
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0)
    throw InputFileError(quote(path) + ": cannot stat " + what + " (" + std::strerror(errno) + ")");
  if (!S_ISREG(st.st_mode))
    throw InputFileError(quote(path) + " is " +
                         (S_ISDIR(st.st_mode) ? "a directory" : "not a regular file (a device, FIFO or socket)") +
                         ", not " + what);
  if (const auto error = input_size_error(std::size_t(st.st_size), max_bytes, what))
    throw InputFileError(quote(path) + ": " + *error);
  std::string text(std::size_t(st.st_size), '\0');
  std::size_t got = 0;
  while (got < text.size()) {
    const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputFileError(quote(path) + ": cannot read " + what + " (" + std::strerror(errno) + ")");
    if (n == 0) break;  // the file shrank meanwhile
    got += std::size_t(n);
  }
  text.resize(got);
  return text;
}

}  // namespace sglab
