// SPDX-License-Identifier: MIT
#include "dualgraph/core/parameter.h"

#include <string>

namespace dualgraph {

Status ParameterContainer::add(std::unique_ptr<ParameterBase> parameter) {
  if (!parameter) return Status(StatusCode::kInvalidArgument, "null parameter");
  const int id = parameter->id();
  if (parameters_.count(id) != 0) {
    return Status(StatusCode::kAlreadyExists, "duplicate parameter id " + std::to_string(id));
  }
  parameters_.emplace(id, std::move(parameter));
  return Status();
}

ParameterBase* ParameterContainer::find(int id) const {
  const auto it = parameters_.find(id);
  return it == parameters_.end() ? nullptr : it->second.get();
}

}  // namespace dualgraph
