// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "dualgraph/frontend/io/camera_io.h"
#include "dualgraph/frontend/gates/camera_model.h"
#include "test/testing/shared_data.h"
#include "dualgraph/types/se3_math.h"

namespace dualgraph {
namespace {

using Distortion = CameraModel::Distortion;

CameraModel ratmRadtan() {
  CameraModel camera = CameraModel::pinhole(289.8846763939774, 387.06227498911073, 316.58338771731684,
                                            241.86918974530997, 640, 480, Distortion::kRadTan);
  camera.distortion << -0.28145280823630314, 0.1091225266070853, 0.00018240521552769957, 6.785645205189456e-05,
      -0.023250148744302514;
  return camera;
}

CameraModel ratmEquidistant() {
  CameraModel camera = CameraModel::pinhole(291.52, 390.011, 316.447, 240.442, 640, 480, Distortion::kEquidistant);
  camera.distortion << 0.048, -0.028, 0.038, -0.018;
  camera.body_T_camera = se3Exp((Vector6d() << 0.04, 0.03, 0.05, -1.2, 0.4, -1.3).finished());
  return camera;
}

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(CameraYaml, RoundTripGivesTheSameCamera) {
  for (const CameraModel& camera : {ratmRadtan(), ratmEquidistant()}) {
    const std::string path = ::testing::TempDir() + "/camera_round_trip.yaml";
    ASSERT_TRUE(saveCameraYaml(path, camera).ok());
    auto loaded = loadCameraYaml(path);
    ASSERT_TRUE(loaded.ok()) << loaded.status().toString();
    EXPECT_EQ(loaded->model, camera.model);
    EXPECT_EQ(loaded->K, camera.K);
    EXPECT_EQ(loaded->distortion, camera.distortion);
    EXPECT_EQ(loaded->width, 640);
    EXPECT_EQ(loaded->height, 480);
    EXPECT_LT((loaded->body_T_camera.matrix() - camera.body_T_camera.matrix()).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_EQ(cameraToYaml(*loaded), cameraToYaml(camera));
  }
}

TEST(CameraYaml, TheClockOffsetIsReadWrittenAndChecked) {
  CameraModel camera = ratmRadtan();
  EXPECT_EQ(cameraToYaml(camera).find("time_offset"), std::string::npos);  // 0: not written, as before
  camera.time_offset = -0.0125;
  auto back = parseCameraYaml(cameraToYaml(camera), "cam.yaml");
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->time_offset, -0.0125);
  auto absent = parseCameraYaml(cameraToYaml(ratmRadtan()), "cam.yaml");
  ASSERT_TRUE(absent.ok());
  EXPECT_EQ(absent->time_offset, 0.0);
  const std::string text = cameraToYaml(ratmRadtan());
  for (const std::string& bad : {std::string("time_offset: 2.5\n"), std::string("time_offset: .nan\n"),
                                 std::string("time_offset: late\n")}) {
    auto refused = parseCameraYaml(text + bad, "cam.yaml");
    ASSERT_FALSE(refused.ok()) << bad;
    EXPECT_NE(refused.status().message().find("field 'time_offset'"), std::string::npos) << refused.status().message();
    const std::string line = "cam.yaml:" + std::to_string(std::count(text.begin(), text.end(), '\n') + 1) + ":";
    EXPECT_EQ(refused.status().message().rfind(line, 0), 0u) << refused.status().message();
  }
}

TEST(CameraYaml, KMatrixFormEqualsTheScalarForm) {
  auto a = parseCameraYaml("model: radtan\nwidth: 640\nheight: 480\nK: [[300, 0, 320], [0, 310, 240], [0, 0, 1]]\n"
                           "distortion: [0.1, 0.01, 0, 0]\n", "k.yaml");
  auto b = parseCameraYaml("model: radtan\nwidth: 640\nheight: 480\nfx: 300\nfy: 310\ncx: 320\ncy: 240\n"
                           "distortion: [0.1, 0.01, 0, 0]\n", "f.yaml");
  ASSERT_TRUE(a.ok()) << a.status().toString();
  ASSERT_TRUE(b.ok()) << b.status().toString();
  EXPECT_EQ(a->K, b->K);
  EXPECT_TRUE(a->body_T_camera.isApprox(Eigen::Isometry3d::Identity()));
}

TEST(CameraYaml, BundledRatmPilotedCameraLoads) {
  auto camera = loadCameraYaml(testing::sourcePath("data/cameras/ratm_piloted.yaml"));
  ASSERT_TRUE(camera.ok()) << camera.status().toString();
  EXPECT_EQ(camera->model, Distortion::kEquidistant);
  EXPECT_DOUBLE_EQ(camera->fx(), 291.520);
  EXPECT_DOUBLE_EQ(camera->distortion[3], -0.018);
  // The optical axis in body FLU: forward and 27.9° up, as the README of ../shared/data/ratm says.
  const Eigen::Vector3d axis = camera->body_T_camera.linear() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(std::asin(axis.z()) * 180.0 / M_PI, 27.9, 0.1);
  EXPECT_NEAR(axis.x(), 0.884, 1e-3);
}

struct BadYaml {
  const char* what;
  std::string text;
  int line;
  const char* field;
};

TEST(CameraYaml, EveryErrorNamesFileLineAndField) {
  const std::string good_tail = "width: 640\nheight: 480\nfx: 300\nfy: 300\ncx: 320\ncy: 240\n";
  const BadYaml cases[] = {
      {"unknown key", "model: radtan\n" + good_tail + "distortion: [0, 0, 0, 0]\nfocal: 3\n", 9, "focal"},
      {"duplicate key", "model: radtan\n" + good_tail + "distortion: [0, 0, 0, 0]\nwidth: 3\n", 9, "width"},
      {"missing model", good_tail + "distortion: [0, 0, 0, 0]\n", 1, "model"},
      {"unknown model", "model: fisheye\n" + good_tail + "distortion: [0, 0, 0, 0]\n", 1, "model"},
      {"negative width", "model: radtan\nwidth: -640\nheight: 480\nfx: 300\nfy: 300\ncx: 320\ncy: 240\ndistortion: [0, 0, 0, 0]\n", 2, "width"},
      {"width not an integer", "model: radtan\nwidth: 640.5\nheight: 480\nfx: 300\nfy: 300\ncx: 320\ncy: 240\ndistortion: [0, 0, 0, 0]\n", 2, "width"},
      {"NaN coefficient", "model: radtan\n" + good_tail + "distortion: [.nan, 0, 0, 0]\n", 8, "distortion[0]"},
      {"3 radtan coefficients", "model: radtan\n" + good_tail + "distortion: [0, 0, 0]\n", 8, "distortion"},
      {"5 equidistant coefficients", "model: equidistant\n" + good_tail + "distortion: [0, 0, 0, 0, 0]\n", 8, "distortion"},
      {"negative fx", "model: radtan\nwidth: 640\nheight: 480\nfx: -300\nfy: 300\ncx: 320\ncy: 240\ndistortion: [0, 0, 0, 0]\n", 4, "fx"},
      {"missing cy", "model: radtan\nwidth: 640\nheight: 480\nfx: 300\nfy: 300\ncx: 320\ndistortion: [0, 0, 0, 0]\n", 1, "cy"},
      {"K 2x3", "model: radtan\nwidth: 640\nheight: 480\nK: [[300, 0, 320], [0, 300, 240]]\ndistortion: [0, 0, 0, 0]\n", 4, "K"},
      {"K row of 2", "model: radtan\nwidth: 640\nheight: 480\nK: [[300, 0, 320], [0, 300], [0, 0, 1]]\ndistortion: [0, 0, 0, 0]\n", 4, "K[1]"},
      {"K with skew", "model: radtan\nwidth: 640\nheight: 480\nK: [[300, 2, 320], [0, 300, 240], [0, 0, 1]]\ndistortion: [0, 0, 0, 0]\n", 4, "K"},
      {"K and fx", "model: radtan\n" + good_tail + "K: [[300, 0, 320], [0, 300, 240], [0, 0, 1]]\ndistortion: [0, 0, 0, 0]\n", 8, "K"},
      {"position of 2", "model: radtan\n" + good_tail + "distortion: [0, 0, 0, 0]\nbody_T_camera:\n  position: [1, 2]\n  quaternion_xyzw: [0, 0, 0, 1]\n", 10, "body_T_camera.position"},
      {"zero quaternion", "model: radtan\n" + good_tail + "distortion: [0, 0, 0, 0]\nbody_T_camera: {position: [0, 0, 0], quaternion_xyzw: [0, 0, 0, 0]}\n", 9, "quaternion_xyzw"},
      {"not a mapping", "- 1\n- 2\n", 1, ""},
      {"syntax error", "model: radtan\nwidth: [640\n", 3, ""},
  };
  for (const BadYaml& c : cases) {
    auto camera = parseCameraYaml(c.text, "cam.yaml");
    ASSERT_FALSE(camera.ok()) << c.what;
    EXPECT_EQ(camera.status().code(), StatusCode::kParseError) << c.what;
    const std::string& message = camera.status().message();
    EXPECT_EQ(message.rfind("cam.yaml:" + std::to_string(c.line) + ":", 0), 0u) << c.what << ": " << message;
    EXPECT_NE(message.find(c.field), std::string::npos) << c.what << ": " << message;
  }
  auto missing = loadCameraYaml(::testing::TempDir() + "/no_such_camera.yaml");
  EXPECT_EQ(missing.status().code(), StatusCode::kIoError);
}

TEST(RatmCalibrationJson, RealFileLoads) {
  const std::string path = testing::sharedPath("data/ratm/tii_camera_calibration/calib_ap-ellipse-lemniscate.json");
  DG_SKIP_WITHOUT_SHARED("data/ratm/tii_camera_calibration/calib_ap-ellipse-lemniscate.json");
  auto camera = loadRatmCalibrationJson(path);
  ASSERT_TRUE(camera.ok()) << camera.status().toString();
  EXPECT_EQ(camera->model, Distortion::kRadTan);
  EXPECT_NEAR(camera->fx(), 289.88, 0.005);
  EXPECT_NEAR(camera->fy(), 387.06, 0.005);
  EXPECT_NEAR(camera->cx(), 316.58, 0.005);
  EXPECT_NEAR(camera->cy(), 241.87, 0.005);
  ASSERT_EQ(camera->distortion.size(), 5);
  EXPECT_DOUBLE_EQ(camera->distortion[0], -0.28145280823630314);
  EXPECT_DOUBLE_EQ(camera->distortion[4], -0.023250148744302514);
  EXPECT_EQ(camera->width, 640);
  EXPECT_EQ(camera->height, 480);
  // The same file read as equidistant needs 4 coefficients: an error at dist, not a silent drop.
  auto wrong = loadRatmCalibrationJson(path, Distortion::kEquidistant);
  EXPECT_EQ(wrong.status().code(), StatusCode::kParseError);
  EXPECT_NE(wrong.status().message().find("dist[0]"), std::string::npos) << wrong.status().message();
}

TEST(RatmCalibrationJson, BadFilesNameFileLineAndField) {
  const std::string mtx = "\"mtx\": [[289.8, 0.0, 316.5], [0.0, 387.0, 241.8], [0.0, 0.0, 1.0]]";
  const BadYaml cases[] = {
      {"mtx 2x3", "{\"mtx\": [[289.8, 0.0, 316.5],\n [0.0, 387.0, 241.8]], \"dist\": [[0.1, 0.1, 0.0, 0.0, 0.0]]}", 1, "mtx"},
      {"4 radtan coefficients", "{" + mtx + ",\n \"dist\": [[0.1, 0.1, 0.0, 0.0]]}", 2, "dist[0]"},
      {"NaN", "{" + mtx + ",\n \"dist\": [[0.1, NaN, 0.0, 0.0, 0.0]]}", 2, "dist[0][1]"},
      {"missing dist", "{" + mtx + "}", 1, "dist"},
      {"zero fy", "{\"mtx\": [[289.8, 0.0, 316.5], [0.0, 0.0, 241.8], [0.0, 0.0, 1.0]],\n \"dist\": [[0, 0, 0, 0, 0]]}", 1, "fy"},
      {"truncated", "{" + mtx + ",\n \"dist\": [[0.1, 0.1", 2, "syntax"},
  };
  for (const BadYaml& c : cases) {
    const std::string path = writeTemp("ratm_bad.json", c.text);
    auto camera = loadRatmCalibrationJson(path);
    ASSERT_FALSE(camera.ok()) << c.what;
    EXPECT_EQ(camera.status().code(), StatusCode::kParseError) << c.what;
    const std::string& message = camera.status().message();
    EXPECT_EQ(message.rfind(path + ":" + std::to_string(c.line) + ":", 0), 0u) << c.what << ": " << message;
    EXPECT_NE(message.find(c.field), std::string::npos) << c.what << ": " << message;
  }
  const std::string good = writeTemp("ratm_good.json", "{" + mtx + ", \"dist\": [[0, 0, 0, 0, 0]]}");
  EXPECT_TRUE(loadRatmCalibrationJson(good).ok());
  EXPECT_EQ(loadRatmCalibrationJson(good, Distortion::kRadTan, -640, 480).status().code(), StatusCode::kInvalidArgument);
}

TEST(CameraModel, ValidateRejectsEachBadField) {
  EXPECT_TRUE(ratmRadtan().validate().ok());
  EXPECT_TRUE(ratmEquidistant().validate().ok());
  auto expectInvalid = [](CameraModel camera, const char* field) {
    const Status status = camera.validate();
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << field;
    EXPECT_NE(status.message().find(std::string("'") + field + "'"), std::string::npos) << status.message();
  };
  CameraModel c = ratmRadtan();
  c.K(0, 0) = 0.0;
  expectInvalid(c, "fx");
  c = ratmRadtan();
  c.K(1, 1) = std::nan("");
  expectInvalid(c, "K");
  c = ratmRadtan();
  c.distortion.resize(3);
  expectInvalid(c, "distortion");
  c = ratmEquidistant();
  c.distortion = Eigen::VectorXd::Zero(5);
  expectInvalid(c, "distortion");
  c = ratmEquidistant();
  c.distortion[2] = INFINITY;
  expectInvalid(c, "distortion");
  c = ratmRadtan();
  c.height = 0;
  expectInvalid(c, "height");
  c = ratmRadtan();
  c.width = -1;
  expectInvalid(c, "width");
  c = ratmRadtan();
  c.body_T_camera.linear() *= 1.01;
  expectInvalid(c, "body_T_camera");
}

TEST(CameraModel, ProjectFlagsPointsBehindAndOutside) {
  const CameraModel camera = ratmEquidistant();
  EXPECT_TRUE(camera.project({0.0, 0.0, 2.0}).valid());
  EXPECT_NEAR((camera.project({0.0, 0.0, 2.0}).pixel - Eigen::Vector2d(316.447, 240.442)).norm(), 0.0, 1e-12);
  EXPECT_FALSE(camera.project({0.0, 0.0, -2.0}).in_front);
  EXPECT_FALSE(camera.project({1.0, 0.0, 0.0}).in_front);
  const Projection outside = camera.project({20.0, 0.0, 1.0});  // 87° off axis
  EXPECT_TRUE(outside.in_front);
  EXPECT_FALSE(outside.in_image);
}

/// project(undistort(pixel)) = pixel on a grid, and undistort(project(p)) = (x/z, y/z) on random points.
void expectProjectUndistortConsistent(const CameraModel& camera, double max_off_axis_deg, double pixel_radius) {
  Eigen::Matrix2Xd pixels(2, 0);
  const Eigen::Vector2d centre(camera.cx(), camera.cy());
  for (double du = -pixel_radius; du <= pixel_radius; du += pixel_radius / 8) {
    for (double dv = -0.75 * pixel_radius; dv <= 0.75 * pixel_radius; dv += pixel_radius / 8) {
      pixels.conservativeResize(2, pixels.cols() + 1);
      pixels.col(pixels.cols() - 1) = centre + Eigen::Vector2d(du, dv);
    }
  }
  auto normalized = camera.undistortToNormalized(pixels);
  ASSERT_TRUE(normalized.ok()) << normalized.status().toString();
  for (Eigen::Index i = 0; i < pixels.cols(); ++i) {
    const Projection back = camera.project(normalized->col(i).homogeneous());
    ASSERT_TRUE(back.in_front);
    EXPECT_LT((back.pixel - pixels.col(i)).norm(), 1e-6) << "pixel " << pixels.col(i).transpose();
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::Matrix3Xd points(3, 500);
  Eigen::Matrix2Xd projected(2, 500);
  for (int i = 0; i < 500; ++i) {
    const double off_axis = max_off_axis_deg * M_PI / 180.0 * std::sqrt(unit(rng));
    const double azimuth = 2.0 * M_PI * unit(rng);
    const double range = 0.5 + 20.0 * unit(rng);
    points.col(i) = range * Eigen::Vector3d(std::sin(off_axis) * std::cos(azimuth), std::sin(off_axis) * std::sin(azimuth),
                                            std::cos(off_axis));
    projected.col(i) = camera.project(points.col(i)).pixel;
  }
  normalized = camera.undistortToNormalized(projected);
  ASSERT_TRUE(normalized.ok()) << normalized.status().toString();
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector2d expected = points.col(i).head<2>() / points(2, i);
    EXPECT_LT((normalized->col(i) - expected).norm(), 1e-9 * (1.0 + expected.norm())) << points.col(i).transpose();
  }
}

TEST(CameraModel, ProjectAndUndistortAreInversesRadTan) {
  // RATM's radtan fit folds back beyond r ≈ 1.5 (56°); stay inside the part where it is invertible.
  expectProjectUndistortConsistent(ratmRadtan(), 42.0, 200.0);
}

TEST(CameraModel, ProjectAndUndistortAreInversesEquidistant) {
  expectProjectUndistortConsistent(ratmEquidistant(), 80.0, 300.0);
}

/// Points the Jacobian tests use: the optical axis exactly and 1e-9 off it, rings out to 70°, and the
/// rays through the pixels 1.5 px inside the four image corners, each at several ranges [m].
Eigen::Matrix3Xd jacobianTestPoints(const CameraModel& camera) {
  std::vector<Eigen::Vector3d> rays = {{0.0, 0.0, 1.0}, {1e-9, 0.0, 1.0}, {0.0, -1e-9, 1.0}, {1e-9, -1e-9, 1.0},
                                       {1e-7, 3e-8, 1.0}, {-1e-5, 2e-5, 1.0}};
  for (double off_axis_deg : {0.5, 5.0, 20.0, 40.0, 55.0, 70.0}) {
    for (int i = 0; i < 8; ++i) {
      const double off_axis = off_axis_deg * M_PI / 180.0;
      const double azimuth = 2.0 * M_PI * (i + 0.3) / 8.0;
      rays.emplace_back(std::sin(off_axis) * std::cos(azimuth), std::sin(off_axis) * std::sin(azimuth), std::cos(off_axis));
    }
  }
  Eigen::Matrix2Xd corners(2, 4);
  corners << 1.0, camera.width - 2.5, 1.0, camera.width - 2.5, 1.0, 1.0, camera.height - 2.5, camera.height - 2.5;
  auto normalized = camera.undistortToNormalized(corners);
  EXPECT_TRUE(normalized.ok()) << normalized.status().toString();
  if (normalized.ok()) {
    for (Eigen::Index i = 0; i < corners.cols(); ++i) rays.push_back(normalized->col(i).homogeneous());
  }
  Eigen::Matrix3Xd points(3, 0);
  for (const Eigen::Vector3d& ray : rays) {
    for (double range : {0.3, 2.0, 25.0}) {
      points.conservativeResize(3, points.cols() + 1);
      points.col(points.cols() - 1) = range * ray / ray.z();
    }
  }
  return points;
}

/// project(p, &J) gives project(p)'s pixel bit for bit, and J equals central differences of
/// project(p).pixel with a step of 1e-6 · |p| in each coordinate, entry by entry to `tolerance` ·
/// max |numeric entry| (the truncation error is O(step²) relative; the rounding error ≈ 1e-15 / 1e-6).
void expectAnalyticJacobianMatchesNumeric(const CameraModel& camera, double tolerance) {
  const Eigen::Matrix3Xd points = jacobianTestPoints(camera);
  ASSERT_GE(points.cols(), 150);
  double worst = 0.0;
  for (Eigen::Index i = 0; i < points.cols(); ++i) {
    const Eigen::Vector3d p = points.col(i);
    Eigen::Matrix<double, 2, 3> analytic;
    analytic.setConstant(NAN);
    const Projection with_jacobian = camera.project(p, &analytic);
    const Projection plain = camera.project(p);
    ASSERT_TRUE(plain.in_front) << p.transpose();
    EXPECT_EQ(with_jacobian.pixel.x(), plain.pixel.x()) << p.transpose();
    EXPECT_EQ(with_jacobian.pixel.y(), plain.pixel.y()) << p.transpose();
    EXPECT_EQ(with_jacobian.in_front, plain.in_front);
    EXPECT_EQ(with_jacobian.in_image, plain.in_image);
    const double step = 1e-6 * p.norm();
    Eigen::Matrix<double, 2, 3> numeric;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d h = step * Eigen::Vector3d::Unit(c);
      numeric.col(c) = (camera.project(p + h).pixel - camera.project(p - h).pixel) / (2.0 * step);
    }
    ASSERT_TRUE(analytic.allFinite()) << p.transpose() << "\n" << analytic;
    const double error = (analytic - numeric).cwiseAbs().maxCoeff() / numeric.cwiseAbs().maxCoeff();
    worst = std::max(worst, error);
    EXPECT_LT(error, tolerance) << "p_camera " << p.transpose() << "\nanalytic:\n" << analytic << "\nnumeric:\n" << numeric;
  }
  ::testing::Test::RecordProperty("worst_relative_error", std::to_string(worst));
}

CameraModel radtanWithLargeTangential() {
  CameraModel camera = ratmRadtan();
  camera.distortion << -0.28, 0.11, 0.012, -0.009, -0.023;  // k1 k2 p1 p2 k3
  return camera;
}

TEST(CameraModel, ProjectJacobianMatchesCentralDifferencesEquidistant) {
  expectAnalyticJacobianMatchesNumeric(ratmEquidistant(), 1e-8);
}

TEST(CameraModel, ProjectJacobianMatchesCentralDifferencesRadTan) {
  expectAnalyticJacobianMatchesNumeric(ratmRadtan(), 1e-8);
  expectAnalyticJacobianMatchesNumeric(radtanWithLargeTangential(), 1e-8);
}

TEST(CameraModel, ProjectJacobianOnTheOpticalAxisIsThePinholeOne) {
  // At p = (0, 0, z) every model is a pinhole to first order: ∂u/∂x = fx / z, ∂v/∂y = fy / z, the rest 0.
  for (const CameraModel& camera : {ratmEquidistant(), ratmRadtan(), radtanWithLargeTangential()}) {
    Eigen::Matrix<double, 2, 3> jacobian;
    ASSERT_TRUE(camera.project({0.0, 0.0, 2.0}, &jacobian).valid());
    Eigen::Matrix<double, 2, 3> expected;
    expected << camera.fx() / 2.0, 0.0, 0.0, 0.0, camera.fy() / 2.0, 0.0;
    EXPECT_EQ(jacobian, expected) << jacobian;
  }
}

TEST(CameraModel, ProjectJacobianIsZeroBehindTheCamera) {
  Eigen::Matrix<double, 2, 3> jacobian;
  jacobian.setConstant(7.0);
  EXPECT_FALSE(ratmEquidistant().project({0.1, 0.2, -1.0}, &jacobian).in_front);
  EXPECT_TRUE(jacobian.isZero(0.0));
  EXPECT_FALSE(ratmEquidistant().project({0.1, NAN, 1.0}, &jacobian).in_front);
  EXPECT_TRUE(jacobian.isZero(0.0));
  EXPECT_TRUE(ratmEquidistant().project({0.1, 0.2, 1.0}, nullptr).valid());
}

TEST(CameraModel, UndistortRejectsNonFinitePixels) {
  Eigen::Matrix2Xd pixels(2, 2);
  pixels << 100, NAN, 100, 100;
  EXPECT_EQ(ratmRadtan().undistortToNormalized(pixels).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace dualgraph
