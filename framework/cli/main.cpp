// cluttertamp: the command-line front end. Each subcommand declares its options in its
// own file of command_line/; main() lists them, runs the one asked for and maps every
// outcome to the documented exit codes (docs/commands.md, "Exit codes").
#include <iostream>
#include <new>

#include "cli/command_line/command.hpp"
#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/core/memory_limit.hpp"
#include "cluttertamp/io/robot_description_io.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/version.hpp"

namespace cli = cluttertamp::cli;
using cluttertamp::run::ExitCode;

namespace {

#define CLUTTERTAMP_CLI_LIST(name) cli::declare_##name,
constexpr cli::CommandDeclaration kCommands[] = {CLUTTERTAMP_CLI_COMMANDS(CLUTTERTAMP_CLI_LIST)};
#undef CLUTTERTAMP_CLI_LIST

// Runs the parsed command; InputError and the rest become exit codes here, in one place.
int run(const cli::Command& command) {
  try {
    return command.run();
  } catch (const cluttertamp::InputError& e) {
    std::cerr << e.diagnostics().str();
    return ExitCode::bad_input;
  } catch (const cluttertamp::io::WriteError& e) {
    // The path was checked before the work: a write failing now is a fault of the run.
    std::cerr << e.what() << "\n";
    return ExitCode::internal_error;
  } catch (const std::bad_alloc&) {
    std::cerr << "cluttertamp: " << cluttertamp::run::memory_limit_reason() << "\n";
    return ExitCode::no_plan;
  } catch (const std::exception& e) {
    std::cerr << "cluttertamp: internal error: " << e.what() << "\n";
    return ExitCode::internal_error;
  } catch (...) {
    std::cerr << "cluttertamp: internal error: an exception of unknown type\n";
    return ExitCode::internal_error;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"cluttertamp " + std::string(cluttertamp::version()) +
               ": task and motion planning for retrieving objects from clutter.\n"
               "Exit codes: 0 solved (or valid), 1 no plan within the limits, 2 bad input, 3 internal error."};
  app.set_version_flag("--version", std::string(cluttertamp::version()));
  app.require_subcommand(1);

  cli::CommonOptions common;
  std::vector<cli::Command> commands;
  for (const cli::CommandDeclaration declare : kCommands) commands.push_back(declare(app, common));

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return ExitCode::bad_input;
  }

  cluttertamp::set_memory_limit(common.memory_limit_mib);
  cluttertamp::io::set_command_line_package_paths(common.package_paths);
  for (const cli::Command& command : commands) {
    if (command.app->parsed()) return run(command);
  }
  return ExitCode::internal_error;
}
