// Step rules of the Jacobian IK iteration (Table 1, line 7-9): how a
// residual e becomes a DOF increment dq for a Jacobian J. Each rule is a
// small callable with a nested `params` struct; solve_ik runs any of them.
//   jacobian_inverse        dq = J^-1 e (square, regular J only)
//   pseudo_inverse          dq = J+ e, minimum norm (SVD, small singular values cut)
//   damped_least_squares    dq = J^T (J J^T + l^2 I)^-1 e, l fixed or adaptive
//   weighted_rule<Rule>     the rule applied to J W^-1/2, then scaled by W^-1/2 (Komura)
// Each rule also takes an ik_step_scratch, where it keeps its decomposition
// and temporaries from call to call: with one, a step of a Jacobian the same
// size as the last allocates nothing (solve_ik_into's game-loop form).
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/ik/kinematic_tree.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

namespace anima {

/// What a step rule found out about J while computing the step.
template <class T>
struct ik_step_info {
    bool singular = false;       ///< the rule could not invert J
    T damping = T(0);            ///< damping used (DLS rules)
    ik_vector<T> singular_values;  ///< of J, when the rule computed them
    bool decomposed = false;     ///< singular_values are this step's (the rule ran an SVD)
};

/// What the library's step rules keep from call to call: decompositions
/// and temporaries sized once for a Jacobian's shape, reused while it stays.
template <class T>
struct ik_step_scratch {
    Eigen::JacobiSVD<ik_matrix<T>> svd;
    Eigen::LDLT<ik_matrix<T>> ldlt;
    Eigen::FullPivLU<ik_matrix<T>> lu;
    ik_matrix<T> product, weighted;  ///< J J^T (DLS); J W^-1/2 (weighted_rule)
    ik_vector<T> projected, scale;   ///< U^T e or a solve's right side; W^-1/2
};

namespace detail {

/// dq = V u from the scratch's SVD of J, u_k = scaled(c_k, s_k) for the
/// components c = U^T e of e and the singular values s.
template <class T, class Scaled>
void svd_step(const ik_vector<T>& e, ik_vector<T>& dq, ik_step_scratch<T>& s, Scaled scaled) {
    const auto& sv = s.svd.singularValues();
    s.projected.noalias() = s.svd.matrixU().transpose() * e;
    for (Eigen::Index k = 0; k < sv.size(); ++k) s.projected[k] = scaled(s.projected[k], sv[k]);
    dq.noalias() = s.svd.matrixV() * s.projected;
}

/// The scratch's SVD of J, its singular values copied to info.
template <class T>
void decompose(const ik_matrix<T>& j, ik_step_info<T>& info, ik_step_scratch<T>& s) {
    s.svd.compute(j, Eigen::ComputeThinU | Eigen::ComputeThinV);
    info.singular_values = s.svd.singularValues();
    info.decomposed = true;
}

}  // namespace detail

/// Whitney's J^-1: only for a square J; a singular J is reported (the step
/// is then zero), not inverted.
template <class T>
struct jacobian_inverse {
    struct params {
        T min_pivot = std::sqrt(std::numeric_limits<T>::epsilon());  ///< relative to the largest pivot
    } prm;
    jacobian_inverse() = default;
    explicit jacobian_inverse(const params& p) : prm(p) {}

    void operator()(const ik_matrix<T>& j, const ik_vector<T>& e, ik_vector<T>& dq, ik_step_info<T>& info) const {
        ik_step_scratch<T> s;
        (*this)(j, e, dq, info, s);
    }
    void operator()(const ik_matrix<T>& j, const ik_vector<T>& e, ik_vector<T>& dq, ik_step_info<T>& info,
                    ik_step_scratch<T>& s) const {
        if (j.rows() != j.cols())
            throw invalid_argument("anima::jacobian_inverse: the Jacobian is " + std::to_string(j.rows()) + " x " +
                                   std::to_string(j.cols()) + ", not square; use pseudo_inverse or damped_least_squares");
        s.lu.compute(j);
        s.lu.setThreshold(prm.min_pivot);
        if (!s.lu.isInvertible()) {
            info.singular = true;
            dq.setZero(j.cols());
            return;
        }
        // P^-1 L U Q^-1 = J, solved in place (FullPivLU::solve would allocate its right side).
        s.projected.noalias() = s.lu.permutationP() * e;
        s.lu.matrixLU().template triangularView<Eigen::UnitLower>().solveInPlace(s.projected);
        s.lu.matrixLU().template triangularView<Eigen::Upper>().solveInPlace(s.projected);
        dq.noalias() = s.lu.permutationQ() * s.projected;
    }
};

/// Moore-Penrose pseudo-inverse by SVD: the minimum-norm least-squares step.
/// Singular values below cutoff * largest are treated as zero.
template <class T>
struct pseudo_inverse {
    struct params {
        T cutoff = T(100) * std::numeric_limits<T>::epsilon();
    } prm;
    pseudo_inverse() = default;
    explicit pseudo_inverse(const params& p) : prm(p) {}

    void operator()(const ik_matrix<T>& j, const ik_vector<T>& e, ik_vector<T>& dq, ik_step_info<T>& info) const {
        ik_step_scratch<T> s;
        (*this)(j, e, dq, info, s);
    }
    void operator()(const ik_matrix<T>& j, const ik_vector<T>& e, ik_vector<T>& dq, ik_step_info<T>& info,
                    ik_step_scratch<T>& s) const {
        detail::decompose(j, info, s);
        const auto& sv = info.singular_values;
        const T smax = sv.size() ? sv[0] : T(0);
        detail::svd_step(e, dq, s, [&](T c, T k) { return k > prm.cutoff * smax && k > T(0) ? c / k : T(0); });
        info.singular = sv.size() == 0 || !(smax > T(0));
    }
};

/// Wampler's damped least squares. Fixed damping: l = `damping`. Adaptive
/// damping (Maciejewski and Klein's rule on the smallest singular value):
/// l^2 = damping^2 * (1 - (s_min / threshold)^2) while s_min < threshold,
/// 0 otherwise, so a well-conditioned J gets the exact pseudo-inverse step
/// and damping grows smoothly toward a singularity. Damping has the units
/// of the Jacobian's entries (a length for position goals).
template <class T>
struct damped_least_squares {
    struct params {
        T damping = T(0.05);
        bool adaptive = false;
        T threshold = T(0.1);  ///< s_min below which adaptive damping starts
    } prm;
    damped_least_squares() = default;
    explicit damped_least_squares(const params& p) : prm(p) {}

    void operator()(const ik_matrix<T>& j, const ik_vector<T>& e, ik_vector<T>& dq, ik_step_info<T>& info) const {
        ik_step_scratch<T> s;
        (*this)(j, e, dq, info, s);
    }
    void operator()(const ik_matrix<T>& j, const ik_vector<T>& e, ik_vector<T>& dq, ik_step_info<T>& info,
                    ik_step_scratch<T>& s) const {
        T l2 = prm.damping * prm.damping;
        if (prm.adaptive) {
            detail::decompose(j, info, s);
            const auto& sv = info.singular_values;
            const Eigen::Index r = std::min(j.rows(), j.cols());
            const T smin = (r > 0 && j.rows() <= j.cols()) ? sv[r - 1] : T(0);
            const T ratio = smin / prm.threshold;
            l2 = smin < prm.threshold ? l2 * (T(1) - ratio * ratio) : T(0);
            // Through the SVD: dq = V diag(s / (s^2 + l^2)) U^T e.
            detail::svd_step(e, dq, s, [&](T c, T k) {
                const T den = k * k + l2;
                return den > T(0) ? c * k / den : T(0);
            });
            info.damping = std::sqrt(l2);
            return;
        }
        info.damping = prm.damping;
        s.product.noalias() = j * j.transpose();
        s.product.diagonal().array() += l2;
        s.ldlt.compute(s.product);
        s.projected = e;
        s.ldlt.solveInPlace(s.projected);
        dq.noalias() = j.transpose() * s.projected;
        if (!dq.allFinite()) {  // l = 0 on a singular J: fall back on the pseudo-inverse
            pseudo_inverse<T>{}(j, e, dq, info, s);
        }
    }
};

namespace detail {

/// rule(j, e, dq, info) with the scratch when the rule takes one (the
/// library's do); info is reset first, keeping its storage.
template <class T, class Rule>
void apply_rule(const Rule& rule, const ik_matrix<T>& j, const ik_vector<T>& e, ik_vector<T>& dq,
                ik_step_info<T>& info, ik_step_scratch<T>& s) {
    info.singular = false;
    info.damping = T(0);
    info.decomposed = false;
    if constexpr (std::is_invocable_v<const Rule&, const ik_matrix<T>&, const ik_vector<T>&, ik_vector<T>&,
                                      ik_step_info<T>&, ik_step_scratch<T>&>) {
        rule(j, e, dq, info, s);
    } else {
        info.singular_values.resize(0);
        rule(j, e, dq, info);
        info.decomposed = info.singular_values.size() > 0;
    }
}

}  // namespace detail

/// Komura's weighted inverse: DOF k costs weights[k] (> 0; larger moves it
/// less). The inner rule runs on J W^-1/2 and its step is scaled back.
template <class T, class Rule>
struct weighted_rule {
    ik_vector<T> weights;
    Rule rule;
    weighted_rule(ik_vector<T> w, Rule r = Rule{}) : weights(std::move(w)), rule(std::move(r)) {
        for (Eigen::Index k = 0; k < weights.size(); ++k)
            if (!(weights[k] > T(0)) || !std::isfinite(weights[k]))
                throw invalid_argument("anima::weighted_rule: weight " + std::to_string(k) + " is " +
                                       detail::argument_text(weights[k]) + ", must be positive and finite");
    }
    void operator()(const ik_matrix<T>& j, const ik_vector<T>& e, ik_vector<T>& dq, ik_step_info<T>& info) const {
        ik_step_scratch<T> s;
        (*this)(j, e, dq, info, s);
    }
    /// The inner rule gets the same scratch: the weighted Jacobian and the
    /// scale are members it does not use.
    void operator()(const ik_matrix<T>& j, const ik_vector<T>& e, ik_vector<T>& dq, ik_step_info<T>& info,
                    ik_step_scratch<T>& s) const {
        if (weights.size() != j.cols())
            throw invalid_argument("anima::weighted_rule: " + std::to_string(weights.size()) + " weights for " +
                                   std::to_string(j.cols()) + " DOFs");
        s.scale = weights.cwiseSqrt().cwiseInverse();
        s.weighted.noalias() = j * s.scale.asDiagonal();
        detail::apply_rule(rule, static_cast<const ik_matrix<T>&>(s.weighted), e, dq, info, s);
        dq.array() *= s.scale.array();
    }
};

}  // namespace anima
