// SPDX-License-Identifier: MIT
#include "dualgraph/solvers/chordal_init.h"

#include <cmath>
#include <memory>
#include <numeric>
#include <string>
#include <unordered_map>
#include <vector>

#include "dualgraph/core/wall_clock.h"
#include "dualgraph/solvers/chordal_systems.h"
#include "dualgraph/types/edge_se2.h"
#include "dualgraph/types/edge_se3.h"

namespace dualgraph {
namespace {

Status notAPoseGraph(const std::string& what) {
  return Status(StatusCode::kFailedPrecondition,
                "chordal initialisation needs a pose graph (only VERTEX_SE2 with EDGE_SE2, or only VERTEX_SE3:QUAT "
                "with EDGE_SE3:QUAT): " + what);
}

/// The estimates of one pose type read into and written back from a chordal::PoseProblem.
template <int D>
struct PoseTraits;

template <>
struct PoseTraits<2> {
  using Vertex = VertexSE2;
  using Edge = EdgeSE2;
  static void read(const Vertex& v, Eigen::Matrix2d& r, Eigen::Vector2d& t) {
    r = v.estimate().rotation();
    t = v.estimate().translation();
  }
  static void write(Vertex& v, const Eigen::Matrix2d& r, const Eigen::Vector2d& t) {
    v.setEstimate(SE2(t.x(), t.y(), std::atan2(r(1, 0), r(0, 0))));
  }
  static chordal::PoseProblem<2>::Edge edge(const Edge& e) {
    chordal::PoseProblem<2>::Edge out;
    out.i_R_j = e.measurement().rotation();
    out.i_t_j = e.measurement().translation();
    out.rotation_weight = e.information()(2, 2);
    out.translation_information = e.information().topLeftCorner<2, 2>();
    return out;
  }
};

template <>
struct PoseTraits<3> {
  using Vertex = VertexSE3;
  using Edge = EdgeSE3;
  static void read(const Vertex& v, Eigen::Matrix3d& r, Eigen::Vector3d& t) {
    r = v.estimate().linear();
    t = v.estimate().translation();
  }
  static void write(Vertex& v, const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = r;
    pose.translation() = t;
    v.reset(pose);
  }
  static chordal::PoseProblem<3>::Edge edge(const Edge& e) {
    chordal::PoseProblem<3>::Edge out;
    out.i_R_j = e.measurement().linear();
    out.i_t_j = e.measurement().translation();
    out.rotation_weight = e.information().bottomRightCorner<3, 3>().trace() / 3.0;  // q.vec rows
    out.translation_information = e.information().topLeftCorner<3, 3>();
    return out;
  }
};

int findRoot(std::vector<int>& parent, int k) {
  while (parent[k] != k) k = parent[k] = parent[parent[k]];
  return k;
}

/// Reads the graph (already checked to be a D-dimensional pose graph), anchors the fixed vertices and one
/// vertex per component without any, runs both steps and writes the free poses back.
template <int D>
Status runChordal(Graph& graph, LinearSolver& solver, PoseGraphInitReport& report) {
  using Traits = PoseTraits<D>;
  chordal::PoseProblem<D> problem;
  std::vector<typename Traits::Vertex*> vertices;
  std::unordered_map<const VertexBase*, int> index;
  for (const auto& [id, base] : graph.vertices()) {
    auto* vertex = static_cast<typename Traits::Vertex*>(base.get());
    index.emplace(vertex, static_cast<int>(vertices.size()));
    vertices.push_back(vertex);
    problem.world_R.emplace_back();
    problem.world_t.emplace_back();
    Traits::read(*vertex, problem.world_R.back(), problem.world_t.back());
    problem.anchored.push_back(vertex->fixed());
  }
  std::vector<int> parent(vertices.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& base : graph.edges()) {
    auto edge = Traits::edge(static_cast<const typename Traits::Edge&>(*base));
    edge.i = index.at(base->vertex(0));
    edge.j = index.at(base->vertex(1));
    parent[findRoot(parent, edge.i)] = findRoot(parent, edge.j);
    problem.edges.push_back(edge);
  }
  // Vertices are in increasing id order: the first of a component without a fixed vertex is its lowest id.
  std::vector<bool> component_anchored(vertices.size(), false);
  for (size_t k = 0; k < vertices.size(); ++k) {
    if (problem.anchored[k]) component_anchored[findRoot(parent, static_cast<int>(k))] = true;
  }
  for (size_t k = 0; k < vertices.size(); ++k) {
    const int root = findRoot(parent, static_cast<int>(k));
    if (!component_anchored[root]) problem.anchored[k] = component_anchored[root] = true;
  }
  const double start = nowMs();
  DG_RETURN_IF_ERROR(chordal::solveRotations<D>(problem, solver));
  report.rotation_ms = nowMs() - start;
  DG_RETURN_IF_ERROR(chordal::solveTranslations<D>(problem, solver));
  report.translation_ms = nowMs() - start - report.rotation_ms;
  for (size_t k = 0; k < vertices.size(); ++k) {
    if (problem.anchored[k]) {
      ++report.anchors;
      continue;
    }
    Traits::write(*vertices[k], problem.world_R[k], problem.world_t[k]);
    ++report.moved_poses;
  }
  report.dimension = D;
  return Status();
}

}  // namespace

Result<PoseGraphInit> parsePoseGraphInit(const std::string& name) {
  if (name == "auto") return PoseGraphInit::kAuto;
  if (name == "chordal") return PoseGraphInit::kChordal;
  if (name == "none") return PoseGraphInit::kNone;
  return Status(StatusCode::kInvalidArgument, "unknown initialisation '" + name + "' (expected auto, chordal or none)");
}

const char* poseGraphInitName(PoseGraphInit init) {
  switch (init) {
    case PoseGraphInit::kAuto: return "auto";
    case PoseGraphInit::kChordal: return "chordal";
    case PoseGraphInit::kNone: return "none";
  }
  return "unknown";
}

Result<int> poseGraphDimension(const Graph& graph) {
  if (graph.numEdges() == 0) return notAPoseGraph("the graph has no edges");
  int dimension = 0;
  for (const auto& [id, vertex] : graph.vertices()) {
    const int d = dynamic_cast<const VertexSE2*>(vertex.get()) != nullptr   ? 2
                  : dynamic_cast<const VertexSE3*>(vertex.get()) != nullptr ? 3
                                                                             : 0;
    if (d == 0) return notAPoseGraph("vertex " + std::to_string(id) + " is neither a VERTEX_SE2 nor a VERTEX_SE3:QUAT");
    if (dimension != 0 && d != dimension) {
      return notAPoseGraph("vertex " + std::to_string(id) + " is " + (d == 2 ? "VERTEX_SE2" : "VERTEX_SE3:QUAT") +
                           " among " + (dimension == 2 ? "VERTEX_SE2" : "VERTEX_SE3:QUAT") + " vertices");
    }
    dimension = d;
  }
  for (size_t k = 0; k < graph.edges().size(); ++k) {
    const EdgeBase* edge = graph.edges()[k].get();
    const bool pose_edge = dimension == 2 ? dynamic_cast<const EdgeSE2*>(edge) != nullptr
                                          : dynamic_cast<const EdgeSE3*>(edge) != nullptr;
    if (!pose_edge) {
      std::string ids;
      for (const VertexBase* v : edge->vertices()) ids += (ids.empty() ? "" : ", ") + std::to_string(v->id());
      return notAPoseGraph("edge " + std::to_string(k) + " (vertices " + ids + ") is not " +
                           (dimension == 2 ? "an EDGE_SE2" : "an EDGE_SE3:QUAT"));
    }
  }
  return dimension;
}

Result<PoseGraphInitReport> initializePoseGraph(Graph& graph, PoseGraphInit init, LinearSolverKind linear_solver) {
  const double start = nowMs();
  PoseGraphInitReport report;
  if (init == PoseGraphInit::kNone) return report;
  const Result<int> dimension = poseGraphDimension(graph);
  if (init == PoseGraphInit::kAuto) {
    if (!dimension.ok()) {
      report.reason = dimension.status().message();
      return report;
    }
    for (const auto& edge : graph.edges()) {
      if (edge->robustKernel() != nullptr) {
        report.reason = "the edges have a robust kernel (outliers expected; the chordal relaxation is not robust)";
        return report;
      }
    }
  } else if (!dimension.ok()) {
    return dimension.status();
  }
  const std::unique_ptr<LinearSolver> solver = makeLinearSolver(linear_solver);
  const Status solved = *dimension == 2 ? runChordal<2>(graph, *solver, report) : runChordal<3>(graph, *solver, report);
  if (!solved.ok()) {
    if (init == PoseGraphInit::kChordal) return solved;
    report = PoseGraphInitReport{};  // kAuto: the estimates are unchanged, say why
    report.reason = solved.message();
    return report;
  }
  report.applied = PoseGraphInit::kChordal;
  report.total_ms = nowMs() - start;
  return report;
}

}  // namespace dualgraph
