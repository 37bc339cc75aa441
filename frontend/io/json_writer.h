// SPDX-License-Identifier: MIT
// JsonObject, a flat JSON object builder, and writeJsonFile, which writes one atomically.
#pragma once

#include <string>
#include <vector>

#include "dualgraph/core/status.h"

namespace dualgraph {

/// Builds one flat JSON object, keys in insertion order; numbers with 17 significant digits,
/// non-finite numbers as null (JSON has no NaN).
class JsonObject {
 public:
  JsonObject& add(const std::string& key, double value);
  JsonObject& add(const std::string& key, long value);
  JsonObject& add(const std::string& key, int value) { return add(key, static_cast<long>(value)); }
  JsonObject& add(const std::string& key, const std::string& value);
  JsonObject& add(const std::string& key, const char* value) { return add(key, std::string(value)); }
  JsonObject& add(const std::string& key, bool value);
  /// An array of objects (e.g. one per lap).
  JsonObject& add(const std::string& key, const std::vector<JsonObject>& items);
  std::string str() const;

 private:
  std::vector<std::pair<std::string, std::string>> fields_;
};

/// Escapes a string for a JSON string literal (without the quotes), through nlohmann-json: control characters
/// escaped, bytes that are not UTF-8 replaced by U+FFFD (so the output is always valid JSON).
std::string jsonEscape(const std::string& text);

/// Writes `json.str()` and a newline to `path` atomically (core/atomic_file.h: temporary + rename,
/// so a failure never leaves a half-written file); kIoError naming the path otherwise.
Status writeJsonFile(const std::string& path, const JsonObject& json);

}  // namespace dualgraph
