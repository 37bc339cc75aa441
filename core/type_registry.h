// SPDX-License-Identifier: MIT
// TypeRegistry: g2o tags to vertex, edge and parameter factories, and types back to their tags.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <typeindex>
#include <vector>

#include "dualgraph/core/edge.h"
#include "dualgraph/core/parameter.h"
#include "dualgraph/core/status.h"
#include "dualgraph/core/vertex.h"

namespace dualgraph {

/// Maps g2o tags (e.g. "VERTEX_SE3:QUAT") to factories for vertex, edge and parameter types, and
/// types back to their tags for writing. An explicit object, not a global: the library's types are
/// added with `registerBuiltinTypes(registry)` (types/), a user's own with `registerVertex<T>(tag)`.
class TypeRegistry {
 public:
  enum class Kind { kVertex, kEdge, kParameter };

  /// AlreadyExists when the tag or the C++ type is registered already.
  template <typename V>
  Status registerVertex(const std::string& tag) {
    Entry entry;
    entry.kind = Kind::kVertex;
    entry.make_vertex = [] { return std::unique_ptr<VertexBase>(new V()); };
    return add(tag, typeid(V), std::move(entry));
  }
  template <typename E>
  Status registerEdge(const std::string& tag) {
    Entry entry;
    entry.kind = Kind::kEdge;
    entry.make_edge = [] { return std::unique_ptr<EdgeBase>(new E()); };
    return add(tag, typeid(E), std::move(entry));
  }
  template <typename P>
  Status registerParameter(const std::string& tag) {
    Entry entry;
    entry.kind = Kind::kParameter;
    entry.make_parameter = [] { return std::unique_ptr<ParameterBase>(new P()); };
    return add(tag, typeid(P), std::move(entry));
  }

  /// nullptr when the tag is not a registered vertex tag.
  std::unique_ptr<VertexBase> createVertex(const std::string& tag) const;
  std::unique_ptr<EdgeBase> createEdge(const std::string& tag) const;
  std::unique_ptr<ParameterBase> createParameter(const std::string& tag) const;

  /// The kind of a tag, or nullptr when unknown.
  const Kind* kindOf(const std::string& tag) const;
  /// The tag of an object's dynamic type; nullptr when the type is not registered.
  const std::string* tagOf(const VertexBase& vertex) const { return tagOfType(typeid(vertex)); }
  const std::string* tagOf(const EdgeBase& edge) const { return tagOfType(typeid(edge)); }
  const std::string* tagOf(const ParameterBase& parameter) const { return tagOfType(typeid(parameter)); }

  /// All registered tags of one kind, sorted.
  std::vector<std::string> tags(Kind kind) const;

 private:
  struct Entry {
    Kind kind = Kind::kVertex;
    std::function<std::unique_ptr<VertexBase>()> make_vertex;
    std::function<std::unique_ptr<EdgeBase>()> make_edge;
    std::function<std::unique_ptr<ParameterBase>()> make_parameter;
  };
  Status add(const std::string& tag, std::type_index type, Entry entry);
  const Entry* find(const std::string& tag, Kind kind) const;
  const std::string* tagOfType(std::type_index type) const;

  std::map<std::string, Entry> by_tag_;
  std::map<std::type_index, std::string> by_type_;
};

}  // namespace dualgraph
