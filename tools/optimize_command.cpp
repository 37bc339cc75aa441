// SPDX-License-Identifier: MIT
#include "tools/optimize_command.h"

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <vector>

#include "dualgraph/core/atomic_file.h"
#include "dualgraph/core/g2o_io.h"
#include "dualgraph/core/optimizer.h"
#include "dualgraph/solvers/chordal_init.h"
#include "dualgraph/solvers/linear_solver_factory.h"
#include "dualgraph/solvers/marginal_covariance.h"
#include "dualgraph/frontend/io/json_writer.h"
#include "dualgraph/types/register_types.h"

namespace dualgraph::tools {
namespace {

double peakRssMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is KiB on Linux
}

int fail(const std::string& message) {
  std::cerr << "dualgraph optimize: " << message << "\n";
  return 1;
}

void listTypes(const TypeRegistry& registry) {
  const std::pair<TypeRegistry::Kind, const char*> kinds[] = {
      {TypeRegistry::Kind::kVertex, "vertex"},
      {TypeRegistry::Kind::kEdge, "edge"},
      {TypeRegistry::Kind::kParameter, "parameter"}};
  for (const auto& [kind, name] : kinds) {
    for (const std::string& tag : registry.tags(kind)) std::cout << name << "\t" << tag << "\n";
  }
}

/// Every free vertex's marginal covariance (those on an edge; a free vertex on no edge has none: counted in
/// `left_out`) at the current estimate, written as `path` (atomically).
Status writeMarginalsCsv(Optimizer& optimizer, const Graph& graph, const std::string& path, int& left_out) {
  MarginalCovariance marginals;
  DG_RETURN_IF_ERROR(marginals.compute(optimizer, graph));
  std::vector<int> ids;
  left_out = 0;
  for (const auto& [id, vertex] : graph.vertices()) {
    if (vertex->fixed()) continue;
    if (optimizer.system().offsetOf(vertex.get()) < 0) {
      ++left_out;
      continue;
    }
    ids.push_back(id);
  }
  Result<std::vector<Eigen::MatrixXd>> blocks = marginals.blocks(ids);
  if (!blocks.ok()) return blocks.status();
  return writeFileAtomically(path, [&](std::ostream& out) {
    out << "# id, then the vertex's D x D marginal covariance row-major, in its tangent space "
           "(VERTEX_SE3:QUAT: g2o's [dt; dq] [m^2, 1]; VERTEX_SE2: [dx dy dtheta] [m^2, rad^2]; points: [m^2])\n";
    char number[32];
    for (size_t k = 0; k < ids.size(); ++k) {
      out << ids[k];
      const Eigen::MatrixXd& sigma = (*blocks)[k];
      for (int r = 0; r < sigma.rows(); ++r) {
        for (int c = 0; c < sigma.cols(); ++c) {
          std::snprintf(number, sizeof(number), ",%.17g", sigma(r, c));
          out << number;
        }
      }
      out << '\n';
    }
    return out ? Status() : Status(StatusCode::kIoError, path + ": write failed");
  });
}

}  // namespace

int runOptimizeCommand(const OptimizeOptions& o) {
  TypeRegistry registry;
  const Status registered = registerBuiltinTypes(registry);
  if (!registered.ok()) return fail(registered.message());
  if (o.list_types) {
    listTypes(registry);
    return 0;
  }
  if (o.input.empty()) return fail("an input file is required (or --list-types)");
  const auto linear_kind = parseLinearSolverKind(o.linear);
  if (!linear_kind.ok()) return fail(linear_kind.status().message());
  const auto init_kind = parsePoseGraphInit(o.init);
  if (!init_kind.ok()) return fail(init_kind.status().message());
  for (const std::string* path : {&o.output, &o.marginals}) {  // before the work, not after it
    if (path->empty()) continue;
    const Status writable = checkWritableFile(*path);
    if (!writable.ok()) return fail(writable.message());
  }

  const auto load_start = std::chrono::steady_clock::now();
  Graph graph;
  G2oReadOptions read_options;
  read_options.repair_information = o.repair_information;
  read_options.skip_unknown_tags = o.skip_unknown_tags;
  const auto report = readG2o(o.input, registry, graph, read_options);
  if (!report.ok()) return fail(report.status().message());
  const double load_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - load_start).count();
  for (const std::string& warning : report->warnings) std::cerr << "warning: " << warning << "\n";
  if (report->repaired_information > 0 && !o.json) {
    std::cout << "repaired " << report->repaired_information << " information matrices\n";
  }
  if (!o.robust.empty()) {
    const auto kernel = makeRobustKernel(o.robust);
    if (!kernel.ok()) return fail(kernel.status().message());
    for (const auto& edge : graph.edges()) edge->setRobustKernel(*kernel);
  }
  int gauge_id = -1;
  if (o.gauge != "none") {
    const GaugeChoice choice = o.gauge == "lowest" ? GaugeChoice::kLowestId : GaugeChoice::kHighestId;
    if (VertexBase* gauge = chooseGaugeVertex(graph, choice)) {
      gauge_id = gauge->id();
      (void)graph.setFixed(gauge_id, true);
    }
  }

  // The file's own χ² stays `initial_chi2`; the initialiser's result is `init_chi2` (issue 22).
  const double file_chi2 = graph.chi2(!o.robust.empty());
  const auto init = initializePoseGraph(graph, *init_kind, *linear_kind);
  if (!init.ok()) return fail(o.input + ": " + init.status().message() + " (--init none keeps the file's estimate)");
  const double init_chi2 = init->applied == PoseGraphInit::kNone ? file_chi2 : graph.chi2(!o.robust.empty());

  OptimizerParams params;
  params.algorithm = o.algorithm == "gn" ? Algorithm::kGaussNewton : Algorithm::kLevenbergMarquardt;
  params.max_iterations = o.iterations;
  params.damping = o.damping == "diagonal" ? LmDamping::kDiagonal : LmDamping::kIdentity;
  params.relative_decrease_stop = o.relative_decrease;
  params.time_budget_ms = o.time_budget_ms;
  if (o.verbose) {
    params.callback = [](const IterationSummary& it) {
      std::fprintf(stderr, "iteration %3d  chi2 %.10g  lambda %.3g  trials %d  %s  %.2f ms\n", it.iteration,
                   it.chi2, it.lambda, it.trials, it.step_accepted ? "accepted" : "rejected", it.iteration_ms);
    };
  }
  Optimizer optimizer(graph, makeLinearSolver(*linear_kind));
  const SolverSummary summary = optimizer.optimize(params);
  const double ms_per_iteration = summary.iterations > 0 ? summary.total_ms / summary.iterations : 0.0;
  // The marginals of the optimised graph (undamped H at the final estimate), before anything is printed or
  // written: a failure (e.g. a free gauge with --gauge none) leaves no output at all.
  double marginals_ms = 0.0;
  if (!o.marginals.empty() && summary.usable()) {
    const auto marginals_start = std::chrono::steady_clock::now();
    int left_out = 0;
    const Status written = writeMarginalsCsv(optimizer, graph, o.marginals, left_out);
    if (!written.ok()) return fail("--marginals: " + written.message());
    marginals_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - marginals_start).count();
    if (left_out > 0) {
      std::cerr << "warning: " << left_out << " free vertices on no edge have no marginal covariance (unbounded): "
                << "not in " << o.marginals << "\n";
    }
  }

  if (o.json) {
    JsonObject json;
    json.add("initial_chi2", file_chi2)
        .add("init", poseGraphInitName(init->applied))
        .add("init_chi2", init_chi2)
        .add("init_ms", init->total_ms)
        .add("final_chi2", summary.final_chi2)
        .add("iterations", summary.iterations)
        .add("termination", terminationReasonName(summary.termination))
        .add("total_ms", summary.total_ms)
        .add("ms_per_iteration", ms_per_iteration)
        .add("vertices", static_cast<long>(graph.numVertices()))
        .add("edges", static_cast<long>(graph.numEdges()))
        .add("message", summary.message)
        .add("gauge_vertex", gauge_id)
        .add("repaired_information", report->repaired_information)
        .add("linear_solver", summary.linear_solver)
        .add("load_ms", load_ms)
        .add("structure_ms", summary.structure_ms)
        .add("linearize_ms", summary.linearize_ms)
        .add("assemble_ms", summary.assemble_ms)
        .add("factorize_ms", summary.factorize_ms)
        .add("solve_ms", summary.solve_ms)
        .add("update_ms", summary.update_ms)
        .add("factorizations", summary.factorizations)
        .add("marginals_ms", marginals_ms)
        .add("peak_rss_mib", peakRssMiB());
    std::cout << json.str() << "\n";
  } else {
    std::printf("%s: %zu vertices, %zu edges (loaded in %.1f ms)%s\n", o.input.c_str(), graph.numVertices(),
                graph.numEdges(), load_ms,
                gauge_id >= 0 ? (", gauge: fixed vertex " + std::to_string(gauge_id)).c_str() : "");
    std::printf("initial chi2   %.10f\n", file_chi2);
    if (init->applied == PoseGraphInit::kChordal) {
      std::printf("init chi2      %.10f (chordal, %.1f ms)\n", init_chi2, init->total_ms);
    } else if (!init->reason.empty()) {
      std::printf("init           none: %s\n", init->reason.c_str());
    }
    std::printf("final chi2     %.10f\n", summary.final_chi2);
    std::printf("iterations     %d (%s%s%s)\n", summary.iterations, terminationReasonName(summary.termination),
                summary.message.empty() ? "" : ": ", summary.message.c_str());
    std::printf("time           %.1f ms total, %.2f ms per iteration (linearize %.1f, assemble %.1f, "
                "factorize %.1f, solve %.1f, update %.1f, structure %.1f) [%s]\n",
                summary.total_ms, ms_per_iteration, summary.linearize_ms, summary.assemble_ms,
                summary.factorize_ms, summary.solve_ms, summary.update_ms, summary.structure_ms,
                summary.linear_solver.c_str());
    if (!o.marginals.empty() && summary.usable()) {
      std::printf("marginals      %.1f ms, written to %s\n", marginals_ms, o.marginals.c_str());
    }
    std::printf("peak memory    %.1f MiB\n", peakRssMiB());
  }
  if (!summary.usable()) return fail(std::string("optimisation failed: ") + terminationReasonName(summary.termination) +
                                     (summary.message.empty() ? "" : ": " + summary.message));
  if (!o.output.empty()) {
    const Status written = writeG2o(o.output, registry, graph);
    if (!written.ok()) return fail(written.message());
  }
  return 0;
}

}  // namespace dualgraph::tools
