// Real-to-real transforms that diagonalise the discrete Laplacian: the sine
// transform DST-I for Dirichlet sides and the cosine transforms DCT-II / III
// for Neumann sides. Unnormalised, with the conventions of FFTW's RODFT00,
// REDFT10 and REDFT01:
//
//   dst1: y_k = 2 sum_{j<n} x_j sin(pi (j+1)(k+1) / (n+1));  its inverse is dst1 / (2(n+1))
//   dct2: y_k = 2 sum_{j<n} x_j cos(pi (j+1/2) k / n)
//   dct3: y_k = x_0 + 2 sum_{0<j<n} x_j cos(pi j (k+1/2) / n); dct3(dct2(x)) = 2n x
//
// Each goes through one complex FFT that carries two real columns at once
// (one in the real part, one in the imaginary part, separated afterwards by
// conjugate symmetry; the second column is first scaled by a power of two to
// the first one's magnitude, so that a small column does not inherit a large
// neighbour's rounding error):
//  - dst1: the odd extension (0, x, 0, -reversed x) of length 2(n + 1),
//    whose DFT is -i dst1(x) on bins 1..n. (Folding it to a transform of
//    length n + 1 would halve the cost, but half the sums must then be
//    recovered by a running sum that accumulates the FFT's rounding errors:
//    ten times less accurate at n = 2049.)
//  - dct2 reorders x into v = (x_0, x_2, x_4, ..., x_5, x_3, x_1), whose
//    DFT V of length n gives y_k = 2 Re(exp(-i pi k / 2n) V_k); dct3 runs
//    that backwards.
#pragma once

#include <anima/core/error.hpp>
#include <anima/poisson/fft.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <string>
#include <vector>

namespace anima {

enum class real_transform_kind : unsigned char { dst1, dct2, dct3 };

inline std::string to_string(real_transform_kind k) {
    return k == real_transform_kind::dst1 ? "dst1" : k == real_transform_kind::dct2 ? "dct2" : "dct3";
}

template <class T>
class real_transform {
public:
    using complex = std::complex<T>;
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    using vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;

    /// A transform of kind `kind` on sequences of length n >= 1.
    real_transform(real_transform_kind kind, Eigen::Index n)
        : kind_(kind), n_(n), fft_(checked_fft_length(kind, n)) {
        const double pi = 3.14159265358979323846264338327950288;
        const auto len = static_cast<std::size_t>(n);
        if (kind != real_transform_kind::dst1) {
            phase_.resize(len);  // exp(-i pi k / 2n)
            for (std::size_t k = 0; k < len; ++k) {
                const double a = -pi * static_cast<double>(k) / (2.0 * static_cast<double>(len));
                phase_[k] = complex(static_cast<T>(std::cos(a)), static_cast<T>(std::sin(a)));
            }
        }
    }

    real_transform_kind kind() const noexcept { return kind_; }
    Eigen::Index size() const noexcept { return n_; }

    /// Transforms every column of m (m.rows() == size()) in place.
    void apply_columns(Eigen::Ref<matrix> m) const {
        if (m.rows() != n_)
            throw invalid_argument("anima::real_transform::apply_columns: the matrix has " + std::to_string(m.rows()) +
                                   " rows, the transform length is " + std::to_string(n_));
        workspace w(fft_.size());
        Eigen::Index j = 0;
        for (; j + 1 < m.cols(); j += 2) apply_pair(&m(0, j), &m(0, j + 1), w);
        if (j < m.cols()) apply_pair(&m(0, j), nullptr, w);
    }

    /// The transform of one vector.
    vector operator()(const vector& x) const {
        matrix m = x;
        apply_columns(m);
        return m.col(0);
    }

    /// Transforms one or two contiguous columns of length size() in place
    /// (b may be null). `w` is scratch space from make_workspace().
    struct workspace {
        explicit workspace(std::size_t len) : z(len), spectrum(len) {}
        std::vector<complex> z, spectrum;
    };
    workspace make_workspace() const { return workspace(fft_.size()); }

    void apply_pair(T* a, T* b, workspace& w) const {
        // Bring b to a's magnitude with an exact power-of-two factor.
        int shift = 0;
        if (b) {
            const auto top = [this](const T* c) {
                T m = T(0);
                for (Eigen::Index j = 0; j < n_; ++j) m = std::max(m, std::abs(c[j]));
                return m;
            };
            const T ma = top(a), mb = top(b);
            if (ma > T(0) && mb > T(0)) {
                int ea = 0, eb = 0;
                std::frexp(ma, &ea);
                std::frexp(mb, &eb);
                shift = ea - eb;
                if (shift != 0)
                    for (Eigen::Index j = 0; j < n_; ++j) b[j] = std::ldexp(b[j], shift);
            }
        }
        switch (kind_) {
            case real_transform_kind::dst1: dst1(a, b, w); break;
            case real_transform_kind::dct2: dct2(a, b, w); break;
            case real_transform_kind::dct3: dct3(a, b, w); break;
        }
        if (shift != 0)
            for (Eigen::Index j = 0; j < n_; ++j) b[j] = std::ldexp(b[j], -shift);
    }

private:
    static std::size_t checked_fft_length(real_transform_kind kind, Eigen::Index n) {
        if (n < 1)
            throw invalid_argument("anima::real_transform: the length must be at least 1, got " + std::to_string(n));
        const auto len = static_cast<std::size_t>(n);
        return kind == real_transform_kind::dst1 ? 2 * (len + 1) : len;
    }

    // The DFTs of the real and the imaginary part of z from its DFT Z, at bin k.
    static void split(const std::vector<complex>& Z, std::size_t k, std::size_t len, complex& ra, complex& rb) {
        const complex p = Z[k], q = std::conj(Z[k == 0 ? 0 : len - k]);
        ra = (p + q) * T(0.5);
        const complex d = (p - q) * T(0.5);
        rb = complex(d.imag(), -d.real());  // d / i
    }

    void dst1(T* a, T* b, workspace& w) const {
        const auto n = static_cast<std::size_t>(n_), len = 2 * (n + 1);
        auto& z = w.z;
        z[0] = z[n + 1] = complex(0, 0);
        for (std::size_t j = 0; j < n; ++j) {
            const complex v(a[j], b ? b[j] : T(0));
            z[j + 1] = v;
            z[len - 1 - j] = -v;
        }
        fft_.forward(z.data(), w.spectrum.data());
        // Bin k holds -i (dst1 a)_{k-1} + (dst1 b)_{k-1}.
        for (std::size_t k = 0; k < n; ++k) {
            const complex v = w.spectrum[k + 1];
            a[k] = -v.imag();
            if (b) b[k] = v.real();
        }
    }

    void dct2(T* a, T* b, workspace& w) const {
        const auto n = static_cast<std::size_t>(n_);
        auto& z = w.z;
        for (std::size_t m = 0; 2 * m < n; ++m) z[m] = complex(a[2 * m], b ? b[2 * m] : T(0));
        for (std::size_t m = 0; 2 * m + 1 < n; ++m) z[n - 1 - m] = complex(a[2 * m + 1], b ? b[2 * m + 1] : T(0));
        fft_.forward(z.data(), w.spectrum.data());
        for (std::size_t k = 0; k < n; ++k) {
            complex va, vb;
            split(w.spectrum, k, n, va, vb);
            a[k] = T(2) * (va * phase_[k]).real();
            if (b) b[k] = T(2) * (vb * phase_[k]).real();
        }
    }

    void dct3(T* a, T* b, workspace& w) const {
        const auto n = static_cast<std::size_t>(n_);
        auto& z = w.z;
        // V_k = exp(i pi k / 2n) (X_k - i X_{n-k}) / 2 for both columns, packed
        // as Va + i Vb and conjugated for the inverse DFT.
        for (std::size_t k = 0; k < n; ++k) {
            const T ak = a[k], an = k ? a[n - k] : T(0);
            const T bk = b ? b[k] : T(0), bn = b && k ? b[n - k] : T(0);
            const complex rot = std::conj(phase_[k]) * T(0.5);
            const complex va = rot * complex(ak, -an), vb = rot * complex(bk, -bn);
            z[k] = std::conj(va + complex(-vb.imag(), vb.real()));
        }
        fft_.forward(z.data(), w.spectrum.data());
        for (std::size_t m = 0; 2 * m < n; ++m) {
            const complex v = std::conj(w.spectrum[m]);
            a[2 * m] = T(2) * v.real();
            if (b) b[2 * m] = T(2) * v.imag();
        }
        for (std::size_t m = 0; 2 * m + 1 < n; ++m) {
            const complex v = std::conj(w.spectrum[n - 1 - m]);
            a[2 * m + 1] = T(2) * v.real();
            if (b) b[2 * m + 1] = T(2) * v.imag();
        }
    }

    real_transform_kind kind_;
    Eigen::Index n_;
    fft_plan<T> fft_;
    std::vector<complex> phase_;
};

}  // namespace anima
