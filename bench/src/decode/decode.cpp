// SPDX-License-Identifier: MIT
// `navbench decode`: the table of protocol decoders (one entry per wire protocol, each in its
// own file under decode/), decode_stream() and reading one port's bytes from a capture.
#include "nav/bench/decode.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>

#include "decode/decode_builders.hpp"
#include "nav/bench/capture.hpp"

namespace nav::bench {

using json = nlohmann::ordered_json;
using protocols::ParseResult;
using protocols::ParseStatus;

const std::vector<ProtocolDecoder>& protocol_decoders() {
  static const std::vector<ProtocolDecoder> decoders{
      {"microstrain-gx3",
       "MicroStrain 3DM-GX3-25 binary replies (0xCB accel/rate/mag, 0xCE Euler, 0xC4 continuous)",
       &detail::parse_gx3, std::nullopt},
      {"nmea0183",
       "NMEA 0183 sentences (GGA, RMC, VTG, HDT, ZDA decoded; others as raw fields; $PNVBSOL, "
       "$PNVBPOS)",
       &detail::parse_nmea, static_cast<std::uint8_t>('#')},
      {"navquest-nq1", "LinkQuest NavQuest DVL $#NQ.RES lines", &detail::parse_navquest_nq1,
       std::nullopt},
      {"rdi-pd0", "Teledyne RDI PD0 ensembles (leaders, bottom track)", &detail::parse_rdi_pd0,
       std::nullopt},
      {"rdi-pd6", "Teledyne RDI PD6 lines (:SA :TS :xI :xS :xE :xD)", &detail::parse_rdi_pd6,
       std::nullopt},
      {"waterlinked-a50", "Water Linked DVL-A50 packets (wrz, wru, wrp, wrx, wrt decoded)",
       &detail::parse_waterlinked_a50, std::nullopt},
      {"ebimu", "E2BOX EBIMU-9DOF '*' lines, read by value count", &detail::parse_ebimu,
       std::nullopt},
      {"keller-bus", "Keller RS-485 bus requests and answers (F48, F69, F73, F95)",
       &detail::parse_keller_bus, std::nullopt},
      {"evologics-usbl",
       "EvoLogics USBLLONG / USBLANGLES notifications (and navbench's NVBRELATT)",
       &detail::parse_evologics_usbl, std::nullopt},
      {"beacon-ins",
       "navbench's beacon INS frames (paper P4: accelerometer, yaw and pitch gyros, compass)",
       &detail::parse_beacon_ins, std::nullopt},
      {detail::kNmea2000,
       "NMEA 2000 candump logs (-l lines or screen print): 127250, 127251, 127257, 128259, "
       "128267, 129025, 129026, 129029 decoded, fast packets reassembled, other PGNs raw",
       &detail::parse_nmea2000_line, static_cast<std::uint8_t>('#')},
  };
  return decoders;
}

const ProtocolDecoder* find_decoder(const std::string& name) {
  for (const auto& d : protocol_decoders()) {
    if (d.name == name) return &d;
  }
  return nullptr;
}

DecodeCounts decode_stream(const ProtocolDecoder& d, protocols::ByteSpan bytes,
                           const std::function<void(const json&)>& emit) {
  // A candump log is line-based text with state across lines (fast packets).
  if (d.name == detail::kNmea2000) return detail::decode_nmea2000_log(bytes, emit);
  DecodeCounts counts;
  struct BadRun {
    std::size_t offset = 0, length = 0;
    std::string error;
  } bad;  // a run of bad bytes, whatever the reasons: one record, the first reason
  const auto flush_bad = [&] {
    if (bad.length == 0) return;
    emit(json{{"type", "error"}, {"offset", bad.offset}, {"length", bad.length},
              {"error", bad.error}});
    ++counts.errors;
    bad = BadRun{};
  };
  const auto at_line_start = [&](std::size_t p) { return p == 0 || bytes[p - 1] == '\n'; };
  std::size_t pos = 0;
  while (pos < bytes.size()) {
    if (d.comment_prefix && bytes[pos] == *d.comment_prefix && at_line_start(pos)) {
      while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
      ++pos;
      continue;
    }
    const auto r = d.parse(bytes.subspan(pos));
    if (r.status == ParseStatus::kComplete) {
      flush_bad();
      json j = *r.message;
      j["offset"] = pos;
      emit(j);
      ++counts.messages;
      pos += r.consumed;
      continue;
    }
    // Need-more at the end of the input is a truncated message: an error too.
    const bool truncated = r.status == ParseStatus::kNeedMore;
    const std::size_t n = truncated ? bytes.size() - pos : std::max<std::size_t>(r.consumed, 1);
    const std::string why = truncated ? "truncated message at end of input" : r.error;
    // Random bytes fail at every offset, often each for a reason of its own (a Keller frame's
    // CRC): reported one record per run, not one per byte. A truncated end is its own record.
    if (bad.length == 0 || bad.offset + bad.length != pos || truncated) {
      flush_bad();
      bad = BadRun{pos, 0, why};
    }
    bad.length += n;
    pos += n;
  }
  flush_bad();
  return counts;
}

Result<protocols::Bytes> bytes_from_capture(const std::string& text, const std::string& port,
                                            const std::string& file) {
  auto lines = parse_capture(text, file);
  if (!lines) return tl::unexpected(lines.error());
  protocols::Bytes out;
  std::vector<std::string> ports;  // in order of first appearance
  bool found = false;
  for (const auto& l : *lines) {
    if (l.port == port) {
      found = true;
      out.insert(out.end(), l.bytes.begin(), l.bytes.end());
    } else if (std::find(ports.begin(), ports.end(), l.port) == ports.end()) {
      ports.push_back(l.port);
    }
  }
  if (!found) {
    std::string list;
    for (const auto& p : ports) list += (list.empty() ? "" : ", ") + p;
    return fail(ErrorCode::kNotFound, file + ": no port '" + port + "' in this capture (" +
                                          (list.empty() ? "it has no lines" : "its ports: " + list) +
                                          ")");
  }
  return out;
}

}  // namespace nav::bench
