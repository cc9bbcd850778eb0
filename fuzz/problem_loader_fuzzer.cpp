// libFuzzer target over the problem loader (docs/problem-format.md, "Fuzzing the loader"). The
// contract under test: for any bytes, load_problem either returns a problem or throws a
// ConfigError (or a ParamError the CLI reports the same way); anything else (another exception,
// a crash, a sanitizer report, a hang) is a bug. Inputs naming `plugin_paths` are skipped: they
// make the loader dlopen arbitrary libraries, which is the feature, not a bug.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "marsyn/core/problem/config_error.hpp"
#include "marsyn/core/problem/problem_loader.hpp"
#include "marsyn/error.hpp"

namespace {
std::string g_path;
// A small budget keeps the loader's estimates, not the fuzzer's RSS limit, in charge.
const marsyn::LoadOptions kLoad{{256.0 * 1024 * 1024, "the fuzzer's budget"}};
}

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* tmp = std::getenv("TMPDIR");
  g_path = std::string(tmp && *tmp ? tmp : "/tmp") + "/marsyn-fuzz-" + std::to_string(::getpid()) + ".yaml";
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (text.find("plugin_paths") != std::string::npos) return 0;
  std::FILE* f = std::fopen(g_path.c_str(), "wb");
  if (!f) std::abort();
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  try {
    const marsyn::LoadedProblem lp = marsyn::load_problem(g_path, kLoad);
    (void)lp;
  } catch (const marsyn::ConfigError& e) {
    // The message must be one printable line.
    for (const char c : std::string(e.what()))
      if (c == '\n' || c == '\0') {
        std::fprintf(stderr, "ConfigError message with a raw newline or NUL: %s\n", e.what());
        std::abort();
      }
  } catch (const marsyn::ParamError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "load_problem threw something other than ConfigError: %s\n", e.what());
    std::abort();
  }
  return 0;
}
