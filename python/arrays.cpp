// SPDX-License-Identifier: MIT
#include "arrays.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "dualgraph/dual_graph/measurements.h"
#include "errors.h"
#include "dualgraph/types/se3_math.h"
#include "dualgraph/types/se3_covariance.h"

namespace py = pybind11;

namespace dualgraph::python {
namespace {

// "name[2, 6]" for the flat index `flat` of an array of `shape`.
std::string indexName(const std::string& name, const std::vector<py::ssize_t>& shape, py::ssize_t flat) {
  std::vector<py::ssize_t> index(shape.size());
  for (size_t d = shape.size(); d-- > 0;) {
    index[d] = flat % shape[d];
    flat /= shape[d];
  }
  std::ostringstream out;
  out << name << "[";
  for (size_t d = 0; d < index.size(); ++d) out << (d ? ", " : "") << index[d];
  out << "]";
  return out.str();
}

std::vector<py::ssize_t> shapeOf(const py::array& array) {
  return std::vector<py::ssize_t>(array.shape(), array.shape() + array.ndim());
}

[[noreturn]] void raiseShape(const std::string& name, const std::string& expected, const py::array& got) {
  raiseInvalid(name + ": expected shape " + expected + ", got " + shapeString(got));
}

// Rigid transform from the 16 row-major entries of a 4×4 matrix (finite already).
Eigen::Isometry3d poseFromMatrix(const double* m, const std::string& name) {
  Eigen::Matrix4d matrix = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(m);
  if (matrix.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) raiseInvalid(name + ": the last row of a 4x4 pose must be 0 0 0 1");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = matrix.topLeftCorner<3, 3>();
  pose.translation() = matrix.topRightCorner<3, 1>();
  check(checkRigidTransform(pose, name));
  return pose;
}

// Pose from [x y z qx qy qz qw] (finite already).
Eigen::Isometry3d poseFromVector(const double* v, const std::string& name) {
  Eigen::Quaterniond q = quatFromXyzw(v[3], v[4], v[5], v[6]);
  const double norm = q.norm();
  if (!(norm > 1e-12)) raiseInvalid(name + ": the quaternion [qx qy qz qw] has zero norm");
  q.coeffs() /= norm;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.toRotationMatrix();
  pose.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return pose;
}

}  // namespace

std::string shapeString(const py::array& array) {
  std::ostringstream out;
  out << "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d) out << (d ? ", " : "") << array.shape(d);
  out << (array.ndim() == 1 ? ",)" : ")");
  return out.str();
}

DoubleArray toDoubles(py::handle object, const std::string& name) {
  py::array array = py::array::ensure(object);
  if (!array) raiseInvalid(name + ": expected an array of numbers, got " + std::string(py::str(py::type::of(object))));
  const char kind = array.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    raiseInvalid(name + ": expected an array of real numbers, got dtype " + std::string(py::str(array.dtype())));
  }
  return DoubleArray::ensure(array);
}

void requireFinite(const DoubleArray& array, const std::string& name) {
  const double* data = array.data();
  for (py::ssize_t i = 0; i < array.size(); ++i) {
    if (!std::isfinite(data[i])) {
      raiseInvalid(indexName(name, shapeOf(array), i) + " is not finite (" + std::string(py::str(py::float_(data[i]))) + ")");
    }
  }
}

std::vector<int> toIds(py::handle object, const std::string& name, long n, int min_id) {
  py::array array = py::array::ensure(object);
  if (!array) raiseInvalid(name + ": expected integer ids, got " + std::string(py::str(py::type::of(object))));
  if (array.ndim() == 0) array = py::array::ensure(array.attr("reshape")(1));
  const char kind = array.dtype().kind();
  if (array.size() > 0 && kind != 'i' && kind != 'u') {
    raiseInvalid(name + ": expected integer ids, got dtype " + std::string(py::str(array.dtype())));
  }
  if (array.ndim() != 1 || (n >= 0 && array.shape(0) != n)) raiseShape(name, n >= 0 ? "(" + std::to_string(n) + ",)" : "(n,)", array);
  auto values = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(array);
  std::vector<int> ids(static_cast<size_t>(values.size()));
  for (py::ssize_t i = 0; i < values.size(); ++i) {
    const long long id = values.data()[i];
    if (id < min_id || id > std::numeric_limits<int>::max()) {
      raiseInvalid(name + "[" + std::to_string(i) + "] = " + std::to_string(id) + " is not a valid id (" +
                   std::to_string(min_id) + " <= id < 2^31)");
    }
    ids[static_cast<size_t>(i)] = static_cast<int>(id);
  }
  return ids;
}

Eigen::Isometry3d toPose(py::handle object, const std::string& name) {
  DoubleArray array = toDoubles(object, name);
  const bool vector = array.ndim() == 1 && array.shape(0) == 7;
  const bool matrix = array.ndim() == 2 && array.shape(0) == 4 && array.shape(1) == 4;
  if (!vector && !matrix) raiseShape(name, "(7,) [x y z qx qy qz qw] or (4, 4)", array);
  requireFinite(array, name);
  return vector ? poseFromVector(array.data(), name) : poseFromMatrix(array.data(), name);
}

IsometryList toPoses(py::handle object, const std::string& name, long n) {
  DoubleArray array = toDoubles(object, name);
  const bool vectors = array.ndim() == 2 && array.shape(1) == 7;
  const bool matrices = array.ndim() == 3 && array.shape(1) == 4 && array.shape(2) == 4;
  const std::string count = n >= 0 ? std::to_string(n) : "n";
  if ((!vectors && !matrices) || (n >= 0 && array.shape(0) != n)) {
    raiseShape(name, "(" + count + ", 7) rows [x y z qx qy qz qw] or (" + count + ", 4, 4)", array);
  }
  requireFinite(array, name);
  IsometryList poses;
  poses.reserve(static_cast<size_t>(array.shape(0)));
  for (py::ssize_t i = 0; i < array.shape(0); ++i) {
    const std::string row = name + "[" + std::to_string(i) + "]";
    poses.push_back(vectors ? poseFromVector(array.data() + 7 * i, row) : poseFromMatrix(array.data() + 16 * i, row));
  }
  return poses;
}

Eigen::MatrixXd toMatrix(py::handle object, const std::string& name, long rows, long cols) {
  DoubleArray array = toDoubles(object, name);
  if (array.ndim() != 2 || array.shape(0) != rows || array.shape(1) != cols) {
    raiseShape(name, "(" + std::to_string(rows) + ", " + std::to_string(cols) + ")", array);
  }
  requireFinite(array, name);
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(array.data(), rows, cols);
}

MatrixList toMatrices(py::handle object, const std::string& name, long n, long rows, long cols) {
  DoubleArray array = toDoubles(object, name);
  const std::string block = std::to_string(rows) + ", " + std::to_string(cols);
  const bool one = array.ndim() == 2 && array.shape(0) == rows && array.shape(1) == cols;
  const bool each = array.ndim() == 3 && array.shape(0) == n && array.shape(1) == rows && array.shape(2) == cols;
  if (!one && !each) raiseShape(name, "(" + block + ") or (" + std::to_string(n) + ", " + block + ")", array);
  requireFinite(array, name);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  MatrixList matrices;
  matrices.reserve(static_cast<size_t>(n));
  for (long i = 0; i < n; ++i) {
    matrices.emplace_back(Eigen::Map<const RowMajor>(array.data() + (one ? 0 : i * rows * cols), rows, cols));
  }
  return matrices;
}

Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> toRows(py::handle object, const std::string& name,
                                                                               long n, long k) {
  DoubleArray array = toDoubles(object, name);
  const bool single = n == 1 && array.ndim() == 1 && array.shape(0) == k;
  const bool rows = array.ndim() == 2 && array.shape(1) == k && (n < 0 || array.shape(0) == n);
  if (!single && !rows) raiseShape(name, "(" + (n >= 0 ? std::to_string(n) : std::string("n")) + ", " + std::to_string(k) + ")", array);
  requireFinite(array, name);
  const long count = single ? 1 : static_cast<long>(array.shape(0));
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(array.data(), count, k);
}

Eigen::Matrix<double, 7, 1> poseToVector(const Eigen::Isometry3d& pose) {
  Eigen::Quaterniond q(pose.linear());
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  Eigen::Matrix<double, 7, 1> v;
  v << pose.translation(), q.x(), q.y(), q.z(), q.w();
  return v;
}

py::array_t<double> poseArray(const Eigen::Isometry3d& pose) {
  py::array_t<double> out(7);
  Eigen::Map<Eigen::Matrix<double, 7, 1>>(out.mutable_data()) = poseToVector(pose);
  return out;
}

py::array_t<double> poseArrays(const IsometryList& poses) {
  py::array_t<double> out({static_cast<py::ssize_t>(poses.size()), py::ssize_t{7}});
  for (size_t i = 0; i < poses.size(); ++i) {
    Eigen::Map<Eigen::Matrix<double, 7, 1>>(out.mutable_data() + 7 * i) = poseToVector(poses[i]);
  }
  return out;
}

py::array_t<double> poseMatrix(const Eigen::Isometry3d& pose) {
  py::array_t<double> out({py::ssize_t{4}, py::ssize_t{4}});
  Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(out.mutable_data()) = pose.matrix();
  return out;
}

py::array_t<double> matrixArray(const Eigen::MatrixXd& matrix) {
  py::array_t<double> out({static_cast<py::ssize_t>(matrix.rows()), static_cast<py::ssize_t>(matrix.cols())});
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(out.mutable_data(), matrix.rows(),
                                                                                    matrix.cols()) = matrix;
  return out;
}

py::array_t<double> vectorArray(const std::vector<double>& values) {
  py::array_t<double> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

}  // namespace dualgraph::python
