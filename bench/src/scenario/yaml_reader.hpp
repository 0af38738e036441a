// SPDX-License-Identifier: MIT
// Reading YAML fields with "file:line:col: path: what was expected" messages. Private to
// nav_bench; the scenario schema itself is in scenario.cpp.
//
// Every value is read through a Field (one YAML node plus its dotted path, e.g.
// "vehicle.devices[1].baud") and every map through a MapReader, which knows the map's allowed
// keys and rejects unknown and duplicate keys up front. A problem throws LoadError, which
// carries the node's mark; load_scenario() catches it and formats the one-line
// "file:line:col: path: what was expected" message. The exception never leaves nav_bench.
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <charconv>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "nav/common/time.hpp"
#include "scenario/quantity.hpp"

namespace nav::bench::detail {


/// A problem at a place in the file. Thrown by Field and MapReader, caught by load_scenario().
struct LoadError {
  YAML::Mark mark;
  std::string message;
};

/// "'text'" (nav::escape_controls()), for naming a value in a message.
std::string quote_value(std::string_view s);

/// The items separated by sep: "a, b, c".
std::string join(const std::vector<std::string>& items, std::string_view sep = ", ");

/// What a node is, for "got ..." in messages.
std::string what_is(const YAML::Node& n);

/// "file:line:col" of a mark (1-based line and column).
std::string location(const std::string& file, const YAML::Mark& mark);

/// Sign constraint on a number.
enum class Bound { kAny, kNonNegative, kPositive, kNonZero };

/// One YAML value and where it is.
class Field {
 public:
  Field(YAML::Node key, YAML::Node value, std::string path)
      : key_(std::move(key)), value_(std::move(value)), path_(std::move(path)) {}

  const YAML::Node& node() const { return value_; }
  const std::string& path() const { return path_; }

  /// Where to point for this value: the value itself, or its key when the value is empty
  /// (yaml-cpp marks an empty value at the next token, possibly lines below).
  YAML::Mark mark() const;

  [[noreturn]] void fail(const std::string& what) const;

  /// The scalar text; anything else fails with "expected <expected>, got a map".
  std::string text(std::string_view expected) const;

  /// A quantity in SI (quantity.hpp) satisfying a sign bound.
  double quantity(Dimension dim, Bound bound = Bound::kAny) const;

  /// A time quantity as nanoseconds.
  Duration duration(Bound bound) const;

  /// A rate in (0, 1000] [Hz].
  double rate() const;

  /// A decimal integer in [lo, hi].
  template <typename Int>
  Int integer(Int lo, Int hi) const {
    const std::string expected =
        "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
    const std::string t = text(expected);
    Int v{};
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc{} || end != t.data() + t.size() || v < lo || v > hi) {
      fail("expected " + expected + ", got " + quote_value(t));
    }
    return v;
  }

  /// A plain number or a ratio in percent ("2 %"), >= 0.
  double ratio() const;

  /// A plain number or a ratio in percent ("-0.5 %"), any sign.
  double signed_ratio() const;

  /// A probability: a plain number or a percentage in [0, 1] ("0.3", "30 %").
  double probability() const;

  /// A YAML boolean: true or false.
  bool boolean() const;

  /// An angle in [-limit_deg, limit_deg], written as plain degrees ("36.38") or as an angle
  /// quantity ("36.38 deg", "0.635 rad") [rad].
  double degrees(std::string_view what, double limit_deg) const;

  /// One line of text for reports: not empty, valid UTF-8, no control characters, at most
  /// max_bytes bytes.
  std::string line(std::string_view expected, std::size_t max_bytes) const;

  /// A name made of [A-Za-z0-9_.-], as used in run folders and "{port:NAME}".
  std::string identifier() const;

  /// One of a fixed set of words.
  template <typename T>
  T choice(const std::vector<std::pair<std::string, T>>& options) const {
    std::vector<std::string> names;
    for (const auto& [name, value] : options) names.push_back(name);
    const std::string expected = "one of " + join(names);
    const std::string t = text(expected);
    for (const auto& [name, value] : options) {
      if (name == t) return value;
    }
    fail("expected " + expected + ", got " + quote_value(t));
  }

  /// "pty" or an absolute device path.
  std::string port() const;

  /// A standard baud rate (kSerialBauds) [bit/s].
  int baud() const;

  /// The items of a list with at least min_items items.
  std::vector<Field> list(std::string_view expected, std::size_t min_items) const;

  /// The value of a key of this map, if the key is there (no check of the other keys).
  std::optional<Field> peek(std::string_view key) const;

  Field child(const YAML::Node& key, const YAML::Node& value) const;

 private:
  YAML::Node key_;
  YAML::Node value_;
  std::string path_;
};

/// The keys of one YAML map. Construction rejects a non-map, duplicate keys and keys not in
/// `allowed` (naming the allowed ones); then fields are taken with required()/optional().
class MapReader {
 public:
  MapReader(const Field& map, std::vector<std::string> allowed);

  std::optional<Field> optional(std::string_view key) const { return map_.peek(key); }

  Field required(std::string_view key) const;

  bool has(std::string_view key) const { return map_.peek(key).has_value(); }
  const Field& field() const { return map_; }

 private:
  Field map_;
  std::vector<std::string> allowed_;
};

}  // namespace nav::bench::detail
