// funnel_export_check CTRL... : exports each funnel controller file to C, answers 1e5 sampled
// (x, k) with the C and with the C++ controller and prints one line per file; exit 1 when a
// status, an input bit or a monitor verdict differs (tests/deploy/c_closed_loop.sh runs it on the
// examples' controllers).
#include <cstdio>
#include <exception>

#include "export_compare.hpp"

int main(int argc, char** argv) {
  int failures = 0;
  for (int a = 1; a < argc; ++a) {
    const std::filesystem::path file(argv[a]);
    try {
      const auto c = marsyn::funnel::read_controller(file.string());
      const auto dir = std::filesystem::temp_directory_path() / ("marsyn_funnel_check_" + file.stem().string());
      const auto r = marsyn::funnel::testing::compare_export(*c, dir, "ctl", 100000, 11);
      std::filesystem::remove_all(dir);
      if (!r.error.empty()) {
        std::printf("%s: %s\n", argv[a], r.error.c_str());
        ++failures;
        continue;
      }
      std::printf("%s: %ld queries, %ld mismatches (Ok %ld, outside the set %ld, outside the horizon %ld; monitor in %ld, "
                  "out %ld; %ld on the sets' boundaries); const data %lld bytes\n%s",
                  argv[a], r.queries, r.mismatches, r.status[0], r.status[1], r.status[2], r.inside, r.outside, r.boundary,
                  r.const_bytes, r.first_mismatches.c_str());
      failures += r.mismatches > 0 || r.status[0] == 0 || r.status[1] == 0 || r.inside == 0 || r.outside == 0;
    } catch (const std::exception& e) {
      std::printf("%s: %s\n", argv[a], e.what());
      ++failures;
    }
  }
  return failures == 0 && argc > 1 ? 0 : 1;
}
