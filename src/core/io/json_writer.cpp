#include "longterm_mapper2d/core/io/json_writer.h"

#include <cmath>
#include <cstdio>

namespace longterm_mapper2d {

std::string JsonEscape(const std::string& text) {
  std::string out = "\"";
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
  return out + "\"";
}

JsonObject& JsonObject::AddRaw(const std::string& key, std::string raw) {
  members_.push_back({key, std::move(raw), nullptr});
  return *this;
}

JsonObject& JsonObject::Add(const std::string& key, double value) {
  if (!std::isfinite(value)) return AddRaw(key, "null");
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.9g", value);
  return AddRaw(key, buffer);
}

JsonObject& JsonObject::Add(const std::string& key, std::int64_t value) {
  return AddRaw(key, std::to_string(value));
}

JsonObject& JsonObject::Add(const std::string& key, std::uint64_t value) {
  return AddRaw(key, std::to_string(value));
}

JsonObject& JsonObject::Add(const std::string& key, bool value) {
  return AddRaw(key, value ? "true" : "false");
}

JsonObject& JsonObject::Add(const std::string& key, const std::string& value) {
  return AddRaw(key, JsonEscape(value));
}

JsonObject& JsonObject::Add(const std::string& key, const JsonObject& value) {
  members_.push_back({key, "", std::make_shared<JsonObject>(value)});
  return *this;
}

JsonObject& JsonObject::Add(const std::string& key, const std::vector<std::string>& values) {
  std::string raw = "[";
  for (std::size_t i = 0; i < values.size(); ++i) raw += (i ? ", " : "") + JsonEscape(values[i]);
  return AddRaw(key, raw + "]");
}

std::string JsonObject::ToString(int indent) const {
  if (members_.empty()) return "{}";
  const std::string pad(2 * (indent + 1), ' ');
  std::string out = "{\n";
  for (std::size_t i = 0; i < members_.size(); ++i) {
    const Member& m = members_[i];
    const std::string value = m.nested ? m.nested->ToString(indent + 1) : m.raw;
    out += pad + JsonEscape(m.key) + ": " + value;
    out += i + 1 < members_.size() ? ",\n" : "\n";
  }
  return out + std::string(2 * indent, ' ') + "}";
}

}  // namespace longterm_mapper2d
