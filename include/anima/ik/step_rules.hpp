// Step rules of the Jacobian IK iteration (Table 1, line 7-9): how a
// residual e becomes a DOF increment dq for a Jacobian J. Each rule is a
// small callable with a nested `params` struct; solve_ik runs any of them.
//   jacobian_inverse        dq = J^-1 e (square, regular J only)
//   pseudo_inverse          dq = J+ e, minimum norm (SVD, small singular values cut)
//   damped_least_squares    dq = J^T (J J^T + l^2 I)^-1 e, l fixed or adaptive
//   weighted_rule<Rule>     the rule applied to J W^-1/2, then scaled by W^-1/2 (Komura)
#pragma once

#include <anima/core/error.hpp>
#include <anima/ik/kinematic_tree.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>

#include <cmath>
#include <limits>
#include <string>

namespace anima {

/// What a step rule found out about J while computing the step.
template <class T>
struct ik_step_info {
    bool singular = false;       ///< the rule could not invert J
    T damping = T(0);            ///< damping used (DLS rules)
    ik_vector<T> singular_values;  ///< of J, when the rule computed them
};

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
        if (j.rows() != j.cols())
            throw invalid_argument("anima::jacobian_inverse: the Jacobian is " + std::to_string(j.rows()) + " x " +
                                   std::to_string(j.cols()) + ", not square; use pseudo_inverse or damped_least_squares");
        Eigen::FullPivLU<ik_matrix<T>> lu(j);
        lu.setThreshold(prm.min_pivot);
        if (!lu.isInvertible()) {
            info.singular = true;
            dq.setZero(j.cols());
            return;
        }
        dq = lu.solve(e);
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
        Eigen::JacobiSVD<ik_matrix<T>> svd(j, Eigen::ComputeThinU | Eigen::ComputeThinV);
        info.singular_values = svd.singularValues();
        const auto& s = info.singular_values;
        const T smax = s.size() ? s[0] : T(0);
        ik_vector<T> ute = svd.matrixU().transpose() * e;
        for (Eigen::Index k = 0; k < s.size(); ++k) ute[k] = s[k] > prm.cutoff * smax && s[k] > T(0) ? ute[k] / s[k] : T(0);
        dq = svd.matrixV() * ute;
        info.singular = s.size() == 0 || !(smax > T(0));
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
        T l2 = prm.damping * prm.damping;
        if (prm.adaptive) {
            Eigen::JacobiSVD<ik_matrix<T>> svd(j, Eigen::ComputeThinU | Eigen::ComputeThinV);
            info.singular_values = svd.singularValues();
            const auto& s = info.singular_values;
            const Eigen::Index r = std::min(j.rows(), j.cols());
            const T smin = (r > 0 && j.rows() <= j.cols()) ? s[r - 1] : T(0);
            const T ratio = smin / prm.threshold;
            l2 = smin < prm.threshold ? l2 * (T(1) - ratio * ratio) : T(0);
            // Through the SVD: dq = V diag(s / (s^2 + l^2)) U^T e.
            ik_vector<T> ute = svd.matrixU().transpose() * e;
            for (Eigen::Index k = 0; k < s.size(); ++k) {
                const T den = s[k] * s[k] + l2;
                ute[k] = den > T(0) ? ute[k] * s[k] / den : T(0);
            }
            dq = svd.matrixV() * ute;
            info.damping = std::sqrt(l2);
            return;
        }
        info.damping = prm.damping;
        ik_matrix<T> a = j * j.transpose();
        a.diagonal().array() += l2;
        Eigen::LDLT<ik_matrix<T>> ldlt(a);
        dq = j.transpose() * ldlt.solve(e);
        if (!dq.allFinite()) {  // l = 0 on a singular J: fall back on the pseudo-inverse
            pseudo_inverse<T>{}(j, e, dq, info);
        }
    }
};

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
                                       std::to_string(static_cast<double>(weights[k])) + ", must be positive and finite");
    }
    void operator()(const ik_matrix<T>& j, const ik_vector<T>& e, ik_vector<T>& dq, ik_step_info<T>& info) const {
        if (weights.size() != j.cols())
            throw invalid_argument("anima::weighted_rule: " + std::to_string(weights.size()) + " weights for " +
                                   std::to_string(j.cols()) + " DOFs");
        const ik_vector<T> scale = weights.cwiseSqrt().cwiseInverse();
        const ik_matrix<T> jw = j * scale.asDiagonal();
        rule(jw, e, dq, info);
        dq = scale.cwiseProduct(dq);
    }
};

}  // namespace anima
