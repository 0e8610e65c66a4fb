// The learned Jacobian inverse (Li, Xia and Wang 2007; Eq 3). Learning: a
// self-organising map clusters the poses of real clips; for each cluster,
// J+ = argmin sum |dq - J+ dg|^2 over its members, dq = member - centre and
// dg = the effectors' displacement between them. Solving: start from the
// cluster centre whose effectors are nearest the targets, take steps with
// the learned J+ of the cluster nearest the current pose, and polish with
// damped least squares. Effector positions are stored in the root joint's
// frame, so one model serves a character wherever it stands.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/ik/detail/som.hpp>
#include <anima/ik/goal.hpp>
#include <anima/ik/kinematic_tree.hpp>
#include <anima/ik/solve.hpp>
#include <anima/ik/step_rules.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <limits>
#include <locale>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace anima {

template <class T>
struct learned_ik_params {
    int rows = 6, cols = 6;      ///< SOM grid
    int epochs = 30;
    T learning_rate = T(0.5);    ///< initial
    T radius = T(0);             ///< initial neighbourhood radius in nodes; 0: half the larger grid side
    T ridge = T(10);             ///< Eq 3 regulariser, relative to the mean squared effector displacement
    std::uint64_t seed = 1;
};

/// A named effector point: a joint and an offset in its frame.
template <class T>
struct ik_effector {
    std::string joint;
    Eigen::Matrix<T, 3, 1> offset = Eigen::Matrix<T, 3, 1>::Zero();
};

/// Effector positions of pose q in the root joint's frame, stacked (3 per
/// effector; joints[i] is effector i's skeleton index).
template <class T>
ik_vector<T> root_frame_effectors(const kinematic_tree<T>& tree, const std::vector<std::size_t>& joints,
                                  const std::vector<ik_effector<T>>& effectors, const ik_vector<T>& q) {
    ik_state<T> s;
    tree.forward_unchecked(q, s);
    ik_vector<T> g(3 * static_cast<Eigen::Index>(joints.size()));
    const auto root_inv = s.orientations[0].conjugate();
    for (std::size_t i = 0; i < joints.size(); ++i)
        g.template segment<3>(3 * static_cast<Eigen::Index>(i)) =
            root_inv * (s.positions[joints[i]] + s.orientations[joints[i]] * effectors[i].offset - s.positions[0]);
    return g;
}

template <class T>
class learned_ik_model {
public:
    learned_ik_model() = default;

    /// Trains on poses (DOF vectors of `tree`, one per column, e.g. from
    /// clip_poses). The tree's root must be fixed and its translation not a
    /// DOF (effectors are measured in the root's frame).
    static learned_ik_model train(const kinematic_tree<T>& tree, std::vector<ik_effector<T>> effectors,
                                  const ik_matrix<T>& poses, const learned_ik_params<T>& prm = {});

    int dofs() const noexcept { return dofs_; }
    Eigen::Index clusters() const noexcept { return centres_.cols(); }
    const std::vector<ik_effector<T>>& effectors() const noexcept { return effectors_; }
    /// Reference poses (SOM nodes), one per column.
    const ik_matrix<T>& centres() const noexcept { return centres_; }
    /// Effector positions of the reference poses in the root frame (3 per effector).
    const ik_matrix<T>& centre_effectors() const noexcept { return centre_effectors_; }
    /// The learned J+ of cluster c (dofs x 3E); empty when it had too few members.
    const ik_matrix<T>& inverse(Eigen::Index c) const { return inverses_.at(static_cast<std::size_t>(c)); }

    /// Clusters blended for a goal and their weights (sum 1).
    struct blend {
        std::vector<Eigen::Index> clusters;  ///< nearest the goal first
        std::vector<T> weights;
    };

    /// The `count` clusters whose reference effectors are nearest `target`
    /// (effector positions in the root frame, stacked as effectors_of
    /// returns them), weighted by inverse squared distance.
    blend nearest_to_goal(const ik_vector<T>& target, int count) const {
        const char* who = "anima::learned_ik_model::nearest_to_goal";
        if (target.size() != centre_effectors_.rows() || !target.allFinite() || count < 1 || !clusters())
            throw invalid_argument(std::string(who) + ": target of " + std::to_string(target.size()) + " values for " +
                                   std::to_string(centre_effectors_.rows()) + " (or non-finite), count " +
                                   std::to_string(count) + " (must be >= 1)");
        const ik_vector<T> d2 = (centre_effectors_.colwise() - target).colwise().squaredNorm().transpose();
        // As solve_ik_learned's goal check: a target whose squared distances
        // overflow would blend with 0/0 weights into a NaN pose.
        if (!d2.allFinite()) fail_far_target(who, target);
        std::vector<Eigen::Index> order(static_cast<std::size_t>(d2.size()));
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<Eigen::Index>(i);
        const auto n = std::min(order.size(), static_cast<std::size_t>(count));
        std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(n), order.end(),
                          [&](Eigen::Index a, Eigen::Index b) { return d2[a] < d2[b]; });
        blend b;
        b.clusters.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(n));
        // A tiny floor (relative to the farthest blended distance) keeps a
        // target sitting on a reference pose finite: that pose then dominates.
        // Weights are taken relative to the nearest (at most 1), so that
        // several at the floor do not overflow their sum.
        const T floor = std::max(d2[b.clusters.back()] * T(1e-12), std::numeric_limits<T>::min());
        const T nearest = d2[b.clusters.front()] + floor;
        T sum = T(0);
        for (const auto c : b.clusters) {
            b.weights.push_back(nearest / (d2[c] + floor));
            sum += b.weights.back();
        }
        for (auto& w : b.weights) w /= sum;
        return b;
    }

    /// The learned pose for a target: sum over the blend of weight x
    /// (centre + J+ (target - centre's effectors)); a cluster without J+
    /// gives its centre. Throws for a target that nearest_to_goal would
    /// refuse, or when the pose is not finite.
    ik_vector<T> predict(const ik_vector<T>& target, const blend& b) const {
        const char* who = "anima::learned_ik_model::predict";
        check_size(who, "target", static_cast<std::size_t>(target.size()),
                   static_cast<std::size_t>(centre_effectors_.rows()), "values");
        if (!target.allFinite()) throw invalid_argument(std::string(who) + ": target must be finite");
        ik_vector<T> q = ik_vector<T>::Zero(dofs_);
        for (std::size_t i = 0; i < b.clusters.size(); ++i) {
            const auto c = b.clusters[i];
            if (!std::isfinite((target - centre_effectors_.col(c)).squaredNorm())) fail_far_target(who, target);
            ik_vector<T> qc = centres_.col(c);
            const auto& inv = inverses_[static_cast<std::size_t>(c)];
            if (inv.size()) qc += inv * (target - centre_effectors_.col(c));
            q += b.weights[i] * qc;
        }
        if (!q.allFinite()) fail_far_target(who, target);
        return q;
    }

    /// The blend's J+ (weights over the clusters that have one, renormalised);
    /// empty when none has.
    ik_matrix<T> blended_inverse(const blend& b) const {
        ik_matrix<T> out;
        T sum = T(0);
        for (std::size_t i = 0; i < b.clusters.size(); ++i) {
            const auto& inv = inverses_[static_cast<std::size_t>(b.clusters[i])];
            if (!inv.size()) continue;
            if (!out.size()) out = ik_matrix<T>::Zero(inv.rows(), inv.cols());
            out += b.weights[i] * inv;
            sum += b.weights[i];
        }
        if (sum > T(0)) out /= sum;
        return out;
    }

    /// Effector positions (root frame, stacked) of pose q.
    ik_vector<T> effectors_of(const kinematic_tree<T>& tree, const std::vector<std::size_t>& joints,
                              const ik_vector<T>& q) const {
        return root_frame_effectors(tree, joints, effectors_, q);
    }

    /// Skeleton indices of the effectors in tree; throws when one is missing
    /// or the DOF count differs.
    std::vector<std::size_t> resolve(const kinematic_tree<T>& tree, const std::string& who) const {
        if (tree.dofs() != dofs_)
            throw invalid_argument(who + ": the model has " + std::to_string(dofs_) + " DOFs, the tree " +
                                   std::to_string(tree.dofs()));
        std::vector<std::size_t> out;
        for (const auto& e : effectors_) {
            const auto j = tree.skeleton().find(e.joint);
            if (!j) throw invalid_argument(who + ": effector joint '" + e.joint + "' is not in the skeleton");
            out.push_back(*j);
        }
        return out;
    }

    static void check_tree(const kinematic_tree<T>& tree, const std::string& who) {
        if (tree.root_translation() || tree.kind(0) != ik_joint_kind::fixed)
            throw invalid_argument(who + ": the tree's root '" + tree.skeleton()[0].name +
                                   "' must be fixed, without translation DOFs (effectors live in its frame)");
    }

    /// Text format, version 1: a header line, then every number on lines
    /// named by their first word.
    void save(std::ostream& out) const {
        out.precision(std::numeric_limits<T>::max_digits10);
        out << "anima-learned-ik 1\n";
        out << "dofs " << dofs_ << "\neffectors " << effectors_.size() << '\n';
        for (const auto& e : effectors_)
            out << "effector " << e.joint << ' ' << e.offset.x() << ' ' << e.offset.y() << ' ' << e.offset.z() << '\n';
        out << "clusters " << centres_.cols() << '\n';
        for (Eigen::Index c = 0; c < centres_.cols(); ++c) {
            write_row(out, "centre", centres_.col(c));
            write_row(out, "reach", centre_effectors_.col(c));
            const auto& inv = inverses_[static_cast<std::size_t>(c)];
            out << "inverse " << (inv.size() ? 1 : 0);
            for (Eigen::Index i = 0; i < inv.rows(); ++i)
                for (Eigen::Index j = 0; j < inv.cols(); ++j) out << ' ' << inv(i, j);
            out << '\n';
        }
    }

    /// Reads what save wrote. Throws anima::parse_error ("source:line: ...").
    static learned_ik_model load(std::istream& in, const std::string& source = "<learned-ik>") {
        learned_ik_model m;
        reader r(in, source);
        r.next("anima-learned-ik");
        if (r.integer() != 1) r.fail("unsupported version (this build reads version 1)");
        r.next("dofs");
        m.dofs_ = r.integer();
        if (m.dofs_ < 1) r.fail("dofs must be at least 1");
        r.next("effectors");
        const int ne = r.integer();
        if (ne < 1) r.fail("effectors must be at least 1");
        for (int i = 0; i < ne; ++i) {
            r.next("effector");
            ik_effector<T> e;
            if (!(r.line >> e.joint)) r.fail("missing joint name");
            for (int k = 0; k < 3; ++k) e.offset[k] = r.number();
            m.effectors_.push_back(std::move(e));
        }
        r.next("clusters");
        const int k = r.integer();
        if (k < 1) r.fail("clusters must be at least 1");
        const Eigen::Index e3 = 3 * ne;
        // The counts are not trusted to size memory: values are collected as
        // they are read, so a file claiming more than it holds fails at its
        // end instead of allocating first.
        std::vector<T> centres, reach;
        for (int c = 0; c < k; ++c) {
            r.next("centre");
            for (int i = 0; i < m.dofs_; ++i) centres.push_back(r.number());
            r.next("reach");
            for (Eigen::Index i = 0; i < e3; ++i) reach.push_back(r.number());
            if (m.inverses_.size() < static_cast<std::size_t>(c) + 1) m.inverses_.resize(static_cast<std::size_t>(c) + 1);
            r.next("inverse");
            const int has = r.integer();
            if (has != 0 && has != 1) r.fail("inverse flag must be 0 or 1");
            if (has) {
                std::vector<T> inv;
                for (Eigen::Index n = 0; n < m.dofs_ * e3; ++n) inv.push_back(r.number());
                m.inverses_[static_cast<std::size_t>(c)] =
                    Eigen::Map<const Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(inv.data(), m.dofs_, e3);
            }
            r.end();
        }
        m.centres_ = Eigen::Map<const ik_matrix<T>>(centres.data(), m.dofs_, k);
        m.centre_effectors_ = Eigen::Map<const ik_matrix<T>>(reach.data(), e3, k);
        return m;
    }

private:
    [[noreturn]] static void fail_far_target(const char* who, const ik_vector<T>& target) {
        throw invalid_argument(std::string(who) + ": target too far out (largest coordinate " +
                               detail::argument_text(target.cwiseAbs().maxCoeff()) +
                               "): its squared distances to the clusters overflow");
    }

    template <class V>
    static void write_row(std::ostream& out, const char* name, const V& v) {
        out << name;
        for (Eigen::Index i = 0; i < v.size(); ++i) out << ' ' << v[i];
        out << '\n';
    }

    struct reader {
        reader(std::istream& stream, std::string name) : in(stream), source(std::move(name)) {}
        std::istream& in;
        std::string source;
        std::size_t number_of_line = 0;
        std::istringstream line;
        [[noreturn]] void fail(const std::string& msg) const { throw parse_error(source, number_of_line, msg); }
        void next(const char* keyword) {
            std::string text;
            if (!std::getline(in, text)) {
                ++number_of_line;
                fail(std::string("file ends; expected '") + keyword + "'");
            }
            ++number_of_line;
            if (!text.empty() && text.back() == '\r') text.pop_back();
            line = std::istringstream(text);
            std::string word;
            line >> word;
            if (word != keyword) fail("expected '" + std::string(keyword) + "', found '" + word + "'");
        }
        int integer() {
            long v;
            if (!(line >> v) || v < 0 || v > 1000000) fail("expected a count between 0 and 1000000");
            return static_cast<int>(v);
        }
        T number() {
            std::string word;
            if (!(line >> word)) fail("line ends; expected a number");
            std::istringstream w(word);
            w.imbue(std::locale::classic());
            long double v;
            if (!(w >> v) || !w.eof() || !std::isfinite(v)) fail("'" + word + "' is not a finite number");
            return static_cast<T>(v);
        }
        void end() {
            std::string rest;
            if (line >> rest) fail("unexpected '" + rest + "' at the end of the line");
        }
    };

    int dofs_ = 0;
    std::vector<ik_effector<T>> effectors_;
    ik_matrix<T> centres_, centre_effectors_;
    std::vector<ik_matrix<T>> inverses_;
};

// Out of the class body so that builds compiling anima's instantiations once
// (ik/instances.hpp) can declare it extern: clang instantiates members
// defined in the class wherever they are used.
template <class T>
learned_ik_model<T> learned_ik_model<T>::train(const kinematic_tree<T>& tree, std::vector<ik_effector<T>> effectors,
                                               const ik_matrix<T>& poses, const learned_ik_params<T>& prm) {
    const std::string who = "anima::learned_ik_model::train";
    check_tree(tree, who);
    if (effectors.empty()) throw invalid_argument(who + ": no effectors");
    for (const auto& e : effectors)
        if (!e.offset.allFinite())
            throw invalid_argument(who + ": effector '" + e.joint + "' has a non-finite offset");
    if (poses.rows() != tree.dofs() || poses.cols() < 2 || !poses.allFinite())
        throw invalid_argument(who + ": need at least 2 finite poses of " + std::to_string(tree.dofs()) +
                               " DOFs, got " + std::to_string(poses.cols()) + " of " + std::to_string(poses.rows()));
    if (prm.rows < 1 || prm.cols < 1 || prm.epochs < 1 || !(prm.learning_rate > T(0)) || !(prm.ridge > T(0)) ||
        !(prm.radius >= T(0)))
        throw invalid_argument(who + ": grid " + std::to_string(prm.rows) + " x " + std::to_string(prm.cols) +
                               ", epochs " + std::to_string(prm.epochs) +
                               ": sizes and epochs must be >= 1, rate and ridge > 0, radius >= 0");
    learned_ik_model m;
    m.dofs_ = tree.dofs();
    m.effectors_ = std::move(effectors);
    const auto joints = m.resolve(tree, who);
    const T radius = prm.radius > T(0) ? prm.radius : T(std::max(prm.rows, prm.cols)) / T(2);
    m.centres_ = detail::train_som<T>(poses, prm.rows, prm.cols, prm.epochs, prm.learning_rate, radius, prm.seed);
    const Eigen::Index k = m.centres_.cols(), e3 = 3 * static_cast<Eigen::Index>(m.effectors_.size());
    m.centre_effectors_.resize(e3, k);
    for (Eigen::Index c = 0; c < k; ++c)
        m.centre_effectors_.col(c) = m.effectors_of(tree, joints, m.centres_.col(c));

    // Eq 3 per cluster: J+ = dQ dG^T (dG dG^T + r I)^-1 (r small, relative).
    std::vector<std::vector<Eigen::Index>> members(static_cast<std::size_t>(k));
    for (Eigen::Index s = 0; s < poses.cols(); ++s)
        members[static_cast<std::size_t>(detail::nearest_column<T>(m.centres_, poses.col(s)))].push_back(s);
    m.inverses_.assign(static_cast<std::size_t>(k), ik_matrix<T>());
    for (Eigen::Index c = 0; c < k; ++c) {
        const auto& mem = members[static_cast<std::size_t>(c)];
        if (mem.size() < 2) continue;  // too few to fit: the solve falls back on DLS here
        ik_matrix<T> dq(m.dofs_, static_cast<Eigen::Index>(mem.size())), dg(e3, dq.cols());
        for (std::size_t i = 0; i < mem.size(); ++i) {
            dq.col(static_cast<Eigen::Index>(i)) = poses.col(mem[i]) - m.centres_.col(c);
            dg.col(static_cast<Eigen::Index>(i)) = m.effectors_of(tree, joints, poses.col(mem[i])) - m.centre_effectors_.col(c);
        }
        ik_matrix<T> a = dg * dg.transpose();
        // The ridge is floored a little above the scalar's rounding so
        // that a rank-deficient cluster still gives a finite fit.
        const T rel = std::max(prm.ridge, T(64) * std::numeric_limits<T>::epsilon());
        a.diagonal().array() += rel * (a.trace() / T(e3)) + std::numeric_limits<T>::min();
        ik_matrix<T> inv = (a.ldlt().solve(dg * dq.transpose())).transpose();
        if (inv.allFinite()) m.inverses_[static_cast<std::size_t>(c)] = std::move(inv);
    }
    return m;
}

/// Options of solve_ik_learned: the shared ones (tolerances, limits,
/// iterations of the DLS polish), the learned steps, the polish's damping.
template <class T>
struct learned_solve_params {
    ik_params<T> ik;
    /// Clusters blended, chosen by the goal: the `blend` whose reference
    /// effectors are nearest the targets, weighted by inverse squared
    /// distance (1: the nearest alone, as in the paper).
    int blend = 4;
    int learned_steps = 20;  ///< at most, stopped when a step stops helping
    typename damped_least_squares<T>::params polish{};
    /// Keep the polish near the learned pose (null space toward it).
    T reference_gain = T(0.1);
};

/// What solve_ik_learned returns: the shared result plus the clusters used.
template <class T>
struct learned_ik_result : ik_result<T> {
    Eigen::Index cluster = 0;                ///< nearest the goal (the main one)
    std::vector<Eigen::Index> blended;       ///< every cluster blended, nearest first
    std::vector<T> weights;                  ///< their weights (sum 1)
    int learned_steps = 0;                   ///< learned steps taken before the polish
};

namespace detail {

template <class T>
void check_learned_goals(const kinematic_tree<T>& tree, const learned_ik_model<T>& model,
                         std::vector<ik_goal<T>>& goals, const learned_solve_params<T>& prm, const std::string& who) {
    learned_ik_model<T>::check_tree(tree, who);
    const auto joints = model.resolve(tree, who);
    check_goals(tree, goals, who);
    check_ik_params(prm.ik, tree.dofs(), who.c_str());
    if (prm.blend < 1 || prm.learned_steps < 0 || !(prm.reference_gain >= T(0)))
        throw invalid_argument(who + ": blend " + std::to_string(prm.blend) + ", learned_steps " +
                               std::to_string(prm.learned_steps) + ", reference_gain " +
                               detail::argument_text(prm.reference_gain) +
                               ": blend must be >= 1, the others >= 0");
    if (goals.size() != joints.size())
        throw invalid_argument(who + ": " + std::to_string(goals.size()) + " goals for a model of " +
                               std::to_string(joints.size()) + " effectors");
    for (std::size_t i = 0; i < goals.size(); ++i)
        if (goals[i].kind != ik_goal_kind::position || goals[i].joint != joints[i] ||
            goals[i].offset != model.effectors()[i].offset)
            throw invalid_argument(who + ": goal " + std::to_string(i) + " is not a position goal on effector '" +
                                   model.effectors()[i].joint + "' with the model's offset");
}

}  // namespace detail

/// Solves position goals on the model's effectors (one per effector, same
/// joints and offsets, in order). Throws anima::invalid_argument otherwise.
/// The start comes from the goal (the model's prediction), not from a pose:
/// the learned pose is blended from the clusters nearest the targets, each
/// cluster's centre moved by its J+ toward the targets; learned steps with
/// the blended J+ refine it while they help; damped least squares, pulled
/// toward the learned pose in the null space, polishes.
template <class T>
learned_ik_result<T> solve_ik_learned(const kinematic_tree<T>& tree, const learned_ik_model<T>& model,
                                      std::vector<ik_goal<T>> goals, const learned_solve_params<T>& prm = {}) {
    const std::string who = "anima::solve_ik_learned";
    detail::check_learned_goals(tree, model, goals, prm, who);
    const auto joints = model.resolve(tree, who);

    // Targets in the root's frame (the root is fixed: any q gives it).
    ik_state<T> s;
    tree.forward_unchecked(ik_vector<T>::Zero(tree.dofs()), s);
    const auto root_inv = s.orientations[0].conjugate();
    ik_vector<T> target(3 * static_cast<Eigen::Index>(goals.size()));
    for (std::size_t i = 0; i < goals.size(); ++i)
        target.template segment<3>(3 * static_cast<Eigen::Index>(i)) = root_inv * (goals[i].position - s.positions[0]);

    const auto blend = model.nearest_to_goal(target, prm.blend);
    ik_vector<T> q = model.predict(target, blend);
    if (prm.ik.limits) q = tree.clamp(q);
    tree.wrap(q);
    const ik_matrix<T> inv = model.blended_inverse(blend);
    T err = (model.effectors_of(tree, joints, q) - target).norm();
    int steps = 0;
    for (; inv.size() && steps < prm.learned_steps; ++steps) {
        ik_vector<T> next = q + prm.ik.step_scale * inv * (target - model.effectors_of(tree, joints, q));
        if (prm.ik.limits) next = tree.clamp(next);
        if (!next.allFinite()) break;
        tree.wrap(next);
        const T e = (model.effectors_of(tree, joints, next) - target).norm();
        if (!(e < err)) break;
        err = e;
        q = next;
    }
    ik_params<T> polish = prm.ik;
    if (prm.reference_gain > T(0)) {
        polish.null_space.gain = prm.reference_gain;
        polish.null_space.reference = q;
    }
    learned_ik_result<T> result;
    static_cast<ik_result<T>&>(result) = solve_ik(tree, std::move(goals), q, damped_least_squares<T>(prm.polish), polish);
    result.iterations += steps;
    result.learned_steps = steps;
    result.cluster = blend.clusters.front();
    result.blended = blend.clusters;
    result.weights = blend.weights;
    return result;
}

/// solve_ik_learned as a solver of the shape solve_clip_ik takes,
/// solve(tree, goals, start, params): the start is not used (the model
/// predicts one from the goals) and params replaces `learned.ik`. When
/// `clusters` is given, each solve appends the cluster nearest its goals.
template <class T>
struct learned_ik_solver {
    const learned_ik_model<T>* model = nullptr;
    learned_solve_params<T> learned;
    std::vector<Eigen::Index>* clusters = nullptr;

    learned_ik_result<T> operator()(const kinematic_tree<T>& tree, const std::vector<ik_goal<T>>& goals,
                                    const ik_vector<T>& /*start*/, const ik_params<T>& params) const {
        if (!model) throw invalid_argument("anima::learned_ik_solver: no model");
        learned_solve_params<T> p = learned;
        p.ik = params;
        learned_ik_result<T> r = solve_ik_learned(tree, *model, goals, p);
        if (clusters) clusters->push_back(r.cluster);
        return r;
    }
};

}  // namespace anima
