// The subcommands of the `anima` tool. Each lives in its own
// cmd_<name>.cpp and adds itself to the application with register_<name>,
// which main() calls in the order the subcommands appear in --help.
//
// A subcommand adds its options and a callback that does the work. The
// callback reports failures by throwing: anima::error or anima_cli::failure
// (common.hpp) for runtime errors (main prints "anima: <message>", exit 1),
// a CLI::ParseError-derived error for usage errors (exit 2).
#pragma once

namespace CLI {
class App;
}

void register_info(CLI::App& app);
void register_convert(CLI::App& app);
void register_render(CLI::App& app);
void register_view(CLI::App& app);
void register_transition(CLI::App& app);
void register_symmetry(CLI::App& app);
void register_playback(CLI::App& app);
void register_poisson(CLI::App& app);
void register_smooth(CLI::App& app);
void register_maxflow(CLI::App& app);
void register_contacts(CLI::App& app);
void register_texture(CLI::App& app);
void register_ik(CLI::App& app);
void register_flight(CLI::App& app);
void register_sadm(CLI::App& app);
