// Netpbm grey and colour images: PGM (P2 text, P5 binary) and PPM (P3 text,
// P6 binary), 8-bit or 16-bit samples. Reading reports malformed files as
// anima::parse_error ("file:line: message"); values are kept as stored
// (0..maxval), with maxval returned alongside.
#pragma once

#include <anima/core/error.hpp>
#include <anima/core/file_io.hpp>
#include <anima/image/image.hpp>

#include <cctype>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

namespace anima {

/// A decoded Netpbm file.
struct pnm_image {
    image<std::uint16_t> pixels;  ///< 1 channel for PGM, 3 for PPM
    int maxval = 255;             ///< the largest sample value the file allows
};

namespace detail {

/// Reads the header's and text bodies' tokens, counting lines for messages.
class pnm_cursor {
public:
    pnm_cursor(std::string_view text, std::string source) : text_(text), source_(std::move(source)) {}

    [[noreturn]] void fail(const std::string& message) const { throw parse_error(source_, line_, message); }

    /// The next non-negative integer, skipping blanks and '#' comments.
    unsigned long number(const char* what) {
        skip_blanks();
        if (pos_ >= text_.size()) fail(std::string("file ends before the ") + what);
        if (!std::isdigit(static_cast<unsigned char>(text_[pos_])))
            fail(std::string("expected the ") + what + ", found '" + std::string(1, text_[pos_]) + "'");
        unsigned long v = 0;
        while (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_]))) {
            v = v * 10 + static_cast<unsigned long>(text_[pos_] - '0');
            if (v > 1000000000UL) fail(std::string("the ") + what + " is too large");
            ++pos_;
        }
        return v;
    }

    std::string_view magic() {
        if (text_.size() < 2) fail("file ends before the magic number (P2, P3, P5 or P6)");
        pos_ = 2;
        return text_.substr(0, 2);
    }

    /// After the header: exactly one whitespace byte precedes binary data.
    std::size_t binary_start() {
        if (pos_ >= text_.size() || !std::isspace(static_cast<unsigned char>(text_[pos_])))
            fail("expected one whitespace byte after maxval");
        if (text_[pos_] == '\n') ++line_;
        return pos_ + 1;
    }

    std::size_t line() const noexcept { return line_; }
    /// Bytes not read yet.
    std::size_t remaining() const noexcept { return text_.size() - pos_; }

private:
    void skip_blanks() {
        while (pos_ < text_.size()) {
            const char c = text_[pos_];
            if (c == '#') {
                while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
            } else if (std::isspace(static_cast<unsigned char>(c))) {
                if (c == '\n') ++line_;
                ++pos_;
            } else {
                break;
            }
        }
    }

    std::string_view text_;
    std::string source_;
    std::size_t pos_ = 0;
    std::size_t line_ = 1;
};

}  // namespace detail

/// Decodes PGM/PPM bytes. `source` names the data in error messages.
/// Throws anima::parse_error for a bad magic number, size, maxval, a sample
/// above maxval or data that ends early.
inline pnm_image parse_pnm(std::string_view bytes, const std::string& source = "<pnm>") {
    detail::pnm_cursor in(bytes, source);
    const std::string_view magic = in.magic();
    if (magic != "P2" && magic != "P3" && magic != "P5" && magic != "P6")
        in.fail("not a PGM/PPM file: the magic number is '" + std::string(magic) + "', expected P2, P3, P5 or P6");
    const bool text = magic == "P2" || magic == "P3";
    const int channels = (magic == "P3" || magic == "P6") ? 3 : 1;
    const unsigned long width = in.number("width"), height = in.number("height");
    if (width == 0 || height == 0 || width > 65535 || height > 65535)
        in.fail("image size " + std::to_string(width) + " x " + std::to_string(height) +
                " is outside 1..65535 on an axis");
    const unsigned long maxval = in.number("maxval");
    if (maxval == 0 || maxval > 65535) in.fail("maxval " + std::to_string(maxval) + " is outside 1..65535");
    // Every sample needs at least one byte (two for 16-bit binary samples, a
    // digit and a separator as text): check before allocating anything.
    const std::size_t samples = static_cast<std::size_t>(width) * height * static_cast<std::size_t>(channels);
    const std::size_t bytes_per_sample = maxval > 255 ? 2 : 1;
    std::size_t start = 0;
    if (text) {
        if (in.remaining() / 2 + 1 < samples)
            in.fail("file ends inside the pixel data: " + std::to_string(in.remaining()) + " bytes cannot hold the " +
                    std::to_string(samples) + " samples of a " + std::to_string(width) + " x " +
                    std::to_string(height) + " image");
    } else {
        start = in.binary_start();
        if (bytes.size() - start < samples * bytes_per_sample)
            in.fail("file ends inside the pixel data: " + std::to_string(bytes.size() - start) + " bytes for " +
                    std::to_string(samples * bytes_per_sample) + " expected (" + std::to_string(width) + " x " +
                    std::to_string(height) + " image)");
    }
    pnm_image out;
    out.maxval = static_cast<int>(maxval);
    out.pixels = image<std::uint16_t>(static_cast<int>(width), static_cast<int>(height), channels);
    auto& px = out.pixels.pixels;
    if (text) {
        for (std::size_t k = 0; k < px.size(); ++k) {
            const unsigned long v = in.number("sample");
            if (v > maxval) in.fail("sample " + std::to_string(v) + " exceeds maxval " + std::to_string(maxval));
            px[k] = static_cast<std::uint16_t>(v);
        }
        return out;
    }
    for (std::size_t k = 0; k < px.size(); ++k) {
        const auto byte = [&](std::size_t i) { return static_cast<unsigned>(static_cast<unsigned char>(bytes[i])); };
        const unsigned v = bytes_per_sample == 2 ? (byte(start + 2 * k) << 8) | byte(start + 2 * k + 1) : byte(start + k);
        if (v > maxval) in.fail("sample " + std::to_string(v) + " exceeds maxval " + std::to_string(maxval));
        px[k] = static_cast<std::uint16_t>(v);
    }
    return out;
}

/// Reads a PGM/PPM file. Throws anima::io_error when it cannot be read (it
/// does not exist, is a folder),
/// anima::parse_error ("path:line: message") when it is malformed.
inline pnm_image read_pnm(const std::string& path) { return parse_pnm(read_file(path), path); }

/// Binary PGM (one channel) or PPM (three channels) bytes of an 8-bit image.
/// Throws anima::invalid_argument for an empty image or a pixel count that
/// does not match the size.
inline std::string format_pnm(const image<unsigned char>& img) {
    if (img.empty() || img.pixels.size() != static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height) *
                                                static_cast<std::size_t>(img.channels))
        throw invalid_argument("anima::format_pnm: the image is empty or its pixel count does not match " +
                               std::to_string(img.width) + " x " + std::to_string(img.height) + " x " +
                               std::to_string(img.channels));
    std::string out = std::string(img.channels == 1 ? "P5" : "P6") + "\n" + std::to_string(img.width) + " " +
                      std::to_string(img.height) + "\n255\n";
    out.append(reinterpret_cast<const char*>(img.pixels.data()), img.pixels.size());
    return out;
}

/// Writes an 8-bit image as binary PGM/PPM, atomically (see
/// write_file_atomically). Throws anima::io_error when the file cannot be
/// written; an existing file is then left as it was.
inline void write_pnm(const std::string& path, const image<unsigned char>& img) {
    write_file_atomically(path, format_pnm(img));
}

/// Writes grey levels (rounded, clamped to 0-255) as a binary PGM. Throws
/// anima::invalid_argument for a non-finite value, anima::io_error when the
/// file cannot be written.
template <class Derived>
void write_pgm(const std::string& path, const Eigen::MatrixBase<Derived>& grey) {
    image<unsigned char> img(static_cast<int>(grey.cols()), static_cast<int>(grey.rows()), 1);
    img.pixels = to_bytes(grey, "anima::write_pgm");
    write_pnm(path, img);
}

/// The grey levels of a PGM/PPM file (see to_grey), scaled to 0-255 when
/// maxval is not 255.
template <class T>
grey_image<T> read_grey_pnm(const std::string& path) {
    const pnm_image p = read_pnm(path);
    grey_image<T> g = to_grey<T>(p.pixels);
    if (p.maxval != 255) g *= T(255) / static_cast<T>(p.maxval);
    return g;
}

}  // namespace anima
