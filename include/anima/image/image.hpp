// A small image type: width x height pixels with 1 (grey) or 3 (RGB)
// interleaved channels, rows top to bottom. Algorithms that work on one
// channel take an Eigen matrix instead (rows = y, columns = x); to_grey and
// from_grey convert between the two.
#pragma once

#include <anima/core/error.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace anima {

/// One channel of an image as a matrix: element (y, x).
template <class T>
using grey_image = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

/// Pixels with interleaved channels, row-major from the top-left corner.
template <class T>
struct image {
    int width = 0;
    int height = 0;
    int channels = 1;       ///< 1 (grey) or 3 (RGB)
    std::vector<T> pixels;  ///< width * height * channels values

    image() = default;
    /// A width x height image with every value set to `fill`. Throws
    /// anima::invalid_argument for a negative size or a channel count other than 1 or 3.
    image(int w, int h, int c = 1, T fill = T(0)) : width(w), height(h), channels(c) {
        if (w < 0 || h < 0)
            throw invalid_argument("anima::image: the size must not be negative, got " + std::to_string(w) + " x " +
                                   std::to_string(h));
        if (c != 1 && c != 3)
            throw invalid_argument("anima::image: channels must be 1 or 3, got " + std::to_string(c));
        pixels.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(c), fill);
    }

    bool empty() const noexcept { return pixels.empty(); }
    std::size_t index(int x, int y, int c = 0) const noexcept {
        return (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) *
                   static_cast<std::size_t>(channels) +
               static_cast<std::size_t>(c);
    }
    T& operator()(int x, int y, int c = 0) noexcept { return pixels[index(x, y, c)]; }
    const T& operator()(int x, int y, int c = 0) const noexcept { return pixels[index(x, y, c)]; }
};

/// The grey levels of an image: the channel itself for grey images, the
/// Rec. 601 luma 0.299 R + 0.587 G + 0.114 B for RGB.
template <class T, class U>
grey_image<T> to_grey(const image<U>& img) {
    grey_image<T> g(img.height, img.width);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            if (img.channels == 1) {
                g(y, x) = static_cast<T>(img(x, y));
            } else {
                const double v = 0.299 * static_cast<double>(img(x, y, 0)) + 0.587 * static_cast<double>(img(x, y, 1)) +
                                 0.114 * static_cast<double>(img(x, y, 2));
                g(y, x) = static_cast<T>(v);
            }
        }
    return g;
}

/// A grey image (1 channel) with the matrix's values.
template <class U, class Derived>
image<U> from_grey(const Eigen::MatrixBase<Derived>& g) {
    image<U> img(static_cast<int>(g.cols()), static_cast<int>(g.rows()), 1);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) img(x, y) = static_cast<U>(g(y, x));
    return img;
}

/// 8-bit grey levels of a matrix: rounded and clamped to 0-255. Throws
/// anima::invalid_argument, naming `who` and the pixel, for a non-finite value.
template <class Derived>
std::vector<unsigned char> to_bytes(const Eigen::MatrixBase<Derived>& g, const std::string& who) {
    std::vector<unsigned char> out(static_cast<std::size_t>(g.rows() * g.cols()));
    std::size_t k = 0;
    for (Eigen::Index y = 0; y < g.rows(); ++y)
        for (Eigen::Index x = 0; x < g.cols(); ++x) {
            const double v = static_cast<double>(g(y, x));
            if (!std::isfinite(v))
                throw invalid_argument(who + ": pixel (x " + std::to_string(x) + ", y " + std::to_string(y) +
                                       ") is not finite");
            out[k++] = static_cast<unsigned char>(v <= 0 ? 0.0 : v >= 255 ? 255.0 : std::round(v));
        }
    return out;
}

}  // namespace anima
