// The grid hierarchy of anima::multigrid_poisson and the kernels that run on
// it. Internal: the public interface is anima/poisson/multigrid_poisson.hpp.
//
// Storage: every level keeps its grid functions in column-major arrays padded
// with one ghost cell on each side ((rows + 2) x (cols + 2)); ghosts hold
// zero, so stencils need no bounds checks. Level 0 works on the unknowns of
// A x = b with the boundary data folded into b.
//
// Coarsening is vertex-centred: coarse point I sits on fine point 2I + 1, so
// any size coarsens (n -> n / 2); an axis shorter than 3 is not coarsened,
// and of two axes with very different spacings only the finer one is
// (semi-coarsening keeps point smoothing effective). Prolongation P is linear
// interpolation (constant extension next to a Neumann side, so that P keeps
// the constants), restriction is P^T, and the coarse operators are Galerkin
// products P^T A P: symmetric 9-point stencils, correct for any size, mask or
// boundary mix. Without a mask, A = Ky (x) Mx + My (x) Kx with 1D tridiagonal
// factors on every level, so P^T A P costs O(n) through 1D products; with a
// mask it is formed cell by cell, with P restricted to the unknown cells.
#pragma once

#include <anima/poisson/grid.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace anima::detail::mg {

using index = Eigen::Index;

inline std::size_t at(index k) { return static_cast<std::size_t>(k); }

/// A symmetric tridiagonal matrix: d[i] = A(i, i), l[i] = A(i, i - 1) (l[0] = 0).
template <class T>
struct tridiagonal {
    std::vector<T> d, l;
};

/// How one axis of a level maps to the next coarser level.
template <class T>
struct axis_map {
    index fine = 0, coarse = 0;
    bool coarsened = false;
    // Prolongation, per fine index: two parents as padded coarse indices (a
    // missing parent points at ghost 0 with weight 0).
    std::vector<index> p0, p1;
    std::vector<T> w0, w1;
    // Restriction, per coarse index: padded fine index of the first of three
    // children, and their weights.
    std::vector<index> first;
    std::vector<T> r0, r1, r2;
};

/// The map of an axis whose points lie at `pos` (in units of the finest
/// spacing; the Dirichlet sides at `lo` and `hi`). Interpolation weights come
/// from the positions, not the indices: once an even length has been halved
/// the last interval is shorter than the others, and index weights would
/// stop reproducing linear functions there (convergence then suffers).
template <class T>
axis_map<T> make_axis_map(const std::vector<double>& pos, double lo, double hi, bool coarsen, bool neumann) {
    const auto n = static_cast<index>(pos.size());
    axis_map<T> m;
    m.fine = n;
    m.coarsened = coarsen;
    m.coarse = coarsen ? n / 2 : n;
    m.p0.assign(at(n), 0);
    m.p1.assign(at(n), 0);
    m.w0.assign(at(n), T(0));
    m.w1.assign(at(n), T(0));
    const index nc = m.coarse;
    for (index i = 0; i < n; ++i) {
        if (!coarsen) {
            m.p0[at(i)] = i + 1;
            m.w0[at(i)] = T(1);
            continue;
        }
        if (i % 2 == 1) {
            m.p0[at(i)] = (i - 1) / 2 + 1;
            m.w0[at(i)] = T(1);
            continue;
        }
        const index left = i / 2 - 1, right = i / 2;  // coarse points at fine i - 1 and i + 1
        const bool has_left = left >= 0, has_right = right < nc;
        const double x = pos[at(i)];
        if (has_left && has_right) {
            const double a = pos[at(i - 1)], b = pos[at(i + 1)];
            m.p0[at(i)] = left + 1;
            m.w0[at(i)] = static_cast<T>((b - x) / (b - a));
            m.p1[at(i)] = right + 1;
            m.w1[at(i)] = static_cast<T>((x - a) / (b - a));
        } else if (has_right) {
            // Next to a side: towards its zero (Dirichlet) or flat (Neumann).
            const double b = pos[at(i + 1)];
            m.p0[at(i)] = right + 1;
            m.w0[at(i)] = neumann ? T(1) : static_cast<T>((x - lo) / (b - lo));
        } else if (has_left) {
            const double a = pos[at(i - 1)];
            m.p0[at(i)] = left + 1;
            m.w0[at(i)] = neumann ? T(1) : static_cast<T>((hi - x) / (hi - a));
        }
    }
    m.first.assign(at(nc), 0);
    m.r0.assign(at(nc), T(0));
    m.r1.assign(at(nc), T(0));
    m.r2.assign(at(nc), T(0));
    for (index c = 0; c < nc; ++c) m.first[at(c)] = coarsen ? 2 * c + 1 : c;  // padded index of child 0
    for (index i = 0; i < n; ++i) {
        const auto add = [&](index pc, T w) {
            if (w == T(0)) return;
            const index c = pc - 1;
            const index a = (i + 1) - m.first[at(c)];
            (a == 0 ? m.r0 : a == 1 ? m.r1 : m.r2)[at(c)] = w;
        };
        add(m.p0[at(i)], m.w0[at(i)]);
        add(m.p1[at(i)], m.w1[at(i)]);
    }
    return m;
}

/// P^T A P for a 1D tridiagonal A and the axis map's P.
template <class T>
tridiagonal<T> galerkin_1d(const tridiagonal<T>& a, const axis_map<T>& m) {
    if (!m.coarsened) return a;
    tridiagonal<T> c;
    c.d.assign(at(m.coarse), T(0));
    c.l.assign(at(m.coarse), T(0));
    const index n = m.fine;
    for (index i = 0; i < n; ++i) {
        const index pi[2] = {m.p0[at(i)] - 1, m.p1[at(i)] - 1};
        const T wi[2] = {m.w0[at(i)], m.w1[at(i)]};
        for (index k = i - 1; k <= i + 1; ++k) {
            if (k < 0 || k >= n) continue;
            const T aik = k == i ? a.d[at(i)] : k < i ? a.l[at(i)] : a.l[at(k)];
            if (aik == T(0)) continue;
            const index pk[2] = {m.p0[at(k)] - 1, m.p1[at(k)] - 1};
            const T wk[2] = {m.w0[at(k)], m.w1[at(k)]};
            for (int s = 0; s < 2; ++s) {
                if (wi[s] == T(0)) continue;
                for (int t = 0; t < 2; ++t) {
                    if (wk[t] == T(0)) continue;
                    const T v = wi[s] * aik * wk[t];
                    if (pk[t] == pi[s]) c.d[at(pi[s])] += v;
                    else if (pk[t] == pi[s] - 1) c.l[at(pi[s])] += v;  // the upper half follows by symmetry
                }
            }
        }
    }
    return c;
}

/// A[i][k] of a symmetric tridiagonal matrix for |i - k| <= 1.
template <class T>
T tri_at(const tridiagonal<T>& a, index i, index k) {
    if (k == i) return a.d[at(i)];
    return k < i ? a.l[at(i)] : a.l[at(k)];
}

/// The nine couplings of the points of one column as vectors over the padded
/// row index: A((i, j), (i + di, j + dj)) named by direction (s: i - 1,
/// n: i + 1, w: j - 1, e: j + 1), the diagonal and its inverse.
template <class T>
struct column_stencil {
    const T *s, *n, *w, *e, *sw, *nw, *se, *ne, *diag, *invd;
};

/// One level of the hierarchy.
template <class T>
struct level {
    index ny = 0, nx = 0, ld = 0;  // ld = ny + 2, the padded column length
    T hy = 1, hx = 1;              // nominal spacings (coarsening decisions only)
    std::vector<double> ypos, xpos;  // positions of the rows / columns, in finest spacings
    bool first = false;            // level 0: constant 5-point stencil
    bool stored = false;           // coarse level with a 2D stencil (masked grids)
    std::vector<T> u, b;
    std::vector<unsigned char> active;  // padded; empty when every point is active
    // Level 0: A = cy (second difference in y) + cx (second difference in x),
    // diagonal dy[i] + dx[j]; inverse diagonals per class of columns.
    T cy = 0, cx = 0;
    std::vector<T> dy, dx;
    // Column classes: columns whose stencil is the same vector over rows
    // (level 0: same dx; unmasked coarse levels: same x factors, which differ
    // only next to the sides). Level 0 keeps 1 / diagonal per class; coarse
    // levels the ten vectors of column_stencil, back to back.
    std::vector<int> col_class;
    std::vector<std::vector<T>> classes;
    // Stored coarse stencil: padded arrays of the couplings to (i-1, j),
    // (i, j-1), (i-1, j-1), (i+1, j-1); the other four are the neighbours'
    // (symmetry).
    std::vector<T> diag, invd, cs, cw, csw, cnw;
    // 1D factors (unmasked grids): A = ky (x) mx + my (x) kx.
    tridiagonal<T> ky, my, kx, mx;
    // To the next coarser level.
    axis_map<T> ymap, xmap;

    index size() const { return ld * (nx + 2); }
    index at2(index i, index j) const { return (j + 1) * ld + (i + 1); }
    bool is_active(index i, index j) const { return active.empty() || active[at(at2(i, j))] != 0; }

    /// A((i, j), (i + di, j + dj)) for di, dj in {-1, 0, 1}; zero outside the grid.
    T coef(index i, index j, int di, int dj) const {
        const index i2 = i + di, j2 = j + dj;
        if (i2 < 0 || i2 >= ny || j2 < 0 || j2 >= nx) return T(0);
        if (first) {
            if (!is_active(i, j) || !is_active(i2, j2)) return T(0);
            if (di == 0 && dj == 0) return dy[at(i + 1)] + dx[at(j + 1)];
            if (dj == 0) return -cy;
            if (di == 0) return -cx;
            return T(0);
        }
        if (!stored) return tri_at(ky, i, i2) * tri_at(mx, j, j2) + tri_at(my, i, i2) * tri_at(kx, j, j2);
        if (di == 0 && dj == 0) return diag[at(at2(i, j))];
        if (dj == 0) return di < 0 ? cs[at(at2(i, j))] : cs[at(at2(i2, j))];
        if (di == 0) return dj < 0 ? cw[at(at2(i, j))] : cw[at(at2(i, j2))];
        if (di == dj) return di < 0 ? csw[at(at2(i, j))] : csw[at(at2(i2, j2))];
        return di > 0 ? cnw[at(at2(i, j))] : cnw[at(at2(i2, j2))];
    }

    /// The stencil of column j (coarse levels).
    column_stencil<T> column(index j) const {
        if (stored) {
            const index o = (j + 1) * ld, o1 = o + ld;
            return {cs.data() + o,      cs.data() + o + 1,   cw.data() + o,       cw.data() + o1,
                    csw.data() + o,     cnw.data() + o,      cnw.data() + o1 - 1, csw.data() + o1 + 1,
                    diag.data() + o,    invd.data() + o};
        }
        const T* v = classes[at(col_class[at(j)])].data();
        return {v, v + ld, v + 2 * ld, v + 3 * ld, v + 4 * ld, v + 5 * ld, v + 6 * ld, v + 7 * ld, v + 8 * ld, v + 9 * ld};
    }
};

/// Column classes of a level 0 (inverse diagonals per distinct dx).
template <class T>
void first_level_classes(level<T>& L) {
    L.col_class.assign(at(L.nx), 0);
    L.classes.clear();
    std::vector<T> keys;
    for (index j = 0; j < L.nx; ++j) {
        const T dxj = L.dx[at(j + 1)];
        std::size_t c = 0;
        while (c < keys.size() && keys[c] != dxj) ++c;
        if (c == keys.size()) {
            keys.push_back(dxj);
            std::vector<T> inv(at(L.ld), T(0));
            for (index i = 1; i <= L.ny; ++i) {
                const T d = L.dy[at(i)] + dxj;
                inv[at(i)] = d > T(0) ? T(1) / d : T(0);
            }
            L.classes.push_back(std::move(inv));
        }
        L.col_class[at(j)] = static_cast<int>(c);
    }
}

/// Column classes of an unmasked coarse level from its 1D factors; returns
/// false (nothing built) when there would be more than `max_classes`.
template <class T>
bool tensor_classes(level<T>& L, std::size_t max_classes) {
    const index ny = L.ny, nx = L.nx, ld = L.ld;
    std::vector<std::array<T, 6>> keys;
    std::vector<int> cls(at(nx), 0);
    for (index j = 0; j < nx; ++j) {
        const std::array<T, 6> k = {L.mx.l[at(j)], L.mx.d[at(j)], j + 1 < nx ? L.mx.l[at(j + 1)] : T(0),
                                    L.kx.l[at(j)], L.kx.d[at(j)], j + 1 < nx ? L.kx.l[at(j + 1)] : T(0)};
        std::size_t c = 0;
        while (c < keys.size() && keys[c] != k) ++c;
        if (c == keys.size()) {
            if (keys.size() == max_classes) return false;
            keys.push_back(k);
        }
        cls[at(j)] = static_cast<int>(c);
    }
    L.col_class = std::move(cls);
    L.classes.assign(keys.size(), std::vector<T>(at(10 * ld), T(0)));
    for (std::size_t c = 0; c < keys.size(); ++c) {
        const auto& k = keys[c];
        const T mxm = k[0], mx0 = k[1], mxp = k[2], kxm = k[3], kx0 = k[4], kxp = k[5];
        T* v = L.classes[c].data();
        for (index i = 0; i < ny; ++i) {
            const auto I = at(i);
            const T kyl = L.ky.l[I], kyd = L.ky.d[I], kyu = i + 1 < ny ? L.ky.l[I + 1] : T(0);
            const T myl = L.my.l[I], myd = L.my.d[I], myu = i + 1 < ny ? L.my.l[I + 1] : T(0);
            const index p = i + 1;
            v[p] = kyl * mx0 + myl * kx0;               // s
            v[ld + p] = kyu * mx0 + myu * kx0;          // n
            v[2 * ld + p] = kyd * mxm + myd * kxm;      // w
            v[3 * ld + p] = kyd * mxp + myd * kxp;      // e
            v[4 * ld + p] = kyl * mxm + myl * kxm;      // sw
            v[5 * ld + p] = kyu * mxm + myu * kxm;      // nw
            v[6 * ld + p] = kyl * mxp + myl * kxp;      // se
            v[7 * ld + p] = kyu * mxp + myu * kxp;      // ne
            const T d = kyd * mx0 + myd * kx0;
            v[8 * ld + p] = d;
            v[9 * ld + p] = d > T(0) ? T(1) / d : T(0);
        }
    }
    return true;
}

/// Fills the stored 9-point stencil of a level from its 1D factors.
template <class T>
void stencil_from_factors(level<T>& L) {
    const index n = L.size();
    L.stored = true;
    L.diag.assign(at(n), T(0));
    L.cs = L.cw = L.csw = L.cnw = L.diag;
    for (index j = 0; j < L.nx; ++j)
        for (index i = 0; i < L.ny; ++i) {
            const auto k = at(L.at2(i, j));
            const auto I = at(i), J = at(j);
            L.diag[k] = L.ky.d[I] * L.mx.d[J] + L.my.d[I] * L.kx.d[J];
            L.cs[k] = L.ky.l[I] * L.mx.d[J] + L.my.l[I] * L.kx.d[J];
            L.cw[k] = L.ky.d[I] * L.mx.l[J] + L.my.d[I] * L.kx.l[J];
            L.csw[k] = L.ky.l[I] * L.mx.l[J] + L.my.l[I] * L.kx.l[J];
            if (i + 1 < L.ny) L.cnw[k] = L.ky.l[I + 1] * L.mx.l[J] + L.my.l[I + 1] * L.kx.l[J];
        }
}

/// The coarse stencil P^T A P formed point by point (masked grids), with P
/// zero on the inactive fine points.
template <class T>
void galerkin_2d(const level<T>& f, level<T>& c) {
    const index n = c.size();
    c.stored = true;
    c.diag.assign(at(n), T(0));
    c.cs = c.cw = c.csw = c.cnw = c.diag;
    const auto& ym = f.ymap;
    const auto& xm = f.xmap;
    for (index j = 0; j < f.nx; ++j)
        for (index i = 0; i < f.ny; ++i) {
            if (!f.is_active(i, j)) continue;
            // Couplings of fine point (i, j).
            int count = 0;
            index gi[9], gj[9];
            T ga[9];
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    const T a = f.coef(i, j, di, dj);
                    if (a == T(0)) continue;
                    gi[count] = i + di;
                    gj[count] = j + dj;
                    ga[count] = a;
                    ++count;
                }
            const index fpi[2] = {ym.p0[at(i)] - 1, ym.p1[at(i)] - 1}, fpj[2] = {xm.p0[at(j)] - 1, xm.p1[at(j)] - 1};
            const T fwi[2] = {ym.w0[at(i)], ym.w1[at(i)]}, fwj[2] = {xm.w0[at(j)], xm.w1[at(j)]};
            for (int sy = 0; sy < 2; ++sy)
                for (int sx = 0; sx < 2; ++sx) {
                    const T pf = fwi[sy] * fwj[sx];
                    if (pf == T(0)) continue;
                    const index I = fpi[sy], J = fpj[sx];
                    const auto k = at(c.at2(I, J));
                    for (int e = 0; e < count; ++e) {
                        const index gpi[2] = {ym.p0[at(gi[e])] - 1, ym.p1[at(gi[e])] - 1};
                        const index gpj[2] = {xm.p0[at(gj[e])] - 1, xm.p1[at(gj[e])] - 1};
                        const T gwi[2] = {ym.w0[at(gi[e])], ym.w1[at(gi[e])]};
                        const T gwj[2] = {xm.w0[at(gj[e])], xm.w1[at(gj[e])]};
                        for (int ty = 0; ty < 2; ++ty)
                            for (int tx = 0; tx < 2; ++tx) {
                                const T pg = gwi[ty] * gwj[tx];
                                if (pg == T(0)) continue;
                                const index dI = gpi[ty] - I, dJ = gpj[tx] - J;
                                const T v = pf * ga[e] * pg;
                                // Only the stored half; the rest follows by symmetry.
                                if (dJ == 0) {
                                    if (dI == 0) c.diag[k] += v;
                                    else if (dI == -1) c.cs[k] += v;
                                } else if (dJ == -1) {
                                    if (dI == 0) c.cw[k] += v;
                                    else if (dI == -1) c.csw[k] += v;
                                    else c.cnw[k] += v;
                                }
                            }
                    }
                }
        }
}

/// Inverse diagonal and activity of a level with a stored stencil.
template <class T>
void finish_stored_level(level<T>& c, bool masked) {
    c.invd.assign(c.diag.size(), T(0));
    if (masked) c.active.assign(c.diag.size(), 0);
    for (index j = 0; j < c.nx; ++j)
        for (index i = 0; i < c.ny; ++i) {
            const auto k = at(c.at2(i, j));
            if (c.diag[k] > T(0)) {
                c.invd[k] = T(1) / c.diag[k];
                if (masked) c.active[k] = 1;
            }
        }
}

// ---------------------------------------------------------------------------
// Kernels
// ---------------------------------------------------------------------------

// Gauss-Seidel on the points of one column with padded rows start,
// start + 2, ... <= ny.
template <class T>
inline void relax_column_5(T* u0, const T* um, const T* up, const T* b0, const T* inv, T cy, T cx, index start,
                           index ny, const unsigned char* act) {
    if (!act) {
        for (index i = start; i <= ny; i += 2)
            u0[i] = (b0[i] + cy * (u0[i - 1] + u0[i + 1]) + cx * (um[i] + up[i])) * inv[i];
    } else {
        for (index i = start; i <= ny; i += 2)
            if (act[i]) u0[i] = (b0[i] + cy * (u0[i - 1] + u0[i + 1]) + cx * (um[i] + up[i])) * inv[i];
    }
}

template <class T>
inline void relax_column_9(T* u0, const T* um, const T* up, const T* b0, const column_stencil<T>& c, index start,
                           index ny) {
    for (index i = start; i <= ny; i += 2) {
        const T s = c.s[i] * u0[i - 1] + c.n[i] * u0[i + 1] + c.w[i] * um[i] + c.e[i] * up[i] + c.sw[i] * um[i - 1] +
                    c.nw[i] * um[i + 1] + c.se[i] * up[i - 1] + c.ne[i] * up[i + 1];
        u0[i] = (b0[i] - s) * c.invd[i];
    }
}

/// Gauss-Seidel on the points of colour `color` ((i + j) mod 2) of column j.
template <class T>
inline void relax(level<T>& L, index j, int color) {
    const index ld = L.ld, o = (j + 1) * ld;
    T* u = L.u.data() + o;
    const T* b = L.b.data() + o;
    const index start = 1 + ((color + j) & 1);
    if (L.first)
        relax_column_5(u, u - ld, u + ld, b, L.classes[at(L.col_class[at(j)])].data(), L.cy, L.cx, start, L.ny,
                       L.active.empty() ? nullptr : L.active.data() + o);
    else
        relax_column_9(u, u - ld, u + ld, b, L.column(j), start, L.ny);
}

/// The residual b - A u of column j (zero on inactive points) written to
/// `out` (a padded column, may be null); returns its squared norm.
template <class T>
T residual_column(const level<T>& L, index j, T* out) {
    const index ny = L.ny, ld = L.ld, o = (j + 1) * ld;
    const T* u0 = L.u.data() + o;
    const T* um = u0 - ld;
    const T* up = u0 + ld;
    const T* b0 = L.b.data() + o;
    T s2 = T(0);
    if (L.first) {
        const T cy = L.cy, cx = L.cx, dxj = L.dx[at(j + 1)];
        const T* dy = L.dy.data();
        const unsigned char* a0 = L.active.empty() ? nullptr : L.active.data() + o;
        for (index i = 1; i <= ny; ++i) {
            T v = b0[i] - ((dy[i] + dxj) * u0[i] - cy * (u0[i - 1] + u0[i + 1]) - cx * (um[i] + up[i]));
            if (a0 && !a0[i]) v = T(0);
            if (out) out[i] = v;
            s2 += v * v;
        }
        return s2;
    }
    const column_stencil<T> c = L.column(j);
    for (index i = 1; i <= ny; ++i) {
        const T s = c.diag[i] * u0[i] + c.s[i] * u0[i - 1] + c.n[i] * u0[i + 1] + c.w[i] * um[i] + c.e[i] * up[i] +
                    c.sw[i] * um[i - 1] + c.nw[i] * um[i + 1] + c.se[i] * up[i - 1] + c.ne[i] * up[i + 1];
        const T v = b0[i] - s;
        if (out) out[i] = v;
        s2 += v * v;
    }
    return s2;
}

/// ||b - A u||^2 over the level.
template <class T>
T residual_norm2(const level<T>& L) {
    T sum = T(0);
    for (index j = 0; j < L.nx; ++j) sum += residual_column(L, j, static_cast<T*>(nullptr));
    return sum;
}

/// Column J of coarse.b = P^T r from the fine residual columns of its three
/// children (`fine[a]`: padded columns, zero outside the grid).
template <class T>
void restrict_column(const level<T>& f, const T* const fine[3], level<T>& c, index J) {
    const auto& ym = f.ymap;
    const auto& xm = f.xmap;
    const T wx[3] = {xm.r0[at(J)], xm.r1[at(J)], xm.r2[at(J)]};
    T* bc = c.b.data() + (J + 1) * c.ld;
    for (index I = 0; I < c.ny; ++I) {
        const index fi = ym.first[at(I)];
        const T wy0 = ym.r0[at(I)], wy1 = ym.r1[at(I)], wy2 = ym.r2[at(I)];
        T sum = T(0);
        for (int a = 0; a < 3; ++a) {
            if (wx[a] == T(0)) continue;
            const T* cl = fine[a];
            sum += wx[a] * (wy0 * cl[fi] + wy1 * cl[fi + 1] + wy2 * cl[fi + 2]);
        }
        bc[I + 1] = sum;
    }
}

/// Column j of fine.u += P coarse.u (inactive fine points untouched).
/// `tmp` is scratch space.
template <class T>
void prolong_column(const level<T>& c, level<T>& f, index j, std::vector<T>& tmp) {
    const auto& ym = f.ymap;
    const auto& xm = f.xmap;
    const index ldc = c.ld;
    // Interpolate along x into one coarse column, then along y.
    const T wx0 = xm.w0[at(j)], wx1 = xm.w1[at(j)];
    const T* e0 = c.u.data() + xm.p0[at(j)] * ldc;
    const T* e1 = c.u.data() + xm.p1[at(j)] * ldc;
    tmp.resize(at(ldc));
    T* ec = tmp.data();
    if (wx1 == T(0))
        for (index i = 0; i < ldc; ++i) ec[i] = wx0 * e0[i];
    else
        for (index i = 0; i < ldc; ++i) ec[i] = wx0 * e0[i] + wx1 * e1[i];
    T* u0 = f.u.data() + (j + 1) * f.ld + 1;
    const unsigned char* a0 = f.active.empty() ? nullptr : f.active.data() + (j + 1) * f.ld + 1;
    const index* p0 = ym.p0.data();
    const index* p1 = ym.p1.data();
    const T* w0 = ym.w0.data();
    const T* w1 = ym.w1.data();
    if (!a0) {
        for (index i = 0; i < f.ny; ++i) u0[i] += w0[i] * ec[p0[i]] + w1[i] * ec[p1[i]];
    } else {
        for (index i = 0; i < f.ny; ++i)
            if (a0[i]) u0[i] += w0[i] * ec[p0[i]] + w1[i] * ec[p1[i]];
    }
}

// The two halves of a cycle on one level, each a single pass over the
// columns: several Gauss-Seidel half-sweeps run as a wavefront (half-sweep s
// one column behind half-sweep s - 1, which has then finished every
// neighbour it needs), followed by the residual and restriction, or preceded
// by the prolongation. The arithmetic is exactly that of separate passes;
// the grid is read and written once instead of once per step.

/// `sweeps` red-black sweeps (red first), then coarse.b = P^T (b - A u).
/// `ring` is scratch space.
template <class T>
void presmooth_restrict(level<T>& L, level<T>& C, int sweeps, std::vector<T>& ring) {
    const index nx = L.nx, ld = L.ld;
    const index S = 2 * static_cast<index>(sweeps);
    ring.assign(at(5 * ld), T(0));  // four residual columns and a zero column
    const T* zero = ring.data() + 4 * ld;
    const auto slot = [&](index c) { return ring.data() + ((c + 1) & 3) * ld; };
    const auto column = [&](index c) -> const T* { return c < 0 || c >= nx ? zero : slot(c); };
    index next = 0;  // next coarse column to restrict
    const auto flush = [&](index done) {
        // Coarse column J needs the residual of fine columns first - 1 .. first + 1.
        while (next < C.nx) {
            const index f0 = L.xmap.first[at(next)] - 1;
            if (std::min(f0 + 2, nx - 1) > done) break;
            const T* cols[3] = {column(f0), column(f0 + 1), column(f0 + 2)};
            restrict_column(L, cols, C, next);
            ++next;
        }
    };
    for (index jj = 0; jj < nx + S; ++jj) {
        for (index s = 0; s < S; ++s) {
            const index c = jj - s;
            if (c >= 0 && c < nx) relax(L, c, static_cast<int>(s & 1));
        }
        const index c = jj - S;
        if (c >= 0) {
            residual_column(L, c, slot(c));
            flush(c);
        }
    }
}

/// fine.u += P coarse.u, then `sweeps` red-black sweeps (black first);
/// returns ||b - A u||^2 afterwards when `norm`, else 0. `tmp` is scratch.
template <class T>
T prolong_postsmooth(const level<T>& C, level<T>& L, int sweeps, bool norm, std::vector<T>& tmp) {
    const index nx = L.nx;
    const index S = 2 * static_cast<index>(sweeps);
    T sum = T(0);
    for (index jj = 0; jj < nx + S + 1; ++jj) {
        if (jj < nx) prolong_column(C, L, jj, tmp);
        for (index s = 0; s < S; ++s) {
            const index c = jj - 1 - s;
            if (c >= 0 && c < nx) relax(L, c, static_cast<int>(1 - (s & 1)));
        }
        const index c = jj - 1 - S;
        if (norm && c >= 0 && c < nx) sum += residual_column(L, c, static_cast<T*>(nullptr));
    }
    return sum;
}

/// Direct solver for the coarsest level: Cholesky, or for a singular
/// operator (pure Neumann) the pseudo-inverse from an eigendecomposition.
template <class T>
struct coarse_solver {
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
    using vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;
    std::vector<index> points;  // padded indices of the active points
    bool use_llt = true;
    Eigen::LLT<matrix> llt;
    matrix vectors;
    vector inv_values;

    void factor(const level<T>& L, bool singular) {
        points.clear();
        std::vector<index> number(at(L.size()), -1);
        for (index j = 0; j < L.nx; ++j)
            for (index i = 0; i < L.ny; ++i)
                if (L.is_active(i, j) && L.coef(i, j, 0, 0) > T(0)) {
                    number[at(L.at2(i, j))] = static_cast<index>(points.size());
                    points.push_back(L.at2(i, j));
                }
        const auto n = static_cast<index>(points.size());
        if (n == 0) return;  // nothing to solve (a single pure-Neumann cell, or no unknowns)
        matrix a = matrix::Zero(n, n);
        for (index k = 0; k < n; ++k) {
            const index p = points[at(k)];
            const index j = p / L.ld - 1, i = p % L.ld - 1;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    const T v = L.coef(i, j, di, dj);
                    if (v == T(0)) continue;
                    const index q = number[at(L.at2(i + di, j + dj))];
                    if (q >= 0) a(k, q) = v;
                }
        }
        use_llt = !singular;
        if (use_llt) {
            llt.compute(a);
            if (llt.info() == Eigen::Success) return;
            use_llt = false;  // rounding made it indefinite: fall back
        }
        Eigen::SelfAdjointEigenSolver<matrix> es(a);
        vectors = es.eigenvectors();
        inv_values = es.eigenvalues();
        const T cut = es.eigenvalues().cwiseAbs().maxCoeff() * T(n) * Eigen::NumTraits<T>::epsilon() * T(16);
        for (index k = 0; k < n; ++k) inv_values[k] = std::abs(inv_values[k]) > cut ? T(1) / inv_values[k] : T(0);
    }

    void solve(level<T>& L) const {
        const auto n = static_cast<index>(points.size());
        if (n == 0) return;
        vector rhs(n);
        for (index k = 0; k < n; ++k) rhs[k] = L.b[at(points[at(k)])];
        vector x = use_llt ? vector(llt.solve(rhs)) : vector(vectors * inv_values.cwiseProduct(vectors.transpose() * rhs));
        for (index k = 0; k < n; ++k) L.u[at(points[at(k)])] = x[k];
    }
};

}  // namespace anima::detail::mg
