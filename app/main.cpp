// The `holopyramid` program: parses the command line and runs one subcommand.
#include <iostream>
#include <map>
#include <memory>

#include "command.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/core/stats.hpp"

namespace holo::app {

namespace {
std::map<std::string, Command>& registry() {
  static std::map<std::string, Command> commands;
  return commands;
}
}  // namespace

bool registerCommand(Command command) {
  auto name = command.name;
  return registry().emplace(std::move(name), std::move(command)).second;
}

}  // namespace holo::app

int main(int argc, char** argv) {
  using namespace holo;
  CLI::App cli{"holopyramid: mixed-reality rendering for a holographic-pyramid display"};
  cli.require_subcommand(1);
  std::string log_level = "info";
  bool print_stats = false;
  cli.add_option("--log-level", log_level, "trace, debug, info, warn, error or off")->capture_default_str();
  cli.add_flag("--stats", print_stats, "Print the statistics counters at exit");

  std::function<int()> run;
  // A name with a space ("eval depth") is a subcommand of a group ("eval"), made on first use.
  std::map<std::string, CLI::App*> groups;
  const std::map<std::string, std::string> group_descriptions = {
      {"eval", "Measure error against ground truth and its cost in time (subcommands)"},
      {"bench", "Measure speed: medians and ratios from one run (subcommands)"},
  };
  for (auto& [name, command] : app::registry()) {
    CLI::App* parent = &cli;
    std::string leaf = name;
    if (const auto space = name.find(' '); space != std::string::npos) {
      const std::string group = name.substr(0, space);
      leaf = name.substr(space + 1);
      auto& g = groups[group];
      if (!g) {
        const auto described = group_descriptions.find(group);
        g = cli.add_subcommand(
            group, described != group_descriptions.end() ? described->second : "Subcommands of " + group);
        g->require_subcommand(1);
      }
      parent = g;
    }
    CLI::App* sub = parent->add_subcommand(leaf, command.description);
    auto runner = std::make_shared<std::function<int()>>(command.setup(*sub));
    sub->callback([runner, &run] { run = *runner; });
  }
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  try {
    initLogging(parseLogLevel(log_level));
    const int code = run ? run() : 0;
    if (print_stats) stats::print(std::cout);
    return code;
  } catch (const InputError& e) {
    std::cerr << "holopyramid: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "holopyramid: error: " << e.what() << "\n";
    return 1;
  }
}
