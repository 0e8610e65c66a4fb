// A small, strict JSON reader for the library's own input files (flight key
// sets): RFC 8259 values into a tree that remembers the line each value
// starts on, so a reader built on it can say "keys.json:14: ..." like the
// BVH and DIMACS readers do. The library takes no JSON dependency for this.
//
// Strict on purpose: no comments, no trailing commas, no NaN/Infinity, no
// duplicate keys, nesting at most `max_depth` deep (no stack overflow on a
// hostile file), numbers parsed without the locale.
#pragma once

#include <anima/core/error.hpp>

#include <charconv>
#include <cstddef>
#include <cstdlib>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace anima {

/// One JSON value: null, true/false, a number, a string, an array or an
/// object (members in file order). `line()` is where it starts (1-based).
class json_value {
public:
    enum class kind { null, boolean, number, string, array, object };
    using member = std::pair<std::string, json_value>;

    json_value() = default;

    kind type() const noexcept { return kind_; }
    std::size_t line() const noexcept { return line_; }
    bool is_null() const noexcept { return kind_ == kind::null; }
    bool is_boolean() const noexcept { return kind_ == kind::boolean; }
    bool is_number() const noexcept { return kind_ == kind::number; }
    bool is_string() const noexcept { return kind_ == kind::string; }
    bool is_array() const noexcept { return kind_ == kind::array; }
    bool is_object() const noexcept { return kind_ == kind::object; }

    /// The value of the kind asked for; anima::invalid_argument when it is
    /// another kind (readers check the kind first and report file and line).
    bool boolean() const { return expect(kind::boolean), boolean_; }
    double number() const { return expect(kind::number), number_; }
    const std::string& string() const { return expect(kind::string), string_; }
    const std::vector<json_value>& array() const { return expect(kind::array), array_; }
    const std::vector<member>& object() const { return expect(kind::object), object_; }

    /// The member named `key` of an object, or nullptr (also for non-objects).
    const json_value* find(std::string_view key) const noexcept {
        if (kind_ != kind::object) return nullptr;
        for (const auto& m : object_)
            if (m.first == key) return &m.second;
        return nullptr;
    }

    /// "null", "a boolean", "a number", "a string", "an array", "an object".
    static const char* kind_name(kind k) noexcept {
        switch (k) {
            case kind::null: return "null";
            case kind::boolean: return "a boolean";
            case kind::number: return "a number";
            case kind::string: return "a string";
            case kind::array: return "an array";
            case kind::object: return "an object";
        }
        return "a value";
    }

private:
    friend class json_parser;

    void expect(kind k) const {
        if (kind_ != k)
            throw invalid_argument(std::string("anima::json_value: asked for ") + kind_name(k) + ", the value on line " +
                                   std::to_string(line_) + " is " + kind_name(kind_));
    }

    kind kind_ = kind::null;
    std::size_t line_ = 1;
    bool boolean_ = false;
    double number_ = 0;
    std::string string_;
    std::vector<json_value> array_;
    std::vector<member> object_;
};

/// Recursive descent over the text; every error is an anima::parse_error
/// with the file name and the line.
class json_parser {
public:
    json_parser(std::string_view text, std::string file, std::size_t max_depth)
        : text_(text), file_(std::move(file)), max_depth_(max_depth) {}

    json_value parse_document() {
        skip_space();
        json_value v = parse_value(0);
        skip_space();
        if (pos_ < text_.size()) fail("unexpected '" + std::string(1, text_[pos_]) + "' after the JSON value");
        return v;
    }

private:
    [[noreturn]] void fail(const std::string& message) const { throw parse_error(file_, line_, message); }

    void skip_space() {
        while (pos_ < text_.size()) {
            const char c = text_[pos_];
            if (c == '\n') ++line_;
            else if (c != ' ' && c != '\t' && c != '\r') return;
            ++pos_;
        }
    }

    bool take(std::string_view word) {
        if (text_.substr(pos_, word.size()) != word) return false;
        pos_ += word.size();
        return true;
    }

    json_value parse_value(std::size_t depth) {
        if (pos_ >= text_.size()) fail("unexpected end of the file, a value was expected");
        json_value v;
        v.line_ = line_;
        const char c = text_[pos_];
        if (c == '{' || c == '[') {
            if (depth >= max_depth_) fail("nested more than " + std::to_string(max_depth_) + " levels deep");
            if (c == '{') parse_object(v, depth + 1);
            else parse_array(v, depth + 1);
        } else if (c == '"') {
            v.kind_ = json_value::kind::string;
            v.string_ = parse_string();
        } else if (take("true") || take("false")) {
            v.kind_ = json_value::kind::boolean;
            v.boolean_ = c == 't';
        } else if (take("null")) {
            v.kind_ = json_value::kind::null;
        } else if (c == '-' || (c >= '0' && c <= '9')) {
            v.kind_ = json_value::kind::number;
            v.number_ = parse_number();
        } else {
            fail("unexpected '" + std::string(1, c) + "', a value was expected");
        }
        return v;
    }

    void parse_object(json_value& v, std::size_t depth) {
        v.kind_ = json_value::kind::object;
        ++pos_;
        skip_space();
        if (take("}")) return;
        for (;;) {
            skip_space();
            if (pos_ >= text_.size() || text_[pos_] != '"') fail("a member name in double quotes was expected");
            std::string key = parse_string();
            if (v.find(key)) fail("the member \"" + key + "\" appears twice");
            skip_space();
            if (!take(":")) fail("':' was expected after \"" + key + "\"");
            skip_space();
            json_value item = parse_value(depth);
            v.object_.emplace_back(std::move(key), std::move(item));
            skip_space();
            if (take("}")) return;
            if (!take(",")) fail("',' or '}' was expected in the object that starts on line " + std::to_string(v.line_));
        }
    }

    void parse_array(json_value& v, std::size_t depth) {
        v.kind_ = json_value::kind::array;
        ++pos_;
        skip_space();
        if (take("]")) return;
        for (;;) {
            skip_space();
            v.array_.push_back(parse_value(depth));
            skip_space();
            if (take("]")) return;
            if (!take(",")) fail("',' or ']' was expected in the array that starts on line " + std::to_string(v.line_));
        }
    }

    static void append_utf8(std::string& out, unsigned long cp) {
        if (cp < 0x80) {
            out += static_cast<char>(cp);
        } else if (cp < 0x800) {
            out += static_cast<char>(0xC0 | (cp >> 6));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else if (cp < 0x10000) {
            out += static_cast<char>(0xE0 | (cp >> 12));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else {
            out += static_cast<char>(0xF0 | (cp >> 18));
            out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        }
    }

    unsigned long hex4() {
        if (pos_ + 4 > text_.size()) fail("\\u needs four hexadecimal digits");
        unsigned long cp = 0;
        for (int k = 0; k < 4; ++k) {
            const char h = text_[pos_++];
            cp <<= 4;
            if (h >= '0' && h <= '9') cp |= static_cast<unsigned long>(h - '0');
            else if (h >= 'a' && h <= 'f') cp |= static_cast<unsigned long>(h - 'a' + 10);
            else if (h >= 'A' && h <= 'F') cp |= static_cast<unsigned long>(h - 'A' + 10);
            else fail("\\u needs four hexadecimal digits");
        }
        return cp;
    }

    std::string parse_string() {
        ++pos_;  // the opening quote
        std::string out;
        for (;;) {
            if (pos_ >= text_.size()) fail("a string is not closed");
            const char c = text_[pos_++];
            if (c == '"') return out;
            if (static_cast<unsigned char>(c) < 0x20) fail("a control character inside a string (escape it)");
            if (c != '\\') {
                out += c;
                continue;
            }
            if (pos_ >= text_.size()) fail("a string is not closed");
            const char e = text_[pos_++];
            switch (e) {
                case '"': out += '"'; break;
                case '\\': out += '\\'; break;
                case '/': out += '/'; break;
                case 'b': out += '\b'; break;
                case 'f': out += '\f'; break;
                case 'n': out += '\n'; break;
                case 'r': out += '\r'; break;
                case 't': out += '\t'; break;
                case 'u': {
                    unsigned long cp = hex4();
                    if (cp >= 0xDC00 && cp <= 0xDFFF) fail("a lone low surrogate in \\u escape");
                    if (cp >= 0xD800 && cp <= 0xDBFF) {
                        if (!take("\\u")) fail("a high surrogate without its low surrogate in \\u escape");
                        const unsigned long low = hex4();
                        if (low < 0xDC00 || low > 0xDFFF) fail("a high surrogate without its low surrogate in \\u escape");
                        cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
                    }
                    append_utf8(out, cp);
                    break;
                }
                default: fail("unknown escape '\\" + std::string(1, e) + "' in a string");
            }
        }
    }

    double parse_number() {
        // The grammar first (from_chars alone would take "01", "1." or ".5").
        const std::size_t start = pos_;
        const auto digits = [&] {
            const std::size_t from = pos_;
            while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') ++pos_;
            return pos_ - from;
        };
        if (text_[pos_] == '-') ++pos_;
        if (pos_ < text_.size() && text_[pos_] == '0') {
            ++pos_;
        } else if (digits() == 0) {
            fail("a number needs digits");
        }
        if (pos_ < text_.size() && text_[pos_] == '.') {
            ++pos_;
            if (digits() == 0) fail("a number needs digits after '.'");
        }
        if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
            ++pos_;
            if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
            if (digits() == 0) fail("a number needs digits in its exponent");
        }
        const std::string_view token = text_.substr(start, pos_ - start);
        double v = 0;
        const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
        if (r.ec == std::errc::result_out_of_range) {
            // Underflow becomes 0; overflow is an error: JSON has no infinity.
            v = std::strtod(std::string(token).c_str(), nullptr);
            if (v > 1 || v < -1) fail("the number " + std::string(token) + " is out of range");
        } else if (r.ec != std::errc() || r.ptr != token.data() + token.size()) {
            fail("cannot read the number " + std::string(token));
        }
        return v;
    }

    std::string_view text_;
    std::string file_;
    std::size_t max_depth_;
    std::size_t pos_ = 0;
    std::size_t line_ = 1;
};

/// The JSON document in `text`; `file` names it in errors (anima::parse_error,
/// "file:line: message").
inline json_value parse_json(std::string_view text, const std::string& file, std::size_t max_depth = 64) {
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // a UTF-8 byte order mark
    return json_parser(text, file, max_depth).parse_document();
}

}  // namespace anima
