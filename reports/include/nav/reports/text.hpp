// SPDX-License-Identifier: MIT
// Text from files and processes made safe for the documents the bench writes: valid UTF-8,
// HTML and XML escaping (json_text.hpp: JSON that any byte string survives).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace nav::reports {

/// s with every byte sequence that is not well-formed UTF-8 (stray continuation bytes,
/// overlong forms, surrogates, code points above U+10FFFF, truncated sequences) replaced by
/// U+FFFD, one per maximal ill-formed subpart as Unicode's "substitution of maximal subparts"
/// practice says; valid text comes back unchanged.
std::string valid_utf8(std::string_view s);

/// The offset of the first byte of s that does not begin a well-formed UTF-8 sequence (as
/// valid_utf8 judges), or nothing when s is valid UTF-8.
std::optional<std::size_t> first_invalid_utf8(std::string_view s);

/// valid_utf8(s) with & < > " ' as character references: safe as HTML text and in a quoted
/// attribute value.
std::string html_escape(std::string_view s);

/// valid_utf8(s) with & < > " ' as entities, and the control characters XML 1.0 forbids
/// (all below U+0020 but tab, line feed and carriage return) as U+FFFD: safe in an XML
/// attribute or text.
std::string xml_escape(std::string_view s);

}  // namespace nav::reports
