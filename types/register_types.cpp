// SPDX-License-Identifier: MIT
#include "dualgraph/types/register_types.h"

#include "dualgraph/types/edge_point_xyz_prior.h"
#include "dualgraph/types/edge_se2.h"
#include "dualgraph/types/edge_se3.h"
#include "dualgraph/types/edge_se3_corner_projection.h"
#include "dualgraph/types/edge_se3_point_xyz.h"
#include "dualgraph/types/edge_se3_prior.h"
#include "dualgraph/types/parameter_se3_offset.h"
#include "dualgraph/types/vertex_point_xyz.h"
#include "dualgraph/types/vertex_se2.h"
#include "dualgraph/types/vertex_se3.h"

namespace dualgraph {

Status registerBuiltinTypes(TypeRegistry& registry) {
  DG_RETURN_IF_ERROR(registry.registerParameter<ParameterSE3Offset>(ParameterSE3Offset::kTag));
  DG_RETURN_IF_ERROR(registry.registerVertex<VertexSE3>(VertexSE3::kTag));
  DG_RETURN_IF_ERROR(registry.registerEdge<EdgeSE3>(EdgeSE3::kTag));
  DG_RETURN_IF_ERROR(registry.registerEdge<EdgeSE3Prior>(EdgeSE3Prior::kTag));
  DG_RETURN_IF_ERROR(registry.registerVertex<VertexPointXYZ>(VertexPointXYZ::kTag));
  DG_RETURN_IF_ERROR(registry.registerEdge<EdgeSE3PointXYZ>(EdgeSE3PointXYZ::kTag));
  DG_RETURN_IF_ERROR(registry.registerEdge<EdgePointXYZPrior>(EdgePointXYZPrior::kTag));
  DG_RETURN_IF_ERROR(registry.registerEdge<EdgeSE3CornerProjection>(EdgeSE3CornerProjection::kTag));
  DG_RETURN_IF_ERROR(registry.registerVertex<VertexSE2>(VertexSE2::kTag));
  DG_RETURN_IF_ERROR(registry.registerEdge<EdgeSE2>(EdgeSE2::kTag));
  return Status();
}

}  // namespace dualgraph
