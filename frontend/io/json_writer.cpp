// SPDX-License-Identifier: MIT
#include "dualgraph/frontend/io/json_writer.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "dualgraph/core/atomic_file.h"

namespace dualgraph {

std::string jsonEscape(const std::string& text) {
  // nlohmann-json's serialiser: control characters escaped, and bytes that are not UTF-8 (a path in Latin-1,
  // say) replaced by U+FFFD instead of written through, which made the file invalid JSON.
  const std::string quoted = nlohmann::json(text).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return quoted.substr(1, quoted.size() - 2);
}

JsonObject& JsonObject::add(const std::string& key, double value) {
  if (!std::isfinite(value)) {
    fields_.emplace_back(key, "null");
    return *this;
  }
  std::ostringstream text;
  text.precision(17);
  text << value;
  fields_.emplace_back(key, text.str());
  return *this;
}

JsonObject& JsonObject::add(const std::string& key, long value) {
  fields_.emplace_back(key, std::to_string(value));
  return *this;
}

JsonObject& JsonObject::add(const std::string& key, const std::string& value) {
  fields_.emplace_back(key, "\"" + jsonEscape(value) + "\"");
  return *this;
}

JsonObject& JsonObject::add(const std::string& key, bool value) {
  fields_.emplace_back(key, value ? "true" : "false");
  return *this;
}

JsonObject& JsonObject::add(const std::string& key, const std::vector<JsonObject>& items) {
  std::string array = "[";
  for (size_t i = 0; i < items.size(); ++i) array += (i > 0 ? ", " : "") + items[i].str();
  fields_.emplace_back(key, array + "]");
  return *this;
}

std::string JsonObject::str() const {
  std::string out = "{";
  for (size_t i = 0; i < fields_.size(); ++i) {
    if (i > 0) out += ", ";
    out += "\"" + jsonEscape(fields_[i].first) + "\": " + fields_[i].second;
  }
  return out + "}";
}

Status writeJsonFile(const std::string& path, const JsonObject& json) {
  return writeFileAtomically(path, [&json](std::ostream& out) {
    out << json.str() << "\n";
    return Status();
  });
}

}  // namespace dualgraph
