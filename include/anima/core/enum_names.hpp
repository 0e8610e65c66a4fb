// Names of enum values, written once per enum and used both ways: to_string
// for output, parse_enum for input (files, command lines), enum_name_list
// for the choices a tool offers. Before, every enum had its own switch and
// its own parser with the choices typed again in the error message, and the
// CLI listed them a third time in its option checks, where they could drift.
//
// An enum takes part by specialising enum_names next to its declaration:
//
//   template <> struct enum_names<root_path> {
//       static constexpr const char* what = "root path";      // for messages
//       static constexpr enum_entry<root_path> entries[] = {
//           {root_path::recorded, "recorded"}, {root_path::in_place, "in_place"}, ...};
//   };
//
// A value may appear more than once (aliases: "1d" and "temporal"); its
// first entry is its name, the others are only accepted by parse_enum.
#pragma once

#include <anima/core/error.hpp>
#include <anima/core/text.hpp>

#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace anima {

template <class E>
struct enum_entry {
    E value;
    const char* name;
};

/// Specialised for each named enum (see above).
template <class E>
struct enum_names;

namespace detail {

template <class E, class = void>
struct has_enum_names : std::false_type {};
template <class E>
struct has_enum_names<E, std::void_t<decltype(enum_names<E>::entries)>> : std::true_type {};

}  // namespace detail

/// Whether E has names.
template <class E>
inline constexpr bool has_enum_names_v = detail::has_enum_names<E>::value;

/// The name of a value ("unknown" for a value outside the enum's list).
template <class E, std::enable_if_t<has_enum_names_v<E>, int> = 0>
constexpr const char* to_string(E value) noexcept {
    for (const auto& e : enum_names<E>::entries)
        if (e.value == value) return e.name;
    return "unknown";
}

/// The names of E's values, one per value, in declaration order of the list.
template <class E>
std::vector<std::string> enum_name_list() {
    static_assert(has_enum_names_v<E>, "anima::enum_name_list: specialise anima::enum_names for this enum");
    std::vector<std::string> names;
    for (const auto& e : enum_names<E>::entries)
        if (std::string_view(to_string(e.value)) == e.name) names.emplace_back(e.name);
    return names;
}

/// "a, b or c": the names for a message.
template <class E>
std::string enum_choices() {
    const auto names = enum_name_list<E>();
    std::string out;
    for (std::size_t k = 0; k < names.size(); ++k)
        out += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + names[k];
    return out;
}

/// The value named `name` (ASCII case ignored, aliases accepted). Throws
/// anima::invalid_argument naming `function`, the text and the choices
/// otherwise.
template <class E>
E parse_enum(std::string_view name, std::string_view function = "anima::parse_enum") {
    static_assert(has_enum_names_v<E>, "anima::parse_enum: specialise anima::enum_names for this enum");
    for (const auto& e : enum_names<E>::entries)
        if (ascii_equal_ignoring_case(name, e.name)) return e.value;
    const std::string what = enum_names<E>::what;
    const bool vowel = !what.empty() && std::string_view("aeiouAEIOU").find(what[0]) != std::string_view::npos;
    throw invalid_argument(std::string(function) + ": '" + escape_for_message(name, 200) + "' is not " +
                           (vowel ? "an " : "a ") + what + ": use " + enum_choices<E>());
}

}  // namespace anima
