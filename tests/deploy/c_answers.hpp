#pragma once
// Answers (x, k) queries with an exported C controller: compiles <dir>/<prefix>.c together with
// tests/deploy/export_driver.c under the strictest flags docs/deploy.md promises, runs it on the
// queries and reads back status, input and the monitor's verdict. Shared by the export tests of
// every tracker, which compare the answers with their C++ controller bit for bit.
// Needs MARSYN_C_COMPILER and MARSYN_EXPORT_DRIVER (paths, defined by CMake).
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace marsyn::deploy_test {

struct CQuery {
  std::int32_t k = 0;
  std::vector<double> x;
};

struct CAnswer {
  std::int32_t status = -1;
  std::vector<double> u;
  std::int32_t inside = -1;
};

// Empty on success, else the exit status and output.
inline std::string run_command(const std::string& cmd) {
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return "popen failed";
  std::string out;
  char buf[4096];
  while (size_t k = fread(buf, 1, sizeof buf, p)) out.append(buf, k);
  const int rc = pclose(p);
  return rc == 0 ? std::string() : "exit " + std::to_string(rc) + ": " + out;
}

inline const char* strict_c99_flags() {
  return "-std=c99 -Wall -Wextra -Werror -pedantic -Wconversion -Wsign-conversion -Wshadow -O2";
}

// Empty on success, else what failed (the compile command and its output, or the run).
inline std::string answer_in_c(const std::filesystem::path& dir, const std::string& prefix, int n, int m,
                               const std::vector<CQuery>& qs, std::vector<CAnswer>& answers) {
  const std::filesystem::path exe = dir / "driver";
  const std::string cc = std::string(MARSYN_C_COMPILER) + " " + strict_c99_flags() + " -I" + dir.string() +
                         " -DCTRL_INPUT=" + prefix + "_input -DCTRL_INSIDE=" + prefix + "_inside \"-DCTRL_HEADER=\\\"" +
                         prefix + ".h\\\"\" -DN=" + std::to_string(n) + " -DM=" + std::to_string(m) + " " +
                         (dir / (prefix + ".c")).string() + " " + MARSYN_EXPORT_DRIVER + " -lm -o " + exe.string();
  if (std::string err = run_command(cc); !err.empty()) return cc + "\n" + err;
  {
    std::ofstream q(dir / "queries.bin", std::ios::binary);
    for (const auto& Q : qs) {
      q.write(reinterpret_cast<const char*>(&Q.k), sizeof Q.k);
      q.write(reinterpret_cast<const char*>(Q.x.data()), static_cast<std::streamsize>(sizeof(double) * Q.x.size()));
    }
  }
  if (std::string err = run_command(exe.string() + " " + (dir / "queries.bin").string() + " " + (dir / "answers.bin").string());
      !err.empty())
    return err;
  std::ifstream a(dir / "answers.bin", std::ios::binary);
  answers.assign(qs.size(), CAnswer{});
  for (auto& A : answers) {
    A.u.resize(static_cast<size_t>(m));
    a.read(reinterpret_cast<char*>(&A.status), sizeof A.status);
    a.read(reinterpret_cast<char*>(A.u.data()), static_cast<std::streamsize>(sizeof(double) * A.u.size()));
    a.read(reinterpret_cast<char*>(&A.inside), sizeof A.inside);
    if (!a) return "answers file too short";
  }
  return "";
}

}  // namespace marsyn::deploy_test
