#pragma once
// The checked-YAML toolkit of the scene readers: values that know their key path and position in
// the file, mappings whose keys are checked (allowed, once each, with a spelling hint), and
// readers of numbers, words, vectors and lists that refuse what they cannot use with a message
// naming file, line, key and what was expected (SceneError). Used by the schema readers
// (scene_loader.cpp) and the shape readers of each family.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scene_loader.hpp"

namespace kdem::scene_yaml {

namespace fs = std::filesystem;
using KeyList = std::vector<std::string>;

// The scene being read: names the file in messages and anchors relative paths.
struct SceneSource {
  std::string display_name;
  fs::path base_dir;
};

[[noreturn]] inline void throw_at(const SceneSource& source, const YAML::Mark& mark,
                                  const std::string& key_path, const std::string& what) {
  const int line = mark.line + 1;
  const int column = mark.column + 1;
  std::string message =
      source.display_name + ":" + std::to_string(line) + ":" + std::to_string(column) + ": ";
  if (!key_path.empty())
    message += key_path + ": ";
  throw SceneError(message + what, line, column, key_path);
}

inline std::string join(const KeyList& words, const std::string& separator = ", ") {
  std::string joined;
  for (std::size_t i = 0; i < words.size(); ++i)
    joined += (i ? separator : "") + words[i];
  return joined;
}

inline std::string format_number(double number) {
  std::ostringstream text;
  text << number;
  return text.str();
}

inline std::string format_vector(const Vec3d& vector) {
  return "[" + format_number(vector[0]) + ", " + format_number(vector[1]) + ", " +
         format_number(vector[2]) + "]";
}

inline std::string quoted_scalar(const std::string& scalar) {
  constexpr std::size_t longest_shown = 60;
  if (scalar.size() <= longest_shown)
    return "\"" + scalar + "\"";
  return "\"" + scalar.substr(0, longest_shown) + "...\"";
}

inline bool all_items_scalar(const YAML::Node& sequence) {
  for (const auto& item : sequence)
    if (!item.IsScalar())
      return false;
  return true;
}

// What a value holds, as shown after "got" in messages.
inline std::string describe_found(const YAML::Node& node) {
  if (node.IsNull())
    return "an empty value";
  if (node.IsScalar())
    return quoted_scalar(node.Scalar());
  if (node.IsMap())
    return "a mapping";
  constexpr std::size_t longest_listed = 6;
  if (node.size() > longest_listed || !all_items_scalar(node))
    return "a sequence of " + std::to_string(node.size()) + " items";
  KeyList items;
  for (const auto& item : node)
    items.push_back(item.Scalar());
  return "[" + join(items) + "]";
}

// A YAML value together with where it sits: its key path and its position in the file. A
// required key that is absent is a missing Value positioned at the mapping that lacks it.
class Value {
public:
  Value(YAML::Node node, std::string path, YAML::Mark mark, const SceneSource& source)
      : node_(std::move(node)), path_(std::move(path)), mark_(mark), source_(&source) {}

  static Value missing_key(const Value& mapping, const std::string& key) {
    Value absent(YAML::Node(), mapping.child_path(key), mapping.mark_, *mapping.source_);
    absent.missing_ = true;
    return absent;
  }

  const YAML::Node& node() const { return node_; }
  const std::string& path() const { return path_; }
  const YAML::Mark& mark() const { return mark_; }
  const SceneSource& source() const { return *source_; }

  bool is_scalar() const { return !missing_ && node_.IsScalar(); }
  bool is_sequence() const { return !missing_ && node_.IsSequence(); }
  bool is_mapping() const { return !missing_ && node_.IsMap(); }

  std::string child_path(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }

  Value item(std::size_t index) const {
    const YAML::Node item_node = node_[index];
    return Value(item_node, path_ + "[" + std::to_string(index) + "]", item_node.Mark(), *source_);
  }

  std::string found() const {
    return missing_ ? "nothing (required key is missing)" : describe_found(node_);
  }

  [[noreturn]] void fail(const std::string& what) const { throw_at(*source_, mark_, path_, what); }
  [[noreturn]] void expected(const std::string& expectation, const std::string& note = "") const {
    fail("expected " + expectation + ", got " + found() + (note.empty() ? "" : " (" + note + ")"));
  }

private:
  YAML::Node node_;
  std::string path_;
  YAML::Mark mark_;
  const SceneSource* source_;
  bool missing_ = false;
};

inline std::size_t edit_distance(const std::string& from, const std::string& to) {
  std::vector<std::size_t> row(to.size() + 1);
  for (std::size_t j = 0; j <= to.size(); ++j)
    row[j] = j;
  for (std::size_t i = 1; i <= from.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= to.size(); ++j) {
      const std::size_t substitution = diagonal + (from[i - 1] == to[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitution});
    }
  }
  return row[to.size()];
}

inline std::string spelling_hint(const std::string& key, const KeyList& allowed_keys) {
  constexpr std::size_t farthest_typo = 2;
  std::string closest;
  std::size_t closest_distance = farthest_typo + 1;
  for (const auto& allowed : allowed_keys) {
    const std::size_t distance = edit_distance(key, allowed);
    if (distance < closest_distance) {
      closest = allowed;
      closest_distance = distance;
    }
  }
  return closest.empty() ? "" : "did you mean \"" + closest + "\"?";
}

// A YAML mapping whose keys have been checked: each one allowed, none twice.
class Mapping {
public:
  Mapping(const Value& value, const KeyList& allowed_keys, const std::string& context = "")
      : self_(value) {
    const std::string keys = join(allowed_keys) + (context.empty() ? "" : " " + context);
    if (!value.is_mapping())
      value.expected("a mapping with keys " + keys);
    for (const auto& entry : value.node())
      add_entry(entry.first, entry.second, allowed_keys, "one of the keys " + keys);
  }

  const Value& value() const { return self_; }
  bool has(const std::string& key) const { return entries_.count(key) != 0; }

  std::optional<Value> find(const std::string& key) const {
    const auto entry = entries_.find(key);
    if (entry == entries_.end())
      return std::nullopt;
    return Value(entry->second.value, self_.child_path(key), value_mark(entry->second),
                 self_.source());
  }

  Value get(const std::string& key) const {
    auto found = find(key);
    return found ? *found : Value::missing_key(self_, key);
  }

  YAML::Mark key_mark(const std::string& key) const { return entries_.at(key).key.Mark(); }

private:
  struct Entry {
    YAML::Node key;
    YAML::Node value;
  };

  void add_entry(const YAML::Node& key, const YAML::Node& value, const KeyList& allowed_keys,
                 const std::string& expectation) {
    const std::string name = key.IsScalar() ? key.Scalar() : "";
    const Value key_value(key, self_.child_path(name), key.Mark(), self_.source());
    const bool allowed =
        std::find(allowed_keys.begin(), allowed_keys.end(), name) != allowed_keys.end();
    if (!allowed)
      key_value.fail("expected " + expectation + ", got the key " + key_value.found() +
                     suffix(spelling_hint(name, allowed_keys)));
    const auto earlier = entries_.find(name);
    if (earlier != entries_.end())
      key_value.fail("expected each key once, got \"" + name + "\" again (first at line " +
                     std::to_string(earlier->second.key.Mark().line + 1) + ")");
    entries_.emplace(name, Entry{key, value});
  }

  static std::string suffix(const std::string& hint) {
    return hint.empty() ? "" : " (" + hint + ")";
  }

  // An empty value is positioned where the next token starts; its key's position is clearer.
  static YAML::Mark value_mark(const Entry& entry) {
    const bool empty = entry.value.IsNull() || entry.value.Mark().is_null();
    return empty ? entry.key.Mark() : entry.value.Mark();
  }

  Value self_;
  std::map<std::string, Entry> entries_;
};

// ---- scalars ----------------------------------------------------------------------------------

inline double finite_number(const Value& value, const std::string& expectation) {
  double number = 0;
  if (!value.is_scalar() || !YAML::convert<double>::decode(value.node(), number) ||
      !std::isfinite(number))
    value.expected(expectation);
  return number;
}

template <class Accept>
inline double number_where(const Value& value, const std::string& expectation, Accept accept) {
  const double number = finite_number(value, expectation);
  if (!accept(number))
    value.expected(expectation);
  return number;
}

inline bool is_positive(double number) {
  return number > 0;
}
inline bool is_non_negative(double number) {
  return number >= 0;
}

inline double positive(const Value& value, const std::string& unit) {
  return number_where(value, "a positive number in " + unit, is_positive);
}

inline double non_negative(const Value& value, const std::string& unit) {
  return number_where(value, "a number >= 0 in " + unit, is_non_negative);
}

inline double restitution(const Value& value) {
  return number_where(value, "a coefficient of restitution in (0, 1]",
                      [](double e) { return e > 0 && e <= 1; });
}

inline double friction(const Value& value) {
  return number_where(value, "a friction coefficient >= 0", is_non_negative);
}

inline double poisson_ratio(const Value& value) {
  return number_where(value, "a Poisson ratio in (-1, 0.5)",
                      [](double nu) { return nu > -1 && nu < 0.5; });
}

// A whole number >= smallest; written as an integer or as an integral number such as 1e5.
inline std::int64_t whole_number(const Value& value, std::int64_t smallest) {
  const std::string expectation = "a whole number >= " + std::to_string(smallest);
  long long whole = 0;
  if (!value.is_scalar() || !YAML::convert<long long>::decode(value.node(), whole)) {
    constexpr double largest_exact_whole = 9007199254740992.0; // 2^53
    const double number = finite_number(value, expectation);
    if (number != std::floor(number) || std::fabs(number) > largest_exact_whole)
      value.expected(expectation);
    whole = static_cast<long long>(number);
  }
  if (whole < smallest)
    value.expected(expectation);
  return whole;
}

inline bool boolean(const Value& value) {
  bool flag = false;
  if (!value.is_scalar() || !YAML::convert<bool>::decode(value.node(), flag))
    value.expected("true or false");
  return flag;
}

inline std::string text(const Value& value, const std::string& expectation) {
  if (!value.is_scalar() || value.node().Scalar().empty())
    value.expected(expectation);
  return value.node().Scalar();
}

inline std::string one_of_words(const Value& value, const KeyList& words) {
  const std::string expectation = "one of " + join(words);
  const std::string word = text(value, expectation);
  if (std::find(words.begin(), words.end(), word) == words.end())
    value.expected(expectation);
  return word;
}

// ---- vectors and lists ------------------------------------------------------------------------

inline Vec3d vector3(const Value& value, const std::string& meaning) {
  if (!value.is_sequence() || value.node().size() != 3)
    value.expected("a sequence of 3 numbers [x, y, z] " + meaning);
  Vec3d vector{};
  for (std::size_t axis = 0; axis < 3; ++axis)
    vector[axis] = finite_number(value.item(axis), "a number " + meaning);
  return vector;
}

inline Vec3d unit_direction(const Value& value) {
  Vec3d direction = vector3(value, "(a direction)");
  const double length = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] +
                                  direction[2] * direction[2]);
  if (length == 0)
    value.expected("a direction vector of non-zero length");
  for (double& component : direction)
    component /= length;
  return direction;
}

inline void require_sequence(const Value& list, const std::string& expectation, bool allow_empty) {
  if (!list.is_sequence() || (!allow_empty && list.node().size() == 0))
    list.expected(expectation);
}

template <class ReadItem>
inline void for_each_item(const Value& list, const std::string& expectation, bool allow_empty,
                          ReadItem read_item) {
  require_sequence(list, expectation, allow_empty);
  for (std::size_t index = 0; index < list.node().size(); ++index)
    read_item(list.item(index));
}

inline std::vector<double> number_list(const Value& list, const std::string& list_expectation,
                                       const std::string& item_expectation,
                                       bool (*accept)(double)) {
  std::vector<double> numbers;
  for_each_item(list, list_expectation, false, [&](const Value& item) {
    numbers.push_back(number_where(item, item_expectation, accept));
  });
  return numbers;
}

// Names seen so far in one list, to refuse a second entry of the same name.
class UniqueNames {
public:
  explicit UniqueNames(std::string list_name) : list_name_(std::move(list_name)) {}

  void add(const Value& where, const std::string& name) {
    const auto earlier = first_use_.find(name);
    if (earlier != first_use_.end())
      where.expected("a name not used by another entry of " + list_name_,
                     "already the name of " + earlier->second);
    first_use_.emplace(name, where.path() + " at line " + std::to_string(where.mark().line + 1));
  }

private:
  std::string list_name_;
  std::map<std::string, std::string> first_use_;
};

inline std::string unique_name(const Value& value, UniqueNames& names) {
  const std::string name = text(value, "a name");
  names.add(value, name);
  return name;
}

// The one key of `choices` that `map` holds; refuses none and more than one.
inline std::string exactly_one_key(const Mapping& map, const KeyList& choices) {
  KeyList present;
  for (const auto& key : choices)
    if (map.has(key))
      present.push_back(key);
  const std::string expectation = "expected exactly one of the keys " + join(choices);
  if (present.empty())
    map.value().fail(expectation + ", got none");
  if (present.size() > 1)
    throw_at(map.value().source(), map.key_mark(present[1]), map.value().path(),
             expectation + ", got " + join(present, " and "));
  return present.front();
}

} // namespace kdem::scene_yaml
