// anima view A.bvh [B.bvh ...] -o PAGE.html: a page that plays the clips in
// a browser, side by side or overlaid, in sync (view_page.hpp).
#include "commands.hpp"
#include "common.hpp"
#include "view_page.hpp"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace anima_cli {
namespace {

struct view_options {
    std::vector<std::string> inputs;
    std::string output, title, up;
    bool overlay = false;
};

void run_view(const view_options& o) {
    check_outputs({{"--output", &o.output}});
    view_page page;
    page.overlay = o.overlay;
    if (!o.up.empty()) page.up = parse_signed_axis(o.up);
    std::vector<std::string> names;
    for (const std::string& path : o.inputs) {
        page.clips.push_back({file_name(path), load_clip(path)});
        names.push_back(file_name(path));
    }
    page.title = o.title.empty() ? join(names, " | ") : o.title;
    report_written(write_view_page(o.output, page));
}

}  // namespace
}  // namespace anima_cli

void register_view(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, opts] = add_command<view_options>(
        app, "view", "Write a self-contained HTML page that plays clips side by side or overlaid, with foot contacts",
        run_view);
    sub->add_option("CLIPS", opts->inputs, "BVH clips to play together")->required()->type_name("CLIP.bvh ...");
    sub->add_option("-o,--output", opts->output, "The page to write (open it in a browser, no server needed)")
        ->required()
        ->type_name("PAGE.html");
    sub->add_flag("--overlay", opts->overlay, "Draw the clips in one place, one colour each, instead of side by side");
    sub->add_option("--title", opts->title, "Title of the page (default: the file names)");
    add_up_option(*sub, opts->up, "The clips' up axis, instead of the one guessed from each skeleton");
}
