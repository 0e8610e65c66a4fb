// A complex fast Fourier transform of any length, for the sine and cosine
// transforms of the fast Poisson solver.
//
// Mixed-radix Cooley-Tukey (decimation in time, radices 4, 2, 3, 5 and any
// other small prime) in O(n log n); a length with a prime factor above 97 goes
// through Bluestein's chirp-z convolution on a length of the form
// 2^a 3^b 5^c instead, so that no length costs O(n^2). Twiddle factors are
// computed in double precision once per plan.
#pragma once

#include <anima/core/error.hpp>

#include <cmath>
#include <complex>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace anima {

template <class T>
class fft_plan {
public:
    using complex = std::complex<T>;

    /// A plan for transforms of length n >= 1.
    explicit fft_plan(std::size_t n) : n_(n) {
        if (n == 0) throw invalid_argument("anima::fft_plan: the length must be at least 1");
        std::size_t rest = n, largest = 1;
        std::vector<std::size_t> primes;
        for (std::size_t p = 2; p * p <= rest; ++p)
            while (rest % p == 0) {
                primes.push_back(p);
                largest = p;
                rest /= p;
            }
        if (rest > 1) {
            primes.push_back(rest);
            if (rest > largest) largest = rest;
        }
        if (largest > max_direct_radix) {
            init_bluestein();
            return;
        }
        // Radix 4 first (fewest passes), then 2, 3, 5 and the other primes.
        std::size_t twos = 0;
        for (std::size_t p : primes) twos += p == 2;
        for (; twos >= 2; twos -= 2) radices_.push_back(4);
        if (twos) radices_.push_back(2);
        for (std::size_t p : primes)
            if (p != 2) radices_.push_back(p);
        std::size_t m = n;
        for (std::size_t p : radices_) {
            m /= p;
            remaining_.push_back(m);
        }
        twiddles_.resize(n);
        for (std::size_t k = 0; k < n; ++k) twiddles_[k] = unit_root(k, n);
    }

    std::size_t size() const noexcept { return n_; }

    /// out[k] = sum_j in[j] exp(-2 pi i j k / n). `in` and `out` must not overlap.
    void forward(const complex* in, complex* out) const {
        if (bluestein_) {
            run_bluestein(in, out);
            return;
        }
        if (n_ == 1) {
            out[0] = in[0];
            return;
        }
        run(out, in, 1, 0);
    }

    /// out[k] = sum_j in[j] exp(+2 pi i j k / n), unnormalised (forward then
    /// inverse multiplies by n). `in` and `out` must not overlap.
    void inverse(const complex* in, complex* out) const {
        std::vector<complex> tmp(in, in + n_);
        for (auto& z : tmp) z = std::conj(z);
        forward(tmp.data(), out);
        for (std::size_t k = 0; k < n_; ++k) out[k] = std::conj(out[k]);
    }

    /// Convenience forms on vectors.
    std::vector<complex> forward(const std::vector<complex>& in) const {
        check_length(in.size(), "forward");
        std::vector<complex> out(n_);
        forward(in.data(), out.data());
        return out;
    }
    std::vector<complex> inverse(const std::vector<complex>& in) const {
        check_length(in.size(), "inverse");
        std::vector<complex> out(n_);
        inverse(in.data(), out.data());
        return out;
    }

    /// The radices used, outermost first (empty for Bluestein and n = 1).
    const std::vector<std::size_t>& radices() const noexcept { return radices_; }
    bool uses_bluestein() const noexcept { return static_cast<bool>(bluestein_); }

private:
    static constexpr std::size_t max_direct_radix = 97;

    struct bluestein_data {
        std::size_t m = 0;
        std::unique_ptr<fft_plan> sub;       // length m, 5-smooth
        std::vector<complex> chirp;          // exp(-i pi j^2 / n), j < n
        std::vector<complex> kernel;         // FFT of the conjugate chirp, divided by m
    };

    static complex unit_root(std::size_t k, std::size_t n) {
        // exp(-2 pi i k / n) in double, reduced to [0, n) for accuracy.
        const double a = -2.0 * 3.14159265358979323846264338327950288 * static_cast<double>(k % n) / static_cast<double>(n);
        return complex(static_cast<T>(std::cos(a)), static_cast<T>(std::sin(a)));
    }

    static complex mul(const complex& a, const complex& b) {
        // Plain product: the library's version also guards against NaN and
        // infinity, which costs a branch in the innermost loop.
        return complex(a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real());
    }
    static complex times_minus_i(const complex& a) { return complex(a.imag(), -a.real()); }

    void check_length(std::size_t got, const char* what) const {
        if (got != n_)
            throw invalid_argument(std::string("anima::fft_plan::") + what + ": the input has " + std::to_string(got) +
                                   " values, the plan length is " + std::to_string(n_));
    }

    void init_bluestein() {
        auto data = std::make_shared<bluestein_data>();
        // The smallest 2^a 3^b 5^c >= 2n - 1 (at most a third above it,
        // where a power of two can be twice as long).
        std::size_t m = 1;
        while (m < 2 * n_ - 1) m *= 2;
        for (std::size_t p2 = 1; p2 < m; p2 *= 2)
            for (std::size_t p3 = p2; p3 < m; p3 *= 3)
                for (std::size_t p5 = p3; p5 < m; p5 *= 5)
                    if (p5 >= 2 * n_ - 1) m = p5;
        data->m = m;
        data->sub = std::make_unique<fft_plan>(m);
        data->chirp.resize(n_);
        const double pi = 3.14159265358979323846264338327950288;
        for (std::size_t j = 0; j < n_; ++j) {
            // j^2 mod 2n keeps the angle small and exact.
            const std::size_t q = static_cast<std::size_t>((static_cast<unsigned long long>(j) * j) % (2 * n_));
            const double a = -pi * static_cast<double>(q) / static_cast<double>(n_);
            data->chirp[j] = complex(static_cast<T>(std::cos(a)), static_cast<T>(std::sin(a)));
        }
        std::vector<complex> b(m, complex(0, 0));
        b[0] = std::conj(data->chirp[0]);
        for (std::size_t j = 1; j < n_; ++j) b[j] = b[m - j] = std::conj(data->chirp[j]);
        data->kernel.resize(m);
        data->sub->forward(b.data(), data->kernel.data());
        const T scale = T(1) / static_cast<T>(m);
        for (auto& z : data->kernel) z *= scale;
        bluestein_ = std::move(data);
    }

    void run_bluestein(const complex* in, complex* out) const {
        const bluestein_data& d = *bluestein_;
        std::vector<complex> a(d.m, complex(0, 0)), fa(d.m);
        for (std::size_t j = 0; j < n_; ++j) a[j] = mul(in[j], d.chirp[j]);
        d.sub->forward(a.data(), fa.data());
        // Inverse transform of the product by conjugation.
        for (std::size_t k = 0; k < d.m; ++k) fa[k] = std::conj(mul(fa[k], d.kernel[k]));
        d.sub->forward(fa.data(), a.data());
        for (std::size_t k = 0; k < n_; ++k) out[k] = mul(std::conj(a[k]), d.chirp[k]);
    }

    // Transforms the sequence in[0], in[s], in[2s]... (s = fstride) of length
    // radices[stage] * remaining[stage] into out[0..len).
    void run(complex* out, const complex* in, std::size_t fstride, std::size_t stage) const {
        const std::size_t p = radices_[stage], m = remaining_[stage];
        if (m == 1) {
            for (std::size_t q = 0; q < p; ++q) out[q] = in[q * fstride];
        } else {
            for (std::size_t q = 0; q < p; ++q) run(out + q * m, in + q * fstride, fstride * p, stage + 1);
        }
        switch (p) {
            case 2: butterfly2(out, fstride, m); break;
            case 3: butterfly3(out, fstride, m); break;
            case 4: butterfly4(out, fstride, m); break;
            case 5: butterfly5(out, fstride, m); break;
            default: butterfly_generic(out, fstride, p, m); break;
        }
    }

    void butterfly2(complex* out, std::size_t fstride, std::size_t m) const {
        for (std::size_t k = 0; k < m; ++k) {
            const complex t = mul(out[k + m], twiddles_[k * fstride]);
            out[k + m] = out[k] - t;
            out[k] += t;
        }
    }

    void butterfly3(complex* out, std::size_t fstride, std::size_t m) const {
        const T h = static_cast<T>(0.86602540378443864676);  // sin(2 pi / 3)
        for (std::size_t k = 0; k < m; ++k) {
            const complex a0 = out[k];
            const complex a1 = mul(out[k + m], twiddles_[k * fstride]);
            const complex a2 = mul(out[k + 2 * m], twiddles_[2 * k * fstride]);
            const complex s = a1 + a2, d = times_minus_i(a1 - a2) * h;
            const complex c = a0 - s * T(0.5);
            out[k] = a0 + s;
            out[k + m] = c + d;
            out[k + 2 * m] = c - d;
        }
    }

    void butterfly4(complex* out, std::size_t fstride, std::size_t m) const {
        for (std::size_t k = 0; k < m; ++k) {
            const complex a0 = out[k];
            const complex a1 = mul(out[k + m], twiddles_[k * fstride]);
            const complex a2 = mul(out[k + 2 * m], twiddles_[2 * k * fstride]);
            const complex a3 = mul(out[k + 3 * m], twiddles_[3 * k * fstride]);
            const complex s02 = a0 + a2, d02 = a0 - a2, s13 = a1 + a3, d13 = times_minus_i(a1 - a3);
            out[k] = s02 + s13;
            out[k + m] = d02 + d13;
            out[k + 2 * m] = s02 - s13;
            out[k + 3 * m] = d02 - d13;
        }
    }

    void butterfly5(complex* out, std::size_t fstride, std::size_t m) const {
        const T c1 = static_cast<T>(0.30901699437494742410), c2 = static_cast<T>(-0.80901699437494742410);
        const T s1 = static_cast<T>(0.95105651629515357212), s2 = static_cast<T>(0.58778525229247312917);
        for (std::size_t k = 0; k < m; ++k) {
            const complex a0 = out[k];
            const complex a1 = mul(out[k + m], twiddles_[k * fstride]);
            const complex a2 = mul(out[k + 2 * m], twiddles_[2 * k * fstride]);
            const complex a3 = mul(out[k + 3 * m], twiddles_[3 * k * fstride]);
            const complex a4 = mul(out[k + 4 * m], twiddles_[4 * k * fstride]);
            const complex b1 = a1 + a4, b2 = a2 + a3, d1 = a1 - a4, d2 = a2 - a3;
            const complex e1 = a0 + b1 * c1 + b2 * c2, e2 = a0 + b1 * c2 + b2 * c1;
            const complex f1 = times_minus_i(d1 * s1 + d2 * s2), f2 = times_minus_i(d1 * s2 - d2 * s1);
            out[k] = a0 + b1 + b2;
            out[k + m] = e1 + f1;
            out[k + 4 * m] = e1 - f1;
            out[k + 2 * m] = e2 + f2;
            out[k + 3 * m] = e2 - f2;
        }
    }

    // An odd prime radix p: the terms q and p - q share a cosine and an
    // opposite sine, so each output pair r, p - r costs (p - 1) / 2 real
    // multiplications per term instead of p complex ones.
    void butterfly_generic(complex* out, std::size_t fstride, std::size_t p, std::size_t m) const {
        const std::size_t h = (p - 1) / 2, root = n_ / p;  // twiddles_[e * root] = exp(-2 pi i e / p)
        std::vector<complex> sum(h + 1), diff(h + 1);
        std::vector<T> c(p), sn(p);
        for (std::size_t e = 0; e < p; ++e) {
            c[e] = twiddles_[e * root].real();
            sn[e] = -twiddles_[e * root].imag();  // sin(2 pi e / p)
        }
        for (std::size_t k = 0; k < m; ++k) {
            const complex a0 = out[k];
            for (std::size_t q = 1; q <= h; ++q) {
                const complex aq = mul(out[k + q * m], twiddles_[q * k * fstride]);
                const complex ar = mul(out[k + (p - q) * m], twiddles_[(p - q) * k * fstride]);
                sum[q] = aq + ar;
                diff[q] = aq - ar;
            }
            complex total = a0;
            for (std::size_t q = 1; q <= h; ++q) total += sum[q];
            out[k] = total;
            for (std::size_t r = 1; r <= h; ++r) {
                complex A = a0, B(0, 0);
                std::size_t e = 0;
                for (std::size_t q = 1; q <= h; ++q) {
                    e += r;
                    if (e >= p) e -= p;
                    A += sum[q] * c[e];
                    B += diff[q] * sn[e];
                }
                const complex minus_i_b = times_minus_i(B);
                out[k + r * m] = A + minus_i_b;
                out[k + (p - r) * m] = A - minus_i_b;
            }
        }
    }

    std::size_t n_;
    std::vector<std::size_t> radices_, remaining_;
    std::vector<complex> twiddles_;
    std::shared_ptr<const bluestein_data> bluestein_;
};

}  // namespace anima
