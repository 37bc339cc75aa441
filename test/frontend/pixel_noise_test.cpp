// SPDX-License-Identifier: MIT
// PixelNoiseEstimator: σ recovered from the reprojection RMS of four-corner PnP fits (SSR = σ²·χ²₂), robust
// to outliers, the prior until enough fits were seen.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dualgraph/frontend/gates/pixel_noise.h"

namespace dualgraph {
namespace {

// The reprojection RMS [px] of a fit with 2 residual degrees of freedom under noise σ: √(σ² χ²₂ / 4).
double fitRms(double sigma, std::mt19937& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const double a = unit(rng), b = unit(rng);
  return std::sqrt(sigma * sigma * (a * a + b * b) / 4.0);
}

TEST(PixelNoiseEstimator, RecoversSigmaFromHalfAPixelToFivePixels) {
  for (double sigma : {0.5, 1.0, 3.0, 5.0}) {
    std::mt19937 rng(7);
    PixelNoiseEstimator estimator(1.0);
    for (int k = 0; k < 2000; ++k) estimator.add(fitRms(sigma, rng));
    EXPECT_NEAR(estimator.sigma(), sigma, 0.08 * sigma) << sigma;  // 300 samples: the median's spread ≈ 4 %
    EXPECT_EQ(estimator.samples(), 2000u);
  }
}

TEST(PixelNoiseEstimator, AThirdOfOutliersMovesItLittle) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  PixelNoiseEstimator estimator(1.0);
  for (int k = 0; k < 2000; ++k) {
    const bool outlier = coin(rng) < 0.3;  // a displaced corner: ten times the residual
    estimator.add((outlier ? 10.0 : 1.0) * fitRms(2.0, rng));
  }
  EXPECT_GT(estimator.sigma(), 2.0);
  EXPECT_LT(estimator.sigma(), 2.0 * 1.5);
}

TEST(PixelNoiseEstimator, ThePriorUntilEnoughFitsAndInvalidValuesIgnored) {
  PixelNoiseEstimator estimator(2.5, 300, 30);
  std::mt19937 rng(5);
  for (int k = 0; k < 29; ++k) estimator.add(fitRms(1.0, rng));
  EXPECT_EQ(estimator.sigma(), 2.5);
  estimator.add(std::nan(""));
  estimator.add(-1.0);
  estimator.add(INFINITY);
  EXPECT_EQ(estimator.samples(), 29u);
  EXPECT_EQ(estimator.sigma(), 2.5);
  estimator.add(fitRms(1.0, rng));
  EXPECT_LT(estimator.sigma(), 2.0);
}

TEST(PixelNoiseEstimator, AFewNoisyFitsWidenThePriorButCleanOnesDoNotNarrowIt) {
  std::mt19937 rng(9);
  PixelNoiseEstimator noisy(1.0, 300, 30);
  noisy.add(fitRms(4.0, rng));
  noisy.add(fitRms(4.0, rng));
  EXPECT_EQ(noisy.sigma(), 1.0);  // two fits say nothing yet
  for (int k = 0; k < 5; ++k) noisy.add(fitRms(4.0, rng));
  EXPECT_GT(noisy.sigma(), 2.0);  // a 4 px detector is not refused by a 1 px gate for 30 fits
  EXPECT_LT(noisy.sigma(), 8.0);
  PixelNoiseEstimator clean(2.5, 300, 30);
  for (int k = 0; k < 10; ++k) clean.add(fitRms(0.5, rng));
  EXPECT_EQ(clean.sigma(), 2.5);  // narrowed only once min_samples fits were seen
}

TEST(PixelNoiseEstimator, FollowsAChangeWithinItsWindow) {
  std::mt19937 rng(11);
  PixelNoiseEstimator estimator(1.0, 300, 30);
  for (int k = 0; k < 1000; ++k) estimator.add(fitRms(1.0, rng));
  for (int k = 0; k < 300; ++k) estimator.add(fitRms(4.0, rng));  // the window is full of the new noise
  EXPECT_NEAR(estimator.sigma(), 4.0, 0.4);
}

// Fits of gates large in the image (side ≥ 50 σ) are kept apart: once 100 were seen they alone give σ, whatever the
// small gates' fits (which read low) say, and however old they are against the window of every fit.
TEST(PixelNoiseEstimator, FitsOfLargeGatesGiveSigmaOnceAHundredWereSeen) {
  std::mt19937 rng(13);
  PixelNoiseEstimator estimator(2.0, 300, 30);
  for (int k = 0; k < 600; ++k) estimator.add(fitRms(1.6, rng), 20.0);  // small gates: 10 σ
  EXPECT_NEAR(estimator.sigma(), 1.6, 0.15);
  for (int k = 0; k < 99; ++k) estimator.add(fitRms(2.0, rng), 200.0);  // 99 large ones: not yet
  EXPECT_EQ(estimator.linearSamples(), 99u);
  EXPECT_LT(estimator.sigma(), 1.85);
  for (int k = 0; k < 201; ++k) estimator.add(fitRms(2.0, rng), 200.0);
  for (int k = 0; k < 600; ++k) estimator.add(fitRms(1.6, rng), 20.0);  // they fill the window of every fit again
  EXPECT_NEAR(estimator.sigma(), 2.0, 0.15);
  EXPECT_EQ(estimator.samples(), 1500u);
  EXPECT_EQ(estimator.linearSamples(), 300u);
  estimator.add(fitRms(2.0, rng), 0.99 * PixelNoiseEstimator::kLinearSidePerSigma * estimator.sigma());  // small
  EXPECT_EQ(estimator.linearSamples(), 300u);
}

// Each stage of the estimate names itself: the prior, the prior widened by noisy early fits, every fit, large gates.
TEST(PixelNoiseEstimator, SaysWhereItsSigmaCameFrom) {
  std::mt19937 rng(17);
  PixelNoiseEstimator estimator(1.0, 300, 30);
  EXPECT_EQ(estimator.source(), PixelSigmaSource::kPrior);
  for (int k = 0; k < 10; ++k) estimator.add(fitRms(0.5, rng), 20.0);  // quieter than the prior: kept
  EXPECT_EQ(estimator.source(), PixelSigmaSource::kPrior);
  EXPECT_DOUBLE_EQ(estimator.sigma(), 1.0);
  for (int k = 0; k < 15; ++k) estimator.add(fitRms(3.0, rng), 20.0);  // noisier: widened
  EXPECT_EQ(estimator.source(), PixelSigmaSource::kWidenedPrior);
  EXPECT_GT(estimator.sigma(), 1.0);
  for (int k = 0; k < 400; ++k) estimator.add(fitRms(2.0, rng), 20.0);
  EXPECT_EQ(estimator.source(), PixelSigmaSource::kAllFits);
  for (int k = 0; k < 100; ++k) estimator.add(fitRms(2.0, rng), 500.0);
  EXPECT_EQ(estimator.source(), PixelSigmaSource::kLargeGates);
  EXPECT_STREQ(pixelSigmaSourceName(estimator.source()), "large_gates");
  EXPECT_STREQ(pixelSigmaSourceName(PixelSigmaSource::kConfigured), "configured");
}

}  // namespace
}  // namespace dualgraph
