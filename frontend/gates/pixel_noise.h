// SPDX-License-Identifier: MIT
// The corner detector's pixel noise, estimated online from PnP reprojection residuals (a robust scale).
#pragma once

#include <cstddef>
#include <vector>

namespace dualgraph {

/// Online estimate of σ, the standard deviation per pixel coordinate [px] of the corner detector's noise,
/// from the reprojection residuals of solved gates. A four-corner PnP fits 6 pose parameters to 8 pixel
/// coordinates, so under isotropic Gaussian noise its sum of squared residuals SSR = 4·rms² is σ²·χ²₂
/// (first order), whose median is σ²·2 ln 2. The estimate is √(median SSR / (2 ln 2)) over the newest
/// `window` solutions: the median ignores up to half of them being outliers (displaced corners, wrong
/// solutions). Until `min_samples` solutions were seen it is the prior σ, widened (never narrowed) by the
/// estimate from the solutions so far once there are three. Clamped to [min_sigma, max_sigma].
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class PixelNoiseEstimator {
 public:
  /// `prior_sigma` [px] > 0; window ≥ min_samples ≥ 1.
  explicit PixelNoiseEstimator(double prior_sigma, size_t window = 300, size_t min_samples = 30,
                               double min_sigma = 0.1, double max_sigma = 50.0);
  /// Adds one solution's reprojection RMS [px] (sqrt of the mean squared corner distance); non-finite or
  /// negative values are ignored.
  void add(double reprojection_rms);
  /// The current σ [px].
  double sigma() const { return sigma_; }
  /// Solutions seen so far (all of them, not only the window's).
  size_t samples() const { return seen_; }

 private:
  void update();

  double prior_;
  size_t window_;
  size_t min_samples_;
  double min_sigma_, max_sigma_;
  std::vector<double> ssr_;  ///< ring buffer of the newest SSRs [px²]
  size_t next_ = 0;
  size_t seen_ = 0;
  double sigma_;
  std::vector<double> scratch_;
};

}  // namespace dualgraph
