#include "view_page.hpp"

#include <anima/motion/contacts.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace anima_cli {

// Generated at build time by view/embed.cpp: pieces of text ended by nullptr.
extern const char* const view_page_html[];
extern const char* const view_player_js[];
extern const char* const view_three_js[];

namespace {

std::string joined(const char* const* pieces) {
    std::string out;
    for (; *pieces; ++pieces) out += *pieces;
    return out;
}

/// How one clip is placed on the page: rows of `basis` are the page's X
/// (the figure's left), Y (up) and Z (its front), scaled to metres, with the
/// clip's lowest point on the ground (y = 0).
struct placement {
    Eigen::Matrix3d basis = Eigen::Matrix3d::Identity();
    double ground = 0;
    anima::signed_axis up;
    vec3 to_page(const vec3& p) const {
        vec3 q = basis * p;
        q.y() -= ground;
        return q;
    }
};

/// Every joint and End Site position of every frame, file coordinates.
using clip_points = anima::clip_points<double>;

/// The page's axes are the front stick view's (the figure's left, up and
/// front), in metres when the unit is a confident guess (else the figure is
/// made 1.7 m tall), the lowest point of the clip on the ground.
placement place(const clip_t& c, const clip_points& pts, std::optional<anima::signed_axis> up_given) {
    const skeleton_t& sk = c.skeleton();
    placement p;
    p.up = up_given ? *up_given : anima::guess_up_axis(sk).up;
    const auto view = anima::make_stick_view<double>(anima::stick_view::front, p.up, anima::left_axis(sk, p.up));
    const anima::unit_guess units = anima::guess_units(sk, p.up);
    const double scale = units.confident ? units.metres_per_unit : units.height > 0 ? 1.7 / units.height : 1.0;
    p.basis.row(0) = view.right.transpose() * scale;
    p.basis.row(1) = view.up.transpose() * scale;
    p.basis.row(2) = view.toward.transpose() * scale;
    const double lowest = anima::lowest_along(pts, view.up) * scale;
    p.ground = std::isfinite(lowest) ? lowest : 0.0;
    return p;
}

/// Millimetres, as integers: the page's positions.
long long mm(double metres) { return std::llround(std::clamp(metres, -1e9, 1e9) * 1000); }

json point_json(const vec3& q) { return json::array({mm(q.x()), mm(q.y()), mm(q.z())}); }

/// The joints of the subtree under `joint` and their End Sites: the points
/// drawn as the foot.
std::vector<std::size_t> foot_points(const skeleton_t& sk, const clip_points& pts, std::size_t joint) {
    std::vector<std::size_t> out;
    for (const auto& p : anima::foot_points_of(sk, joint)) out.push_back(p.end_site ? pts.end_site_point[p.joint] : p.joint);
    return out;
}

json contacts_json(const clip_t& c, const clip_points& pts, anima::signed_axis up) {
    anima::contact_params<double> params;
    params.up = up;
    json feet = json::array();
    try {
        const auto contacts = anima::find_contacts(c, params);
        for (const auto& foot : contacts.feet) {
            feet.push_back({{"name", foot.name},
                            {"points", foot_points(c.skeleton(), pts, foot.joint)},
                            {"runs", to_json(foot.contacts)}});
        }
    } catch (const anima::error&) {
        // A skeleton without feet (a hand, a single chain): no contacts to show.
    }
    return feet;
}

json clip_json(const view_clip& v, const clip_points& pts, const placement& p) {
    json bones = json::array();
    for (const anima::stick_bone& b : anima::stick_bones(v.motion.skeleton()))
        bones.push_back({b.from, b.end_site ? pts.end_site_point[b.to] : b.to, static_cast<int>(b.side)});
    json positions = json::array();
    for (const vec3& q : pts.points) {
        const vec3 r = p.to_page(q);
        positions.push_back(mm(r.x()));
        positions.push_back(mm(r.y()));
        positions.push_back(mm(r.z()));
    }
    return {{"label", v.label},
            {"frames", v.motion.frames()},
            {"frame_time", v.motion.frame_time()},
            {"points", pts.per_frame},
            {"up", anima::to_string(p.up)},
            {"bones", bones},
            {"feet", contacts_json(v.motion, pts, p.up)},
            {"positions", positions}};
}

/// The template with each @ANIMA_NAME@ replaced by its value, in one pass
/// (inserted text is not searched again). Every name must be used once.
std::string fill_template(const std::string& text, const std::map<std::string, std::string>& values) {
    std::string out;
    std::map<std::string, int> used;
    std::size_t pos = 0;
    for (;;) {
        const std::size_t at = text.find("@ANIMA_", pos);
        if (at == std::string::npos) break;
        const std::size_t end = text.find('@', at + 1);
        const auto it = end == std::string::npos ? values.end() : values.find(text.substr(at + 1, end - at - 1));
        if (it == values.end()) throw std::logic_error("view page template: unknown placeholder at byte " + std::to_string(at));
        out.append(text, pos, at - pos);
        out += it->second;
        ++used[it->first];
        pos = end + 1;
    }
    out.append(text, pos, std::string::npos);
    for (const auto& [name, value] : values)
        if (used[name] != 1) throw std::logic_error("view page template: @" + name + "@ is used " + std::to_string(used[name]) + " times");
    return out;
}

/// JSON to put inside a <script> element: '<' written as \u003c, so that no
/// "</script" or "<!--" in a name can end or change the element.
std::string script_json(const json& value) {
    const std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        if (c == '<') out += "\\u003c";
        else out += c;
    }
    return out;
}

}  // namespace

bool view_has_three() { return view_three_js[0] != nullptr; }

std::string make_view_page(const view_page& page) {
    if (page.clips.empty()) throw failure("a page needs at least one clip");
    double values = 0;
    for (const auto& v : page.clips) {
        if (v.motion.empty()) throw failure("'" + v.label + "' has no frames to show");
        values += static_cast<double>(v.motion.frames()) * static_cast<double>(v.motion.skeleton().size() * 2) * 3;
    }
    // Each position is about 6 bytes of text, held twice (JSON and page).
    check_request_memory(values, 40, "a page of " + std::to_string(static_cast<long long>(values)) + " coordinates",
                         "the number of frames");
    for (const auto& m : page.markers) {
        if (m.clip >= page.clips.size() || m.last < m.first || m.last >= page.clips[m.clip].motion.frames())
            throw std::logic_error("view page: marker '" + m.label + "' is outside its clip");
    }
    json clips = json::array(), targets = json::array(), markers = json::array();
    std::vector<placement> placements;
    for (const auto& v : page.clips) {
        const clip_points pts = anima::global_points(v.motion);
        placements.push_back(place(v.motion, pts, page.up));
        clips.push_back(clip_json(v, pts, placements.back()));
    }
    for (const auto& m : page.markers)
        markers.push_back({{"clip", m.clip}, {"first", m.first}, {"last", m.last}, {"kind", m.kind}, {"label", m.label}});
    for (const auto& t : page.targets) {
        if (t.clip >= page.clips.size() || t.frame >= page.clips[t.clip].motion.frames())
            throw std::logic_error("view page: target '" + t.label + "' is outside its clip");
        targets.push_back({{"clip", t.clip}, {"frame", t.frame}, {"label", t.label},
                           {"position", point_json(placements[t.clip].to_page(t.position))}});
    }
    const json data = {{"title", page.title},     {"overlay", page.overlay}, {"clips", clips},
                       {"markers", markers},      {"targets", targets},
                       {"three", view_has_three() ? ANIMA_THREE_VERSION : ""}};
    const std::string body = "data-renderer=\"none\" data-frame=\"0\" data-frames=\"" +
                             std::to_string(page.clips[0].motion.frames()) + "\" data-clips=\"" +
                             std::to_string(page.clips.size()) + "\" data-markers=\"" +
                             std::to_string(page.markers.size()) + "\"";
    return fill_template(joined(view_page_html), {{"ANIMA_TITLE", xml_escape(page.title)},
                                                  {"ANIMA_BODY", body},
                                                  {"ANIMA_DATA", script_json(data)},
                                                  {"ANIMA_THREE", joined(view_three_js)},
                                                  {"ANIMA_PLAYER", joined(view_player_js)}});
}

std::string write_view_page(const std::string& path, const view_page& page) {
    const std::string html = make_view_page(page);
    write_text_file(path, html);
    std::vector<std::string> clips;
    for (const auto& v : page.clips) clips.push_back(v.label + " " + std::to_string(v.motion.frames()) + " frames");
    const std::size_t markers = page.markers.size();
    return path + ": " + std::to_string(page.clips.size()) + (page.clips.size() == 1 ? " clip (" : " clips (") +
           join(clips) + ")" + (page.overlay ? " overlaid" : "") + ", " + std::to_string(markers) +
           (markers == 1 ? " marker, " : " markers, ") + format_number(static_cast<double>(html.size()) / 1e6, 3) +
           " MB; draws with " +
           (view_has_three() ? std::string("three.js ") + ANIMA_THREE_VERSION + " (WebGL), or a 2D canvas without WebGL"
                             : std::string("a 2D canvas (this anima was built without three.js)"));
}

std::vector<view_marker> frame_markers(std::size_t clip, const std::vector<std::size_t>& frames, const std::string& kind,
                                       const std::string& label) {
    std::vector<bool> marked(frames.empty() ? 0 : *std::max_element(frames.begin(), frames.end()) + 1);
    for (const std::size_t f : frames) marked[f] = true;
    std::vector<view_marker> out;
    for (const auto& run : anima::true_runs(marked)) {
        const std::string span = run.first == run.last ? "frame " + std::to_string(run.first)
                                                       : "frames " + std::to_string(run.first) + "-" + std::to_string(run.last);
        out.push_back({clip, run.first, run.last, kind, label + " (" + span + ")"});
    }
    return out;
}

CLI::Option* add_view_option(CLI::App& sub, std::string& path, const std::string& what) {
    return sub.add_option("--view", path, "Write a page to watch " + what + " in a browser (self-contained HTML)")
        ->type_name("PAGE.html");
}

}  // namespace anima_cli
