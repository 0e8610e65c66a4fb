// The `anima` command line tool: builds the CLI11 application, lets every
// subcommand register itself, and turns exceptions into messages and exit
// codes (0 success, 1 error, 2 usage error).
#include "commands.hpp"
#include "common.hpp"

#include <anima/core/version.hpp>

#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>
#include <string>

namespace {

std::string version_string() {
    return "anima " + std::to_string(anima::version_major) + "." + std::to_string(anima::version_minor) + "." +
           std::to_string(anima::version_patch);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"anima: character animation on BVH motion capture clips.", "anima"};
    // Set before adding subcommands: they copy it when created.
    app.failure_message([](const CLI::App* a, const CLI::Error& e) { return "anima: " + CLI::FailureMessage::simple(a, e); });
    app.set_version_flag("--version", version_string(), "Print the version and exit");
    app.require_subcommand(1);

    register_info(app);
    register_convert(app);
    register_render(app);
    register_transition(app);
    register_symmetry(app);
    register_playback(app);
    register_poisson(app);
    register_smooth(app);
    register_maxflow(app);
    register_texture(app);
    register_ik(app);
    register_flight(app);
    register_sadm(app);
    // Keep after the last register_*: subcommands created later would copy it
    // into their own --help.
    app.footer("Run 'anima SUBCOMMAND --help' for the options of a subcommand.");

    try {
        app.parse(argc, argv);
    } catch (const CLI::Error& e) {
        // --help and --version come here too, with exit code 0.
        return app.exit(e) == 0 ? 0 : 2;
    } catch (const std::exception& e) {
        std::cout.flush();
        std::cerr << "anima: " << e.what() << '\n';
        return 1;
    }
    std::cout.flush();
    if (!std::cout) {
        std::cerr << "anima: error while writing to standard output\n";
        return 1;
    }
    return 0;
}
