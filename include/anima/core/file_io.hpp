// Reading and writing whole files, shared by every reader and writer of the
// library (and by the command line tool):
//   read_file             the content of a file, with a size limit checked
//                         before anything is allocated;
//   check_output_path     whether a file can be created at a path (its folder
//                         exists, the path is not a folder), before any work;
//   write_file_atomically the content is written to a temporary file in the
//                         same folder and renamed into place only once it is
//                         complete, so a failed write (disk full, file size
//                         limit, a missing folder) leaves an existing file as
//                         it was;
//   output_files          several files written as one: all renamed into
//                         place once every one is complete, or none.
// Everything thrown is an anima::io_error naming the file and the reason.
#pragma once

#include <anima/core/error.hpp>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace anima {

/// The largest file read_file reads by default (1 GiB).
constexpr std::uintmax_t default_max_file_bytes = std::uintmax_t{1} << 30;

namespace detail {

inline std::string errno_reason(int err) { return err ? std::string(": ") + std::strerror(err) : std::string(); }

/// Closes a FILE on scope exit.
struct file_closer {
    std::FILE* f = nullptr;
    ~file_closer() {
        if (f) std::fclose(f);
    }
};

}  // namespace detail

/// The whole content of a file. Throws anima::io_error when it does not
/// exist, is a folder, cannot be read, or is larger than `max_bytes` (checked
/// before anything is allocated).
inline std::string read_file(const std::string& path, std::uintmax_t max_bytes = default_max_file_bytes) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (status.type() == fs::file_type::not_found) throw io_error("cannot read '" + path + "': it does not exist");
    if (status.type() == fs::file_type::directory) throw io_error("cannot read '" + path + "': it is a directory");
    errno = 0;
    detail::file_closer in{std::fopen(path.c_str(), "rb")};
    if (!in.f) throw io_error("cannot open '" + path + "' for reading" + detail::errno_reason(errno));
    std::string text;
    if (status.type() == fs::file_type::regular) {
        const std::uintmax_t size = fs::file_size(path, ec);
        if (!ec && size > max_bytes)
            throw io_error("cannot read '" + path + "': it has " + std::to_string(size) + " bytes, more than the " +
                           std::to_string(max_bytes) + " this reader accepts");
        if (!ec) text.reserve(static_cast<std::size_t>(size));
    }
    char buffer[1 << 16];
    for (;;) {
        const std::size_t got = std::fread(buffer, 1, sizeof buffer, in.f);
        if (got > 0) {
            if (text.size() + got > max_bytes)
                throw io_error("cannot read '" + path + "': it is larger than the " + std::to_string(max_bytes) +
                               " bytes this reader accepts");
            text.append(buffer, got);
        }
        if (got < sizeof buffer) break;
    }
    if (std::ferror(in.f)) throw io_error("error while reading '" + path + "'" + detail::errno_reason(errno));
    return text;
}

/// Throws anima::io_error unless a file can be created or replaced at `path`:
/// the path is not empty and not a folder, and its folder exists. `what`
/// prefixes the message (an option name such as "--plot", or a function).
inline void check_output_path(const std::string& path, std::string_view what = {}) {
    namespace fs = std::filesystem;
    const std::string prefix = what.empty() ? std::string() : std::string(what) + ": ";
    if (path.empty()) throw io_error(prefix + "empty output path");
    std::error_code ec;
    const fs::path p(path);
    if (fs::is_directory(p, ec)) throw io_error(prefix + "cannot write '" + path + "': it is a directory");
    const fs::path folder = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    const fs::file_status s = fs::status(folder, ec);
    if (s.type() == fs::file_type::not_found)
        throw io_error(prefix + "cannot write '" + path + "': the folder '" + folder.string() + "' does not exist");
    if (s.type() != fs::file_type::directory && s.type() != fs::file_type::unknown)
        throw io_error(prefix + "cannot write '" + path + "': '" + folder.string() + "' is not a folder");
}

namespace detail {

/// Whether `path` names an existing file that is neither a regular file nor
/// a folder: a FIFO, a device such as /dev/stdout. Renaming a temporary onto
/// it would replace the node with a regular file, so it is written in place.
inline bool is_special_file(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status s = fs::status(path, ec);
    return !ec && s.type() != fs::file_type::not_found && s.type() != fs::file_type::regular &&
           s.type() != fs::file_type::directory;
}

/// Writes `content` to the file at `file` (created or truncated); `path` is
/// the name the messages give. `cleanup` runs before anything is thrown.
template <class Cleanup>
void write_bytes(const std::string& file, const std::string& path, std::string_view content, Cleanup cleanup) {
    const auto fail = [&](const std::string& what, int err) {
        cleanup();
        throw io_error(what + errno_reason(err));
    };
    errno = 0;
    file_closer out{std::fopen(file.c_str(), "wb")};
    if (!out.f) fail("cannot open '" + file + "' for writing" + (file == path ? "" : " (to replace '" + path + "')"), errno);
    if (!content.empty() && std::fwrite(content.data(), 1, content.size(), out.f) != content.size())
        fail("error while writing '" + path + "'", errno);
    if (std::fflush(out.f) != 0) fail("error while writing '" + path + "'", errno);
    const int closed = std::fclose(out.f);
    out.f = nullptr;
    if (closed != 0) fail("error while writing '" + path + "'", errno);
}

/// `content` in a new temporary file beside `path`, whose name it returns.
inline std::filesystem::path write_temporary(const std::string& path, std::string_view content) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    std::random_device entropy;
    std::mt19937_64 bits((static_cast<std::uint64_t>(entropy()) << 32) ^ entropy());
    fs::path temp;
    std::error_code ec;
    for (int attempt = 0;; ++attempt) {
        char suffix[32];
        std::snprintf(suffix, sizeof suffix, ".%016llx.tmp", static_cast<unsigned long long>(bits()));
        temp = target.parent_path() / ("." + target.filename().string() + suffix);
        if (!fs::exists(temp, ec)) break;
        if (attempt == 16) throw io_error("cannot write '" + path + "': no free temporary file name next to it");
    }
    write_bytes(temp.string(), path, content, [&] { fs::remove(temp, ec); });
    return temp;
}

/// Renames a complete temporary onto `path`; a replaced file's permissions
/// carry over. The temporary is removed when the rename fails.
inline void rename_into_place(const std::filesystem::path& temp, const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status old = fs::status(path, ec);
    if (!ec && fs::is_regular_file(old)) fs::permissions(temp, old.permissions(), ec);
    fs::rename(temp, path, ec);
    if (ec) {
        const std::string reason = ec.message();
        fs::remove(temp, ec);
        throw io_error("cannot replace '" + path + "': " + reason);
    }
}

}  // namespace detail


/// Files written as one: write() puts each file's bytes in a temporary file
/// beside it, and commit() renames them all into place once every one is
/// complete. Destroyed (or discarded) without a commit, it removes its
/// temporaries, so a run that fails after writing some of its outputs leaves
/// every existing file as it was. A FIFO or a device is written in place at
/// the commit, before the renames, so that one refusing its bytes (a full
/// disk, /dev/full) replaces nothing. Only the renames are left for the
/// commit after that: should one of them fail, the files before it have
/// been replaced and the rest are not.
/// Throws anima::io_error naming the file and the reason.
class output_files {
public:
    output_files() = default;
    output_files(const output_files&) = delete;
    output_files& operator=(const output_files&) = delete;
    ~output_files() { discard(); }

    void write(const std::string& path, std::string_view content) {
        check_output_path(path);
        if (detail::is_special_file(path))
            entries_.push_back({path, {}, std::string(content)});
        else
            entries_.push_back({path, detail::write_temporary(path, content), {}});
    }

    void commit() {
        // The files written in place first: a device or FIFO that refuses
        // its bytes then leaves every regular file as it was.
        std::stable_partition(entries_.begin(), entries_.end(), [](const entry& e) { return e.temp.empty(); });
        std::size_t done = 0;
        try {
            for (; done < entries_.size(); ++done) {
                const entry& e = entries_[done];
                if (e.temp.empty())
                    detail::write_bytes(e.path, e.path, e.content, [] {});
                else
                    detail::rename_into_place(e.temp, e.path);
            }
        } catch (...) {
            entries_.erase(entries_.begin(), entries_.begin() + static_cast<std::ptrdiff_t>(done) + 1);
            discard();
            throw;
        }
        entries_.clear();
    }

    /// Removes the temporaries of files not yet committed.
    void discard() noexcept {
        std::error_code ec;
        for (const entry& e : entries_)
            if (!e.temp.empty()) std::filesystem::remove(e.temp, ec);
        entries_.clear();
    }

    std::size_t pending() const noexcept { return entries_.size(); }

private:
    struct entry {
        std::string path;
        std::filesystem::path temp;  ///< empty for a file written in place
        std::string content;         ///< the bytes of a file written in place
    };
    std::vector<entry> entries_;
};

/// Writes `content` to `path`, replacing the file: the bytes go to a
/// temporary file next to it, which is renamed into place once it is
/// complete and closed. When anything fails the temporary is removed and an
/// existing file at `path` is left as it was. A replaced file keeps its
/// permissions. A FIFO or a device (/dev/stdout) is written in place, not
/// replaced. Throws anima::io_error naming the file and the reason.
inline void write_file_atomically(const std::string& path, std::string_view content) {
    output_files out;  // one file: the same temporary, rename and in-place writing
    out.write(path, content);
    out.commit();
}

}  // namespace anima
