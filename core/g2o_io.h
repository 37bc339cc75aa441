// SPDX-License-Identifier: MIT
// Reading and writing g2o text files (parameters, vertices, edges, FIX), with file:line errors.
#pragma once

#include <istream>
#include <ostream>
#include <string>
#include <vector>

#include "dualgraph/core/graph.h"
#include "dualgraph/core/status.h"
#include "dualgraph/core/type_registry.h"

namespace dualgraph {

/// How strictly `readG2o` treats questionable input.
struct G2oReadOptions {
  /// Unknown tags are errors by default; when true they are skipped and listed in the report.
  bool skip_unknown_tags = false;
  /// Information matrices that are not symmetric positive definite are errors by default; when
  /// true each is replaced by the nearest positive-definite matrix (eigenvalue clamping).
  bool repair_information = false;
};

/// What `readG2o` loaded.
struct G2oReadReport {
  int vertices = 0;
  int edges = 0;
  int parameters = 0;
  int fixed = 0;
  int repaired_information = 0;      ///< edges whose Ω was repaired
  int skipped_lines = 0;             ///< lines with unknown tags (when skipping)
  std::vector<std::string> warnings; ///< one per skipped tag kind, with its first line
};

/// Reads a g2o text file into `graph`, which must be empty. Lines are `TAG id ...` (vertices,
/// parameters), `TAG id_1 .. id_n ...` (edges; vertices must be declared before use) and
/// `FIX id ...`; `#` starts a comment. Any error leaves `graph` empty and names file and line.
Result<G2oReadReport> readG2o(const std::string& path, const TypeRegistry& registry, Graph& graph,
                              const G2oReadOptions& options = {});
/// The same from a stream; `source_name` is used in messages.
Result<G2oReadReport> readG2o(std::istream& in, const std::string& source_name,
                              const TypeRegistry& registry, Graph& graph,
                              const G2oReadOptions& options = {});

/// Writes parameters, vertices (by id), edges (in order) and `FIX` lines with 17 significant
/// digits. Every type must be registered. The file is written to a temporary name beside `path`
/// and renamed, so a failed write never leaves a half-written file.
Status writeG2o(const std::string& path, const TypeRegistry& registry, const Graph& graph);
Status writeG2o(std::ostream& out, const TypeRegistry& registry, const Graph& graph);

}  // namespace dualgraph
