#pragma once
#include <Eigen/Core>

namespace granflow {
template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
}
