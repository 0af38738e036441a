// SPDX-License-Identifier: MIT
// DBC text (protocols/dbc.hpp) as navd's --dbc and the bench's wheel-encoder devices load it,
// then the signal codec run against what loaded: every signal that fits its message gets raw
// values written and read back (they must come back unchanged), every message decodes a frame
// of fuzz bytes, and the wheel-encoder check runs on the database.
#include "fuzz_support.hpp"
#include "nav/protocols/dbc.hpp"
#include "nav/protocols/wheel_encoder.hpp"

namespace {

namespace dbc = nav::protocols::dbc;

void check_signal(const dbc::Signal& s, std::span<std::uint8_t> frame) {
  if (!dbc::fits(s, frame.size())) {
    NAV_ENSURE(!dbc::get_raw(s, frame), "get_raw of a signal that does not fit");
    return;
  }
  const std::uint64_t mask = s.length >= 64 ? ~0ull : (1ull << s.length) - 1;
  for (const std::uint64_t pattern : {0ull, ~0ull, 0x5A5A5A5A5A5A5A5Aull}) {
    dbc::put_raw(s, pattern & mask, frame);
    const auto raw = dbc::get_raw(s, frame);
    NAV_ENSURE(raw.has_value() && *raw == (pattern & mask), "put_raw/get_raw of " + s.name);
  }
  (void)dbc::decode(s, frame);
}

void check(const dbc::Database& db, nav::fuzz::ByteSpan payload) {
  for (const auto& m : db.messages) {
    NAV_ENSURE(m.dlc <= dbc::kMaxDataBytes, "DLC above 64");
    (void)db.cycle_time(m);
    nav::protocols::Bytes frame(m.dlc);
    std::copy_n(payload.begin(), std::min(payload.size(), frame.size()), frame.begin());
    if (const auto values = dbc::decode(m, frame)) {
      std::map<std::string, double, std::less<>> by_name;
      for (const auto& v : *values) by_name[v.signal->name] = v.value;
      (void)dbc::encode(m, by_name);
    }
    for (const auto& s : m.signals) check_signal(s, frame);
  }
  (void)nav::protocols::wheel_encoder::check_database(db);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The first 64 bytes are a frame's payload for the messages, the rest the DBC text.
  const nav::fuzz::ByteSpan all(data, size);
  const std::size_t split = std::min<std::size_t>(size, dbc::kMaxDataBytes);
  const std::string_view text(reinterpret_cast<const char*>(data) + split, size - split);
  const auto db = dbc::parse(text, "fuzz.dbc");
  if (db) check(*db, all.first(split));
  return 0;
}
