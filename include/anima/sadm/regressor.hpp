// The SADM regressors behind one interface: make one by kind, load a saved
// one. The interface itself (regressor, regressor_kind, regressor_options)
// is in regressor_base.hpp; this header brings every concrete regressor.
#pragma once

#include <anima/core/error.hpp>
#include <anima/sadm/detail/regress_io.hpp>
#include <anima/sadm/linear_regressor.hpp>
#include <anima/sadm/mlp_regressor.hpp>
#include <anima/sadm/polynomial_regressor.hpp>
#include <anima/sadm/regressor_base.hpp>
#include <anima/sadm/svr_regressor.hpp>

#include <istream>
#include <memory>
#include <string>
#include <vector>

namespace anima {

/// A new, unfitted regressor of the given kind with its part of options.
/// Throws anima::invalid_argument for bad options.
template <class T>
std::unique_ptr<regressor<T>> make_regressor(regressor_kind kind, const regressor_options<T>& options = {}) {
    switch (kind) {
        case regressor_kind::linear: return std::make_unique<linear_regressor<T>>(options.linear);
        case regressor_kind::poly2: return std::make_unique<polynomial_regressor<T>>(options.poly2);
        case regressor_kind::svr: return std::make_unique<svr_regressor<T>>(options.svr, options.progress);
        case regressor_kind::mlp: return std::make_unique<mlp_regressor<T>>(options.mlp, options.progress);
    }
    throw invalid_argument("anima::make_regressor: unknown regressor kind " + std::to_string(static_cast<int>(kind)));
}

/// Reads what regressor::save wrote. source names the stream in errors,
/// which are anima::parse_error ("source:line: message").
template <class T>
std::unique_ptr<regressor<T>> load_regressor(std::istream& in, const std::string& source = "<stream>") {
    detail::regress_reader reader(in, source);
    const std::vector<std::string> header = reader.next_tokens("anima-regressor");
    if (header.size() != 3 || header[0] != "anima-regressor")
        reader.fail("not a saved regressor: the first line must read 'anima-regressor <kind> 1'");
    if (header[2] != "1") reader.fail("unsupported regressor format version '" + header[2] + "'");
    regressor_kind kind;
    try {
        kind = parse_regressor_kind(header[1]);
    } catch (const invalid_argument&) {
        reader.fail("unknown regressor kind '" + header[1] + "'");
    }
    switch (kind) {
        case regressor_kind::linear:
            return std::make_unique<linear_regressor<T>>(linear_regressor<T>::read_body(reader));
        case regressor_kind::poly2:
            return std::make_unique<polynomial_regressor<T>>(polynomial_regressor<T>::read_body(reader));
        case regressor_kind::svr: return std::make_unique<svr_regressor<T>>(svr_regressor<T>::read_body(reader));
        case regressor_kind::mlp: return std::make_unique<mlp_regressor<T>>(mlp_regressor<T>::read_body(reader));
    }
    reader.fail("unknown regressor kind '" + header[1] + "'");
}

}  // namespace anima
