// SPDX-License-Identifier: MIT
#include "aiding_input.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <type_traits>
#include <utility>

namespace nav::dut {
namespace {

namespace nq1 = protocols::navquest_nq1;
namespace pd0 = protocols::rdi_pd0;
namespace pd6 = protocols::rdi_pd6;
namespace a50 = protocols::waterlinked_a50;
namespace ebimu = protocols::ebimu;
namespace evo = protocols::evologics;
namespace nmea = protocols::nmea;
namespace keller = protocols::keller;
namespace beacon = protocols::beacon_ins;

struct ProtocolEntry {
  InputProtocol protocol;
  std::string_view name;
};

constexpr std::array<ProtocolEntry, 9> kProtocols = {{
    {InputProtocol::kNq1, "nq1"},
    {InputProtocol::kPd0, "pd0"},
    {InputProtocol::kPd6, "pd6"},
    {InputProtocol::kA50, "a50"},
    {InputProtocol::kEbimu, "ebimu"},
    {InputProtocol::kUsbl, "usbl"},
    {InputProtocol::kNmea, "nmea"},
    {InputProtocol::kKeller, "keller"},
    {InputProtocol::kBeaconIns, "beacon-ins"},
}};

constexpr std::size_t kMaxNameLength = 32;

bool name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

/// Evologics notifications start with '+' (data mode) or an upper-case letter (command mode).
bool usbl_sync(std::uint8_t b) { return b == '+' || (b >= 'A' && b <= 'Z'); }

/// A Keller frame has no sync byte; it starts with a bus address (0..250), so only bytes
/// above 250 count as skipped while hunting.
bool keller_sync(std::uint8_t b) { return b <= keller::kMaxAddress; }

tl::unexpected<Error> spec_error(std::string_view text, const std::string& why) {
  return fail(ErrorCode::kInvalidArgument,
              "--input '" + std::string(text) + "': " + why +
                  " (expected NAME=PROTOCOL:PATH[@BAUD], PROTOCOL one of " + protocol_names() +
                  ")");
}

std::string track_prefix(pd6::Track t) { return t == pd6::Track::kBottom ? "B" : "W"; }

}  // namespace

std::string_view protocol_name(InputProtocol p) {
  for (const auto& e : kProtocols) {
    if (e.protocol == p) return e.name;
  }
  return "?";
}

std::string protocol_names() {
  std::string s;
  for (const auto& e : kProtocols) {
    if (!s.empty()) s += ", ";
    s += e.name;
  }
  return s;
}

int default_baud(InputProtocol p) {
  return p == InputProtocol::kNmea || p == InputProtocol::kKeller ? 9600 : 115200;
}

Result<InputSpec> parse_input_spec(std::string_view text, const std::vector<int>& bauds) {
  const auto eq = text.find('=');
  if (eq == std::string_view::npos) return spec_error(text, "no '=' after NAME");
  const std::string_view name = text.substr(0, eq);
  if (name.empty()) return spec_error(text, "empty NAME");
  if (name.size() > kMaxNameLength) {
    return spec_error(text, "NAME longer than " + std::to_string(kMaxNameLength) + " characters");
  }
  if (!std::all_of(name.begin(), name.end(), name_char)) {
    return spec_error(text, "NAME '" + std::string(name) + "' has a character outside [a-z0-9_-]");
  }
  if (name == "ahrs" || name == "gps" || name == "output") {
    return spec_error(text, "NAME '" + std::string(name) + "' is reserved");
  }
  const std::string_view rest = text.substr(eq + 1);
  const auto colon = rest.find(':');
  if (colon == std::string_view::npos) return spec_error(text, "no ':' after PROTOCOL");
  const std::string_view proto = rest.substr(0, colon);
  const auto* entry = std::find_if(kProtocols.begin(), kProtocols.end(),
                                   [proto](const ProtocolEntry& e) { return e.name == proto; });
  if (entry == kProtocols.end()) {
    return spec_error(text, "unknown PROTOCOL '" + std::string(proto) + "'");
  }
  InputSpec spec;
  spec.name = std::string(name);
  spec.protocol = entry->protocol;
  auto port = parse_path_baud(rest.substr(colon + 1), bauds, default_baud(spec.protocol));
  if (!port) return spec_error(text, port.error().detail);
  spec.path = std::move(port->path);
  spec.baud = port->baud;
  return spec;
}

Result<PortAddress> parse_path_baud(std::string_view text, const std::vector<int>& bauds,
                                    int default_baud) {
  PortAddress port{std::string(), default_baud};
  std::string_view path = text;
  if (const auto at = text.rfind('@'); at != std::string_view::npos) {
    const std::string_view baud_text = text.substr(at + 1);
    int baud = 0;
    const auto [end, ec] =
        std::from_chars(baud_text.data(), baud_text.data() + baud_text.size(), baud);
    if (baud_text.empty() || ec != std::errc() || end != baud_text.data() + baud_text.size()) {
      return fail(ErrorCode::kInvalidArgument,
                  "BAUD '" + std::string(baud_text) + "' is not a number");
    }
    if (std::find(bauds.begin(), bauds.end(), baud) == bauds.end()) {
      return fail(ErrorCode::kInvalidArgument, "unsupported BAUD " + std::to_string(baud));
    }
    port.baud = baud;
    path = text.substr(0, at);
  }
  if (path.empty()) return fail(ErrorCode::kInvalidArgument, "empty PATH");
  port.path = std::string(path);
  return port;
}

Result<std::vector<InputSpec>> parse_input_specs(const std::vector<std::string>& texts,
                                                 const std::vector<int>& bauds) {
  std::vector<InputSpec> out;
  for (const auto& t : texts) {
    auto spec = parse_input_spec(t, bauds);
    if (!spec) return tl::unexpected(spec.error());
    for (const auto& prev : out) {
      if (prev.name == spec->name) {
        return spec_error(t, "NAME '" + spec->name + "' is already used by '" + to_string(prev) +
                                 "'");
      }
    }
    out.push_back(std::move(*spec));
  }
  return out;
}

std::string to_string(const InputSpec& spec) {
  return spec.name + "=" + std::string(protocol_name(spec.protocol)) + ":" + spec.path + "@" +
         std::to_string(spec.baud);
}

AidingInput::Decoder AidingInput::make_decoder(InputProtocol protocol, std::size_t max_buffer) {
  switch (protocol) {
    case InputProtocol::kNq1:
      return StreamDecoder<nq1::Nq1>(&nq1::parse, '$', max_buffer);
    case InputProtocol::kPd0:
      return StreamDecoder<pd0::Ensemble>(&pd0::parse, pd0::kHeaderId,
                                          std::max(max_buffer, kPd0BufferBytes));
    case InputProtocol::kPd6:
      return StreamDecoder<pd6::Line>(&pd6::parse, ':', max_buffer);
    case InputProtocol::kA50:
      return StreamDecoder<a50::Packet>(&a50::parse, 'w', max_buffer);
    case InputProtocol::kEbimu:
      return StreamDecoder<ebimu::Line>(&ebimu::parse, ebimu::kStartOfLine, max_buffer);
    case InputProtocol::kUsbl:
      return StreamDecoder<evo::Notification>(&evo::parse, &usbl_sync, max_buffer);
    case InputProtocol::kKeller:
      return StreamDecoder<keller::Response>(&keller::parse_response, &keller_sync, max_buffer);
    case InputProtocol::kBeaconIns:
      return StreamDecoder<beacon::Sample>(&beacon::parse, beacon::kSync1, max_buffer);
    case InputProtocol::kNmea:
      break;
  }
  return StreamDecoder<nmea::Sentence>(&nmea::parse, '$', max_buffer);
}

AidingInput::AidingInput(std::string name, InputProtocol protocol, std::size_t max_buffer)
    : name_(std::move(name)), protocol_(protocol), decoder_(make_decoder(protocol, max_buffer)) {}

void AidingInput::feed(protocols::ByteSpan bytes) {
  if (protocol_ == InputProtocol::kEbimu) {
    // A line decodes when its LF is fed: feeding up to each LF names every line decoded by
    // that piece with the LFs counted before it (the line's ordinal).
    auto& decoder = std::get<StreamDecoder<ebimu::Line>>(decoder_);
    std::vector<ebimu::Line> lines;
    while (!bytes.empty()) {
      const auto lf = std::find(bytes.begin(), bytes.end(), std::uint8_t{'\n'});
      const bool whole = lf != bytes.end();
      const std::size_t n =
          whole ? static_cast<std::size_t>(lf - bytes.begin()) + 1 : bytes.size();
      lines.clear();
      decoder.feed(bytes.first(n), lines);
      for (const auto& m : lines) {
        on_message(m);
        ebimu_lines_.push_back({line_feeds_, m});
      }
      if (whole) ++line_feeds_;
      bytes = bytes.subspan(n);
    }
    return;
  }
  std::visit(
      [&](auto& decoder) {
        using D = std::decay_t<decltype(decoder)>;
        std::vector<typename D::MessageType> msgs;
        decoder.feed(bytes, msgs);
        for (const auto& m : msgs) on_message(m);
      },
      decoder_);
}

std::vector<beacon::Sample> AidingInput::take_beacon_frames() {
  std::vector<beacon::Sample> out;
  out.swap(beacon_frames_);
  return out;
}

void AidingInput::on_message(const beacon::Sample& m) {
  count("frame");
  beacon_frames_.push_back(m);
  last_ = m;
}

std::vector<AidingInput::EbimuLine> AidingInput::take_ebimu_lines() {
  std::vector<EbimuLine> out;
  out.swap(ebimu_lines_);
  return out;
}

bool AidingInput::is_dvl() const {
  switch (protocol_) {
    case InputProtocol::kNq1:
    case InputProtocol::kPd0:
    case InputProtocol::kPd6:
    case InputProtocol::kA50: return true;
    default: return false;
  }
}

std::uint64_t AidingInput::messages() const {
  std::uint64_t n = 0;
  for (const auto& [type, count] : by_type_) n += count;
  return n;
}

InputRejects AidingInput::rejects() const {
  InputRejects r;
  r.stream = std::visit([](const auto& d) { return d.rejects(); }, decoder_);
  r.fields = field_errors_;
  return r;
}

std::size_t AidingInput::buffered() const {
  return std::visit([](const auto& d) { return d.buffered(); }, decoder_);
}

std::vector<keller::Response> AidingInput::take_keller_answers() {
  std::vector<keller::Response> out;
  out.swap(keller_answers_);
  return out;
}

std::string AidingInput::counters_text() const {
  std::string s = "messages=" + std::to_string(messages()) + "{";
  bool first = true;
  for (const auto& [type, n] : by_type_) {
    if (!first) s += ' ';
    first = false;
    s += type + "=" + std::to_string(n);
  }
  const auto r = rejects();
  s += "}";
  if (unpaired_relative_ > 0) s += " unpaired_nvbrelatt=" + std::to_string(unpaired_relative_);
  s += " rejects{checksum=" + std::to_string(r.stream.checksum) +
       " framing=" + std::to_string(r.stream.framing) +
       " sync_bytes=" + std::to_string(r.stream.sync_bytes) +
       " overflow_bytes=" + std::to_string(r.stream.overflow_bytes) +
       " fields=" + std::to_string(r.fields) + "}";
  return s;
}

void AidingInput::on_message(const nq1::Nq1& m) {
  count("res");
  if (auto v = nq1::vehicle_velocity_mps(m)) set_velocity(*v);
  last_ = m;
}

void AidingInput::on_message(const pd0::Ensemble& m) {
  count("ensemble");
  if (m.bottom_track) {
    if (auto v = pd0::vehicle_velocity_mps(*m.bottom_track)) set_velocity(*v);
  }
  last_ = m;
}

void AidingInput::on_message(const pd6::Line& m) {
  std::visit(
      [this](const auto& line) {
        using L = std::decay_t<decltype(line)>;
        if constexpr (std::is_same_v<L, pd6::Attitude>) {
          count("SA");
        } else if constexpr (std::is_same_v<L, pd6::TimeAndScaling>) {
          count("TS");
        } else if constexpr (std::is_same_v<L, pd6::InstrumentVelocity>) {
          count(track_prefix(line.track) + "I");
          const auto x = pd6::to_mps(line.xyze_mmps[0]);
          const auto y = pd6::to_mps(line.xyze_mmps[1]);
          const auto z = pd6::to_mps(line.xyze_mmps[2]);
          if (line.track == pd6::Track::kBottom && line.valid && x && y && z) {
            set_velocity({*x, *y, *z});
          }
        } else if constexpr (std::is_same_v<L, pd6::ShipVelocity>) {
          count(track_prefix(line.track) + "S");
        } else if constexpr (std::is_same_v<L, pd6::EarthVelocity>) {
          count(track_prefix(line.track) + "E");
        } else {
          count(track_prefix(line.track) + "D");
        }
      },
      m);
  last_ = m;
}

void AidingInput::on_message(const a50::Packet& m) {
  if (m.direction != 'r') {
    count("other");  // a command echoed on the line: not a report
    last_ = m;
    return;
  }
  bool ok = true;
  switch (m.command) {
    case 'z':
      if (auto v = a50::decode_velocity(m)) {
        count("wrz");
        if (v->valid) set_velocity({v->vx_mps, v->vy_mps, v->vz_mps});
      } else {
        ok = false;
      }
      break;
    case 'u':
      ok = a50::decode_transducer(m).has_value();
      if (ok) count("wru");
      break;
    case 'p':
      ok = a50::decode_position(m).has_value();
      if (ok) count("wrp");
      break;
    case 'x':
      if (auto v = a50::decode_legacy_velocity(m)) {
        count("wrx");
        if (v->valid) set_velocity({v->vx_mps, v->vy_mps, v->vz_mps});
      } else {
        ok = false;
      }
      break;
    case 't':
      ok = a50::decode_legacy_transducer(m).has_value();
      if (ok) count("wrt");
      break;
    default:
      count("other");  // command replies (wra, wrn, wrv, ...)
      break;
  }
  if (!ok) {
    ++field_errors_;
    return;
  }
  last_ = m;
}

void AidingInput::on_message(const ebimu::Line& m) {
  count("line");
  last_ = m;
}

void AidingInput::on_message(const evo::Notification& m) {
  count(std::string(evo::header_of(m.fix)));
  last_ = m;
  if (const auto* l = std::get_if<evo::UsblLong>(&m.fix)) {
    last_long_ = *l;
  } else if (const auto* a = std::get_if<evo::RelativeAttitude>(&m.fix)) {
    if (last_long_ && last_long_->measurement_time_s == a->measurement_time_s &&
        last_long_->remote_address == a->remote_address) {
      relative_fixes_.push_back({*last_long_, *a});
    } else {
      ++unpaired_relative_;
    }
    last_long_.reset();
  } else {
    last_long_.reset();
  }
}

std::vector<AidingInput::RelativeFix> AidingInput::take_relative_fixes() {
  std::vector<RelativeFix> out;
  out.swap(relative_fixes_);
  return out;
}

void AidingInput::on_message(const nmea::Sentence& m) {
  bool ok = true;
  if (m.type == "GGA") {
    ok = nmea::decode_gga(m).has_value();
  } else if (m.type == "RMC") {
    ok = nmea::decode_rmc(m).has_value();
  } else if (m.type == "VTG") {
    ok = nmea::decode_vtg(m).has_value();
  } else if (m.type == "HDT") {
    ok = nmea::decode_hdt(m).has_value();
  } else if (m.type == "ZDA") {
    ok = nmea::decode_zda(m).has_value();
  } else {
    count("other");
    last_ = m;
    return;
  }
  if (!ok) {
    ++field_errors_;
    return;
  }
  count(m.type);
  last_ = m;
}

void AidingInput::on_message(const keller::Response& m) {
  std::visit(
      [this](const auto& body) {
        using T = std::decay_t<decltype(body)>;
        if constexpr (std::is_same_v<T, keller::InitInfo>) {
          count("F48");
        } else if constexpr (std::is_same_v<T, keller::SerialNumber>) {
          count("F69");
        } else if constexpr (std::is_same_v<T, keller::ChannelValue>) {
          count("F73");
        } else if constexpr (std::is_same_v<T, keller::ZeroAck>) {
          count("F95");
        } else {
          count("exception");
        }
      },
      m.body);
  keller_answers_.push_back(m);
  last_ = m;
}

}  // namespace nav::dut
