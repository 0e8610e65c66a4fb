// Dynamic-size Eigen vector and matrix aliases shared by the modules.
#pragma once

#include <Eigen/Core>

namespace anima {

template <class T>
using vector_x = Eigen::Matrix<T, Eigen::Dynamic, 1>;
template <class T>
using matrix_x = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

}  // namespace anima
