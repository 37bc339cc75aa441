// SPDX-License-Identifier: MIT
// ParameterBase, a constant edges share by id (e.g. a sensor offset), and a graph's ParameterContainer.
#pragma once

#include <map>
#include <memory>
#include <ostream>

#include "dualgraph/core/status.h"
#include "dualgraph/core/token_reader.h"

namespace dualgraph {

/// A constant shared by edges and stored in g2o files as its own line (`PARAMS_SE3OFFSET id ...`),
/// e.g. a sensor offset. Edges refer to parameters by id.
class ParameterBase {
 public:
  explicit ParameterBase(int id = -1) : id_(id) {}
  virtual ~ParameterBase() = default;
  int id() const { return id_; }
  void setId(int id) { id_ = id; }
  /// Reads the fields after `TAG id`.
  virtual Status read(TokenReader& in) = 0;
  /// Writes the fields after `TAG id`.
  virtual void write(std::ostream& out) const = 0;
  /// A new parameter of the same type and value, as cloneGraph copies a graph; nullptr for a type that does not
  /// implement it.
  virtual std::unique_ptr<ParameterBase> clone() const { return nullptr; }

 private:
  int id_;
};

/// The parameters of one graph, keyed by id.
class ParameterContainer {
 public:
  /// Takes ownership; error on a duplicate id or a null pointer.
  Status add(std::unique_ptr<ParameterBase> parameter);
  /// nullptr when absent.
  ParameterBase* find(int id) const;
  const std::map<int, std::unique_ptr<ParameterBase>>& all() const { return parameters_; }
  void clear() { parameters_.clear(); }

 private:
  std::map<int, std::unique_ptr<ParameterBase>> parameters_;
};

}  // namespace dualgraph
