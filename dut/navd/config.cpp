// SPDX-License-Identifier: MIT
#include "config.hpp"

#include <cstdio>
#include <exception>

#include <yaml-cpp/yaml.h>

namespace nav::dut {
namespace {

std::string where(const std::string& path, const YAML::Mark& m) {
  if (m.is_null()) return path;
  return path + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
}

std::string known_keys() {
  std::string s;
  for (const auto& f : estimator::param_fields()) {
    if (!s.empty()) s += ", ";
    s += f.name;
  }
  return s;
}

const estimator::ParamField* find_field(const std::string& key) {
  for (const auto& f : estimator::param_fields()) {
    if (key == f.name) return &f;
  }
  return nullptr;
}

}  // namespace

Result<estimator::FilterParams> load_config(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    return fail(ErrorCode::kNotFound, "cannot read config " + path);
  } catch (const YAML::Exception& e) {
    return fail(ErrorCode::kParse, where(path, e.mark) + ": " + e.msg);
  }
  estimator::FilterParams params;
  if (root.IsNull()) return params;  // an empty file keeps every default
  if (!root.IsMap()) {
    return fail(ErrorCode::kParse, where(path, root.Mark()) +
                                       ": expected a map of parameter: value");
  }
  for (const auto& kv : root) {
    const YAML::Node& key = kv.first;
    const YAML::Node& value = kv.second;
    const std::string name = key.IsScalar() ? key.Scalar() : std::string("?");
    const estimator::ParamField* field = find_field(name);
    if (field == nullptr) {
      return fail(ErrorCode::kParse, where(path, key.Mark()) + ": unknown key '" + name +
                                         "' (expected one of: " + known_keys() + ")");
    }
    double v = 0.0;
    try {
      if (!value.IsScalar()) throw YAML::Exception(value.Mark(), "not a scalar");
      v = value.as<double>();
    } catch (const YAML::Exception&) {
      return fail(ErrorCode::kParse, where(path, value.Mark()) + ": '" + name +
                                         "' expects a number (" + field->doc + ")");
    }
    params.*(field->member) = v;
    // Defaults are valid and fields are independent, so a failure here is this value's.
    if (auto ok = estimator::validate(params); !ok) {
      return fail(ErrorCode::kInvalidArgument, where(path, value.Mark()) + ": " +
                                                   ok.error().detail);
    }
  }
  return params;
}

std::string config_keys_help() {
  const estimator::FilterParams defaults;
  std::string s;
  for (const auto& f : estimator::param_fields()) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", defaults.*(f.member));
    s += std::string("  ") + f.name + " (default " + value + "): " + f.doc + "\n";
  }
  return s;
}

}  // namespace nav::dut
