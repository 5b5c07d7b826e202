// libFuzzer target: the CSV reader every `sglab` command that reads a table uses (csv.hpp).
// Any input must give either a table whose rows all have the header's field count or the reader's
// own InputError with a short message; anything else (another exception, a crash, a sanitizer
// report, a message as long as the input) is a finding. See docs/testing.md.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <sstream>
#include <string>

#include "input_error.hpp"
#include "csv.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::istringstream in(text);
  try {
    const auto table = sglab::runner::read_csv(in, "<fuzz>");
    for (const auto& row : table.rows)
      if (row.fields.size() != table.header.size())
        sglab::fuzz::fail("a row whose field count differs from the header's");
  } catch (const sglab::runner::InputError& e) {
    sglab::fuzz::check_message(e.what());
  }
  return 0;
}
