// SPDX-License-Identifier: MIT
// Text checks the report tests share: occurrences of a string, self-closed polylines, no NaN/inf in the page.
#pragma once

#include <regex>
#include <string>

namespace dualgraph::report_test {

inline size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

// Every <polyline ...> closes itself: the next '>' after its start is "/>".
inline bool polylinesSelfClosed(const std::string& text) {
  for (size_t at = text.find("<polyline"); at != std::string::npos; at = text.find("<polyline", at + 1)) {
    const size_t end = text.find('>', at);
    if (end == std::string::npos || text[end - 1] != '/') return false;
  }
  return true;
}

inline bool mentionsNonFinite(const std::string& text) {
  static const std::regex kToken("(^|[^a-z])(nan|inf)([^a-z]|$)", std::regex::icase);
  return std::regex_search(text, kToken);
}

}  // namespace dualgraph::report_test
