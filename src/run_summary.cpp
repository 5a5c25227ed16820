#include "run_summary.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "atomic_file.hpp"

namespace kdem {

namespace {

std::string escaped_control_character(unsigned char c) {
  switch (c) {
  case '\b':
    return "\\b";
  case '\f':
    return "\\f";
  case '\n':
    return "\\n";
  case '\r':
    return "\\r";
  case '\t':
    return "\\t";
  default: {
    char buffer[8];
    std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(c));
    return buffer;
  }
  }
}

// Builds `"key": value` lines of one JSON object at a given indentation.
class JsonObjectText {
public:
  explicit JsonObjectText(std::string indent) : indent_(std::move(indent)) {}
  void add_raw(const std::string& key, const std::string& value_text) {
    text_ += (text_.empty() ? "" : ",\n") + indent_ + "  " + json_string(key) + ": " + value_text;
  }
  void add(const std::string& key, const std::string& value) { add_raw(key, json_string(value)); }
  void add(const std::string& key, std::int64_t value) { add_raw(key, std::to_string(value)); }
  void add(const std::string& key, double value) { add_raw(key, json_number(value)); }
  std::string str() const { return text_.empty() ? "{}" : "{\n" + text_ + "\n" + indent_ + "}"; }

private:
  std::string indent_;
  std::string text_;
};

} // namespace

std::string json_string(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += c;
    } else if (byte < 0x20) {
      quoted += escaped_control_character(byte);
    } else {
      quoted += c; // UTF-8 sequences pass through unchanged
    }
  }
  return quoted + "\"";
}

std::string json_number(double value) {
  if (!std::isfinite(value)) {
    return "null";
  }
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string to_json(const RunSummary& summary) {
  JsonObjectText extra("  ");
  for (const auto& [name, value] : summary.extra) {
    extra.add(name, value);
  }
  JsonObjectText object("");
  object.add("version", summary.version);
  object.add("git_hash", summary.git_hash);
  object.add("backend", summary.backend);
  object.add("threads", std::int64_t{summary.threads});
  object.add("particles", summary.particles);
  object.add("steps", summary.steps);
  object.add("contacts", summary.contacts);
  object.add("narrow_phase_failures", summary.narrow_phase_failures);
  object.add("wall_seconds", summary.wall_seconds);
  object.add("particle_steps_per_second", summary.particle_steps_per_second);
  object.add("largest_overlap_ratio", summary.largest_overlap_ratio);
  object.add("simulated_time", summary.simulated_time);
  object.add("discharged_mass", summary.discharged_mass);
  object.add("energy_drift", summary.energy_drift);
  object.add_raw("extra", extra.str());
  return object.str() + "\n";
}

void write_run_json(const std::filesystem::path& path, const RunSummary& summary) {
  write_text_atomically(path, to_json(summary));
}

} // namespace kdem
