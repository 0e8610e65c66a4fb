// anima ik IN.bvh --frame F --effector NAME --target X,Y,Z [...] -o OUT.bvh:
// solves frame F's pose so that each named joint reaches its target and
// writes the clip with that frame replaced. --offset NAME --frames A-B --by
// X,Y,Z instead moves a joint by an offset over a frame range, and
// --targets FILE.csv gives world targets per frame (lines
// "frame,effector,x,y,z"); both solve frame by frame with
// anima::solve_clip_ik: each frame starts from its recorded pose plus the
// previous frame's correction and is pulled toward its recorded pose in the
// null space, so the result stays smooth.
#include "commands.hpp"
#include "common.hpp"
#include "view_page.hpp"

#include <anima/core/stopwatch.hpp>
#include <anima/core/text.hpp>
#include <anima/ik.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace anima_cli {
namespace {

struct ik_options {
    std::string input, output, view, rotation_order, solver = "dls", offset, frames, by, model_out, targets_file;
    std::size_t frame = 0;
    std::vector<std::string> effectors, targets, train;
    int iterations = 100, restarts = 3;
    double tolerance = 1e-5;
    bool json = false;
};

vec3 parse_vec3(const std::string& text, const char* option) {
    std::stringstream s(text);
    vec3 v;
    char c1 = 0, c2 = 0;
    if (!(s >> v.x() >> c1 >> v.y() >> c2 >> v.z()) || c1 != ',' || c2 != ',' || !v.allFinite())
        throw CLI::ValidationError(option, "expected X,Y,Z (three finite numbers), got '" + text + "'");
    return v;
}

using frame_targets = std::map<std::size_t, std::vector<std::pair<std::string, vec3>>>;

/// A frame number: digits only (no sign, no spaces), at most max_frames.
bool parse_frame(const std::string& text, std::size_t& frame) {
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return false;
    unsigned long long v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (r.ec != std::errc() || v > max_frames) return false;
    frame = static_cast<std::size_t>(v);
    return true;
}

/// The goals of a --targets file (anima::parse_position_targets: every
/// error names the file and line), by effector name.
frame_targets read_targets(const std::string& path, const clip_t& c) {
    frame_targets targets;
    for (const auto& frame : anima::parse_position_targets(read_text_file(path), path, c.skeleton(), c.frames()))
        for (const auto& goal : frame.goals) targets[frame.frame].emplace_back(c.skeleton()[goal.joint].name, goal.position);
    return targets;
}

using wanted_list = std::vector<std::pair<std::string, vec3>>;

/// A frame's targets in the order of the learned model's effectors; every
/// effector must have one.
wanted_list in_model_order(const wanted_list& listed, const wanted_list& model, std::size_t frame) {
    wanted_list out;
    for (const auto& m : model) {
        const auto it = std::find_if(listed.begin(), listed.end(), [&](const auto& w) { return w.first == m.first; });
        if (it == listed.end())
            throw failure("frame " + std::to_string(frame) + " has no target for '" + m.first +
                          "': the learned solver needs a target for every effector it was trained on, in every frame");
        out.push_back(*it);
    }
    return out;
}

struct solver_setup {
    anima::kinematic_tree<double> tree;
    anima::ik_params<double> params;
    std::unique_ptr<anima::learned_ik_model<double>> model;
};

/// The library's solvers and the learned one.
std::vector<std::string> solver_names() {
    auto names = anima::enum_name_list<anima::ik_solver>();
    names.push_back("learned");
    return names;
}

/// The index of joint `name`, or a failure naming the file (and a joint
/// whose name differs only in case).
std::size_t joint_named(const skeleton_t& sk, const std::string& name, const std::string& input) {
    if (const auto j = sk.find(name)) return *j;
    throw failure("no joint named '" + name + "' in '" + input + "'" + sk.did_you_mean(name));
}

/// Per frame, the effectors and their world targets (in offset mode the
/// joint's recorded position plus the offset: anima::offset_goals), from
/// whichever of the three modes the options use.
frame_targets collect_targets(const ik_options& o, const clip_t& c) {
    const bool offset_mode = !o.offset.empty();
    const bool file_mode = !o.targets_file.empty();
    if (offset_mode + file_mode + !o.effectors.empty() > 1)
        throw CLI::ValidationError("--offset/--targets/--effector", "use one of target, offset and file mode");
    frame_targets per_frame;
    if (file_mode) {
        per_frame = read_targets(o.targets_file, c);
    } else if (offset_mode) {
        const auto dash = o.frames.find('-');
        std::size_t first = 0, last = 0;
        if (!parse_frame(o.frames.substr(0, dash), first) ||
            !parse_frame(dash == std::string::npos ? o.frames : o.frames.substr(dash + 1), last))
            throw CLI::ValidationError("--frames", "expected A-B (two frame numbers, A <= B), got '" +
                                                       anima::escape_for_message(o.frames, 60) + "'");
        if (first > last)
            throw CLI::ValidationError("--frames", o.frames + " is reversed: the first frame comes after the last (use " +
                                                       std::to_string(last) + "-" + std::to_string(first) + ")");
        if (last >= c.frames())
            throw failure("--frames " + o.frames + " is not within 0.." + std::to_string(c.frames() - 1) + " of '" +
                          o.input + "'");
        const vec3 by = parse_vec3(o.by, "--by");
        for (const auto& g : anima::offset_goals(c, joint_named(c.skeleton(), o.offset, o.input), by, first, last))
            per_frame[g.frame].emplace_back(o.offset, g.goals[0].position);
    } else {
        if (o.effectors.empty() || o.effectors.size() != o.targets.size())
            throw CLI::ValidationError("--effector/--target", "give one --target per --effector (" +
                                       std::to_string(o.effectors.size()) + " effectors, " +
                                       std::to_string(o.targets.size()) + " targets)");
        if (o.frame >= c.frames())
            throw failure("--frame " + std::to_string(o.frame) + " is outside 0.." + std::to_string(c.frames() - 1));
        for (std::size_t i = 0; i < o.effectors.size(); ++i)
            per_frame[o.frame].emplace_back(o.effectors[i], parse_vec3(o.targets[i], "--target"));
    }
    return per_frame;
}

/// Trains the learned solver's model on the --train clips (and saves it
/// with --save-model).
void train_model(const ik_options& o, solver_setup& s, const wanted_list& wanted) {
    const auto& sk = s.tree.skeleton();
    if (o.train.empty()) throw CLI::ValidationError("--train", "the learned solver needs at least one --train clip");
    std::vector<anima::ik_effector<double>> eff;
    for (const auto& w : wanted) eff.push_back({w.first, vec3::Zero()});
    anima::ik_matrix<double> poses(s.tree.dofs(), 0);
    for (const auto& path : o.train) {
        const clip_t t = load_clip(path);
        if (t.skeleton() != sk) throw failure("--train '" + path + "' has another skeleton than '" + o.input + "'");
        const auto p = anima::clip_poses(s.tree, t);
        poses.conservativeResize(Eigen::NoChange, poses.cols() + p.cols());
        poses.rightCols(p.cols()) = p;
    }
    std::cerr << "anima ik: training on " << poses.cols() << " poses\n";
    s.model = std::make_unique<anima::learned_ik_model<double>>(
        anima::learned_ik_model<double>::train(s.tree, eff, poses));
    if (!o.model_out.empty()) {
        std::ostringstream text;
        s.model->save(text);
        write_text_file(o.model_out, text.str());
    }
}

/// The JSON entries of the effectors (a range reports its last frame), and
/// a warning on stderr for each effector that missed its target anywhere.
json effector_report(const anima::clip_ik_result<double>& solved, const std::vector<anima::frame_goals<double>>& goals,
                     const std::vector<wanted_list>& goal_names, const skeleton_t& sk,
                     const std::vector<Eigen::Index>& clusters, double tolerance, bool smooth) {
    const std::size_t last = solved.frames.back();
    const bool learned = !clusters.empty();
    json effectors = json::array();
    for (std::size_t i = 0; i < solved.frames.size(); ++i) {
        const std::size_t f = solved.frames[i];
        const auto& r = solved.results[i];
        for (std::size_t k = 0; k < goal_names[i].size(); ++k) {
            const double error = r.errors[k].position;
            if (smooth && f != last) continue;  // a range reports its last frame
            json e = {{"name", goal_names[i][k].first},
                      {"frame", f},
                      {"error", error},
                      {"reached", error <= tolerance},
                      {"status", anima::to_string(r.status)}};
            if (learned) e["cluster"] = clusters[i];
            effectors.push_back(std::move(e));
        }
    }
    // Warned about in the order of their names.
    std::vector<anima::goal_misses<double>> missed = anima::missed_goals(solved, goals, tolerance);
    std::sort(missed.begin(), missed.end(), [&](const auto& a, const auto& b) { return sk[a.joint].name < sk[b.joint].name; });
    for (const auto& m : missed) {
        std::cerr << "anima: warning: effector '" << sk[m.joint].name << "' did not reach its target";
        if (solved.frames.size() > 1) std::cerr << " in " << m.frames << " of " << solved.frames.size() << " frames";
        std::cerr << ": it is " << format_number(m.worst, 3) << " units away";
        if (solved.frames.size() > 1) std::cerr << " at frame " << m.worst_frame;
        else std::cerr << " (frame " << m.worst_frame << ")";
        std::cerr << ", the tolerance is " << format_number(tolerance, 3) << '\n';
    }
    return effectors;
}

void run_ik(const ik_options& o) {
    check_outputs({{"--output", &o.output}, {"--save-model", &o.model_out}, {"--view", &o.view}});
    const anima::stopwatch timer;
    const clip_t c = load_clip(o.input);
    const auto& sk = c.skeleton();
    // Body scale: the diagonal of the first frame's joint bounding box.
    const double scale = std::max(anima::pose_diagonal(c, 0), 1e-9);
    solver_setup s{anima::kinematic_tree<double>(sk), {}, nullptr};
    const bool learned = o.solver == "learned";
    if (learned) s.tree.set_fixed(0);
    else if (sk.translation_slot(0) >= 0) s.tree.set_root_translation(true);
    s.params.tolerance = o.tolerance * scale;
    s.params.max_iterations = o.iterations;
    s.params.restarts = o.restarts;

    const bool offset_mode = !o.offset.empty();
    const bool file_mode = !o.targets_file.empty();
    const frame_targets per_frame = collect_targets(o, c);
    const bool smooth = offset_mode || file_mode;
    std::vector<std::pair<std::string, vec3>> wanted;  // every effector named, once
    for (const auto& entry : per_frame)
        for (const auto& w : entry.second)
            if (std::none_of(wanted.begin(), wanted.end(), [&](const auto& x) { return x.first == w.first; }))
                wanted.push_back(w);
    for (const auto& w : wanted) (void)joint_named(sk, w.first, o.input);

    if (learned) train_model(o, s, wanted);

    const std::size_t first = per_frame.begin()->first, last = per_frame.rbegin()->first;
    // The goals per frame (the learned model solves for all its effectors at
    // once, in its order).
    std::vector<anima::frame_goals<double>> goals;
    std::vector<wanted_list> goal_names;
    std::vector<view_target> shown;  // every goal's world position, for --view
    for (const auto& [f, listed] : per_frame) {
        const auto frame_wanted = learned ? in_model_order(listed, wanted, f) : listed;
        anima::frame_goals<double> g{f, {}};
        for (const auto& [name, target] : frame_wanted) {
            g.goals.push_back(anima::position_goal<double>(sk.index_of(name), target));
            for (const std::size_t clip : {std::size_t{0}, std::size_t{1}}) shown.push_back({clip, f, target, name});
        }
        goals.push_back(std::move(g));
        goal_names.push_back(frame_wanted);
    }
    // Over a range: warm starts, and a pull toward each frame's recorded pose
    // in the null space. One frame: no pull, random restarts allowed.
    anima::clip_ik_params<double> cp;
    cp.ik = s.params;
    cp.pose_pull = smooth ? 0.2 : 0.0;
    if (smooth) cp.ik.restarts = 0;
    cp.progress = [&](std::size_t done, std::size_t total) {
        if (smooth && done % 20 == 0) std::cerr << "anima ik: " << done << " of " << total << " frames solved\n";
    };
    std::vector<Eigen::Index> clusters;  // of the learned solver, per frame
    const auto solved =
        learned ? anima::solve_clip_ik(s.tree, c, goals, anima::learned_ik_solver<double>{s.model.get(), {}, &clusters}, cp)
                : anima::solve_clip_ik(s.tree, c, goals, anima::ik_solver_call<double>{anima::parse_ik_solver(o.solver)}, cp);
    std::string page_written;
    if (!o.view.empty()) {
        view_page page;
        page.title = "IK on " + file_name(o.input) + " (" + o.solver + ")";
        page.clips = {{"before", c}, {"after", solved.edited}};
        page.targets = shown;
        std::vector<std::size_t> frames;
        std::vector<std::string> names;
        for (const auto& w : wanted) names.push_back(w.first);
        for (const auto& g : goals) frames.push_back(g.frame);
        page.markers = frame_markers(1, frames, "target", "targets of " + join(names));
        page_written = write_view_page(o.view, page);
    }

    const json effectors = effector_report(solved, goals, goal_names, sk, clusters, s.params.tolerance, smooth);
    const double seconds = timer.elapsed();
    if (!o.output.empty()) write_text_file(o.output, bvh_text(solved.edited, o.rotation_order));
    json out = {{"input", o.input},
                {"solver", o.solver},
                {"frames", json::array({first, last})},
                {"effectors", effectors},
                {"converged_frames", solved.converged_frames},
                {"largest_error", solved.largest_error},
                {"tolerance", s.params.tolerance},
                {"iterations", solved.iterations},
                {"seconds", seconds},
                {"max_joint_step_deg_before", anima::degrees(solved.max_joint_step_before)},
                {"max_joint_step_deg_after", anima::degrees(solved.max_joint_step_after)}};
    if (!o.output.empty()) out["output"] = o.output;
    if (!o.view.empty()) out["view"] = o.view;
    if (o.json) return print_json(out);
    std::cout << "solved " << per_frame.size() << " frame" << (per_frame.size() == 1 ? "" : "s") << " with " << o.solver
              << ": " << solved.converged_frames << " converged, largest error " << format_number(solved.largest_error, 3)
              << " (tolerance " << format_number(s.params.tolerance, 3) << "), " << solved.iterations << " iterations, "
              << format_number(seconds, 3) << " s\n";
    if (!o.output.empty()) report_written(o.output + " (the edited motion)");
    if (!o.model_out.empty()) report_written(o.model_out + " (the learned model)");
    if (!o.view.empty()) report_written(page_written);
}

}  // namespace
}  // namespace anima_cli

void register_ik(CLI::App& app) {
    using namespace anima_cli;
    const auto [sub, o] = add_command<ik_options>(
        app, "ik",
        "Inverse kinematics: move joints to targets in one frame, by an offset over a range, or per frame from a "
        "CSV file",
        run_ik);
    sub->add_option("input", o->input, "Input BVH file")->required()->check(CLI::ExistingFile);
    sub->add_option("--frame", o->frame, "Frame to solve (target mode)")->check(count_up_to(max_frames));
    sub->add_option("--effector", o->effectors, "Joint to move (repeat, one per --target)");
    sub->add_option("--target", o->targets, "World position X,Y,Z for the matching --effector");
    sub->add_option("--offset", o->offset, "Offset mode: the joint to move by --by over --frames");
    sub->add_option("--frames", o->frames, "Offset mode: frame range A-B");
    sub->add_option("--by", o->by, "Offset mode: displacement X,Y,Z in the clip's units");
    sub->add_option("--targets", o->targets_file, "File mode: CSV of frame,effector,x,y,z world targets")
        ->check(CLI::ExistingFile);
    sub->add_option("--solver", o->solver, "pinv, dls (adaptive damping), ccd, bfgs, lm (Levenberg-Marquardt) or learned")
        ->check(CLI::IsMember(solver_names()));
    sub->add_option("--train", o->train, "Clips to learn the Jacobian inverse from (learned solver)");
    sub->add_option("--save-model", o->model_out, "Write the learned model to this file");
    sub->add_option("--tolerance", o->tolerance, "Position tolerance relative to the body scale")
        ->check(number_in(0, 1, true));
    sub->add_option("--iterations", o->iterations, "Iteration cap per attempt")->check(integer_in(0, 100000));
    sub->add_option("--restarts", o->restarts, "Random restarts after a failed attempt (target mode)")
        ->check(integer_in(0, 1000));
    sub->add_option("-o,--output", o->output, "Output BVH file");
    add_rotation_order_option(*sub, o->rotation_order);
    add_view_option(*sub, o->view, "the clip before and after, the targets shown");
    sub->add_flag("--json", o->json, "Print a JSON object instead of text");
}
