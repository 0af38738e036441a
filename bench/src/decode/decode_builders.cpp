// SPDX-License-Identifier: MIT
#include "decode/decode_builders.hpp"

namespace nav::bench::detail {

using protocols::ParseResult;
using protocols::ParseStatus;

ParseResult<json> first_complete(std::initializer_list<ParseResult<json>> results) {
  const ParseResult<json>* fewest = nullptr;  // the malformed result skipping the fewest bytes
  bool need_more = false;
  for (const auto& r : results) {
    if (r.status == ParseStatus::kComplete) return r;
    if (r.status == ParseStatus::kNeedMore) need_more = true;
    if (r.status == ParseStatus::kMalformed && (!fewest || r.consumed < fewest->consumed)) {
      fewest = &r;
    }
  }
  if (need_more || !fewest) return ParseResult<json>{};
  return *fewest;
}

}  // namespace nav::bench::detail
