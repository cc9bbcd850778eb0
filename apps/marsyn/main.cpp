// The marsyn command line: parses arguments and hands over to core. Bad input of any kind ends
// here as one precise message on stderr and exit code 2.
#include <CLI/CLI.hpp>

#include <iostream>

#include "commands.hpp"
#include "marsyn/core/config_error.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "marsyn: formally guaranteed, decentralized controllers for multi-agent reach-avoid problems\n"
      "(plan globally, project per agent, track locally with a sound abstraction)"};
  app.set_version_flag("--version", std::string("marsyn ") + MARSYN_VERSION);
  app.require_subcommand(1);

  bool show_params = false;
  auto* plugins = app.add_subcommand("plugins", "list every plugin found: kind, name, library");
  plugins->add_flag("--params", show_params, "also list each plugin's parameters");

  std::string config;
  auto* check = app.add_subcommand("check", "load and validate a problem file, print a summary");
  check->add_option("CONFIG", config, "problem file (YAML)")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  try {
    if (*plugins) return marsyn::cli::run_plugins(show_params);
    if (*check) return marsyn::cli::run_check(config);
  } catch (const marsyn::ConfigError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
  return 2;
}
