// SPDX-License-Identifier: MIT
#include "config.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <exception>

#include <yaml-cpp/yaml.h>

#include "config_p1.hpp"
#include "config_p2.hpp"
#include "config_p3.hpp"
#include "config_p4.hpp"
#include "nav/common/escape.hpp"
#include "nav/common/format.hpp"
#include "nav/estimator/p1_driver.hpp"

namespace nav::dut {
namespace {

std::string where(const std::string& path, const YAML::Mark& m) {
  if (m.is_null()) return path;
  return path + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
}

/// One NavdParams field by name (as estimator::ParamField for FilterParams).
struct NavdField {
  const char* name;
  double NavdParams::*member;
  const char* doc;
  double lo, hi;  ///< valid range (lo, hi] [unit of the field]
};

constexpr std::array<NavdField, 1> kNavdFields = {{
    {"modem_period_s", &NavdParams::modem_period_s,
     "time between $PNVBPOS position reports on the acoustic modem (--modem), on the AHRS "
     "timer, (0, 3600] [s]",
     0.0, 3600.0},
}};

/// The keys whose value is a name rather than a number.
constexpr const char* kNavigatorKey = "navigator";
constexpr const char* kAttitudeKey = "attitude_filter";

std::string known_keys() {
  std::string s = std::string(kNavigatorKey) + ", " + kAttitudeKey;
  for (const auto& f : estimator::param_fields()) {
    if (!s.empty()) s += ", ";
    s += f.name;
  }
  for (const auto& f : kNavdFields) s += std::string(", ") + f.name;
  for (const auto& f : p1_fields()) s += std::string(", ") + f.name;
  for (const auto& f : p2_fields()) s += std::string(", ") + f.name;
  for (const auto& f : p3_fields()) s += std::string(", ") + f.name;
  for (const auto& f : p4_fields()) s += std::string(", ") + f.name;
  for (const auto& f : p4_choice_fields()) s += std::string(", ") + f.name;
  return s;
}

const estimator::ParamField* find_field(const std::string& key) {
  for (const auto& f : estimator::param_fields()) {
    if (key == f.name) return &f;
  }
  return nullptr;
}

const NavdField* find_navd_field(const std::string& key) {
  for (const auto& f : kNavdFields) {
    if (key == f.name) return &f;
  }
  return nullptr;
}

/// Sets `navigator` or `attitude_filter` from a scalar; the error is the reason only.
Result<void> set_choice(NavdConfig& config, const std::string& key, const YAML::Node& value) {
  if (!value.IsScalar()) return fail(ErrorCode::kParse, "'" + key + "' expects a name");
  const std::string v = escape_controls(value.Scalar());
  if (key == kNavigatorKey) {
    if (v == "gps-ins") {
      config.navigator = NavigatorKind::kGpsIns;
    } else if (v == "dvl") {
      config.navigator = NavigatorKind::kDvl;
    } else if (v == "p2") {
      config.navigator = NavigatorKind::kP2;
    } else if (v == p3_method_name(P3Method::kDeadReckoning)) {
      config.navigator = NavigatorKind::kP3;
      config.p3.method = P3Method::kDeadReckoning;
    } else if (v == p3_method_name(P3Method::kEkf)) {
      config.navigator = NavigatorKind::kP3;
      config.p3.method = P3Method::kEkf;
    } else if (v == p3_method_name(P3Method::kEkfKr)) {
      config.navigator = NavigatorKind::kP3;
      config.p3.method = P3Method::kEkfKr;
    } else if (v == p4_method_name(P4Method::kUkf)) {
      config.navigator = NavigatorKind::kP4;
      config.p4.method = P4Method::kUkf;
    } else if (v == p4_method_name(P4Method::kDwtUkf)) {
      config.navigator = NavigatorKind::kP4;
      config.p4.method = P4Method::kDwtUkf;
    } else if (estimator::make_p1_navigator(v, estimator::P1Params{})) {
      config.navigator = NavigatorKind::kP1;
      config.p1_navigator = v;
    } else {
      return fail(ErrorCode::kInvalidArgument, "unknown navigator '" + v +
                                                   "' (expected gps-ins, dvl, p2, p3-dr, p3-ekf, "
                                                   "p3-ekf-kr, p4-ukf, p4-dwt-ukf or a paper P1 "
                                                   "navigator: " +
                                                   estimator::p1_navigator_names() + ")");
    }
    return {};
  }
  auto kind = estimator::parse_attitude_filter(v);
  if (!kind) return fail(kind.error().code, kind.error().detail);
  config.attitude = *kind;
  return {};
}

/// The number `value` holds, or the located error "'name' expects a number (doc)".
Result<double> number_at(const std::string& path, const std::string& name,
                         const YAML::Node& value, const char* doc) {
  try {
    if (!value.IsScalar()) throw YAML::Exception(value.Mark(), "not a scalar");
    return value.as<double>();
  } catch (const YAML::Exception&) {
    return fail(ErrorCode::kParse, where(path, value.Mark()) + ": '" + name +
                                       "' expects a number (" + doc + ")");
  }
}

/// Sets a paper's key (a P1Field of P1Params, a P2Field of P2Config) from `value`, then
/// checks its group; defaults are valid and fields independent, so a failure is this value's.
template <class Field, class Group>
Result<void> set_paper_field(const Field& f, Group& group, const std::string& path,
                             const std::string& name, const YAML::Node& value) {
  const auto v = number_at(path, name, value, f.doc);
  if (!v) return tl::unexpected(v.error());
  f.set(group, *v);
  if (auto ok = validate(group); !ok) {
    return fail(ErrorCode::kInvalidArgument,
                where(path, value.Mark()) + ": " + name + ": " + ok.error().detail);
  }
  return {};
}

}  // namespace

std::string navigator_name(const NavdConfig& config) {
  switch (config.navigator) {
    case NavigatorKind::kGpsIns: return "gps-ins";
    case NavigatorKind::kDvl: return "dvl";
    case NavigatorKind::kP1: return config.p1_navigator;
    case NavigatorKind::kP2: return "p2";
    case NavigatorKind::kP3: return p3_method_name(config.p3.method);
    case NavigatorKind::kP4: return p4_method_name(config.p4.method);
  }
  return "?";
}

Result<void> validate(const NavdParams& p) {
  for (const NavdField& f : kNavdFields) {
    const double v = p.*(f.member);
    if (!std::isfinite(v) || v <= f.lo || v > f.hi) {
      return fail(ErrorCode::kInvalidArgument, std::string(f.name) + " = " + format_g(v) +
                                                   " is outside (" + format_g(f.lo) + ", " +
                                                   format_g(f.hi) + "]");
    }
  }
  return {};
}

Result<NavdConfig> load_config(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    return fail(ErrorCode::kNotFound, "cannot read config " + path);
  } catch (const YAML::Exception& e) {
    return fail(ErrorCode::kParse, where(path, e.mark) + ": " + escape_controls(e.msg));
  }
  NavdConfig config;
  if (root.IsNull()) return config;  // an empty file keeps every default
  if (!root.IsMap()) {
    return fail(ErrorCode::kParse, where(path, root.Mark()) +
                                       ": expected a map of parameter: value");
  }
  for (const auto& kv : root) {
    const YAML::Node& key = kv.first;
    const YAML::Node& value = kv.second;
    const std::string name = key.IsScalar() ? escape_controls(key.Scalar()) : std::string("?");
    if (name == kNavigatorKey || name == kAttitudeKey) {
      if (auto ok = set_choice(config, name, value); !ok) {
        return fail(ok.error().code, where(path, value.Mark()) + ": " + ok.error().detail);
      }
      continue;
    }
    // A paper's keys: the field's setter, then its group's check (the error names the key).
    if (const P1Field* p1 = find_p1_field(name)) {
      if (auto ok = set_paper_field(*p1, config.p1, path, name, value); !ok) {
        return tl::unexpected(ok.error());
      }
      continue;
    }
    if (const P2Field* p2 = find_p2_field(name)) {
      if (auto ok = set_paper_field(*p2, config.p2, path, name, value); !ok) {
        return tl::unexpected(ok.error());
      }
      continue;
    }
    if (const P3Field* p3 = find_p3_field(name)) {
      if (auto ok = set_paper_field(*p3, config.p3, path, name, value); !ok) {
        return tl::unexpected(ok.error());
      }
      continue;
    }
    if (const P4Field* p4 = find_p4_field(name)) {
      if (auto ok = set_paper_field(*p4, config.p4, path, name, value); !ok) {
        return tl::unexpected(ok.error());
      }
      continue;
    }
    if (const P4ChoiceField* p4 = find_p4_choice_field(name)) {
      Result<void> ok = fail(ErrorCode::kParse, "expects a name (" + std::string(p4->doc) + ")");
      if (value.IsScalar()) ok = p4->set(config.p4, escape_controls(value.Scalar()));
      if (ok) ok = validate(config.p4);
      if (!ok) {
        return fail(ok.error().code, where(path, value.Mark()) + ": " + name + ": " +
                                         ok.error().detail);
      }
      continue;
    }
    const estimator::ParamField* field = find_field(name);
    const NavdField* navd_field = find_navd_field(name);
    if (field == nullptr && navd_field == nullptr) {
      return fail(ErrorCode::kParse, where(path, key.Mark()) + ": unknown key '" + name +
                                         "' (expected one of: " + known_keys() + ")");
    }
    const auto v = number_at(path, name, value, field != nullptr ? field->doc : navd_field->doc);
    if (!v) return tl::unexpected(v.error());
    if (field != nullptr) {
      config.filter.*(field->member) = *v;
    } else {
      config.navd.*(navd_field->member) = *v;
    }
    // Defaults are valid and fields are independent, so a failure here is this value's.
    auto ok = field != nullptr ? estimator::validate(config.filter) : validate(config.navd);
    if (!ok) {
      return fail(ErrorCode::kInvalidArgument, where(path, value.Mark()) + ": " +
                                                   ok.error().detail);
    }
  }
  return config;
}

std::string config_keys_help() {
  const estimator::FilterParams defaults;
  std::string s = std::string("  ") + kNavigatorKey +
                  " (default gps-ins): gps-ins (AHRS + GPS Kalman filter anchored at the first "
                  "GPS fix), dvl (DVL dead reckoning from origin_lat_deg/origin_lon_deg/"
                  "origin_depth_m, paper P0), a paper P1 navigator from that origin (" +
                  estimator::p1_navigator_names() +
                  ": strapdown INS only, or with the 15-state error EKF; the p1_* keys), or "
                  "p2 (paper P2: DVL dead reckoning from the first GPS fix, joined with the "
                  "other vehicles' over the modem and the iUSBL fixes; the p2_* keys), or p3-dr, "
                  "p3-ekf, p3-ekf-kr (paper P3: a crawler on a wall from CAN wheel encoders, "
                  "the EBIMU as trigger and a Keller depth; dead reckoning, the EKF with y and "
                  "heading, or with the kinematic x too; the p3_* keys)\n  " +
                  kAttitudeKey + " (default mahony): attitude source, one of " +
                  estimator::attitude_filter_names() +
                  " (raw/ekf/ukf/cf: paper P0's no-filtering, Euler EKF, Euler UKF and PI "
                  "complementary filter; eskf: error-state quaternion EKF with gyro bias, "
                  "hard iron (given eskf_mag_field_*_t) and a gated heading-only "
                  "magnetometer)\n";
  for (const auto& f : estimator::param_fields()) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", defaults.*(f.member));
    s += std::string("  ") + f.name + " (default " + value + "): " + f.doc + "\n";
  }
  const NavdParams navd_defaults;
  for (const auto& f : kNavdFields) {
    s += std::string("  ") + f.name + " (default " + format_g(navd_defaults.*(f.member)) +
         "): " + f.doc + "\n";
  }
  const P2Config p2_defaults;
  for (const auto& f : p2_fields()) {
    s += std::string("  ") + f.name + " (default " + format_g(f.get(p2_defaults)) + "): " +
         f.doc + "\n";
  }
  const P3Config p3_defaults;
  for (const auto& f : p3_fields()) {
    s += std::string("  ") + f.name + " (default " + format_g(f.get(p3_defaults)) + "): " +
         f.doc + "\n";
  }
  const P4Config p4_defaults;
  for (const auto& f : p4_fields()) {
    s += std::string("  ") + f.name + " (default " + format_g(f.get(p4_defaults)) + "): " +
         f.doc + "\n";
  }
  for (const auto& f : p4_choice_fields()) {
    s += std::string("  ") + f.name + " (default " + f.get(p4_defaults) + "): " + f.doc + "\n";
  }
  const estimator::P1Params p1_defaults;
  for (const auto& f : p1_fields()) {
    s += std::string("  ") + f.name + " (default " + format_g(f.get(p1_defaults)) + "): " +
         f.doc + "\n";
  }
  return s;
}

}  // namespace nav::dut
