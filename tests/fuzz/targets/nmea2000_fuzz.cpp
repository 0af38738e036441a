// SPDX-License-Identifier: MIT
// NMEA 2000 (protocols.md 5) as navd's CAN front end sees a bus: frames of any identifier
// (can_frames.hpp), 29-bit ones of the eight PGNs decoded, 129029 reassembled from fast
// packets of many senders. Invariants: an identifier is its header; a decoded message is a
// fixed point of encode(decode(.)); a reassembled payload split into fast-packet frames again
// reassembles to itself, on its last frame only.
#include "can_frames.hpp"
#include "fuzz_support.hpp"
#include "nav/protocols/nmea2000.hpp"

namespace {

namespace n2k = nav::protocols::n2k;
using nav::protocols::Bytes;
using nav::protocols::ByteSpan;

constexpr std::uint32_t kEdpBit = 1u << 25;  // extended data page: not NMEA 2000

void fixed_point(std::uint32_t pgn, ByteSpan payload) {
  const auto m = n2k::decode(pgn, payload);
  if (!m) return;
  NAV_ENSURE(n2k::pgn_of(*m) == pgn, "decoded message of another PGN");
  const Bytes bytes = n2k::encode(*m);
  const auto again = n2k::decode(pgn, bytes);
  NAV_ENSURE(again.has_value(), "an encoded message does not decode");
  NAV_ENSURE(n2k::encode(*again) == bytes, "encode(decode(.)) moves");
}

void reassembles(const n2k::Header& h, const Bytes& payload, std::uint8_t sequence) {
  n2k::FastPacketAssembler fresh;
  const auto frames = n2k::fast_packet_frames(h, payload, sequence);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto whole = fresh.add(h.source, h.pgn, frames[i].payload());
    NAV_ENSURE(whole.has_value() == (i + 1 == frames.size()), "completed on the wrong frame");
    if (whole) NAV_ENSURE(*whole == payload, "fast packet reassembles differently");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ByteSpan bytes(data, size);
  n2k::FastPacketAssembler assembler;
  std::size_t completed = 0;
  while (const auto f = nav::fuzz::next_frame(bytes)) {
    if (!f->extended || f->error || f->rtr || (f->id & kEdpBit) != 0) continue;
    const n2k::Header h = n2k::from_can_id(f->id);
    NAV_ENSURE(n2k::to_can_id(h) == f->id, "an identifier is not its header");
    if (!n2k::is_fast_packet(h.pgn)) {
      if (n2k::decodes(h.pgn)) fixed_point(h.pgn, f->payload());
      continue;
    }
    const auto whole = assembler.add(h.source, h.pgn, f->payload());
    if (!whole) continue;
    ++completed;
    NAV_ENSURE(whole->size() <= n2k::kMaxFastPacketLength, "fast packet too long");
    reassembles(h, *whole, static_cast<std::uint8_t>(f->data[0] >> 5));
    if (n2k::decodes(h.pgn)) fixed_point(h.pgn, *whole);
  }
  NAV_ENSURE(assembler.stats().completed == completed, "completed count");
  return 0;
}
