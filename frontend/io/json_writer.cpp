// SPDX-License-Identifier: MIT
#include "frontend/io/json_writer.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/atomic_file.h"

namespace dualgraph {

std::string jsonEscape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof(buffer), "\\u%04x", c);
          out += buffer;
        } else {
          out += c;
        }
    }
  }
  return out;
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
