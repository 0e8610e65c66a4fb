// A trained shape-appearance dependence mapping (SADM): the shape model
// (Eq 1), the grey-level model (Eq 2) with its reference triangulation, and a
// regressor from shape parameters b_s to grey parameters b_g. Synthesis
// follows the paper's steps: landmarks -> b_s (1-2) -> clamp (Eq 6) -> b_g
// (3) -> clamp -> g (4) -> warp onto the landmarks (5), then paste into a
// neutral frame with Poisson blending. Saved as text with a version header.
#pragma once

#include <anima/core/check_argument.hpp>
#include <anima/core/error.hpp>
#include <anima/sadm/appearance_model.hpp>
#include <anima/sadm/detail/regress_io.hpp>
#include <anima/sadm/landmarks.hpp>
#include <anima/sadm/pca.hpp>
#include <anima/sadm/regressor.hpp>
#include <anima/sadm/shape_model.hpp>
#include <anima/sadm/synthesis.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <optional>
#include <functional>
#include <istream>
#include <memory>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace anima {

/// Settings of sadm_model::train.
template <class T>
struct sadm_options {
    shape_model_options<T> shape{};           ///< PCA of the aligned shapes: 98 % of the variance
    pca_options<T> grey{T(0.95), 0};          ///< PCA of the warped grey levels: 95 % of the variance
    regressor_kind mapping = regressor_kind::linear;
    regressor_options<T> regressor{};
    /// Pixels per unit of the (unit-size) mean shape in the reference frame;
    /// 0: the training shapes' mean size, so the reference keeps the images' resolution.
    T reference_scale = T(0);
    T clamp_limit = T(3);  ///< Eq 6: parameters limited to +-clamp_limit sqrt(lambda)
    /// Progress of the long stages: ("warp", done, total), then the regressor's own stages.
    std::function<void(const std::string& stage, int done, int total)> progress;
};

template <class T>
class sadm_model {
public:
    using vector = Eigen::Matrix<T, Eigen::Dynamic, 1>;
    using matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

    sadm_model() = default;
    sadm_model(shape_model<T> shape, grey_model<T> grey, std::unique_ptr<regressor<T>> mapping, T clamp_limit = T(3))
        : shape_(std::move(shape)), grey_(std::move(grey)), mapping_(std::move(mapping)), clamp_limit_(clamp_limit) {
        const std::string who = "anima::sadm_model";
        if (!mapping_ || !mapping_->fitted()) throw invalid_argument(who + ": the mapping is missing or not fitted");
        if (mapping_->input_size() != shape_.size() || mapping_->output_size() != grey_.size())
            throw invalid_argument(who + ": the mapping takes " + std::to_string(mapping_->input_size()) + " -> " +
                                   std::to_string(mapping_->output_size()) + " parameters, the models have " +
                                   std::to_string(shape_.size()) + " and " + std::to_string(grey_.size()));
        if (const std::string problem = clamp_limit_problem(clamp_limit_); !problem.empty())
            throw invalid_argument(who + ": " + problem);
    }

    /// What is wrong with a clamp limit (empty when it is finite and >= 0):
    /// the constructor's check, which load makes on the limit's own line.
    static std::string clamp_limit_problem(T limit) {
        if (limit >= T(0) && std::isfinite(limit)) return {};
        return "clamp_limit must be finite and >= 0, got " + detail::argument_text(limit);
    }

    /// Trains on frames (grey levels, rows = y) and their landmarks. Throws
    /// anima::invalid_argument for fewer than 2 frames, counts that differ, or
    /// what the models and the regressor refuse (a shape model without any
    /// variation, for one).
    template <class Image>
    static sadm_model train(const std::vector<Image>& images, const std::vector<landmark_set<T>>& landmarks,
                            const sadm_options<T>& options = {});

    const shape_model<T>& shape() const noexcept { return shape_; }
    const grey_model<T>& grey() const noexcept { return grey_; }
    const regressor<T>& mapping() const { return *mapping_; }
    T clamp_limit() const noexcept { return clamp_limit_; }

    /// Steps 1-2 with Eq 6: the clamped b_s of a landmark set.
    vector shape_parameters(const landmark_set<T>& landmarks) const {
        return shape_.model().clamp(shape_.parameters(landmarks), clamp_limit_);
    }

    /// Step 3 with Eq 6: the clamped b_g the mapping predicts for b_s.
    vector grey_parameters(const vector& bs) const {
        const matrix in = bs.transpose();
        return grey_.model().clamp(vector(mapping_->predict(in).row(0).transpose()), clamp_limit_);
    }

    /// Steps 1-4: the grey levels g (reference frame) for a landmark set.
    vector grey_levels(const landmark_set<T>& landmarks) const {
        return grey_.grey_levels(grey_parameters(shape_parameters(landmarks)));
    }

    /// Steps 1-5: the synthesised face on a rows x cols raster, at the landmarks.
    face_patch<T> render(const landmark_set<T>& landmarks, Eigen::Index rows, Eigen::Index cols) const {
        return render_face(grey_, grey_levels(landmarks), landmarks, rows, cols);
    }

    /// The synthesised face pasted into a neutral frame with Poisson blending.
    grey_image<T> synthesize(const landmark_set<T>& landmarks, const grey_image<T>& neutral_frame) const {
        return blend_face(neutral_frame, render(landmarks, neutral_frame.rows(), neutral_frame.cols()));
    }

    /// Text: "anima-sadm 1", the models, then the regressor's own text
    /// (regressor::save). Numbers with full precision.
    void save(std::ostream& out) const {
        if (!mapping_) throw error("anima::sadm_model::save: the model is empty");
        detail::regress_stream_format format(out, T(0));
        out << "anima-sadm 1\n";
        out << "clamp_limit " << clamp_limit_ << '\n';
        write_pca(out, "shape", shape_.model());
        const auto& r = grey_.reference();
        out << "raster " << grey_.raster().rows << ' ' << grey_.raster().cols << '\n';
        detail::write_regress_matrix(out, "reference", r);
        Eigen::Matrix<int, Eigen::Dynamic, 3> tris(static_cast<Eigen::Index>(grey_.triangles().size()), 3);
        for (std::size_t t = 0; t < grey_.triangles().size(); ++t)
            for (int v = 0; v < 3; ++v) tris(static_cast<Eigen::Index>(t), v) = grey_.triangles()[t][static_cast<std::size_t>(v)];
        detail::write_regress_matrix(out, "triangles", tris);
        write_pca(out, "grey", grey_.model());
        mapping_->save(out);
        if (!out) throw io_error("anima::sadm_model::save: writing failed");
    }

    /// Reads what save wrote. Throws anima::parse_error ("source:line:
    /// message") for anything malformed or inconsistent.
    static sadm_model load(std::istream& in, const std::string& source = "<stream>");

private:
    static void write_pca(std::ostream& out, const std::string& name, const pca<T>& p) {
        out << name << "_pca " << p.dimension() << ' ' << p.size() << '\n';
        out << "total_variance " << p.total_variance() << '\n';
        detail::write_regress_values(out, "mean", p.mean().transpose());
        detail::write_regress_values(out, "eigenvalues", p.eigenvalues().transpose());
        detail::write_regress_matrix(out, "components", p.components().transpose());
    }

    static pca<T> read_pca(detail::regress_reader& reader, const std::string& name) {
        const std::string key = name + "_pca";
        const auto t = reader.expect(key.c_str());
        if (t.size() != 2) reader.fail("'" + key + "' takes the dimension and the component count");
        const long d = reader.parse_count(t[0], "dimension"), k = reader.parse_count(t[1], "component count", d);
        const T total = reader.read_scalar<T>("total_variance");
        vector mean = reader.read_values<T>("mean", d).transpose();
        vector values = reader.read_values<T>("eigenvalues", k).transpose();
        matrix components = reader.read_matrix<T>("components", k, d).transpose();
        try {
            return pca<T>(std::move(mean), std::move(components), std::move(values), total);
        } catch (const invalid_argument& e) {
            reader.fail(e.what());
        }
    }

    shape_model<T> shape_;
    grey_model<T> grey_;
    std::unique_ptr<regressor<T>> mapping_;
    T clamp_limit_ = T(3);
};

// Out of the class body (not inline), so that a build compiling the heavy
// templates once (sadm/instances.hpp) can declare them extern.
template <class T>
template <class Image>
sadm_model<T> sadm_model<T>::train(const std::vector<Image>& images, const std::vector<landmark_set<T>>& landmarks,
                                   const sadm_options<T>& options) {
    const std::string who = "anima::sadm_model::train";
    if (images.size() < 2 || images.size() != landmarks.size())
        throw invalid_argument(who + ": needs at least 2 frames with one landmark set each, got " +
                               std::to_string(images.size()) + " images and " + std::to_string(landmarks.size()) +
                               " landmark sets");
    for (std::size_t k = 0; k < images.size(); ++k)
        check_landmarks_inside(landmarks[k], static_cast<Eigen::Index>(images[k].cols()),
                               static_cast<Eigen::Index>(images[k].rows()), who + ": frame " + std::to_string(k));
    shape_model<T> shape = shape_model<T>::fit(landmarks, options.shape);
    if (shape.size() == 0) throw invalid_argument(who + ": the landmark sets do not vary: no shape parameter");
    T scale = options.reference_scale;
    if (scale == T(0)) {
        for (const auto& s : landmarks) scale += (s.rowwise() - s.colwise().mean()).norm();
        scale /= static_cast<T>(landmarks.size());
    }
    Eigen::Index rows = 0, cols = 0;
    const landmark_set<T> reference = grey_model<T>::place_reference(shape.mean(), scale, rows, cols);
    grey_model_options<T> grey_options;
    grey_options.pca = options.grey;
    if (options.progress) grey_options.progress = [&](int done, int total) { options.progress("warp", done, total); };
    grey_model<T> grey = grey_model<T>::fit(images, landmarks, reference, rows, cols, grey_options);
    if (grey.size() == 0) throw invalid_argument(who + ": the warped images do not vary: no grey parameter");
    matrix bs(static_cast<Eigen::Index>(images.size()), shape.size());
    matrix bg(static_cast<Eigen::Index>(images.size()), grey.size());
    for (std::size_t k = 0; k < images.size(); ++k) {
        const auto i = static_cast<Eigen::Index>(k);
        bs.row(i) = shape.parameters(landmarks[k]).transpose();
        bg.row(i) = grey.parameters(grey.sample(images[k], landmarks[k])).transpose();
    }
    regressor_options<T> ropt = options.regressor;
    if (options.progress && !ropt.progress) ropt.progress = options.progress;
    std::unique_ptr<regressor<T>> mapping = make_regressor<T>(options.mapping, ropt);
    mapping->fit(bs, bg);
    return sadm_model(std::move(shape), std::move(grey), std::move(mapping), options.clamp_limit);
}

template <class T>
sadm_model<T> sadm_model<T>::load(std::istream& in, const std::string& source) {
    detail::regress_reader reader(in, source);
    const auto header = reader.next_tokens("anima-sadm");
    if (header.size() != 2 || header[0] != "anima-sadm")
        reader.fail("not a SADM model: the first line must read 'anima-sadm 1'");
    if (header[1] != "1") reader.fail("unsupported SADM model version '" + header[1] + "'");
    const T limit = reader.read_scalar<T>("clamp_limit");
    if (const std::string problem = clamp_limit_problem(limit); !problem.empty()) reader.fail(problem);
    pca<T> shape_pca = read_pca(reader, "shape");
    const auto raster = reader.expect("raster");
    const std::size_t raster_line = reader.line();
    if (raster.size() != 2) reader.fail("'raster' takes rows and columns");
    const long rows = reader.parse_count(raster[0], "raster rows"), cols = reader.parse_count(raster[1], "raster columns");
    if (rows < 1 || cols < 1 || rows > max_raster_pixels / cols)
        reader.fail("raster " + std::to_string(rows) + " x " + std::to_string(cols) + " is outside 1.." +
                    std::to_string(max_raster_pixels) + " pixels (anima::max_raster_pixels)");
    const Eigen::Index points = shape_pca.dimension() / 2;
    const landmark_set<T> reference = reader.read_matrix<T>("reference", points, 2);
    const auto tri_line = reader.expect("triangles");
    if (tri_line.size() != 2 || tri_line[1] != "3") reader.fail("'triangles' takes a count and 3");
    const long count = reader.parse_count(tri_line[0], "triangle count");
    std::vector<triangle_indices> tris;
    tris.reserve(static_cast<std::size_t>(std::min(count, 1L << 16)));  // the count is not trusted
    for (long n = 0; n < count; ++n) {
        triangle_indices& t = tris.emplace_back();
        const auto v = reader.next_tokens("a triangle");
        if (v.size() != 3) reader.fail("a triangle takes 3 point indices");
        for (int k = 0; k < 3; ++k) {
            const long index = reader.parse_count(v[static_cast<std::size_t>(k)], "point index", points - 1);
            t[static_cast<std::size_t>(k)] = static_cast<int>(index);
        }
    }
    // The grey model checked where it ends (its reference and raster against its PCA).
    std::optional<grey_model<T>> grey;
    try {
        grey.emplace(reference, std::move(tris), rows, cols, read_pca(reader, "grey"));
    } catch (const invalid_argument& e) {
        reader.fail("the grey model does not fit the raster of line " + std::to_string(raster_line) + ": " + e.what());
    }
    const std::size_t regressor_line = reader.line();
    std::unique_ptr<regressor<T>> mapping;
    try {
        mapping = load_regressor<T>(in, source);
    } catch (const parse_error& e) {
        throw parse_error(source, e.line() + regressor_line, e.message());
    }
    try {
        return sadm_model(shape_model<T>(std::move(shape_pca)), std::move(*grey), std::move(mapping), limit);
    } catch (const invalid_argument& e) {
        throw parse_error(source, reader.line(), std::string("inconsistent model: ") + e.what());
    }
}

}  // namespace anima
