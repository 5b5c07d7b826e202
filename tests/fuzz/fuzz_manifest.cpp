// libFuzzer target: `sglab merge` reading a shard's manifest and per-point CSV (sweep.hpp,
// merge_sweep_shards). The input is the manifest text, a NUL, then the CSV text; they are written
// as fz_sweep.shard-0-of-2.json and fz_points.shard-0-of-2.csv into a fresh directory and merged
// (a one-point sweep is whole from shard 0 alone, so a valid pair merges and writes its output).
// Any input must give either a merge or the merge's own InputError with a short message.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "input_error.hpp"
#include "fuzz_common.hpp"
#include "sweep.hpp"

namespace fs = std::filesystem;

namespace {

// A directory of this process, removed at exit (never destroyed before that: the handler uses it).
const fs::path& work_dir() {
  static const fs::path* dir = [] {
    std::string t = (fs::temp_directory_path() / "sglab-fuzz-manifest-XXXXXX").string();
    if (!mkdtemp(t.data())) sglab::fuzz::fail("cannot create a temporary directory");
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(work_dir(), ec);
    });
    return new fs::path(t);
  }();
  return *dir;
}

void write(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::size_t nul = input.find('\0');
  const fs::path in = work_dir() / "in", out = work_dir() / "out";
  fs::remove_all(in);
  fs::remove_all(out);
  fs::create_directories(in);
  const sglab::runner::Shard shard{0, 2};
  write(sglab::runner::sweep_manifest_path(in, "fz", shard), input.substr(0, nul));
  write(sglab::runner::sweep_points_path(in, "fz", shard), nul == std::string::npos ? "" : input.substr(nul + 1));
  try {
    sglab::runner::merge_sweep_shards({in}, out);
  } catch (const sglab::runner::InputError& e) {
    sglab::fuzz::check_message(e.what());
  }
  return 0;
}
