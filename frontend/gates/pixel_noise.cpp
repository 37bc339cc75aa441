// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/gates/pixel_noise.h"

#include <algorithm>
#include <cmath>

namespace dualgraph {

const char* pixelSigmaSourceName(PixelSigmaSource source) {
  switch (source) {
    case PixelSigmaSource::kConfigured: return "configured";
    case PixelSigmaSource::kPrior: return "prior";
    case PixelSigmaSource::kWidenedPrior: return "widened_prior";
    case PixelSigmaSource::kAllFits: return "all_fits";
    case PixelSigmaSource::kLargeGates: return "large_gates";
  }
  return "unknown";
}

PixelNoiseEstimator::PixelNoiseEstimator(double prior_sigma, size_t window, size_t min_samples, double min_sigma,
                                         double max_sigma)
    : prior_(prior_sigma), window_(std::max<size_t>(window, 1)), min_samples_(std::max<size_t>(min_samples, 1)),
      min_sigma_(min_sigma), max_sigma_(max_sigma), sigma_(prior_sigma) {
  all_.ssr.reserve(window_);
  scratch_.reserve(window_);
}

void PixelNoiseEstimator::Ring::add(double value, size_t window) {
  if (ssr.size() < window) {
    ssr.push_back(value);
  } else {
    ssr[next] = value;
  }
  next = (next + 1) % window;
  ++seen;
}

void PixelNoiseEstimator::add(double reprojection_rms, double gate_side_px) {
  if (!std::isfinite(reprojection_rms) || reprojection_rms < 0.0) return;
  const double ssr = 4.0 * reprojection_rms * reprojection_rms;
  all_.add(ssr, window_);
  if (std::isfinite(gate_side_px) && gate_side_px >= kLinearSidePerSigma * sigma_) linear_.add(ssr, window_);
  update();
}

void PixelNoiseEstimator::update() {
  constexpr size_t kFirstSamples = 3;  // the median of three ignores one outlier
  if (all_.seen < std::min(kFirstSamples, min_samples_)) {
    sigma_ = prior_;
    source_ = PixelSigmaSource::kPrior;
    return;
  }
  const bool large_gates = linear_.seen >= std::max(kMinLinearSamples, min_samples_);
  const Ring& ring = large_gates ? linear_ : all_;
  scratch_.assign(ring.ssr.begin(), ring.ssr.end());
  const auto middle = scratch_.begin() + static_cast<std::ptrdiff_t>(scratch_.size() / 2);
  std::nth_element(scratch_.begin(), middle, scratch_.end());
  const double median = *middle;
  constexpr double kChi2TwoMedian = 1.3862943611198906;  // 2 ln 2
  const double estimate = std::clamp(std::sqrt(median / kChi2TwoMedian), min_sigma_, max_sigma_);
  // Before min_samples the few fits only widen the prior: a detector noisier than assumed is not refused
  // until enough of its fits were seen (at the start of a flight, where the frame search needs them).
  if (all_.seen >= min_samples_) {
    sigma_ = estimate;
    source_ = large_gates ? PixelSigmaSource::kLargeGates : PixelSigmaSource::kAllFits;
  } else {
    sigma_ = std::max(prior_, estimate);
    source_ = estimate > prior_ ? PixelSigmaSource::kWidenedPrior : PixelSigmaSource::kPrior;
  }
}

}  // namespace dualgraph
