// SPDX-License-Identifier: MIT
// Private to nav_bench: the per-protocol parsers behind protocol_decoders() that turn one codec
// message into JSON ("type" first, then fields named with their SI unit suffix; decode_stream
// adds "offset"). decode_gx3_nmea.cpp holds the GX3 and NMEA 0183, decode_dvl.cpp the DVLs,
// decode_serial.cpp the other serial devices, decode_can.cpp NMEA 2000 candump logs; the
// helpers below are in decode_builders.cpp. decode.cpp, the table, depends on all of them and
// none of them on it.
#pragma once

#include <functional>
#include <initializer_list>
#include <optional>
#include <utility>

#include <nlohmann/json.hpp>

#include "nav/bench/decode.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::bench::detail {

using json = nlohmann::ordered_json;

/// Carries a parser's status and counts over to a JSON result (j is used when complete).
template <typename M>
protocols::ParseResult<json> with(const protocols::ParseResult<M>& r, json j) {
  protocols::ParseResult<json> out{r.status, r.consumed, std::nullopt, r.error};
  if (r.status == protocols::ParseStatus::kComplete) out.message = std::move(j);
  return out;
}

/// Combines the results of several parsers run at the same byte: the first complete one;
/// else need-more if any needs more; else the malformed result that skips the fewest bytes
/// (so no parser hunting for its own sync byte jumps over another's message).
protocols::ParseResult<json> first_complete(
    std::initializer_list<protocols::ParseResult<json>> results);

/// A JSON number, or null when absent.
template <typename T>
json or_null(const std::optional<T>& v) {
  return v ? json(*v) : json(nullptr);
}

// decode_gx3_nmea.cpp
/// MicroStrain GX3 replies (0xCB, 0xCE, 0xC4).
protocols::ParseResult<json> parse_gx3(protocols::ByteSpan b);
/// NMEA 0183 sentences, navd's $PNVBSOL and $PNVBPOS included.
protocols::ParseResult<json> parse_nmea(protocols::ByteSpan b);

// decode_dvl.cpp
/// LinkQuest NavQuest NQ1 lines.
protocols::ParseResult<json> parse_navquest_nq1(protocols::ByteSpan b);
/// Teledyne RDI PD0 ensembles: leaders and bottom track.
protocols::ParseResult<json> parse_rdi_pd0(protocols::ByteSpan b);
/// Teledyne RDI PD6 lines.
protocols::ParseResult<json> parse_rdi_pd6(protocols::ByteSpan b);
/// Water Linked DVL-A50 packets (reports decoded, other packets as raw options).
protocols::ParseResult<json> parse_waterlinked_a50(protocols::ByteSpan b);

// decode_serial.cpp
/// E2BOX EBIMU lines, interpreted by their value count.
protocols::ParseResult<json> parse_ebimu(protocols::ByteSpan b);
/// Keller RS-485 bus: master requests and device answers.
protocols::ParseResult<json> parse_keller_bus(protocols::ByteSpan b);
/// EvoLogics USBLLONG / USBLANGLES notifications.
protocols::ParseResult<json> parse_evologics_usbl(protocols::ByteSpan b);
/// Paper P4's beacon INS frames.
protocols::ParseResult<json> parse_beacon_ins(protocols::ByteSpan b);

// decode_can.cpp
/// Name of the candump-log decoder, which decode_stream() runs line by line.
inline constexpr const char* kNmea2000 = "nmea2000";
/// One candump line as one frame, without fast-packet reassembly (no state across calls):
/// single-frame PGNs decoded, fast-packet frames raw. decode_stream() uses
/// decode_nmea2000_log() instead.
protocols::ParseResult<json> parse_nmea2000_line(protocols::ByteSpan b);
/// A whole candump log, line by line, fast packets reassembled per (source, PGN); records carry
/// "line" and "offset" (of the line) and the log's "t_s".
DecodeCounts decode_nmea2000_log(protocols::ByteSpan bytes,
                                 const std::function<void(const json&)>& emit);

}  // namespace nav::bench::detail
