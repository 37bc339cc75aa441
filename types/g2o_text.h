// SPDX-License-Identifier: MIT
// What the types share to read and write g2o text: 17-digit numbers, Ω's layout, pose fields.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <ostream>

#include "dualgraph/core/status.h"
#include "dualgraph/core/token_reader.h"

namespace dualgraph {

/// Significant digits of every number the types write: enough for any double to read back
/// bit-identically (g2o writes 6, which alone can move a χ² by percents).
constexpr int kG2oWritePrecision = 17;

/// Sets a stream's precision for the lifetime of the guard and restores it afterwards.
class StreamPrecisionGuard {
 public:
  StreamPrecisionGuard(std::ostream& out, int precision) : out_(out), saved_(out.precision(precision)) {}
  ~StreamPrecisionGuard() { out_.precision(saved_); }
  StreamPrecisionGuard(const StreamPrecisionGuard&) = delete;
  StreamPrecisionGuard& operator=(const StreamPrecisionGuard&) = delete;

 private:
  std::ostream& out_;
  std::streamsize saved_;
};

/// Writes `count` numbers separated by single spaces (no leading or trailing space), 17 digits.
void writeNumbers(std::ostream& out, const double* values, int count);

/// g2o's information layout: the upper triangle row by row, 17 digits, space separated.
template <int N>
void writeUpperTriangle(std::ostream& out, const Eigen::Matrix<double, N, N>& matrix) {
  std::array<double, N*(N + 1) / 2> values{};
  int k = 0;
  for (int r = 0; r < N; ++r) {
    for (int c = r; c < N; ++c) values[k++] = matrix(r, c);
  }
  writeNumbers(out, values.data(), k);
}

/// How the quaternion of a g2o line becomes a rotation matrix.
enum class QuaternionReading {
  /// q/|q|, as g2o reads EDGE_SE3:QUAT measurements and PARAMS_SE3OFFSET offsets.
  kNormalise,
  /// As g2o reads VERTEX_SE3:QUAT and EDGE_SE3_PRIOR: the quaternion exactly as written (files carry ~6 digits, so
  /// |q| = 1 ± 1e-6, and normalising would move the χ² of the public datasets by up to 2e-8
  /// relative). A quaternion farther than kQuaternionAsWrittenTolerance from unit norm is
  /// normalised instead, where g2o would build a scaled, non-rotation matrix.
  kAsWrittenNearUnit,
};

/// Largest | |q| − 1 | that kAsWrittenNearUnit keeps as written.
constexpr double kQuaternionAsWrittenTolerance = 1e-3;
/// Quaternions shorter than this are rejected as "zero-norm quaternion".
constexpr double kMinQuaternionNorm = 1e-12;

/// Reads and writes a pose as g2o's seven fields `x y z qx qy qz qw`.
/// It remembers the quaternion it last read, and writes it back unchanged while the pose's
/// rotation is still the matrix built from it: a write→read→write round trip is then
/// bit-identical, which a matrix → quaternion → matrix conversion alone cannot guarantee.
/// A pose set or changed in code is written as its rotation's unit quaternion (g2o's sign).
class G2oPoseText {
 public:
  explicit G2oPoseText(QuaternionReading reading) : reading_(reading) {}

  /// Errors name the field: non-finite values, "zero-norm quaternion".
  Status read(TokenReader& in, Eigen::Isometry3d& pose);
  void write(std::ostream& out, const Eigen::Isometry3d& pose) const;

  /// The rotation matrix this reader builds from a quaternion given as [x y z w].
  Eigen::Matrix3d rotationFrom(const std::array<double, 4>& xyzw) const;

 private:
  QuaternionReading reading_;
  std::array<double, 4> read_xyzw_{0.0, 0.0, 0.0, 1.0};
  bool has_read_ = false;
};

}  // namespace dualgraph
