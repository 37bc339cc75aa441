// SPDX-License-Identifier: MIT
// numpy ⇄ Eigen at the binding boundary, with the checks the library leaves to its callers: dtype, shape,
// finite values, quaternion norm, rigid 4×4 matrices. Every failure raises InvalidArgumentError naming the
// argument and, for values, the offending index (e.g. "poses[2, 6] is not finite (nan)").
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace dualgraph::python {

using DoubleArray = pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast>;
using IsometryList = std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>>;
using MatrixList = std::vector<Eigen::MatrixXd>;

/// "(3, 7)".
std::string shapeString(const pybind11::array& array);
/// Any real-valued array-like (float, int) as C-contiguous float64; strings, objects, complex and ragged
/// lists are rejected. Values are not checked here.
DoubleArray toDoubles(pybind11::handle object, const std::string& name);
/// Raises naming `name[i, j, ...]` at the first NaN/Inf.
void requireFinite(const DoubleArray& array, const std::string& name);
/// Ids: an integer array-like or a scalar, 1-D after conversion, each in [min_id, 2^31); n = -1 accepts any count.
std::vector<int> toIds(pybind11::handle object, const std::string& name, long n = -1, int min_id = 0);

/// One pose: `[x y z qx qy qz qw]` (quaternion Hamilton, normalised here; zero norm rejected) or a rigid 4×4
/// homogeneous matrix (last row 0 0 0 1, orthonormal rotation with det +1 to 1e-6).
Eigen::Isometry3d toPose(pybind11::handle object, const std::string& name);
/// n poses: (n, 7) or (n, 4, 4); n = -1 accepts any count.
IsometryList toPoses(pybind11::handle object, const std::string& name, long n = -1);
/// A rows × cols matrix of finite values.
Eigen::MatrixXd toMatrix(pybind11::handle object, const std::string& name, long rows, long cols);
/// n matrices rows × cols: (n, rows, cols), or one (rows, cols) used for all n.
MatrixList toMatrices(pybind11::handle object, const std::string& name, long n, long rows, long cols);
/// n rows of k finite values: (n, k) (a 1-D (k,) when n = 1 is also accepted); n = -1 accepts any count.
Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> toRows(pybind11::handle object,
                                                                               const std::string& name, long n, long k);

/// `[x y z qx qy qz qw]` with the quaternion's w ≥ 0.
Eigen::Matrix<double, 7, 1> poseToVector(const Eigen::Isometry3d& pose);
/// (7,) array.
pybind11::array_t<double> poseArray(const Eigen::Isometry3d& pose);
/// (n, 7) array.
pybind11::array_t<double> poseArrays(const IsometryList& poses);
/// (4, 4) array.
pybind11::array_t<double> poseMatrix(const Eigen::Isometry3d& pose);
/// (rows, cols) array.
pybind11::array_t<double> matrixArray(const Eigen::MatrixXd& matrix);
/// (n,) array.
pybind11::array_t<double> vectorArray(const std::vector<double>& values);

}  // namespace dualgraph::python
