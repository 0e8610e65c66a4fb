// BVH writer: a document or a clip to BVH text, tab-indented, LF line endings,
// numbers in fixed notation with a chosen number of decimals.
#pragma once

#include <anima/bvh/document.hpp>
#include <anima/core/error.hpp>
#include <anima/core/file_io.hpp>
#include <anima/motion/clip.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace anima {

struct bvh_write_options {
    /// Decimals written for offsets and channel values: 6 keeps angles within
    /// 5e-7 degrees and lengths within 5e-7 units of the clip.
    int decimals = 6;
    /// How a clip's rotations become Euler angles (see to_document).
    euler_angles angles = euler_angles::continuous;
};

namespace detail {

template <class T>
void append_fixed(std::string& out, T v, int decimals) {
    char buf[128];
    auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
    if (r.ec != std::errc()) {
        // Only astronomically large values do not fit; scientific always does.
        r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::scientific, decimals);
    }
    std::string_view s(buf, static_cast<std::size_t>(r.ptr - buf));
    // "-0.000000" reads back as 0 anyway; write it as such.
    if (!s.empty() && s[0] == '-' && s.find_first_not_of("-0.") == std::string_view::npos) s.remove_prefix(1);
    out.append(s);
}

template <class T>
void append_offset(std::string& out, const Eigen::Matrix<T, 3, 1>& o, int decimals) {
    out += "OFFSET";
    for (int k = 0; k < 3; ++k) {
        out += ' ';
        append_fixed(out, o[k], decimals);
    }
    out += '\n';
}

}  // namespace detail

/// BVH text of a document. Joints are written depth-first from each root, so
/// a skeleton built in another parents-first order comes back reordered.
/// Throws anima::invalid_argument for a non-finite value (naming frame and
/// channel), an empty skeleton, or decimals outside 0..17.
template <class T>
std::string format_bvh(const bvh_document<T>& doc, const bvh_write_options& options = {}) {
    constexpr std::size_t max_indent = 64;
    const auto& sk = doc.skeleton;
    const int dec = options.decimals;
    if (dec < 0 || dec > 17) throw invalid_argument("anima::format_bvh: decimals must be 0..17");
    if (sk.empty()) throw invalid_argument("anima::format_bvh: the skeleton has no joints");
    for (const auto& j : sk.joints())
        if (!detail::bvh_writable_name(j.name))
            throw invalid_argument("anima::format_bvh: joint name '" + escape_for_message(j.name) +
                                   "' cannot be written to BVH (braces, line breaks or edge spaces)");
    const std::size_t nc = sk.channel_count();
    if (doc.values.size() != doc.frames * nc)
        throw invalid_argument("anima::format_bvh: " + std::to_string(doc.values.size()) + " values for " +
                               std::to_string(doc.frames) + " frames of " + std::to_string(nc) + " channels");
    if (!(doc.frame_time > T(0)) || !std::isfinite(doc.frame_time))
        throw invalid_argument("anima::format_bvh: frame time must be positive and finite");

    // Channel offset of every joint in the document's (skeleton) order.
    std::vector<std::size_t> first_channel(sk.size());
    for (std::size_t j = 0, c = 0; j < sk.size(); ++j) {
        first_channel[j] = c;
        c += sk[j].channels.size();
    }
    std::vector<std::vector<std::size_t>> children(sk.size());
    for (std::size_t j = 0; j < sk.size(); ++j)
        if (sk[j].parent >= 0) children[static_cast<std::size_t>(sk[j].parent)].push_back(j);

    std::string out = "HIERARCHY\n";
    std::vector<std::size_t> written;  // depth-first joint order = motion column order
    struct item {
        std::size_t joint;
        std::size_t next_child;
    };
    for (std::size_t root = 0; root < sk.size(); ++root) {
        if (sk[root].parent >= 0) continue;
        std::vector<item> stack{{root, 0}};
        // Indentation stops growing at max_indent tabs, so that the text of a
        // deep hierarchy stays linear in its size.
        const auto tabs = [&](std::size_t depth) { out.append(std::min(depth, max_indent), '\t'); };
        const auto indent = [&](std::size_t extra) { tabs(stack.size() - 1 + extra); };
        out += "ROOT " + sk[root].name + "\n{\n";
        written.push_back(root);
        indent(1);
        detail::append_offset(out, sk[root].offset, dec);
        const auto channels_line = [&](std::size_t j) {
            indent(1);
            out += "CHANNELS " + std::to_string(sk[j].channels.size());
            for (channel c : sk[j].channels) {
                out += ' ';
                out += to_string(c);
            }
            out += '\n';
        };
        channels_line(root);
        while (!stack.empty()) {
            item& it = stack.back();
            const std::size_t j = it.joint;
            if (it.next_child < children[j].size()) {
                const std::size_t c = children[j][it.next_child++];
                indent(1);
                out += "JOINT " + sk[c].name + "\n";
                indent(1);
                out += "{\n";
                stack.push_back({c, 0});
                written.push_back(c);
                indent(1);
                detail::append_offset(out, sk[c].offset, dec);
                channels_line(c);
                continue;
            }
            if (sk[j].end_site) {
                indent(1);
                out += "End Site\n";
                indent(1);
                out += "{\n";
                indent(2);
                detail::append_offset(out, *sk[j].end_site, dec);
                indent(1);
                out += "}\n";
            }
            stack.pop_back();
            tabs(stack.size());
            out += "}\n";
        }
    }

    out += "MOTION\nFrames: " + std::to_string(doc.frames) + "\nFrame Time: ";
    {
        char buf[64];
        const auto r = std::to_chars(buf, buf + sizeof buf, doc.frame_time);  // shortest exact form
        out.append(buf, static_cast<std::size_t>(r.ptr - buf));
        out += '\n';
    }
    out.reserve(out.size() + doc.values.size() * static_cast<std::size_t>(dec + 5));
    for (std::size_t f = 0; f < doc.frames; ++f) {
        const T* v = doc.values.data() + f * nc;
        bool first = true;
        for (std::size_t j : written) {
            for (std::size_t k = 0; k < sk[j].channels.size(); ++k) {
                const T x = v[first_channel[j] + k];
                if (!std::isfinite(x))
                    throw invalid_argument("anima::format_bvh: non-finite value at frame " + std::to_string(f) +
                                           ", joint '" + sk[j].name + "', channel " +
                                           std::string(to_string(sk[j].channels[k])));
                if (!first) out += ' ';
                first = false;
                detail::append_fixed(out, x, dec);
            }
        }
        out += '\n';
    }
    return out;
}

/// BVH text of a clip (see to_document for how rotations become angles).
template <class T>
std::string format_bvh(const clip<T>& c, const bvh_write_options& options = {}) {
    return format_bvh(to_document(c, options.angles), options);
}

/// Writes a document or a clip to a BVH file, atomically (see
/// write_file_atomically). Throws anima::io_error when the file cannot be
/// written; nothing is written when formatting fails, and an existing file is
/// left as it was when writing fails.
template <class Motion>
void write_bvh(const Motion& motion, const std::string& path, const bvh_write_options& options = {}) {
    write_file_atomically(path, format_bvh(motion, options));
}

}  // namespace anima
