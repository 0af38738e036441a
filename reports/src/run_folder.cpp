// SPDX-License-Identifier: MIT
#include "nav/reports/run_folder.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string_view>

namespace nav::reports {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

/// The fields of a line between separators, into out (reused from line to line).
void split(std::string_view line, char sep, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t start = 0;
  for (;;) {
    const auto at = line.find(sep, start);
    out.push_back(line.substr(start, at - start));  // at == npos: the rest of the line
    if (at == std::string_view::npos) return;
    start = at + 1;
  }
}

/// A decimal number (from_chars: no leading '+', no spaces); NaN for an empty field.
bool parse_number(std::string_view text, double& v) {
  if (text.empty()) {
    v = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  return ec == std::errc{} && end == text.data() + text.size();
}

/// A whole file's text, or nothing when it cannot be read.
std::optional<std::string> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return std::nullopt;
  const std::streamoff size = in.tellg();
  if (size < 0) return std::nullopt;
  std::string text(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  in.read(text.data(), static_cast<std::streamsize>(size));
  text.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  if (in.bad()) return std::nullopt;
  return text;
}

/// The lines of a text, as std::getline finds them, each without its '\n' and a '\r' before it.
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const auto nl = text_.find('\n', pos_);
    const std::size_t end = nl == std::string_view::npos ? text_.size() : nl;
    line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return true;
  }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
};

Error damaged(const std::string& path, std::size_t line, const std::string& what) {
  return Error{ErrorCode::kParse, path + ":" + std::to_string(line) + ": " + what};
}

/// The last kDutLogTailBytes of a file, from a line start.
std::string tail_of(const std::string& path, bool& cut) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const auto size = static_cast<std::size_t>(std::max<std::streamoff>(in.tellg(), 0));
  cut = size > kDutLogTailBytes;
  in.seekg(static_cast<std::streamoff>(cut ? size - kDutLogTailBytes : 0));
  std::string text(std::min(size, kDutLogTailBytes), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  if (cut) {
    const auto nl = text.find('\n');
    if (nl != std::string::npos) text.erase(0, nl + 1);
  }
  return text;
}

/// What a summary.json must hold for a report: an object with a verdict and a scenario name.
std::string summary_problem(const json& j) {
  if (!j.is_object()) return "not a JSON object";
  const auto verdict = j.find("verdict");
  if (verdict == j.end() || !verdict->is_string()) return "no \"verdict\"";
  const auto sc = j.find("scenario");
  if (sc == j.end() || !sc->is_object() || !sc->contains("name") || !(*sc)["name"].is_string()) {
    return "no \"scenario\" with a \"name\"";
  }
  return {};
}

template <typename T>
Result<bool> read_optional(const fs::path& path, T read, bool& has) {
  std::error_code ec;
  has = fs::is_regular_file(path, ec);
  if (!has) return false;
  return read(path.string());
}

}  // namespace

const std::vector<double>& CsvColumns::operator[](const std::string& name) const {
  static const std::vector<double> kEmpty;
  const auto it = numbers.find(name);
  return it == numbers.end() ? kEmpty : it->second;
}

std::map<std::string, InnovationSeries> innovations_by_source(const CsvColumns& csv) {
  std::map<std::string, InnovationSeries> out;
  const auto sources = csv.texts.find("source");
  if (sources == csv.texts.end()) return out;
  const auto& src = sources->second;
  const auto& t = csv["t_s"];
  const auto& dof = csv["dof"];
  const auto& nis = csv["nis"];
  const std::size_t n = std::min({src.size(), t.size(), dof.size(), nis.size()});
  for (std::size_t k = 0; k < n; ++k) {
    if (!(dof[k] >= 1.0 && dof[k] <= 4.0)) continue;
    const int m = static_cast<int>(dof[k]);
    auto& series = out[src[k]];
    if (series.dof == 0) series.dof = m;
    if (series.dof != m) continue;  // another dimension under the same name
    series.t_s.push_back(t[k]);
    series.nis.push_back(nis[k]);
  }
  return out;
}

Result<CsvColumns> read_csv(const std::string& path, const std::vector<std::string>& text_columns) {
  const auto text = slurp(path);
  if (!text) return fail(ErrorCode::kNotFound, path + ": cannot be read");
  Lines lines(*text);
  std::string_view line;
  if (!lines.next(line)) return tl::unexpected(damaged(path, 1, "empty file, expected a header line"));
  std::vector<std::string_view> fields;
  split(line, ',', fields);
  const std::vector<std::string> names(fields.begin(), fields.end());
  CsvColumns out;
  std::vector<std::vector<double>*> num(names.size(), nullptr);
  std::vector<std::vector<std::string>*> txt(names.size(), nullptr);
  for (std::size_t c = 0; c < names.size(); ++c) {
    const bool is_text =
        std::find(text_columns.begin(), text_columns.end(), names[c]) != text_columns.end();
    if (is_text) txt[c] = &out.texts[names[c]];
    else num[c] = &out.numbers[names[c]];
  }
  std::size_t line_no = 1;
  while (lines.next(line)) {
    ++line_no;
    if (line.empty()) continue;
    split(line, ',', fields);
    if (fields.size() != names.size()) {
      return tl::unexpected(damaged(path, line_no, "expected " + std::to_string(names.size()) +
                                                       " fields, got " + std::to_string(fields.size())));
    }
    for (std::size_t c = 0; c < fields.size(); ++c) {
      if (txt[c]) {
        txt[c]->emplace_back(fields[c]);
        continue;
      }
      double v = 0.0;
      if (!parse_number(fields[c], v)) {
        return tl::unexpected(damaged(path, line_no, "column " + names[c] + ": expected a number, got '" +
                                                         std::string(fields[c].substr(0, 40)) + "'"));
      }
      num[c]->push_back(v);
    }
    ++out.rows;
  }
  return out;
}

Result<std::vector<TumPose>> read_tum(const std::string& path) {
  const auto text = slurp(path);
  if (!text) return fail(ErrorCode::kNotFound, path + ": cannot be read");
  Lines lines(*text);
  std::vector<TumPose> out;
  std::vector<std::string_view> fields;
  std::string_view line;
  std::size_t line_no = 0;
  while (lines.next(line)) {
    ++line_no;
    if (line.empty() || line.front() == '#') continue;
    split(line, ' ', fields);
    std::array<double, 8> v{};
    if (fields.size() != v.size()) {
      return tl::unexpected(damaged(path, line_no, "expected 8 numbers (t x y z qx qy qz qw), got " +
                                                       std::to_string(fields.size()) + " fields"));
    }
    for (std::size_t k = 0; k < v.size(); ++k) {
      if (!parse_number(fields[k], v[k]) || std::isnan(v[k])) {
        return tl::unexpected(damaged(path, line_no, "expected a number, got '" +
                                                         std::string(fields[k].substr(0, 40)) + "'"));
      }
    }
    out.push_back({v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]});
  }
  return out;
}

Result<RunFolder> read_run_folder(const std::string& dir) {
  RunFolder f;
  f.dir = dir;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return fail(ErrorCode::kNotFound, dir + ": not a folder");
  const fs::path root(dir);
  const std::string summary_path = (root / "summary.json").string();
  const auto text = slurp(summary_path);
  if (!text) {
    return fail(ErrorCode::kNotFound,
                dir + ": not a run folder (no summary.json) nor a campaign folder (no "
                      "campaign.json)");
  }
  f.summary = json::parse(*text, nullptr, false);
  if (f.summary.is_discarded()) {
    return fail(ErrorCode::kParse, summary_path + ": not valid JSON (damaged or cut short)");
  }
  if (const auto problem = summary_problem(f.summary); !problem.empty()) {
    return fail(ErrorCode::kParse, summary_path + ": not a navbench run summary: " + problem);
  }

  const auto csv = [](std::vector<std::string> texts, CsvColumns& into) {
    return [texts = std::move(texts), &into](const std::string& path) -> Result<bool> {
      auto t = read_csv(path, texts);
      if (!t) return tl::unexpected(t.error());
      into = std::move(*t);
      return true;
    };
  };
  for (auto r : {read_optional(root / "timeseries.csv", csv({}, f.timeseries), f.has_timeseries),
                 read_optional(root / "latency.csv", csv({}, f.latency), f.has_latency),
                 read_optional(root / "lateness.csv", csv({"device"}, f.lateness), f.has_lateness),
                 read_optional(root / "device-rates.csv", csv({"device"}, f.rates), f.has_rates),
                 read_optional(root / "innovations.csv", csv({"source"}, f.innovations),
                               f.has_innovations)}) {
    if (!r) return tl::unexpected(r.error());
  }

  // Vehicles: as summary.json lists them; an older run: the primary's truth.tum/estimate.tum.
  std::vector<std::pair<std::string, bool>> names;
  if (const auto v = f.summary.find("vehicles"); v != f.summary.end() && v->is_array()) {
    for (const auto& veh : *v) {
      if (veh.is_object() && veh.contains("name") && veh["name"].is_string()) {
        names.emplace_back(veh["name"].get<std::string>(), veh.value("primary", false));
      }
    }
  }
  if (names.empty()) names.emplace_back("", true);
  for (const auto& [name, primary] : names) {
    VehicleFiles v;
    v.name = name;
    v.primary = primary;
    // (v's copies, not the structured bindings: clang 14 cannot capture those)
    const auto file = [&](const std::string& kind) {
      const fs::path own = root / (kind + "-" + v.name + ".tum");
      return v.name.empty() || (v.primary && !fs::exists(own, ec)) ? root / (kind + ".tum")
                                                                    : own;
    };
    const auto tum = [](std::vector<TumPose>& into) {
      return [&into](const std::string& path) -> Result<bool> {
        auto t = read_tum(path);
        if (!t) return tl::unexpected(t.error());
        into = std::move(*t);
        return true;
      };
    };
    for (auto r : {read_optional(file("truth"), tum(v.truth), v.has_truth),
                   read_optional(file("estimate"), tum(v.estimate), v.has_estimate)}) {
      if (!r) return tl::unexpected(r.error());
    }
    f.vehicles.push_back(std::move(v));
  }

  const fs::path log = root / "dut.log";
  f.has_dut_log = fs::is_regular_file(log, ec);
  if (f.has_dut_log) f.dut_log_tail = tail_of(log.string(), f.dut_log_cut);
  return f;
}

}  // namespace nav::reports
