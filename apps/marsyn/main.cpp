// The marsyn command line: parses arguments and hands over to core. Bad input of any kind ends
// here as one precise message on stderr and exit code 2; a valid problem on which the method
// fails (no plan, no controller, a violation) ends with exit code 1.
#include <CLI/CLI.hpp>

#include <cstdlib>
#include <iostream>

#include "cli_options.hpp"
#include "commands.hpp"
#include "marsyn/core/problem/config_error.hpp"
#include "marsyn/core/mpi/world.hpp"
#include "marsyn/error.hpp"

int main(int argc, char** argv) {
  // MPI starts only under mpirun/srun (docs/mpi.md); otherwise a world of one, as before.
  marsyn::mpi::World world(argc, argv);
  marsyn::cli::CliOptions o;  // before app, which writes into it
  CLI::App app{
      "marsyn: formally guaranteed, decentralized controllers for multi-agent reach-avoid problems\n"
      "(plan globally, project per agent, track locally with a sound abstraction)"};
  app.set_version_flag("--version", std::string("marsyn ") + MARSYN_VERSION + "\nMPI: " + marsyn::mpi::description());
  app.require_subcommand(1);
  marsyn::cli::add_options(app, o);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Every rank parses the same arguments: rank 0 alone says what is wrong.
    const int code = world.root() ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 2);
    return code == 0 ? 0 : 2;
  }
  const marsyn::Collective* cluster = world.collective();
  // Over MPI, solve and track share the work; any other subcommand is rank 0's alone.
  if (cluster && !world.root() && !marsyn::cli::runs_on_every_rank(o)) return 0;
  // An error in an MPI run: said once, by the rank that had it, and the whole run ends at once
  // (MPI_Abort), never a hang; unless every rank already knows (a bad problem file).
  auto fail = [&](const std::string& message, int code) {
    if (!cluster || marsyn::cli::failure_is_shared()) {
      if (world.root()) std::cerr << message << "\n";
      return code;
    }
    std::cerr << "marsyn (rank " << world.rank() << " of " << world.size() << "): " << message << "\n";
    world.abort(code);
  };

  // One budget for the run, handed to the loader and from there to every stage.
  marsyn::LoadOptions load;
  if (!o.memory_budget.empty()) {
    const std::optional<double> bytes = marsyn::parse_bytes(o.memory_budget);
    if (!bytes)
      return fail("--memory-budget: expected a positive number of bytes such as 8e9 or 8G, got '" + o.memory_budget + "'",
                  2);
    load.memory_budget = {*bytes, "--memory-budget"};
  }

  try {
    return marsyn::cli::run_command(o, load, cluster);
  } catch (const marsyn::cli::QuietExit& e) {
    return e.code;
  } catch (const marsyn::ConfigError& e) {
    return fail(std::string("error: ") + e.what(), 2);
  } catch (const marsyn::ParamError& e) {
    return fail("error: parameter " + marsyn::printable(e.field()) + ": " + marsyn::printable(e.what()), 2);
  } catch (const std::exception& e) {
    return fail("error: " + marsyn::printable(e.what()), 1);
  }
}
