// The bad-input suite: tests/bad_inputs/<fault>.yaml, one fault class per file, each derived from
// a valid problem. Every file states where the fault is and what the message must say:
//   # at: LINE:COLUMN      (or '-' for a fault of the file as a whole)
//   # field: PATH          (or '-' when the message names no field)
//   # message: TEXT        (a part of the expected message)
// `marsyn check` must answer each with exit code 2 and exactly one line
// "error: FILE:LINE:COLUMN: PATH: ..." containing TEXT, with no raw control bytes or malformed
// UTF-8 in it. `solve` must give the same answer before creating any file.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "run.hpp"

namespace fs = std::filesystem;
using marsyn::test::run_marsyn;
using marsyn::test::slurp;

namespace {

const fs::path kDir = fs::path(MARSYN_SOURCE_DIR) / "tests/bad_inputs";

std::vector<std::string> bad_input_files() {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(kDir))
    if (e.path().extension() == ".yaml") out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

struct Expectation {
  std::string at, field, message;
};

Expectation header(const std::string& text) {
  Expectation e;
  std::size_t pos = 0;
  while (pos < text.size() && text[pos] == '#') {
    const std::size_t end = text.find('\n', pos);
    const std::string line = text.substr(pos, end - pos);
    auto value = [&](const std::string& key) { return line.rfind(key, 0) == 0 ? line.substr(key.size()) : std::string(); };
    if (!value("# at: ").empty()) e.at = value("# at: ");
    if (!value("# field: ").empty()) e.field = value("# field: ");
    if (!value("# message: ").empty()) e.message = value("# message: ");
    if (end == std::string::npos) break;
    pos = end + 1;
  }
  return e;
}

// No byte a terminal would interpret: printable ASCII, or well-formed UTF-8 sequences, and one
// newline at the end.
bool terminal_safe(const std::string& s) {
  for (std::size_t i = 0; i + 1 < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 || c == 0x7F) return false;
    if (c >= 0x80) {
      const int len = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
      if (len == 0 || i + len > s.size()) return false;
      for (int k = 1; k < len; ++k)
        if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return false;
      i += len - 1;
    }
  }
  return s.empty() || s.back() == '\n';
}

std::set<std::string> files_under(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) out.insert(e.path().string());
  return out;
}

class BadInput : public ::testing::TestWithParam<std::string> {};

TEST_P(BadInput, CheckAnswersWithOneLocatedLine) {
  const std::string file = (kDir / GetParam()).string();
  const Expectation e = header(slurp(file));
  ASSERT_FALSE(e.at.empty() || e.field.empty() || e.message.empty())
      << file << " must carry '# at:', '# field:' and '# message:' lines";
  const auto r = run_marsyn("check " + file);
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  std::string prefix = "error: " + file + (e.at == "-" ? "" : ":" + e.at) + ": ";
  if (e.field != "-") prefix += e.field + ": ";
  EXPECT_EQ(r.err.rfind(prefix, 0), 0u) << "expected the prefix\n  " << prefix << "\ngot\n  " << r.err;
  EXPECT_NE(r.err.find(e.message), std::string::npos) << "expected '" << e.message << "' in\n  " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "exactly one line: " << r.err;
  EXPECT_TRUE(terminal_safe(r.err)) << "raw control bytes or malformed UTF-8 on stderr";
}

// Every command loads the problem first: solve answers the same way and writes nothing, neither
// under --out nor anywhere else in its working directory (marsyn-out/ included).
TEST_P(BadInput, SolveAnswersTheSameAndWritesNothing) {
  const std::string file = (kDir / GetParam()).string();
  const fs::path scratch = fs::temp_directory_path() / ("marsyn_bad_" + std::to_string(::getpid()) + "_" +
                                                        fs::path(GetParam()).stem().string());
  fs::remove_all(scratch);
  fs::create_directories(scratch / "cwd");
  const auto check = run_marsyn("check " + file);
  const auto solve = run_marsyn("solve " + file + " --out " + (scratch / "cwd/out").string() + " --runs 5",
                                "cd " + (scratch / "cwd").string() + " &&");
  EXPECT_EQ(solve.code, 2) << solve.err;
  EXPECT_EQ(solve.err, check.err);
  const auto plan = run_marsyn("plan " + file, "cd " + (scratch / "cwd").string() + " &&");
  EXPECT_EQ(plan.code, 2) << plan.err;
  EXPECT_EQ(files_under(scratch), std::set<std::string>{(scratch / "cwd").string()});
  fs::remove_all(scratch);
}

INSTANTIATE_TEST_SUITE_P(Files, BadInput, ::testing::ValuesIn(bad_input_files()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string n = fs::path(info.param).stem().string();
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

}  // namespace
