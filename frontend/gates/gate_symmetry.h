// SPDX-License-Identifier: MIT
// nearestGateSymmetry: the relabelling of a square gate's frame that brings a detected orientation nearest another.
#pragma once

#include <Eigen/Core>

namespace dualgraph {

/// Which of a square gate's symmetries nearestGateSymmetry may choose: the quarter turns about its normal (x)
/// only — the side is known — or each also with the half turn about z that swaps its front and back.
enum class GateSides { kKnown, kEither };

/// The symmetry S of a square gate (a rotation of the gate frame: a quarter turn about x, with kEither possibly
/// after the half turn about z) for which the detected gate frame relabelled, `R_detected · S`, is nearest
/// `R_reference` (the smallest angle of `R_referenceᵀ · R_detected · S`). Both orientations are of the same gate in
/// one frame (world or body, as the caller has them). A point p in the detected gate frame lies at Sᵀ · p in the
/// relabelled one. A corner detector orders the corners by the image, so a banked drone labels them a quarter turn
/// off; PnP's frame is fixed only up to these turns. On a tie the first candidate wins (sides, then quarter turns,
/// each in increasing order: the identity first). Pure function; thread-safe.
Eigen::Matrix3d nearestGateSymmetry(const Eigen::Matrix3d& R_reference, const Eigen::Matrix3d& R_detected,
                                    GateSides sides);

}  // namespace dualgraph
