// The `anima` command line tool: builds the CLI11 application, lets every
// subcommand register itself, and turns exceptions into messages and exit
// codes (0 success, 1 error, 2 usage error).
#include "commands.hpp"
#include "common.hpp"

#include <anima/core/error.hpp>
#include <anima/core/version.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstddef>
#include <exception>
#include <iostream>
#include <string>
#include <string_view>

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
    register_view(app);
    register_transition(app);
    register_symmetry(app);
    register_playback(app);
    register_poisson(app);
    register_smooth(app);
    register_maxflow(app);
    register_contacts(app);
    register_texture(app);
    register_ik(app);
    register_flight(app);
    register_sadm(app);
    // Keep after the last register_*: subcommands created later would copy it
    // into their own --help.
    app.footer("Run 'anima SUBCOMMAND --help' for the options of a subcommand.");

    // CLI11 would say "A subcommand is required" for a mistyped one: name it.
    if (argc > 1 && argv[1][0] != '-') {
        const std::string name = argv[1];
        bool known = false;
        for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
            known = known || sub->check_name(name);
        if (!known) {
            std::cerr << "anima: '" << anima::escape_for_message(name, 100)
                      << "' is not a subcommand; run 'anima --help' for the list\n";
            return 2;
        }
    }
    try {
        app.parse(argc, argv);
        anima_cli::commit_outputs();
    } catch (const CLI::Error& e) {
        anima_cli::discard_outputs();
        // --help and --version come here too, with exit code 0.
        return app.exit(e) == 0 ? 0 : 2;
    } catch (const std::exception& e) {
        anima_cli::discard_outputs();
        std::cout.flush();
        // Text quoted from files is escaped where it is quoted; this catches
        // anything else (a path, a system message) with raw bytes in it.
        // Line breaks of a multi-line message stay.
        const std::string what = e.what();
        std::string shown;
        for (std::size_t begin = 0; begin <= what.size();) {
            const std::size_t end = std::min(what.find('\n', begin), what.size());
            if (begin) shown += '\n';
            shown += anima::escape_for_message(std::string_view(what).substr(begin, end - begin), 4000);
            begin = end + 1;
        }
        std::cerr << "anima: " << shown << '\n';
        return 1;
    }
    std::cout.flush();
    if (!std::cout) {
        std::cerr << "anima: error while writing to standard output\n";
        return 1;
    }
    return 0;
}
