#pragma once
// Runs the marsyn executable as a user would and captures exit code, stdout and stderr.
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../support/temp_dir.hpp"

namespace marsyn::test {

struct RunResult {
  int code = -1;
  std::string out, err;
};

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

inline RunResult run_exe(const std::string& exe, const std::string& args, const std::string& env = "") {
  namespace fs = std::filesystem;
  static int counter = 0;
  const fs::path dir = process_temp_dir("marsyn_cli_");
  const std::string base = (dir / std::to_string(counter++)).string();
  const std::string cmd = env + " " + exe + " " + args + " >" + base + ".out 2>" + base + ".err";
  const int status = std::system(cmd.c_str());
  RunResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(base + ".out");
  r.err = slurp(base + ".err");
  return r;
}

inline RunResult run_marsyn(const std::string& args, const std::string& env = "") { return run_exe(MARSYN_EXE, args, env); }

inline std::string write_temp(const std::string& name, const std::string& text) {
  const std::filesystem::path p = process_temp_dir("marsyn_cfg_") / name;
  std::ofstream(p) << text;
  return p.string();
}

}  // namespace marsyn::test
