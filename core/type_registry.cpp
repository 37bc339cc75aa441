// SPDX-License-Identifier: MIT
#include "dualgraph/core/type_registry.h"

namespace dualgraph {

Status TypeRegistry::add(const std::string& tag, std::type_index type, Entry entry) {
  if (tag.empty() || tag.find_first_of(" \t\r\n#") != std::string::npos) {
    return Status(StatusCode::kInvalidArgument, "invalid tag '" + tag + "' (empty or whitespace)");
  }
  if (by_tag_.count(tag) != 0) {
    return Status(StatusCode::kAlreadyExists, "tag '" + tag + "' is already registered");
  }
  if (by_type_.count(type) != 0) {
    return Status(StatusCode::kAlreadyExists,
                  "type is already registered as '" + by_type_.at(type) + "'");
  }
  by_tag_.emplace(tag, std::move(entry));
  by_type_.emplace(type, tag);
  return Status();
}

const TypeRegistry::Entry* TypeRegistry::find(const std::string& tag, Kind kind) const {
  const auto it = by_tag_.find(tag);
  return it == by_tag_.end() || it->second.kind != kind ? nullptr : &it->second;
}

std::unique_ptr<VertexBase> TypeRegistry::createVertex(const std::string& tag) const {
  const Entry* entry = find(tag, Kind::kVertex);
  return entry ? entry->make_vertex() : nullptr;
}

std::unique_ptr<EdgeBase> TypeRegistry::createEdge(const std::string& tag) const {
  const Entry* entry = find(tag, Kind::kEdge);
  return entry ? entry->make_edge() : nullptr;
}

std::unique_ptr<ParameterBase> TypeRegistry::createParameter(const std::string& tag) const {
  const Entry* entry = find(tag, Kind::kParameter);
  return entry ? entry->make_parameter() : nullptr;
}

const TypeRegistry::Kind* TypeRegistry::kindOf(const std::string& tag) const {
  const auto it = by_tag_.find(tag);
  return it == by_tag_.end() ? nullptr : &it->second.kind;
}

const std::string* TypeRegistry::tagOfType(std::type_index type) const {
  const auto it = by_type_.find(type);
  return it == by_type_.end() ? nullptr : &it->second;
}

std::vector<std::string> TypeRegistry::tags(Kind kind) const {
  std::vector<std::string> out;
  for (const auto& [tag, entry] : by_tag_) {
    if (entry.kind == kind) out.push_back(tag);
  }
  return out;
}

}  // namespace dualgraph
