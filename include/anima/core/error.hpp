// Exceptions thrown by anima. Every failure the library reports derives from
// anima::error, so `catch (const anima::error&)` is enough for callers.
#pragma once

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace anima {

/// Text from a file made safe to print in a message: control characters,
/// NUL and bytes that are not valid UTF-8 become \xNN (a tab stays a tab),
/// and text longer than `max_bytes` is cut in the middle ("..."). Valid UTF-8
/// is kept as it is, so joint names in any script read normally.
inline std::string escape_for_message(std::string_view text, std::size_t max_bytes = 2000) {
    static constexpr char hex[] = "0123456789abcdef";
    std::string out;
    out.reserve(std::min(text.size(), max_bytes) + 16);
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const auto escape = [&](unsigned char c) {
        out += "\\x";
        out += hex[c >> 4];
        out += hex[c & 15];
    };
    std::size_t i = 0;
    const std::size_t keep_head = max_bytes / 2;
    while (i < text.size()) {
        if (out.size() >= keep_head && text.size() - i > max_bytes / 2) {
            // Skip to the last max_bytes / 2 bytes, at a character boundary.
            std::size_t j = text.size() - max_bytes / 2;
            while (j < text.size() && (byte(j) & 0xC0) == 0x80) ++j;
            out += " ... ";
            i = j;
            continue;
        }
        const unsigned char c = byte(i);
        if (c < 0x80) {
            if ((c < 0x20 && c != '\t') || c == 0x7f) escape(c);
            else out += static_cast<char>(c);
            ++i;
            continue;
        }
        // A UTF-8 sequence: lead byte, then 1-3 continuation bytes; no
        // overlong forms, surrogates or code points above U+10FFFF.
        std::size_t n = 0;
        unsigned long cp = 0;
        if (c >= 0xC2 && c <= 0xDF) n = 1, cp = c & 0x1Fu;
        else if (c >= 0xE0 && c <= 0xEF) n = 2, cp = c & 0x0Fu;
        else if (c >= 0xF0 && c <= 0xF4) n = 3, cp = c & 0x07u;
        bool ok = n > 0;
        for (std::size_t k = 1; ok && k <= n; ++k) {
            if (i + k >= text.size() || (byte(i + k) & 0xC0) != 0x80) ok = false;
            else cp = (cp << 6) | (byte(i + k) & 0x3Fu);
        }
        if (ok && ((n == 2 && cp < 0x800) || (n == 3 && (cp < 0x10000 || cp > 0x10FFFF)) || (cp >= 0xD800 && cp <= 0xDFFF)))
            ok = false;
        if (!ok) {
            escape(c);
            ++i;
            continue;
        }
        out.append(text.substr(i, n + 1));
        i += n + 1;
    }
    return out;
}

/// Base of every exception anima throws.
class error : public std::runtime_error {
public:
    explicit error(const std::string& what) : std::runtime_error(what) {}
};

/// A function received an argument it cannot work with (wrong size, out of
/// range, non-finite value...). The message names the function and the value.
class invalid_argument : public error {
public:
    explicit invalid_argument(const std::string& what) : error(what) {}
};

/// A file could not be parsed. Carries the file name and 1-based line number;
/// what() reads "file:line: message" like a compiler diagnostic. Bytes of the
/// message that are not printable text (control characters, NUL, invalid
/// UTF-8, say from a binary file) are escaped as \xNN.
class parse_error : public error {
public:
    parse_error(std::string file, std::size_t line, const std::string& message)
        : error(escape_for_message(file) + ":" + std::to_string(line) + ": " +
                escape_for_message(message)),
          file_(std::move(file)),
          line_(line),
          message_(message) {}

    const std::string& file() const noexcept { return file_; }
    std::size_t line() const noexcept { return line_; }
    const std::string& message() const noexcept { return message_; }

private:
    std::string file_;
    std::size_t line_;
    std::string message_;
};

/// A file could not be opened, read or written.
class io_error : public error {
public:
    explicit io_error(const std::string& what) : error(what) {}
};

}  // namespace anima
