#pragma once
// One function per subcommand. Each returns the process exit code: 0 success, 1 the problem was
// processed but the method failed (no plan, no controller), 2 bad input.
#include <string>

namespace marsyn::cli {

int run_plugins(bool show_params);
int run_check(const std::string& config);

}  // namespace marsyn::cli
