// SPDX-License-Identifier: MIT
#include "scenario/yaml_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include "nav/common/bauds.hpp"
#include "nav/common/escape.hpp"
#include "nav/common/units.hpp"
#include "nav/reports/text.hpp"

namespace nav::bench::detail {
namespace {

/// Highest device or truth rate accepted [Hz].
constexpr double kMaxRateHz = 1000.0;

bool satisfies(double v, Bound b) {
  switch (b) {
    case Bound::kAny: return true;
    case Bound::kNonNegative: return v >= 0.0;
    case Bound::kPositive: return v > 0.0;
    case Bound::kNonZero: return v != 0.0;
  }
  return false;
}

/// "a positive duration such as '20 s'".
std::string describe_bounded(Dimension dim, Bound b) {
  const std::string plain = describe(dim);  // "a duration such as '20 s'" / "an angle ..."
  const auto noun = plain.substr(plain.find(' ') + 1);
  switch (b) {
    case Bound::kAny: return plain;
    case Bound::kNonNegative: return "a non-negative " + noun;
    case Bound::kPositive: return "a positive " + noun;
    case Bound::kNonZero: return "a non-zero " + noun;
  }
  return plain;
}

}  // namespace

std::string quote_value(std::string_view s) {
  return "'" + escape_controls(s) + "'";
}

std::string join(const std::vector<std::string>& items, std::string_view sep) {
  std::string out;
  for (const auto& s : items) {
    if (!out.empty()) out += sep;
    out += s;
  }
  return out;
}

std::string what_is(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map: return "a map";
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Scalar: return quote_value(n.Scalar());
    default: return "nothing";
  }
}

std::string location(const std::string& file, const YAML::Mark& mark) {
  return file + ":" + std::to_string(std::max(mark.line, 0) + 1) + ":" +
         std::to_string(std::max(mark.column, 0) + 1);
}

// ---------------------------------------------------------------------------------------------
// Field

YAML::Mark Field::mark() const {
  if (value_.IsNull() && key_.Mark().line >= 0) return key_.Mark();
  return value_.Mark();
}

void Field::fail(const std::string& what) const {
  throw LoadError{mark(), path_.empty() ? what : path_ + ": " + what};
}

std::string Field::text(std::string_view expected) const {
  if (!value_.IsScalar()) fail("expected " + std::string(expected) + ", got " + what_is(value_));
  return value_.Scalar();
}

double Field::quantity(Dimension dim, Bound bound) const {
  const std::string t = text(describe_bounded(dim, bound));
  const auto v = parse_quantity(t, dim);
  if (!v) fail(v.error().detail);
  if (!satisfies(*v, bound)) {
    fail("expected " + describe_bounded(dim, bound) + ", got " + quote_value(t));
  }
  return *v;
}

Duration Field::duration(Bound bound) const {
  const std::string t = text(describe_bounded(Dimension::kTime, bound));
  const auto d = parse_duration(t);
  if (!d) fail(d.error().detail);
  if (!satisfies(static_cast<double>(d->count()), bound)) {
    fail("expected " + describe_bounded(Dimension::kTime, bound) + ", got " + quote_value(t));
  }
  return *d;
}

double Field::rate() const {
  const double hz = quantity(Dimension::kFrequency, Bound::kPositive);
  if (hz > kMaxRateHz) {
    fail("expected a frequency such as '100 Hz' of at most 1000 Hz, got " +
         quote_value(value_.Scalar()));
  }
  return hz;
}

double Field::ratio() const {
  const std::string t = text("a ratio such as '2 %' or 0.02");
  const auto v = parse_ratio(t);
  if (!v) fail(v.error().detail);
  if (*v < 0.0) fail("expected a non-negative ratio such as '2 %' or 0.02, got " + quote_value(t));
  return *v;
}

double Field::signed_ratio() const {
  const std::string t = text("a ratio such as '2 %' or 0.02");
  const auto v = parse_ratio(t);
  if (!v) fail(v.error().detail);
  return *v;
}

double Field::probability() const {
  const std::string t = text("a probability from 0 to 1 such as 0.3 or '30 %'");
  const auto v = parse_ratio(t);
  if (!v || *v < 0.0 || *v > 1.0) {
    fail("expected a probability from 0 to 1 such as 0.3 or '30 %', got " + quote_value(t));
  }
  return *v;
}

bool Field::boolean() const {
  const std::string t = text("true or false");
  if (t == "true") return true;
  if (t == "false") return false;
  fail("expected true or false, got " + quote_value(t));
}

double Field::degrees(std::string_view what, double limit_deg) const {
  const std::string expected = std::string(what) +
                               " in degrees such as 36.3833 or '36.3833 deg', from " +
                               std::to_string(static_cast<int>(-limit_deg)) + " to " +
                               std::to_string(static_cast<int>(limit_deg));
  const std::string t = text(expected);
  std::optional<double> rad;
  if (const auto deg = parse_number(t)) {
    rad = units::deg_to_rad(*deg);
  } else if (const auto q = parse_quantity(t, Dimension::kAngle)) {
    rad = *q;
  }
  if (!rad || std::abs(*rad) > units::deg_to_rad(limit_deg) * (1.0 + 1e-12)) {
    fail("expected " + expected + ", got " + quote_value(t));
  }
  return *rad;
}

std::string Field::line(std::string_view expected, std::size_t max_bytes) const {
  const std::string t = text(expected);
  if (t.empty()) fail("expected " + std::string(expected) + ", got an empty text");
  if (reports::valid_utf8(t) != t) fail("expected " + std::string(expected) + ", got bytes that are not UTF-8");
  const bool control = std::any_of(t.begin(), t.end(), [](char c) {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7F;
  });
  if (control) fail("expected " + std::string(expected) + " on one line, got control characters");
  if (t.size() > max_bytes) {
    fail("expected " + std::string(expected) + " of at most " + std::to_string(max_bytes) +
         " bytes, got " + std::to_string(t.size()));
  }
  return t;
}

std::string Field::identifier() const {
  const std::string t = text("a name made of letters, digits, '_', '.' and '-'");
  const bool ok = !t.empty() && std::all_of(t.begin(), t.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-';
  });
  if (!ok) fail("expected a name made of letters, digits, '_', '.' and '-', got " + quote_value(t));
  return t;
}

std::string Field::port() const {
  const std::string expected = "'pty' or an absolute device path such as /dev/ttyUSB0";
  const std::string t = text(expected);
  if (t != "pty" && (t.size() < 2 || t.front() != '/')) {
    fail("expected " + expected + ", got " + quote_value(t));
  }
  return t;
}

int Field::baud() const {
  const auto& bauds = kSerialBauds;
  std::vector<std::string> names;
  for (const int b : bauds) names.push_back(std::to_string(b));
  const std::string expected = "a standard baud rate (" + join(names) + ")";
  const std::string t = text(expected);
  int v = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc{} || end != t.data() + t.size() ||
      std::find(bauds.begin(), bauds.end(), v) == bauds.end()) {
    fail("expected " + expected + ", got " + quote_value(t));
  }
  return v;
}

std::vector<Field> Field::list(std::string_view expected, std::size_t min_items) const {
  if (!value_.IsSequence()) fail("expected " + std::string(expected) + ", got " + what_is(value_));
  if (value_.size() < min_items) {
    fail("expected " + std::string(expected) + " with at least " + std::to_string(min_items) +
         (min_items == 1 ? " item" : " items"));
  }
  std::vector<Field> items;
  for (std::size_t i = 0; i < value_.size(); ++i) {
    items.emplace_back(YAML::Node(), value_[i], path_ + "[" + std::to_string(i) + "]");
  }
  return items;
}

std::optional<Field> Field::peek(std::string_view key) const {
  if (!value_.IsMap()) return std::nullopt;
  for (const auto& kv : value_) {
    if (kv.first.IsScalar() && kv.first.Scalar() == key) return child(kv.first, kv.second);
  }
  return std::nullopt;
}

Field Field::child(const YAML::Node& key, const YAML::Node& value) const {
  const std::string name = key.IsScalar() ? key.Scalar() : "?";
  return Field(key, value, path_.empty() ? name : path_ + "." + name);
}

// ---------------------------------------------------------------------------------------------
// MapReader

MapReader::MapReader(const Field& map, std::vector<std::string> allowed)
    : map_(map), allowed_(std::move(allowed)) {
  if (!map.node().IsMap()) {
    map.fail("expected a map with keys " + join(allowed_) + ", got " + what_is(map.node()));
  }
  std::map<std::string, int> seen;  // key -> 1-based line
  for (const auto& kv : map.node()) {
    const Field key(YAML::Node(), kv.first, map.path());
    if (!kv.first.IsScalar()) key.fail("expected a key name, got " + what_is(kv.first));
    const std::string& name = kv.first.Scalar();
    if (std::find(allowed_.begin(), allowed_.end(), name) == allowed_.end()) {
      key.fail("unknown key " + quote_value(name) + " (allowed: " + join(allowed_) + ")");
    }
    const auto [it, fresh] = seen.emplace(name, kv.first.Mark().line + 1);
    if (!fresh) {
      key.fail("duplicate key " + quote_value(name) + " (first at line " + std::to_string(it->second) +
               ")");
    }
  }
}

Field MapReader::required(std::string_view key) const {
  if (auto f = map_.peek(key)) return *f;
  map_.fail("missing required key " + quote_value(key));
}

}  // namespace nav::bench::detail
