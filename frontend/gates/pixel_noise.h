// SPDX-License-Identifier: MIT
// The corner detector's pixel noise, estimated online from PnP reprojection residuals (a robust scale).
#pragma once

#include <cstddef>
#include <vector>

namespace dualgraph {

/// Where the σ PnP used came from (metrics.json `pixel_sigma_source`).
enum class PixelSigmaSource {
  kConfigured,    ///< `pnp.pixel_sigma` as configured (adaptive_pixel_sigma off)
  kPrior,         ///< the prior: too few fits yet, or they read below it before min_samples
  kWidenedPrior,  ///< before min_samples, the fits so far read above the prior and widened it
  kAllFits,       ///< the median over every fit (fewer than kMinLinearSamples large-gate fits seen)
  kLargeGates,    ///< the median over the fits of large gates only
};
/// "configured", "prior", "widened_prior", "all_fits", "large_gates".
const char* pixelSigmaSourceName(PixelSigmaSource source);

/// Online estimate of σ, the standard deviation per pixel coordinate [px] of the corner detector's noise,
/// from the reprojection residuals of solved gates. A four-corner PnP fits 6 pose parameters to 8 pixel
/// coordinates, so under isotropic Gaussian noise its sum of squared residuals SSR = 4·rms² is σ²·χ²₂
/// (first order), whose median is σ²·2 ln 2. The estimate is √(median SSR / (2 ln 2)) over the newest
/// `window` solutions: the median ignores up to half of them being outliers (displaced corners, wrong
/// solutions). Until `min_samples` solutions were seen it is the prior σ, widened (never narrowed) by the
/// estimate from the solutions so far once there are three. Clamped to [min_sigma, max_sigma].
/// χ²₂ holds where the fit is nearly linear. A gate small in the image (mean side under ≈ 50 σ) has a flat or
/// two-peaked tilt likelihood, and its best fit absorbs part of the noise: σ reads 4–15 % low from sides of 10–40 σ
/// (bench/README.md, "Far gates"). So the solutions whose gate side was at least kLinearSidePerSigma current σ are
/// also kept apart (their newest `window`), and once kMinLinearSamples of them (at least `min_samples`) were seen
/// the estimate comes from those. A median of n fits spreads by ≈ 0.72/√n of σ: 7 % at 100, below the bias it
/// removes; 13 % at 30 would not be.
/// Threads: one thread at a time per instance (no locks inside); distinct instances share no mutable state and
/// may run on different threads at once. StreamingLocalizer (frontend/pipeline/) is the class for several threads.
class PixelNoiseEstimator {
 public:
  /// `prior_sigma` [px] > 0; window ≥ min_samples ≥ 1.
  explicit PixelNoiseEstimator(double prior_sigma, size_t window = 300, size_t min_samples = 30,
                               double min_sigma = 0.1, double max_sigma = 50.0);
  /// Mean image side of a gate [px], in units of σ, from which its fit counts as linear (see above).
  static constexpr double kLinearSidePerSigma = 50.0;
  /// Fits of such gates needed before they alone give σ.
  static constexpr size_t kMinLinearSamples = 100;
  /// Adds one solution's reprojection RMS [px] (sqrt of the mean squared corner distance) and its gate's mean
  /// side in the image [px] (meanSidePx; 0: unknown, counted as small); non-finite or negative values are ignored.
  void add(double reprojection_rms, double gate_side_px = 0.0);
  /// The current σ [px].
  double sigma() const { return sigma_; }
  /// Where it came from (never kConfigured).
  PixelSigmaSource source() const { return source_; }
  /// Solutions seen so far (all of them, not only the window's).
  size_t samples() const { return all_.seen; }
  /// Of those, the solutions of gates large enough for χ²₂.
  size_t linearSamples() const { return linear_.seen; }

 private:
  /// The newest `window` SSRs [px²] of one kind of solution.
  struct Ring {
    std::vector<double> ssr;
    size_t next = 0;
    size_t seen = 0;
    void add(double value, size_t window);
  };
  void update();

  double prior_;
  size_t window_;
  size_t min_samples_;
  double min_sigma_, max_sigma_;
  Ring all_;     ///< every solution
  Ring linear_;  ///< solutions whose gate side was at least kLinearSidePerSigma σ
  double sigma_;
  PixelSigmaSource source_ = PixelSigmaSource::kPrior;
  std::vector<double> scratch_;
};

}  // namespace dualgraph
