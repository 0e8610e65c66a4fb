// A joint hierarchy: names, parents, rest offsets, the channel layout each
// joint was animated with (as in BVH), and optional end sites.
#pragma once

#include <anima/core/error.hpp>
#include <anima/core/text.hpp>
#include <anima/rotation/euler.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace anima {

/// One animated degree of freedom of a joint, as a BVH CHANNELS entry names it.
enum class channel : unsigned char { x_position, y_position, z_position, x_rotation, y_rotation, z_rotation };

inline bool is_rotation(channel c) { return c >= channel::x_rotation; }
inline bool is_position(channel c) { return c <= channel::z_position; }
/// The axis a channel moves along or about.
inline axis axis_of(channel c) { return static_cast<axis>(static_cast<int>(c) % 3); }

/// "Xposition", "Zrotation"... as written in BVH files.
inline std::string_view to_string(channel c) {
    static constexpr std::string_view names[] = {"Xposition", "Yposition", "Zposition",
                                                 "Xrotation", "Yrotation", "Zrotation"};
    return names[static_cast<int>(c)];
}

/// Parses a BVH channel name (case-insensitive); empty when it is not one.
inline std::optional<channel> try_parse_channel(std::string_view s) {
    if (s.size() != 9) return std::nullopt;
    const auto lower = [](char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; };
    const char a = lower(s[0]);
    if (a < 'x' || a > 'z') return std::nullopt;
    std::string rest;
    for (std::size_t i = 1; i < s.size(); ++i) rest += lower(s[i]);
    const int ax = a - 'x';
    if (rest == "position") return static_cast<channel>(ax);
    if (rest == "rotation") return static_cast<channel>(3 + ax);
    return std::nullopt;
}

/// As try_parse_channel, and throws anima::invalid_argument naming the text
/// for anything that is not a channel name.
inline channel parse_channel(std::string_view s) {
    if (const auto c = try_parse_channel(s)) return *c;
    throw invalid_argument("anima::parse_channel: '" + escape_for_message(s, 200) +
                           "' is not a BVH channel: use Xposition, Yposition, Zposition, Xrotation, Yrotation or "
                           "Zrotation (any case)");
}

template <class T>
struct joint {
    using vector3 = Eigen::Matrix<T, 3, 1>;
    std::string name;
    int parent = -1;                     ///< index of the parent joint, -1 for a root
    vector3 offset = vector3::Zero();    ///< rest translation from the parent, in its frame
    std::vector<channel> channels;       ///< animated channels in file order
    std::optional<vector3> end_site;     ///< offset of a BVH End Site below this joint
};

/// A forest of joints stored parents-first (every parent index is smaller than
/// its child's), so one forward pass visits parents before children.
template <class T>
class skeleton {
public:
    using scalar = T;
    using vector3 = Eigen::Matrix<T, 3, 1>;

    /// Appends a joint. parent must be -1 or an existing joint (so no cycle can
    /// form); names must be unique and non-empty; channels must not repeat and
    /// the rotation channels' axes must be distinct. Returns the new index.
    std::size_t add_joint(std::string name, int parent, const vector3& offset, std::vector<channel> channels = {}) {
        const std::string where = "anima::skeleton::add_joint('" + name + "')";
        if (name.empty()) throw invalid_argument("anima::skeleton::add_joint: empty joint name");
        if (parent < -1 || parent >= static_cast<int>(joints_.size()))
            throw invalid_argument(where + ": parent index " + std::to_string(parent) + " is not an existing joint");
        if (find(name)) throw invalid_argument(where + ": a joint of that name already exists");
        if (!offset.allFinite()) throw invalid_argument(where + ": offset is not finite");
        bool seen[6] = {};
        for (channel c : channels) {
            if (seen[static_cast<int>(c)])
                throw invalid_argument(where + ": channel " + std::string(to_string(c)) + " appears twice");
            seen[static_cast<int>(c)] = true;
        }
        joint<T> j;
        j.name = std::move(name);
        j.parent = parent;
        j.offset = offset;
        j.channels = std::move(channels);
        joints_.push_back(std::move(j));
        const std::size_t index = joints_.size() - 1;
        by_name_.emplace(joints_.back().name, index);
        translation_slot_.push_back(has_position_channels(index) ? static_cast<int>(translated_++) : -1);
        return index;
    }

    /// Builds a skeleton from parent indices in any order, re-sorting it
    /// parents-first. Throws anima::invalid_argument on a cycle (naming a joint
    /// on it), a bad index, or mismatched sizes.
    static skeleton from_parents(const std::vector<std::string>& names, const std::vector<int>& parents,
                                 const std::vector<vector3>& offsets) {
        const std::size_t n = names.size();
        if (parents.size() != n || offsets.size() != n)
            throw invalid_argument("anima::skeleton::from_parents: names, parents and offsets differ in size");
        for (std::size_t i = 0; i < n; ++i)
            if (parents[i] < -1 || parents[i] >= static_cast<int>(n))
                throw invalid_argument("anima::skeleton::from_parents: joint '" + names[i] + "' has parent index " +
                                       std::to_string(parents[i]) + " out of range");
        // Depth by walking up to a joint whose depth is known, so each joint
        // is walked once (linear even for a chain of 100,000 joints); meeting
        // a joint of the current walk again means a cycle.
        std::vector<std::size_t> order(n);
        std::vector<std::size_t> depth(n, 0);
        std::vector<char> state(n, 0);  // 0 unknown, 1 on the current walk, 2 known
        std::vector<std::size_t> walk;
        for (std::size_t i = 0; i < n; ++i) {
            order[i] = i;
            walk.clear();
            std::size_t j = i;
            while (state[j] == 0) {
                state[j] = 1;
                walk.push_back(j);
                if (parents[j] == -1) break;
                j = static_cast<std::size_t>(parents[j]);
            }
            if (state[j] == 1 && parents[j] != -1)
                throw invalid_argument("anima::skeleton::from_parents: joint '" + names[j] + "' is on a cycle of parents");
            std::size_t d = state[j] == 2 ? depth[j] + 1 : 0;  // j known: its children are one deeper; j a root: 0
            for (std::size_t k = walk.size(); k-- > 0;) {
                depth[walk[k]] = d++;
                state[walk[k]] = 2;
            }
        }
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return depth[a] < depth[b]; });
        std::vector<int> new_index(n);
        for (std::size_t k = 0; k < n; ++k) new_index[order[k]] = static_cast<int>(k);
        skeleton s;
        for (std::size_t k = 0; k < n; ++k) {
            const std::size_t i = order[k];
            s.add_joint(names[i], parents[i] == -1 ? -1 : new_index[static_cast<std::size_t>(parents[i])], offsets[i]);
        }
        return s;
    }

    std::size_t size() const noexcept { return joints_.size(); }
    bool empty() const noexcept { return joints_.empty(); }
    const joint<T>& operator[](std::size_t i) const { return joints_[i]; }
    const joint<T>& at(std::size_t i) const {
        check_index(i, "anima::skeleton::at");
        return joints_[i];
    }
    const std::vector<joint<T>>& joints() const noexcept { return joints_; }

    /// Index of the joint called name, if any (a hash lookup).
    std::optional<std::size_t> find(std::string_view name) const {
        const auto it = by_name_.find(std::string(name));
        if (it == by_name_.end()) return std::nullopt;
        return it->second;
    }
    /// Index of the joint called name; throws anima::invalid_argument when absent.
    std::size_t index_of(std::string_view name) const {
        if (auto i = find(name)) return *i;
        throw invalid_argument("anima::skeleton: no joint named '" + std::string(name) + "'" + did_you_mean(name));
    }
    /// For a message about a name that is not found: " (did you mean 'X'?)"
    /// when joint X differs from it only in case (names are matched
    /// exactly: CMU's rHand and a user's RHand), "" otherwise.
    std::string did_you_mean(std::string_view name) const {
        for (const auto& j : joints_)
            if (ascii_equal_ignoring_case(j.name, name)) return " (did you mean '" + j.name + "'?)";
        return "";
    }

    std::vector<std::size_t> children(std::size_t i) const {
        check_index(i, "anima::skeleton::children");
        std::vector<std::size_t> out;
        for (std::size_t k = i + 1; k < joints_.size(); ++k)
            if (joints_[k].parent == static_cast<int>(i)) out.push_back(k);
        return out;
    }

    void set_end_site(std::size_t i, const vector3& offset) {
        check_index(i, "anima::skeleton::set_end_site");
        if (!offset.allFinite()) throw invalid_argument("anima::skeleton::set_end_site: offset is not finite");
        joints_[i].end_site = offset;
    }

    /// Replaces a joint's channel layout (how it is written to BVH). The
    /// clip's motion is stored as quaternions and translations, so changing
    /// e.g. the rotation order does not change the motion; adding or removing
    /// position channels does change the clip's storage, hence only clips
    /// built after the call see it.
    void set_channels(std::size_t i, std::vector<channel> channels) {
        check_index(i, "anima::skeleton::set_channels");
        const bool had = has_position_channels(i);
        bool seen[6] = {};
        for (channel c : channels) {
            if (seen[static_cast<int>(c)])
                throw invalid_argument("anima::skeleton::set_channels: channel " + std::string(to_string(c)) +
                                       " appears twice on joint '" + joints_[i].name + "'");
            seen[static_cast<int>(c)] = true;
        }
        joints_[i].channels = std::move(channels);
        if (had != has_position_channels(i)) renumber_slots();
    }

    void set_offset(std::size_t i, const vector3& offset) {
        check_index(i, "anima::skeleton::set_offset");
        if (!offset.allFinite()) throw invalid_argument("anima::skeleton::set_offset: offset is not finite");
        joints_[i].offset = offset;
    }

    bool has_position_channels(std::size_t i) const {
        for (channel c : joints_[i].channels)
            if (is_position(c)) return true;
        return false;
    }
    bool has_rotation_channels(std::size_t i) const {
        for (channel c : joints_[i].channels)
            if (is_rotation(c)) return true;
        return false;
    }
    /// The axes of the joint's rotation channels, in file order (0 to 3 axes).
    std::vector<axis> rotation_axes(std::size_t i) const {
        std::vector<axis> out;
        for (channel c : joints_[i].channels)
            if (is_rotation(c)) out.push_back(axis_of(c));
        return out;
    }

    /// Slot of the joint's animated translation in a clip, or -1 when the joint
    /// has no position channels (its translation is then its rest offset).
    int translation_slot(std::size_t i) const { return translation_slot_[i]; }
    /// Number of joints with position channels.
    std::size_t translated_joint_count() const noexcept { return translated_; }

    /// Total number of channels, i.e. numbers per BVH motion line.
    std::size_t channel_count() const noexcept {
        std::size_t n = 0;
        for (const auto& j : joints_) n += j.channels.size();
        return n;
    }

    friend bool operator==(const skeleton& a, const skeleton& b) {
        if (a.joints_.size() != b.joints_.size()) return false;
        for (std::size_t i = 0; i < a.joints_.size(); ++i) {
            const auto &x = a.joints_[i], &y = b.joints_[i];
            if (x.name != y.name || x.parent != y.parent || x.offset != y.offset || x.channels != y.channels ||
                x.end_site.has_value() != y.end_site.has_value() || (x.end_site && *x.end_site != *y.end_site))
                return false;
        }
        return true;
    }
    friend bool operator!=(const skeleton& a, const skeleton& b) { return !(a == b); }

private:
    void check_index(std::size_t i, const char* who) const {
        if (i >= joints_.size())
            throw invalid_argument(std::string(who) + ": joint index " + std::to_string(i) + " out of range (" +
                                   std::to_string(joints_.size()) + " joints)");
    }
    void renumber_slots() {
        translated_ = 0;
        for (std::size_t i = 0; i < joints_.size(); ++i)
            translation_slot_[i] = has_position_channels(i) ? static_cast<int>(translated_++) : -1;
    }

    std::vector<joint<T>> joints_;
    std::vector<int> translation_slot_;
    std::size_t translated_ = 0;
    std::unordered_map<std::string, std::size_t> by_name_;  // joint name -> index
};

/// Every joint once, depth-first from each root in index order (children in
/// index order, as BVH lists them), with its depth (0 for a root). Iterative,
/// so a very deep skeleton cannot overflow the stack.
template <class T>
std::vector<std::pair<std::size_t, std::size_t>> depth_first_order(const skeleton<T>& sk) {
    std::vector<std::vector<std::size_t>> children(sk.size());
    for (std::size_t j = 0; j < sk.size(); ++j)
        if (sk[j].parent >= 0) children[static_cast<std::size_t>(sk[j].parent)].push_back(j);
    std::vector<std::pair<std::size_t, std::size_t>> out, stack;
    for (std::size_t r = sk.size(); r-- > 0;)
        if (sk[r].parent < 0) stack.emplace_back(r, 0);
    while (!stack.empty()) {
        const auto [j, depth] = stack.back();
        stack.pop_back();
        out.emplace_back(j, depth);
        for (std::size_t k = children[j].size(); k-- > 0;) stack.emplace_back(children[j][k], depth + 1);
    }
    return out;
}

/// The distinct orders of the joints' rotation channels, in order of first
/// appearance: "ZXY" for three channels, "Z" or "ZX" for joints with fewer;
/// joints without rotation channels add nothing.
template <class T>
std::vector<std::string> rotation_orders(const skeleton<T>& sk) {
    std::vector<std::string> out;
    for (std::size_t j = 0; j < sk.size(); ++j) {
        std::string order;
        for (axis a : sk.rotation_axes(j)) order += static_cast<char>('X' + static_cast<int>(a));
        if (!order.empty() && std::find(out.begin(), out.end(), order) == out.end()) out.push_back(order);
    }
    return out;
}

/// Throws anima::invalid_argument naming the first joint whose name, parent
/// or position channels differ between the two skeletons. Offsets (bone
/// lengths) and rotation channel orders may differ.
template <class T>
void check_same_hierarchy(const skeleton<T>& a, const skeleton<T>& b) {
    const std::size_t n = std::min(a.size(), b.size());
    for (std::size_t j = 0; j < n; ++j) {
        if (a[j].name != b[j].name || a[j].parent != b[j].parent ||
            a.has_position_channels(j) != b.has_position_channels(j))
            throw invalid_argument("anima::check_same_hierarchy: the clips' hierarchies differ at joint " + std::to_string(j) + " ('" +
                                   a[j].name + "' vs '" + b[j].name + "')");
    }
    if (a.size() != b.size())
        throw invalid_argument("anima::check_same_hierarchy: the clips' hierarchies differ: " + std::to_string(a.size()) + " vs " +
                               std::to_string(b.size()) + " joints (first extra joint '" +
                               (a.size() > n ? a[n].name : b[n].name) + "')");
}

}  // namespace anima
