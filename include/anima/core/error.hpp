// Exceptions thrown by anima. Every failure the library reports derives from
// anima::error, so `catch (const anima::error&)` is enough for callers.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

namespace anima {

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
/// what() reads "file:line: message" like a compiler diagnostic.
class parse_error : public error {
public:
    parse_error(std::string file, std::size_t line, const std::string& message)
        : error(file + ":" + std::to_string(line) + ": " + message),
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
